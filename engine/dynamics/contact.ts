/*
 * A contact: a pair of shapes on two bodies whose fat AABBs overlap, its manifold, and the solver
 * data of its points. A compound body touching another has one contact per pair of touching shapes.
 * A contact lives from the step the broadphase pairs its shapes until their fat AABBs part;
 * it is "touching" while the narrowphase reports at least one (possibly speculative) point.
 *
 * The solver copies touching contacts into flat constraint records each step and stores the
 * accumulated impulses back (contact-solver.ts). When the manifold is recomputed, a new point
 * inherits the impulses of the old point with the same feature id (Box2D's b2UpdateContact).
 */

import {
  collideChainSegmentAt,
  collideGeometryAt,
  Manifold,
  type ManifoldPoint,
  type Shape,
} from '../collision/index.ts'
import type { Body } from './body.ts'
import type { BodyShape } from './body-shape.ts'
import {
  ANCHOR_AX,
  ANCHOR_AY,
  ANCHOR_BX,
  ANCHOR_BY,
  APPROACH,
  type ContactStore,
  FRICTION,
  HIT_X,
  HIT_Y,
  hitOffset,
  ID,
  NORMAL_IMPULSE,
  NORMAL_X,
  NORMAL_Y,
  POINT_0,
  POINT_FIELDS,
  PX,
  PY,
  RESTITUTION,
  ROLLING_IMPULSE,
  ROLLING_RESISTANCE,
  SEPARATION,
  TANGENT_IMPULSE,
  TANGENT_SPEED,
  TOTAL_NORMAL,
  TOTAL_TANGENT,
} from './contact-record.ts'

/** Multiplier that makes the pair key (a * KEY_SCALE + b) unique for shape ids below 2^26. */
export const KEY_SCALE = 67108864

/** The persistent fields of a contact point; a contact has each twice, suffixed 0 and 1. */
export const CONTACT_POINT_FIELDS = [
  'id',
  'anchorAx',
  'anchorAy',
  'anchorBx',
  'anchorBy',
  'separation',
  'px',
  'py',
  'normalImpulse',
  'tangentImpulse',
  'totalNormalImpulse',
  'totalTangentImpulse',
] as const

/**
 * A contact between two shapes, shapeA.id < shapeB.id, on bodies bodyA and bodyB (the shapes'
 * bodies; their ids may be in either order). Its numbers live in the world's ContactStore
 * (contact-record.ts) at offset `base`; the hot passes read them there by offset, and the named
 * properties below (friction, normalX, anchorAx0, ...) read and write the same record for
 * everything else (saving, read-back, tests).
 */
