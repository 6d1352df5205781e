/*
 * Mouse (grab) joint (Box2D v3 mouse_joint.c): a soft spring of `hertz` and `dampingRatio` pulls a
 * point of body B toward a moving world target, with the force capped at `maxForce` so a grabbed
 * body cannot be driven through walls or launched. Several mouse joints may act on one body (one
 * per player); each has its own accumulated impulse and cap. Body A is the world.
 */
import { DPX, DPY, DQC, DQS, Softness, VX, VY, W } from '../dynamics/index.ts'
import type { Joint } from './joint.ts'
import { type JointStepContext, setSpringSoftness, solve22, solved2, system22 } from './joint-math.ts'

const softness = new Softness()

/** Per-step preparation of a mouse joint. */
export function prepareMouse(joint: Joint, ctx: JointStepContext): void {
  setSpringSoftness(softness, joint, ctx)
  joint.springBiasRate = softness.biasRate
  joint.springMassScale = softness.massScale
  joint.springImpulseScale = softness.impulseScale
}

/** Applies the accumulated impulse of a mouse joint. */
export function warmStartMouse(joint: Joint, state: Float64Array): void {
  const b = joint.bodyB
  const oB = joint.offsetB
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  const px = joint.linearImpulseX
  const py = joint.linearImpulseY
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * (rBx * py - rBy * px)
}

/** One iteration of a mouse joint (always soft: the spring is the behaviour, not a correction). */
export function solveMouse(joint: Joint, state: Float64Array, ctx: JointStepContext): void {
  const b = joint.bodyB
  const oB = joint.offsetB
  const mB = b.invMass
  const iB = b.invInertia
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  const cdotX = state[oB + VX] - state[oB + W] * rBy
  const cdotY = state[oB + VY] + state[oB + W] * rBx
  // Error: the grabbed point (centre + delta + arm) minus the target.
  const sepX = b.cx + state[oB + DPX] + rBx - joint.targetX
  const sepY = b.cy + state[oB + DPY] + rBy - joint.targetY
  const k11 = mB + rBy * rBy * iB
  const k12 = -rBy * rBx * iB
  const k22 = mB + rBx * rBx * iB
  system22[0] = k11
  system22[1] = k12
  system22[2] = k22
  system22[3] = cdotX + joint.springBiasRate * sepX
  system22[4] = cdotY + joint.springBiasRate * sepY
  solve22()
  const oldX = joint.linearImpulseX
  const oldY = joint.linearImpulseY
  let ix = oldX - joint.springMassScale * solved2[0] - joint.springImpulseScale * oldX
  let iy = oldY - joint.springMassScale * solved2[1] - joint.springImpulseScale * oldY
  const maxImpulse = joint.maxForce * ctx.h
  const lengthSquared = ix * ix + iy * iy
  if (!(lengthSquared <= maxImpulse * maxImpulse)) {
    // Too strong (or, from an overflow no finite input should cause, not finite): cap the force.
    const scale = lengthSquared < Number.POSITIVE_INFINITY ? maxImpulse / Math.sqrt(lengthSquared) : 0
    ix = scale > 0 ? ix * scale : 0
    iy = scale > 0 ? iy * scale : 0
  }
  joint.linearImpulseX = ix
  joint.linearImpulseY = iy
  const dx = ix - oldX
  const dy = iy - oldY
  state[oB + VX] += mB * dx
  state[oB + VY] += mB * dy
  state[oB + W] += iB * (rBx * dy - rBy * dx)
}
