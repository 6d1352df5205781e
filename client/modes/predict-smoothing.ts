/*
 * Smoothing a predicting client's corrections. A rollback can move a body by a few millimetres or
 * more between one frame and the next; drawn as is, that is a visible pop. At each rollback the
 * difference between where the old present had a body and where the corrected present has it (at
 * the same tick) becomes a drawing offset, added to the body's pose and decayed exponentially
 * (half-life HALF_LIFE_MS), so small errors glide away in a few frames. Errors larger than
 * SNAP_DISTANCE (a teleport, a body thrown elsewhere) are shown at once. The simulation is never
 * touched: only what is drawn.
 */
import type { RoomSimulation } from '../../shared/index.ts'

/** Half-life of a drawing offset (ms). */
export const HALF_LIFE_MS = 60
/** Corrections larger than this are drawn at once (m). */
export const SNAP_DISTANCE = 1

/** A body's drawing offset: position (m) and angle (rad). */
export interface DrawOffset {
  x: number
  y: number
  a: number
}

/** Per-body drawing offsets after rollbacks. */
export class CorrectionSmoother {
  readonly offsets = new Map<number, DrawOffset>()
  private readonly p = { x: 0, y: 0 }
  private readonly q = { x: 0, y: 0 }

  /** A rollback replaced `before` with `after` (both at the same tick): keep what was drawn. */
  correct(before: RoomSimulation, after: RoomSimulation): void {
    const wb = before.world
    const wa = after.world
    for (const id of wa.bodyIds()) {
      if (wa.getBodyType(id) === 'static' || !wb.hasBody(id)) continue
      const p = wb.getPosition(id, this.p)
      const q = wa.getPosition(id, this.q)
      let da = wb.getAngle(id) - wa.getAngle(id)
      if (da > Math.PI) da -= 2 * Math.PI
      if (da < -Math.PI) da += 2 * Math.PI
      const old = this.offsets.get(id)
      const x = (old?.x ?? 0) + p.x - q.x
      const y = (old?.y ?? 0) + p.y - q.y
      const a = (old?.a ?? 0) + da
      if (x * x + y * y > SNAP_DISTANCE * SNAP_DISTANCE || (x === 0 && y === 0 && a === 0))
        this.offsets.delete(id)
      else this.offsets.set(id, { x, y, a })
    }
  }

  /** Let `dtMs` pass: every offset shrinks; tiny ones are dropped. */
  decay(dtMs: number): void {
    const f = 0.5 ** (dtMs / HALF_LIFE_MS)
    for (const [id, o] of this.offsets) {
      o.x *= f
      o.y *= f
      o.a *= f
      if (Math.abs(o.x) + Math.abs(o.y) < 1e-5 && Math.abs(o.a) < 1e-5) this.offsets.delete(id)
    }
  }

  /** The offset to add to a body's drawn pose, or undefined. */
  offset(id: number): DrawOffset | undefined {
    return this.offsets.get(id)
  }
}