export class Contact {
  // V8 lays an object's fields out in declaration order: the fields the solver's per-contact passes
  // read (prepareContacts: bodyA to surface; storeImpulses: store and base) come first, next to
  // the object header, so those passes touch one or two of the object's cache lines, not three.
  bodyA: Body
  bodyB: Body
  /** The store holding this contact's record, and the record's offset in store.data. */
  readonly store: ContactStore
  readonly base: number
  pointCount = 0
  /**
   * Whether the pair has a rolling resistance or a tangent speed other than +0 (set by mixMaterials,
   * which alone sets both). The solver reads and writes those numbers, and the rolling impulse, only
   * then: they sit in the last cache line of the record, which a one-point contact otherwise never
   * touches. A pair without rolling resistance keeps a zero rolling impulse all its life.
   */
  surface = false
  /** SLENDER_A | SLENDER_B: which of the shapes is slender (BodyShape.slender), for prepareContacts. */
  slender = 0
  touching = false
  /** Which events the pair reports: CONTACT_EVENTS | HIT_EVENTS (either shape asking is enough). */
  events = 0
  /**
   * The shapes' proxies, geometries and narrowphase layouts, copied here when the pair is made
   * (they never change during a shape's life): the collide loop then reads only the contact and
   * its bodies, as it did when a body had one shape, not the shape objects (a cache miss each).
   */
  proxyA: number
  proxyB: number
  geomA: Shape
  geomB: Shape
  layoutA: Float64Array
  layoutB: Float64Array
  key: number
  shapeA: BodyShape
  shapeB: BodyShape
  declare friction: number
  declare restitution: number
  /** Mixed rolling resistance (m) and tangent speed (m/s), and the accumulated rolling impulse (N m s). */
  declare rollingResistance: number
  declare tangentSpeed: number
  declare rollingImpulse: number
  /** World unit normal from A to B. */
  declare normalX: number
  declare normalY: number
  /** Feature ids of the points. */
  declare id0: number
  declare id1: number
  /** Points relative to each body's centre of mass at the step start (m). */
  declare anchorAx0: number
  declare anchorAy0: number
  declare anchorBx0: number
  declare anchorBy0: number
  declare anchorAx1: number
  declare anchorAy1: number
  declare anchorBx1: number
  declare anchorBy1: number
  /** Separations reported by the narrowphase, negative when overlapping (m). */
  declare separation0: number
  declare separation1: number
  /** World points from the narrowphase (m). */
  declare px0: number
  declare py0: number
  declare px1: number
  declare py1: number
  /** Accumulated impulses, warm started across steps (N s). */
  declare normalImpulse0: number
  declare tangentImpulse0: number
  declare normalImpulse1: number
  declare tangentImpulse1: number
  /** Total impulses applied during the last step, all sub-steps (N s); tangent along (ny, -nx). */
  declare totalNormalImpulse0: number
  declare totalTangentImpulse0: number
  declare totalNormalImpulse1: number
  declare totalTangentImpulse1: number

  constructor(shapeA: BodyShape, shapeB: BodyShape, store: ContactStore) {
    this.key = shapeA.id * KEY_SCALE + shapeB.id
    this.shapeA = shapeA
    this.shapeB = shapeB
    this.bodyA = shapeA.body
    this.bodyB = shapeB.body
    this.proxyA = shapeA.proxy
    this.proxyB = shapeB.proxy
    this.geomA = shapeA.shape
    this.geomB = shapeB.shape
    this.layoutA = shapeA.geometry
    this.layoutB = shapeB.geometry
    this.slender = slenderBits(shapeA, shapeB)
    this.store = store
    this.base = store.allocate()
    mixMaterials(this)
  }

  /** Reinitializes a pooled contact for a new pair (no allocation). */
  reset(shapeA: BodyShape, shapeB: BodyShape): this {
    this.key = shapeA.id * KEY_SCALE + shapeB.id
    this.shapeA = shapeA
    this.shapeB = shapeB
    this.bodyA = shapeA.body
    this.bodyB = shapeB.body
    this.proxyA = shapeA.proxy
    this.proxyB = shapeB.proxy
    this.geomA = shapeA.shape
    this.geomB = shapeB.shape
    this.layoutA = shapeA.geometry
    this.layoutB = shapeB.geometry
    this.slender = slenderBits(shapeA, shapeB)
    this.touching = false
    this.pointCount = 0
    const d = this.store.data
    const o = this.base
    mixMaterials(this)
    d[o + NORMAL_X] = 0
    d[o + NORMAL_Y] = 0
    d[o + ROLLING_IMPULSE] = 0
    for (let p = o + POINT_0; p < o + POINT_0 + 2 * POINT_FIELDS; p += POINT_FIELDS) {
      d[p + NORMAL_IMPULSE] = 0
      d[p + TANGENT_IMPULSE] = 0
      d[p + TOTAL_NORMAL] = 0
      d[p + TOTAL_TANGENT] = 0
    }
    return this
  }
}

/** Contact.slender bits: shape A is slender; shape B is. */
export const SLENDER_A = 1
export const SLENDER_B = 2

function slenderBits(a: BodyShape, b: BodyShape): number {
  return (a.slender ? SLENDER_A : 0) | (b.slender ? SLENDER_B : 0)
}

/** Contact.events bit: begin and end events. */
export const CONTACT_EVENTS = 1
/** Contact.events bit: hit events. */
export const HIT_EVENTS = 2

