/*
 * Mouse (grab) joint (Box2D v3 mouse_joint.c): a soft spring of `hertz` and `dampingRatio` pulls a
 * point of body B toward a moving world target, with the force capped at `maxForce` so a grabbed
 * body cannot be driven through walls or launched. Several mouse joints may act on one body (one
 * per player); each has its own accumulated impulse and cap. Body A is the world.
 */
import { type Joint, type JointStepContext, solve22, solved2 } from './joint.ts'
import { Softness } from './softness.ts'

const softness = new Softness()

/** Per-step preparation of a mouse joint. */
export function prepareMouse(joint: Joint, ctx: JointStepContext): void {
  softness.set(joint.hertz, joint.dampingRatio, ctx.h)
  joint.springBiasRate = softness.biasRate
  joint.springMassScale = softness.massScale
  joint.springImpulseScale = softness.impulseScale
}

/** Applies the accumulated impulse of a mouse joint. */
export function warmStartMouse(joint: Joint): void {
  const b = joint.bodyB
  const rBx = b.dqc * joint.anchorBx - b.dqs * joint.anchorBy
  const rBy = b.dqs * joint.anchorBx + b.dqc * joint.anchorBy
  const px = joint.linearImpulseX
  const py = joint.linearImpulseY
  b.vx += b.invMass * px
  b.vy += b.invMass * py
  b.w += b.invInertia * (rBx * py - rBy * px)
}

/** One iteration of a mouse joint (always soft: the spring is the behaviour, not a correction). */
export function solveMouse(joint: Joint, ctx: JointStepContext): void {
  const b = joint.bodyB
  const mB = b.invMass
  const iB = b.invInertia
  const rBx = b.dqc * joint.anchorBx - b.dqs * joint.anchorBy
  const rBy = b.dqs * joint.anchorBx + b.dqc * joint.anchorBy
  const cdotX = b.vx - b.w * rBy
  const cdotY = b.vy + b.w * rBx
  // Error: the grabbed point (centre + delta + arm) minus the target.
  const sepX = b.cx + b.dpx + rBx - joint.targetX
  const sepY = b.cy + b.dpy + rBy - joint.targetY
  const k11 = mB + rBy * rBy * iB
  const k12 = -rBy * rBx * iB
  const k22 = mB + rBx * rBx * iB
  solve22(k11, k12, k22, cdotX + joint.springBiasRate * sepX, cdotY + joint.springBiasRate * sepY)
  const oldX = joint.linearImpulseX
  const oldY = joint.linearImpulseY
  let ix = oldX - joint.springMassScale * solved2[0] - joint.springImpulseScale * oldX
  let iy = oldY - joint.springMassScale * solved2[1] - joint.springImpulseScale * oldY
  const maxImpulse = joint.maxForce * ctx.h
  const lengthSquared = ix * ix + iy * iy
  if (lengthSquared > maxImpulse * maxImpulse) {
    const scale = maxImpulse / Math.sqrt(lengthSquared)
    ix *= scale
    iy *= scale
  }
  joint.linearImpulseX = ix
  joint.linearImpulseY = iy
  const dx = ix - oldX
  const dy = iy - oldY
  b.vx += mB * dx
  b.vy += mB * dy
  b.w += iB * (rBx * dy - rBy * dx)
}
