/*
 * Concord's own engine as a benchmark peer: createWorld({ enableSleep }), buildScene, step().
 * Every other world setting keeps its default (4 sub-steps, contact hertz 30, continuous on).
 */
import {
  type BodyDef,
  type BodyId,
  buildScene,
  createWorld,
  type SceneBlueprint,
  type World,
} from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

/** A Concord world holding the blueprint, sleeping on or off. */
export class ConcordPeer implements PeerWorld {
  readonly engine = 'concord'
  /** The world itself (the benchmark page checks its broadphase). */
  readonly world: World
  private readonly ids: BodyId[]

  constructor(blueprint: SceneBlueprint, enableSleep: boolean) {
    this.world = createWorld({ gravity: { x: blueprint.gravity.x, y: blueprint.gravity.y }, enableSleep })
    this.ids = buildScene(this.world, blueprint)
  }

  addBody(def: BodyDef): void {
    this.ids.push(this.world.createBody(def))
  }

  step(): void {
    this.world.step()
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.ids.length * 4)
    const p = { x: 0, y: 0 }
    const v = { x: 0, y: 0 }
    this.ids.forEach((id, i) => {
      this.world.getPosition(id, p)
      this.world.getLinearVelocity(id, v)
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    return this.world.awakeBodyCount()
  }

  dispose(): void {
    // A Concord world lives entirely on the JavaScript heap; dropping the reference frees it.
  }
}