/**
 * Sets the pair's friction (geometric mean), restitution (larger), rolling resistance (the larger
 * coefficient times the larger shape radius) and tangent speed (sum) from its shapes (Box2D v3.1's
 * mixing), and which events it reports.
 */
export function mixMaterials(c: Contact): void {
  const sa = c.shapeA
  const sb = c.shapeB
  c.events =
    (sa.enableContactEvents || sb.enableContactEvents ? CONTACT_EVENTS : 0) |
    (sa.enableHitEvents || sb.enableHitEvents ? HIT_EVENTS : 0)
  const d = c.store.data
  d[c.base + FRICTION] = Math.sqrt(c.shapeA.friction * c.shapeB.friction)
  d[c.base + RESTITUTION] = Math.max(c.shapeA.restitution, c.shapeB.restitution)
  // Box2D v3.1 b2UpdateContact: a length, so the torque limit is resistance x radius x normal force.
  d[c.base + ROLLING_RESISTANCE] =
    sa.rollingResistance > 0 || sb.rollingResistance > 0
      ? Math.max(sa.rollingResistance, sb.rollingResistance) * Math.max(sa.shape.radius, sb.shape.radius)
      : 0
  d[c.base + TANGENT_SPEED] = sa.tangentSpeed + sb.tangentSpeed
  // The test prepareContacts made per step before this flag (contact-solver.ts), on the same numbers.
  c.surface = d[c.base + ROLLING_RESISTANCE] > 0 || !Object.is(d[c.base + TANGENT_SPEED], 0)
}

/** The named properties of a contact's record and their offsets in it. */
const RECORD_PROPERTIES: [string, number][] = [
  ['friction', FRICTION],
  ['restitution', RESTITUTION],
  ['rollingResistance', ROLLING_RESISTANCE],
  ['tangentSpeed', TANGENT_SPEED],
  ['rollingImpulse', ROLLING_IMPULSE],
  ['normalX', NORMAL_X],
  ['normalY', NORMAL_Y],
]
const POINT_OFFSETS = [ID, ANCHOR_AX, ANCHOR_AY, ANCHOR_BX, ANCHOR_BY, SEPARATION, PX, PY]
const IMPULSE_OFFSETS = [NORMAL_IMPULSE, TANGENT_IMPULSE, TOTAL_NORMAL, TOTAL_TANGENT]
for (let j = 0; j < 2; j++) {
  const offsets = [...POINT_OFFSETS, ...IMPULSE_OFFSETS]
  CONTACT_POINT_FIELDS.forEach((field, k) => {
    RECORD_PROPERTIES.push([`${field}${j}`, POINT_0 + j * POINT_FIELDS + offsets[k]])
  })
}
for (const [name, offset] of RECORD_PROPERTIES) {
  Object.defineProperty(Contact.prototype, name, {
    get(this: Contact): number {
      return this.store.data[this.base + offset]
    },
    set(this: Contact, value: number): void {
      this.store.data[this.base + offset] = value
    },
  })
}

const scratch = new Manifold()
// Previous ids and impulses while a manifold is rebuilt: [id0, id1, normal0, normal1, tangent0,
// tangent1, count]. A typed array, because a module-level `let` holding a double allocates a heap
// number on every write in V8.
const old = new Float64Array(7)

/** Impulses the old point with feature id `id` had, into found[0..1]; zero if none. */
function inherit(id: number): void {
  found[0] = 0
  found[1] = 0
  if (old[6] > 0 && old[0] === id) {
    found[0] = old[2]
    found[1] = old[4]
  } else if (old[6] > 1 && old[1] === id) {
    found[0] = old[3]
    found[1] = old[5]
  }
}
const found = new Float64Array(2)

/**
 * Marks a contact as not touching without running the narrowphase, for bodies whose bounding
 * circles are already farther apart than the speculative distance (what the narrowphase would say).
 */
export function clearContact(c: Contact): void {
  c.pointCount = 0
  const d = c.store.data
  d[c.base + NORMAL_X] = 0
  d[c.base + NORMAL_Y] = 0
  // Only a pair with a surface record can hold a rolling impulse (Contact.surface).
  if (c.surface) d[c.base + ROLLING_IMPULSE] = 0
  c.touching = false
}

