/*
 * The numbers of every contact, one fixed-size record per contact in one Float64Array per world
 * (structure of arrays instead of object fields).
 *
 * Why: in V8 a double field of an object is a pointer to a separate heap number, so every pass
 * over the contacts (narrowphase update, solver prepare and store) chased about 30 pointers per
 * contact to memory that is not next to the contact or to each other; in a worker stepping ten
 * rooms those were the hottest cache misses of the step (`old[2] = c.normalImpulse0` alone was 46 %
 * of updateContact's time in a bench:room-tick profile). A record is CONTACT_STRIDE doubles
 * (256 bytes, four cache lines), read and written by offset like the solver's body state.
 *
 * A contact keeps its record for life: pooled contacts are reused with their record, so records
 * are never freed and the array only grows (by doubling, while the world's contact count rises).
 */

/** Friction of the pair (the geometric mean of the bodies'). */
export const FRICTION = 0
/** Restitution of the pair (the larger of the bodies'). */
export const RESTITUTION = 1
/** World unit normal from A to B. */
export const NORMAL_X = 2
export const NORMAL_Y = 3
/** Offset of point 0's fields; point j starts at POINT_0 + j * POINT_FIELDS. */
export const POINT_0 = 4
/** Numbers per point. */
export const POINT_FIELDS = 12
// Point fields, relative to the point's start.
/** Feature id. */
export const ID = 0
/** Point relative to each body's centre of mass at the step start (m). */
export const ANCHOR_AX = 1
export const ANCHOR_AY = 2
export const ANCHOR_BX = 3
export const ANCHOR_BY = 4
/** Separation reported by the narrowphase, negative when overlapping (m). */
export const SEPARATION = 5
/** World point from the narrowphase (m). */
export const PX = 6
export const PY = 7
/** Accumulated impulses, warm started across steps (N s). */
export const NORMAL_IMPULSE = 8
export const TANGENT_IMPULSE = 9
/** Total impulses applied during the last step, all sub-steps (N s); tangent along (ny, -nx). */
export const TOTAL_NORMAL = 10
export const TOTAL_TANGENT = 11
/**
 * Rolling resistance of the pair (m): the larger of the shapes' rollingResistance times the larger of
 * their radii (Box2D v3.1's mixing); the rolling impulse is clamped to it times the normal impulse.
 */
export const ROLLING_RESISTANCE = 28
/** Surface speed of the pair along the tangent (ny, -nx) (m/s): the sum of the shapes' tangentSpeed. */
export const TANGENT_SPEED = 29
/** Accumulated rolling (angular) impulse, warm started across steps (N m s); kept while the pair touches. */
export const ROLLING_IMPULSE = 30
/** Numbers per contact record (31 used; 32 keeps records on 64-byte boundaries). */
export const CONTACT_STRIDE = 32
/**
 * For hit events, set by the narrowphase pass of the step for contacts that ask for them: the
 * fastest approach speed along the normal of the manifold's points at the step start (m/s) and that
 * point (world, m). Not saved: recomputed before every use. They live in a side record of HIT_STRIDE
 * numbers per contact (ContactStore.hits, at hitOffset(base)), not in the contact record, so that the
 * contact record stays 32 numbers (four cache lines) for the passes every contact takes.
 */
export const APPROACH = 0
export const HIT_X = 1
export const HIT_Y = 2
/** Numbers per hit record (3 used). */
export const HIT_STRIDE = 4

/** Offset in ContactStore.hits of the hit record of the contact whose record starts at `base`. */
export function hitOffset(base: number): number {
  return (base / CONTACT_STRIDE) * HIT_STRIDE
}

/** The contact records of one world. */
export class ContactStore {
  /** The records: contact k's fields at [k * CONTACT_STRIDE, (k + 1) * CONTACT_STRIDE). */
  data = new Float64Array(64 * CONTACT_STRIDE)
  /** The hit records (APPROACH, HIT_X, HIT_Y): contact k's at [k * HIT_STRIDE, (k + 1) * HIT_STRIDE). */
  hits = new Float64Array(64 * HIT_STRIDE)
  /** Records handed out. */
  count = 0

  /** Hands out a zeroed record and returns its offset (grows by doubling). */
  allocate(): number {
    const offset = this.count * CONTACT_STRIDE
    if (offset + CONTACT_STRIDE > this.data.length) {
      const grown = new Float64Array(2 * this.data.length)
      grown.set(this.data)
      this.data = grown
      const hits = new Float64Array(2 * this.hits.length)
      hits.set(this.hits)
      this.hits = hits
    }
    this.count++
    return offset
  }
}
