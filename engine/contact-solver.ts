/*
 * The soft-step contact solver (Erin Catto, "Solver2D" 2024; Box2D v3 contact_solver.c).
 *
 * Stages, called by World.step in this order:
 *   prepareContacts   once per step: anchors, effective masses, softness, pre-step normal velocity
 *   warmStartContacts each sub-step: apply last impulses
 *   solveContacts     each sub-step with bias (soft push-out of overlap), then again without (relax)
 *   applyRestitution  once per step, after the sub-steps, for contacts closing faster than the threshold
 *
 * Within a sub-step the separation is not recomputed by the narrowphase: it is the step-start
 * separation plus the bodies' position and rotation deltas projected on the fixed normal:
 *   s = baseSeparation + dot(dpB - dpA + rot(dqB, rB) - rot(dqA, rA), n)
 * Positive separation is handled speculatively (the contact only stops the bodies from closing
 * more than the gap); negative separation is pushed out by a soft spring of stiffness `contactHertz`
 * (twice that against static bodies), limited to `maxContactPushSpeed`.
 * Friction is a Coulomb cone: the tangent impulse is clamped to friction * normal impulse.
 */
import type { Contact } from './contact.ts'
import type { Softness } from './softness.ts'

/** Computes each contact's anchors, effective masses, softness and pre-step velocity. */
export function prepareContacts(
  contacts: Contact[],
  count: number,
  contactSoftness: Softness,
  staticSoftness: Softness,
): void {
  for (let i = 0; i < count; i++) {
    const c = contacts[i]
    const a = c.bodyA
    const b = c.bodyB
    const mA = a.invMass
    const iA = a.invInertia
    const mB = b.invMass
    const iB = b.invInertia
    const soft = mA === 0 || mB === 0 ? staticSoftness : contactSoftness
    c.biasRate = soft.biasRate
    c.massScale = soft.massScale
    c.impulseScale = soft.impulseScale
    const nx = c.normalX
    const ny = c.normalY
    // tangent = right perpendicular of the normal (ny, -nx)
    const tx = ny
    const ty = -nx
    for (let j = 0; j < c.pointCount; j++) {
      const cp = j === 0 ? c.p0 : c.p1
      const rAx = cp.anchorAx
      const rAy = cp.anchorAy
      const rBx = cp.anchorBx
      const rBy = cp.anchorBy
      cp.baseSeparation = cp.separation - ((rBx - rAx) * nx + (rBy - rAy) * ny)
      cp.totalNormalImpulse = 0
      cp.totalTangentImpulse = 0
      const rnA = rAx * ny - rAy * nx
      const rnB = rBx * ny - rBy * nx
      const kNormal = mA + mB + iA * rnA * rnA + iB * rnB * rnB
      cp.normalMass = kNormal > 0 ? 1 / kNormal : 0
      const rtA = rAx * ty - rAy * tx
      const rtB = rBx * ty - rBy * tx
      const kTangent = mA + mB + iA * rtA * rtA + iB * rtB * rtB
      cp.tangentMass = kTangent > 0 ? 1 / kTangent : 0
      const dvx = b.vx - b.w * rBy - (a.vx - a.w * rAy)
      const dvy = b.vy + b.w * rBx - (a.vy + a.w * rAx)
      cp.relativeVelocity = nx * dvx + ny * dvy
    }
  }
}

/** Applies the accumulated impulses of the previous step or sub-step. */
export function warmStartContacts(contacts: Contact[], count: number): void {
  for (let i = 0; i < count; i++) {
    const c = contacts[i]
    const a = c.bodyA
    const b = c.bodyB
    const mA = a.invMass
    const iA = a.invInertia
    const mB = b.invMass
    const iB = b.invInertia
    const nx = c.normalX
    const ny = c.normalY
    let vAx = a.vx
    let vAy = a.vy
    let wA = a.w
    let vBx = b.vx
    let vBy = b.vy
    let wB = b.w
    for (let j = 0; j < c.pointCount; j++) {
      const cp = j === 0 ? c.p0 : c.p1
      const px = cp.normalImpulse * nx + cp.tangentImpulse * ny
      const py = cp.normalImpulse * ny - cp.tangentImpulse * nx
      cp.totalNormalImpulse += cp.normalImpulse
      cp.totalTangentImpulse += cp.tangentImpulse
      wA -= iA * (cp.anchorAx * py - cp.anchorAy * px)
      vAx -= mA * px
      vAy -= mA * py
      wB += iB * (cp.anchorBx * py - cp.anchorBy * px)
      vBx += mB * px
      vBy += mB * py
    }
    a.vx = vAx
    a.vy = vAy
    a.w = wA
    b.vx = vBx
    b.vy = vBy
    b.w = wB
  }
}

