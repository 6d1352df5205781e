/*
 * A contact: a pair of bodies whose fat AABBs overlap, its manifold, and the solver data of its
 * points. A contact lives from the step the broadphase pairs its bodies until their fat AABBs part;
 * it is "touching" while the narrowphase reports at least one (possibly speculative) point.
 *
 * The contact is its own constraint: the solver writes accumulated impulses straight into its
 * points, so warm starting needs no separate store. When the manifold is recomputed, a new point
 * inherits the impulses of the old point with the same feature id (Box2D's b2UpdateContact).
 */
import type { Body } from './body.ts'
import { collideShapes } from './collide.ts'
import { Manifold } from './manifold.ts'

/** Multiplier that makes the pair key (a * KEY_SCALE + b) unique for body ids below 2^26. */
export const KEY_SCALE = 67108864

/** Solver data of one contact point. */
export class ContactPoint {
  /** Feature id of the manifold point. */
  id = 0
  /** Contact point relative to each body's centre of mass at the step start (m). */
  anchorAx = 0
  anchorAy = 0
  anchorBx = 0
  anchorBy = 0
  /** Separation at the step start minus the anchors' offset along the normal (m). */
  baseSeparation = 0
  /** Separation reported by the narrowphase (m). */
  separation = 0
  /** Accumulated impulses (N s). */
  normalImpulse = 0
  tangentImpulse = 0
  /** Total normal impulse applied during the last step, all sub-steps (N s). */
  totalNormalImpulse = 0
  /** Total friction impulse applied during the last step along (ny, -nx) (N s). */
  totalTangentImpulse = 0
  /** World point from the narrowphase (m). */
  px = 0
  py = 0
  normalMass = 0
  tangentMass = 0
  /** Relative normal velocity before the step, for restitution (m/s). */
  relativeVelocity = 0
}

/** A contact between two bodies, bodyA.id < bodyB.id. */
export class Contact {
  key: number
  bodyA: Body
  bodyB: Body
  friction: number
  restitution: number
  touching = false
  pointCount = 0
  normalX = 0
  normalY = 0
  readonly p0 = new ContactPoint()
  readonly p1 = new ContactPoint()
  /** Soft-contact coefficients for this step (static or dynamic softness). */
  biasRate = 0
  massScale = 1
  impulseScale = 0

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
    this.p0.normalImpulse = 0
    this.p0.tangentImpulse = 0
    this.p1.normalImpulse = 0
    this.p1.tangentImpulse = 0
    return this
  }
}

const scratch = new Manifold()
// Previous ids and impulses while a manifold is rebuilt: [id0, id1, normal0, normal1, tangent0,
// tangent1, count]. A typed array, because a module-level `let` holding a double allocates a heap
// number on every write in V8.
const old = new Float64Array(7)

function fillPoint(cp: ContactPoint, index: number, a: Body, b: Body): void {
  const mp = scratch.points[index]
  cp.id = mp.id
  cp.anchorAx = mp.x - a.cx
  cp.anchorAy = mp.y - a.cy
  cp.anchorBx = mp.x - b.cx
  cp.anchorBy = mp.y - b.cy
  cp.separation = mp.separation
  cp.px = mp.x
  cp.py = mp.y
  cp.normalImpulse = 0
  cp.tangentImpulse = 0
  if (old[6] > 0 && old[0] === mp.id) {
    cp.normalImpulse = old[2]
    cp.tangentImpulse = old[4]
  } else if (old[6] > 1 && old[1] === mp.id) {
    cp.normalImpulse = old[3]
    cp.tangentImpulse = old[5]
  }
}

/** Recomputes a contact's manifold at the bodies' current transforms; returns whether it touches. */
export function updateContact(contact: Contact, speculativeDistance: number): boolean {
  const a = contact.bodyA
  const b = contact.bodyB
  collideShapes(a.shape, a.x, a.y, a.c, a.s, b.shape, b.x, b.y, b.c, b.s, speculativeDistance, scratch)
  old[0] = contact.p0.id
  old[1] = contact.p1.id
  old[2] = contact.p0.normalImpulse
  old[3] = contact.p1.normalImpulse
  old[4] = contact.p0.tangentImpulse
  old[5] = contact.p1.tangentImpulse
  old[6] = contact.pointCount
  const count = scratch.pointCount
  contact.pointCount = count
  contact.normalX = scratch.normalX
  contact.normalY = scratch.normalY
  if (count > 0) fillPoint(contact.p0, 0, a, b)
  if (count > 1) fillPoint(contact.p1, 1, a, b)
  contact.touching = count > 0
  return contact.touching
}
