/*
 * One engine running one comparison scene: build, step in timed chunks, measure the end state.
 * The terminal benchmark runs one of these per child process; the benchmark page runs one per
 * engine in the visitor's browser.
 *
 * Only world.step() is timed (performance.now() around each call). Bodies arriving in a rain are
 * created before their step, outside the timing, and the awake count (to find when everything
 * fell asleep) is read after it, also outside.
 */
import type { BodyDef } from '../engine/index.ts'
import type { Arrival, BenchScene, BenchSceneInstance } from './bench-scenes.ts'
import { createPeer, type PeerEngine } from './peers/index.ts'
import { allBodies, measureQuality, type SceneQuality } from './scene-quality.ts'
import type { PeerWorld } from './stats.ts'

const STEP_SECONDS = 1 / 60

/** One engine's world for one scene, stepped in chunks. */
export class PeerRun {
  /** Steps taken so far (warm-up included). */
  stepIndex = 0
  private nextArrival = 0
  private sleptAfter: number | null = null
  private readonly bodies: BodyDef[]

  private constructor(
    readonly engine: PeerEngine,
    readonly scene: BenchScene,
    readonly instance: BenchSceneInstance,
    readonly sleep: boolean,
    readonly peer: PeerWorld,
    /** Time to build the scene (ms). */
    readonly buildMs: number,
  ) {
    this.bodies = allBodies(instance.blueprint, instance.arrivals)
  }

  /** Builds `scene` with `count` bodies in `engine`. */
  static async start(engine: PeerEngine, scene: BenchScene, count: number, sleep: boolean): Promise<PeerRun> {
    const instance = scene.make(count)
    const t0 = performance.now()
    const peer = await createPeer(engine, instance.blueprint, sleep)
    return new PeerRun(engine, scene, instance, sleep, peer, performance.now() - t0)
  }

  /** Dynamic bodies in the scene once every arrival is in. */
  get dynamicBodies(): number {
    return this.bodies.filter((def) => (def.type ?? 'dynamic') === 'dynamic').length
  }

  private addArrivals(): void {
    const arrivals: readonly Arrival[] = this.instance.arrivals
    while (this.nextArrival < arrivals.length && arrivals[this.nextArrival].step <= this.stepIndex) {
      this.peer.addBody(arrivals[this.nextArrival].def)
      this.nextArrival++
    }
  }

  /** Takes `steps` steps, appending each step's time (ms) to `times`. */
  stepChunk(steps: number, times: number[]): void {
    for (let s = 0; s < steps; s++) {
      this.addArrivals()
      const t0 = performance.now()
      this.peer.step()
      times.push(performance.now() - t0)
      this.stepIndex++
      const allArrived = this.nextArrival >= this.instance.arrivals.length
      if (this.sleep && this.sleptAfter === null && allArrived && this.peer.awakeCount() === 0) {
        this.sleptAfter = this.stepIndex * STEP_SECONDS
      }
    }
  }

  /** The end state so far (bodies not yet arrived are left out). */
  quality(): SceneQuality {
    const end = this.peer.readBodies()
    return measureQuality(
      this.scene.kind,
      this.instance.blueprint,
      this.bodies.slice(0, end.length / 4),
      end,
      this.peer.awakeCount(),
      this.sleptAfter,
    )
  }

  /** The bodies' positions and velocities (readBodies) for drawing. */
  readBodies(): Float64Array {
    return this.peer.readBodies()
  }

  /** Frees the engine's world. */
  dispose(): void {
    this.peer.dispose()
  }
}