/** Recomputes a contact's manifold at the bodies' current transforms; returns whether it touches. */
export function updateContact(c: Contact, speculativeDistance: number): boolean {
  const a = c.bodyA
  const b = c.bodyB
  if (c.geomA.type === 'chainSegment' || c.geomB.type === 'chainSegment') {
    // Chain pairs go through their own entry, with poses read from the bodies (see collide.ts).
    collideChainSegmentAt(c.geomA, c.layoutA, a, c.geomB, c.layoutB, b, scratch)
  } else collideGeometryAt(c.geomA, c.layoutA, a, c.geomB, c.layoutB, b, scratch, speculativeDistance)
  const d = c.store.data
  const o = c.base
  const p0 = o + POINT_0
  const p1 = p0 + POINT_FIELDS
  // The old points' ids and impulses, read only for the points the contact had (inherit() looks at
  // no others): a one-point contact's second point lies in cache lines it otherwise never touches.
  const before = c.pointCount
  old[6] = before
  if (before > 0) {
    old[0] = d[p0 + ID]
    old[2] = d[p0 + NORMAL_IMPULSE]
    old[4] = d[p0 + TANGENT_IMPULSE]
  }
  if (before > 1) {
    old[1] = d[p1 + ID]
    old[3] = d[p1 + NORMAL_IMPULSE]
    old[5] = d[p1 + TANGENT_IMPULSE]
  }
  const count = scratch.pointCount
  c.pointCount = count
  d[o + NORMAL_X] = scratch.normalX
  d[o + NORMAL_Y] = scratch.normalY
  if (count > 0) writePoint(d, p0, scratch.points[0], a, b)
  if (count > 1) writePoint(d, p1, scratch.points[1], a, b)
  // The rolling impulse is the contact's, not a point's: kept while the pair touches (Box2D v3.1).
  if (count === 0 && c.surface) d[o + ROLLING_IMPULSE] = 0
  c.touching = count > 0
  return c.touching
}

/** Writes manifold point `mp` into the point record at `p`, inheriting the old impulses by feature id. */
function writePoint(d: Float64Array, p: number, mp: ManifoldPoint, a: Body, b: Body): void {
  d[p + ID] = mp.id
  d[p + ANCHOR_AX] = mp.x - a.cx
  d[p + ANCHOR_AY] = mp.y - a.cy
  d[p + ANCHOR_BX] = mp.x - b.cx
  d[p + ANCHOR_BY] = mp.y - b.cy
  d[p + SEPARATION] = mp.separation
  d[p + PX] = mp.x
  d[p + PY] = mp.y
  inherit(mp.id)
  d[p + NORMAL_IMPULSE] = found[0]
  d[p + TANGENT_IMPULSE] = found[1]
}

/**
 * Stores the fastest approach speed along the normal among the contact's points, at the bodies'
 * velocities before the step's solve (m/s, positive when closing), and that point, for hit events.
 */
export function measureApproach(c: Contact): void {
  const a = c.bodyA
  const b = c.bodyB
  const d = c.store.data
  const o = c.base
  const h = c.store.hits
  const ho = hitOffset(o)
  const nx = d[o + NORMAL_X]
  const ny = d[o + NORMAL_Y]
  let best = Number.NEGATIVE_INFINITY
  for (let j = 0; j < c.pointCount; j++) {
    const p = o + POINT_0 + j * POINT_FIELDS
    const rax = d[p + ANCHOR_AX]
    const ray = d[p + ANCHOR_AY]
    const rbx = d[p + ANCHOR_BX]
    const rby = d[p + ANCHOR_BY]
    const dvx = b.vx - b.w * rby - (a.vx - a.w * ray)
    const dvy = b.vy + b.w * rbx - (a.vy + a.w * rax)
    const approach = -(dvx * nx + dvy * ny)
    if (approach > best) {
      best = approach
      h[ho + HIT_X] = d[p + PX]
      h[ho + HIT_Y] = d[p + PY]
    }
  }
  h[ho + APPROACH] = best
}
