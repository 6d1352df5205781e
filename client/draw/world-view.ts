/*
 * Bodies as drawn from a world that steps in the page (the offline sandbox and the replay player):
 * one ViewBody per body, kept between frames, with the pose before the last step so a frame can be
 * drawn between the last two steps (alpha 0 is the previous pose, 1 the current one).
 */
import type { World } from '../../engine/index.ts'
import { cssColor, type WireShape, wireShapesOf } from '../../shared/index.ts'
import type { ViewBody } from '../modes/index.ts'

const KIND = { static: 0, kinematic: 1, dynamic: 2 } as const

/** A drawn body with its pose before the last step. */
interface StepViewBody extends ViewBody {
  px: number
  py: number
  pa: number
}

/** The drawn bodies of one world (see the file comment). */
export class WorldView {
  private readonly shapes = new Map<number, WireShape[]>()
  /** A body's colour (0xRRGGBB; RoomSimulation.bodyColors) when the world belongs to a room. */
  colorOf: (id: number) => number | undefined = () => undefined
  private readonly view: StepViewBody[] = []
  private readonly byId = new Map<number, StepViewBody>()
  private readonly scratch = { x: 0, y: 0 }

  /** Forget every body (a new world). */
  clear(): void {
    this.shapes.clear()
    this.byId.clear()
    this.view.length = 0
  }

  /** Forget one body (destroyed). */
  remove(id: number): void {
    this.byId.delete(id)
    this.view.length = 0
  }

  /** A body's shapes, colour or type changed (the sandbox's edit commands): draw it afresh. */
  changed(id: number): void {
    this.shapes.delete(id)
    this.remove(id)
  }

  /** The drawn body of that id, if it is drawn. */
  get(id: number): ViewBody | undefined {
    return this.byId.get(id)
  }

  /** Every drawn body (the array and objects are reused between frames). */
  bodies(): readonly ViewBody[] {
    return this.view
  }

  /** Remember every body's pose before the step about to be taken. */
  capturePrevious(world: World): void {
    this.sync(world)
    const p = this.scratch
    for (const v of this.view) {
      world.getPosition(v.id, p)
      v.px = p.x
      v.py = p.y
      v.pa = world.getAngle(v.id)
    }
  }

  /** Place every body between its previous and current pose; `grabColor` colours held bodies. */
  refresh(world: World, alpha: number, grabColor: (id: number) => string | null): void {
    this.sync(world)
    const p = this.scratch
    for (const v of this.view) {
      world.getPosition(v.id, p)
      const angle = world.getAngle(v.id)
      let turn = angle - v.pa
      if (turn > Math.PI) turn -= 2 * Math.PI
      else if (turn < -Math.PI) turn += 2 * Math.PI
      v.x = v.px + (p.x - v.px) * alpha
      v.y = v.py + (p.y - v.py) * alpha
      v.angle = v.pa + turn * alpha
      v.awake = world.isAwake(v.id)
      v.grabColor = grabColor(v.id)
    }
  }

  private sync(world: World): void {
    const ids = world.bodyIds()
    if (ids.length === this.view.length) return
    this.view.length = 0
    for (const id of ids) this.view.push(this.body(world, id))
  }

  private body(world: World, id: number): StepViewBody {
    let v = this.byId.get(id)
    if (!v) {
      let shapes = this.shapes.get(id)
      if (!shapes) {
        shapes = wireShapesOf(world, id)
        this.shapes.set(id, shapes)
      }
      const p = world.getPosition(id)
      const angle = world.getAngle(id)
      v = {
        id,
        kind: KIND[world.getBodyType(id)],
        shapes,
        color: cssColor(this.colorOf(id)),
        x: p.x,
        y: p.y,
        angle,
        awake: true,
        grabColor: null,
        px: p.x,
        py: p.y,
        pa: angle,
      }
      this.byId.set(id, v)
    }
    return v
  }
}
