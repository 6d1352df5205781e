/*
 * A contact: a pair of bodies whose fat AABBs overlap, its manifold, and the solver data of its
 * points. A contact lives from the step the broadphase pairs its bodies until their fat AABBs part;
 * it is "touching" while the narrowphase reports at least one (possibly speculative) point.
 *
 * The solver copies touching contacts into flat constraint records each step and stores the
 * accumulated impulses back (contact-solver.ts). When the manifold is recomputed, a new point
 * inherits the impulses of the old point with the same feature id (Box2D's b2UpdateContact).
 */
import type { Body } from './body.ts'
import { collideGeometry } from './collide.ts'
import { Manifold } from './manifold.ts'

/** Multiplier that makes the pair key (a * KEY_SCALE + b) unique for body ids below 2^26. */
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
 * A contact between two bodies, bodyA.id < bodyB.id. The two points' fields are flattened into the
 * contact (suffix 0 and 1) so the narrowphase and the solver read one object, not three.
 */
export class Contact {
  key: number
  bodyA: Body
  bodyB: Body
  friction: number
  restitution: number
  touching = false
  pointCount = 0
  /** World unit normal from A to B. */
  normalX = 0
  normalY = 0
  /** Feature ids of the points. */
  id0 = 0
  id1 = 0
  /** Points relative to each body's centre of mass at the step start (m). */
  anchorAx0 = 0
  anchorAy0 = 0
  anchorBx0 = 0
  anchorBy0 = 0
  anchorAx1 = 0
  anchorAy1 = 0
  anchorBx1 = 0
  anchorBy1 = 0
  /** Separations reported by the narrowphase, negative when overlapping (m). */
  separation0 = 0
  separation1 = 0
  /** World points from the narrowphase (m). */
  px0 = 0
  py0 = 0
  px1 = 0
  py1 = 0
  /** Accumulated impulses, warm started across steps (N s). */
  normalImpulse0 = 0
  tangentImpulse0 = 0
  normalImpulse1 = 0
  tangentImpulse1 = 0
  /** Total impulses applied during the last step, all sub-steps (N s); tangent along (ny, -nx). */
  totalNormalImpulse0 = 0
  totalTangentImpulse0 = 0
  totalNormalImpulse1 = 0
  totalTangentImpulse1 = 0

  constructor(bodyA: Body, bodyB: Body) {
    this.key = bodyA.id * KEY_SCALE + bodyB.id
    this.bodyA = bodyA
    this.bodyB = bodyB
    this.friction = Math.sqrt(bodyA.friction * bodyB.friction)
    this.restitution = Math.max(bodyA.restitution, bodyB.restitution)
  }

  /** Reinitializes a pooled contact for a new pair (no allocation). */
  reset(bodyA: Body, bodyB: Body): this {
    this.key = bodyA.id * KEY_SCALE + bodyB.id
    this.bodyA = bodyA
    this.bodyB = bodyB
    this.friction = Math.sqrt(bodyA.friction * bodyB.friction)
    this.restitution = Math.max(bodyA.restitution, bodyB.restitution)
    this.touching = false
    this.pointCount = 0
    this.normalX = 0
    this.normalY = 0
    this.normalImpulse0 = 0
    this.tangentImpulse0 = 0
    this.normalImpulse1 = 0
    this.tangentImpulse1 = 0
    this.totalNormalImpulse0 = 0
    this.totalTangentImpulse0 = 0
    this.totalNormalImpulse1 = 0
    this.totalTangentImpulse1 = 0
    return this
  }
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
  c.normalX = 0
  c.normalY = 0
  c.touching = false
}

/** Recomputes a contact's manifold at the bodies' current transforms; returns whether it touches. */
export function updateContact(c: Contact, speculativeDistance: number): boolean {
  const a = c.bodyA
  const b = c.bodyB
  collideGeometry(
    a.shape,
    a.geometry,
    a.x,
    a.y,
    a.c,
    a.s,
    b.shape,
    b.geometry,
    b.x,
    b.y,
    b.c,
    b.s,
    speculativeDistance,
    scratch,
  )
  old[0] = c.id0
  old[1] = c.id1
  old[2] = c.normalImpulse0
  old[3] = c.normalImpulse1
  old[4] = c.tangentImpulse0
  old[5] = c.tangentImpulse1
  old[6] = c.pointCount
  const count = scratch.pointCount
  c.pointCount = count
  c.normalX = scratch.normalX
  c.normalY = scratch.normalY
  if (count > 0) {
    const mp = scratch.points[0]
    c.id0 = mp.id
    c.anchorAx0 = mp.x - a.cx
    c.anchorAy0 = mp.y - a.cy
    c.anchorBx0 = mp.x - b.cx
    c.anchorBy0 = mp.y - b.cy
    c.separation0 = mp.separation
    c.px0 = mp.x
    c.py0 = mp.y
    inherit(mp.id)
    c.normalImpulse0 = found[0]
    c.tangentImpulse0 = found[1]
  }
  if (count > 1) {
    const mp = scratch.points[1]
    c.id1 = mp.id
    c.anchorAx1 = mp.x - a.cx
    c.anchorAy1 = mp.y - a.cy
    c.anchorBx1 = mp.x - b.cx
    c.anchorBy1 = mp.y - b.cy
    c.separation1 = mp.separation
    c.px1 = mp.x
    c.py1 = mp.y
    inherit(mp.id)
    c.normalImpulse1 = found[0]
    c.tangentImpulse1 = found[1]
  }
  c.touching = count > 0
  return c.touching
}