/** One iteration over the contacts; `useBias` pushes overlap apart, false is the relax pass. */
export function solveContacts(
  contacts: Contact[],
  count: number,
  invH: number,
  maxPushSpeed: number,
  useBias: boolean,
): void {
  for (let i = 0; i < count; i++) {
    const c = contacts[i]
    const a = c.bodyA
    const b = c.bodyB
    const mA = a.invMass
    const iA = a.invInertia
    const mB = b.invMass
    const iB = b.invInertia
    let vAx = a.vx
    let vAy = a.vy
    let wA = a.w
    let vBx = b.vx
    let vBy = b.vy
    let wB = b.w
    const qAc = a.dqc
    const qAs = a.dqs
    const qBc = b.dqc
    const qBs = b.dqs
    const dpx = b.dpx - a.dpx
    const dpy = b.dpy - a.dpy
    const nx = c.normalX
    const ny = c.normalY
    const pointCount = c.pointCount

    // Non-penetration
    for (let j = 0; j < pointCount; j++) {
      const cp = j === 0 ? c.p0 : c.p1
      const rAx = cp.anchorAx
      const rAy = cp.anchorAy
      const rBx = cp.anchorBx
      const rBy = cp.anchorBy
      // current separation from the sub-step deltas
      const dx = dpx + (qBc * rBx - qBs * rBy) - (qAc * rAx - qAs * rAy)
      const dy = dpy + (qBs * rBx + qBc * rBy) - (qAs * rAx + qAc * rAy)
      const s = cp.baseSeparation + dx * nx + dy * ny
      let velocityBias = 0
      let massScale = 1
      let impulseScale = 0
      if (s > 0) {
        velocityBias = s * invH // speculative: close at most the gap this sub-step
      } else if (useBias) {
        velocityBias = Math.max(c.massScale * c.biasRate * s, -maxPushSpeed)
        massScale = c.massScale
        impulseScale = c.impulseScale
      }
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vn = dvx * nx + dvy * ny
      let impulse = -cp.normalMass * (massScale * vn + velocityBias) - impulseScale * cp.normalImpulse
      const newImpulse = Math.max(cp.normalImpulse + impulse, 0)
      impulse = newImpulse - cp.normalImpulse
      cp.normalImpulse = newImpulse
      cp.totalNormalImpulse += impulse
      const px = impulse * nx
      const py = impulse * ny
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }

    // Friction (Coulomb cone), tangent = (ny, -nx)
    const friction = c.friction
    for (let j = 0; j < pointCount; j++) {
      const cp = j === 0 ? c.p0 : c.p1
      const rAx = cp.anchorAx
      const rAy = cp.anchorAy
      const rBx = cp.anchorBx
      const rBy = cp.anchorBy
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vt = dvx * ny - dvy * nx
      let impulse = -cp.tangentMass * vt
      const maxFriction = friction * cp.normalImpulse
      const newImpulse = Math.max(-maxFriction, Math.min(cp.tangentImpulse + impulse, maxFriction))
      impulse = newImpulse - cp.tangentImpulse
      cp.tangentImpulse = newImpulse
      cp.totalTangentImpulse += impulse
      const px = impulse * ny
      const py = -impulse * nx
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }
    a.vx = vAx
    a.vy = vAy
    a.w = wA
    b.vx = vBx
    b.vy = vBy
    b.w = wB
  }
}

/** Restitution after the sub-steps: bounce contacts that closed faster than the threshold (m/s). */
export function applyRestitution(contacts: Contact[], count: number, threshold: number): void {
  for (let i = 0; i < count; i++) {
    const c = contacts[i]
    const restitution = c.restitution
    if (restitution === 0) continue
    const a = c.bodyA
    const b = c.bodyB
    const mA = a.invMass
    const iA = a.invInertia
    const mB = b.invMass
    const iB = b.invInertia
    const nx = c.normalX
    const ny = c.normalY
    let vAx = a.vx
    let vAy = a.vy
    let wA = a.w
    let vBx = b.vx
    let vBy = b.vy
    let wB = b.w
    for (let j = 0; j < c.pointCount; j++) {
      const cp = j === 0 ? c.p0 : c.p1
      // Skip slow contacts and speculative points that never pushed.
      if (cp.relativeVelocity > -threshold || cp.totalNormalImpulse === 0) continue
      const rAx = cp.anchorAx
      const rAy = cp.anchorAy
      const rBx = cp.anchorBx
      const rBy = cp.anchorBy
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vn = dvx * nx + dvy * ny
      let impulse = -cp.normalMass * (vn + restitution * cp.relativeVelocity)
      const newImpulse = Math.max(cp.normalImpulse + impulse, 0)
      impulse = newImpulse - cp.normalImpulse
      cp.normalImpulse = newImpulse
      cp.totalNormalImpulse += impulse
      const px = impulse * nx
      const py = impulse * ny
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }
    a.vx = vAx
    a.vy = vAy
    a.w = wA
    b.vx = vBx
    b.vy = vBy
    b.w = wB
  }
}
