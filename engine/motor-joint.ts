/*
 * Motor joint (Box2D v3 motor_joint.c): drives B toward a pose relative to A: B's centre of mass
 * at `linearOffset` in A's frame (m) and B's angle at angleA + `angularOffset` (rad), with a force
 * of at most `maxForce` (N) and a torque of at most `maxTorque` (N m). Each sub-step it asks for
 * the velocity that closes `correctionFactor` (0..1) of the error, so within its caps it follows a
 * moving offset with no lag, and beyond them it accelerates B at maxForce / mB until it catches up.
 * Used to move a platform or a character along a path while still colliding like a dynamic body.
 */
import { DPX, DPY, DQC, DQS, VX, VY, W } from './body-state.ts'
import type { Joint } from './joint.ts'
import { type JointStepContext, relativeAngle, solve22, solved2, system22, unwind } from './joint-math.ts'

/** Per-step preparation of a motor joint: arms to the offset point and B's centre. */
export function prepareMotor(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  // A's arm reaches the target point (linearOffset in A's frame, from A's centre of mass); B's arm
  // is zero (B's centre of mass is driven there).
  const lx = joint.linearOffsetX - a.localCenterX
  const ly = joint.linearOffsetY - a.localCenterY
  joint.anchorAx = a.c * lx - a.s * ly
  joint.anchorAy = a.s * lx + a.c * ly
  joint.anchorBx = 0
  joint.anchorBy = 0
  joint.deltaAngle = unwind(relativeAngle(b.c, b.s, a.c, a.s) - joint.angularOffset)
  const k = a.invInertia + b.invInertia
  joint.angularMass = k > 0 ? 1 / k : 0
}

/** Applies the accumulated impulses of a motor joint. */
export function warmStartMotor(joint: Joint, state: Float64Array): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const px = joint.linearImpulseX
  const py = joint.linearImpulseY
  state[oA + VX] -= a.invMass * px
  state[oA + VY] -= a.invMass * py
  state[oA + W] -= a.invInertia * (rAx * py - rAy * px + joint.angularImpulse)
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * joint.angularImpulse
}

/** One iteration of a motor joint (the same in both passes: the correction is its purpose). */
export function solveMotor(joint: Joint, state: Float64Array, ctx: JointStepContext): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  const rate = joint.correctionFactor * ctx.invH
  {
    const C =
      relativeAngle(state[oB + DQC], state[oB + DQS], state[oA + DQC], state[oA + DQS]) + joint.deltaAngle
    const cdot = state[oB + W] - state[oA + W]
    const old = joint.angularImpulse
    const cap = joint.maxTorque * ctx.h
    let sum = old - joint.angularMass * (cdot + rate * C)
    if (sum > cap) sum = cap
    else if (sum < -cap) sum = -cap
    else if (Number.isNaN(sum)) sum = 0
    joint.angularImpulse = sum
    state[oA + W] -= iA * (sum - old)
    state[oB + W] += iB * (sum - old)
  }
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const wA = state[oA + W]
  const cx = state[oB + DPX] - state[oA + DPX] - rAx + joint.deltaCenterX
  const cy = state[oB + DPY] - state[oA + DPY] - rAy + joint.deltaCenterY
  system22[0] = mA + mB + rAy * rAy * iA
  system22[1] = -rAy * rAx * iA
  system22[2] = mA + mB + rAx * rAx * iA
  system22[3] = state[oB + VX] - (state[oA + VX] - wA * rAy) + rate * cx
  system22[4] = state[oB + VY] - (state[oA + VY] + wA * rAx) + rate * cy
  solve22()
  const oldX = joint.linearImpulseX
  const oldY = joint.linearImpulseY
  let ix = oldX - solved2[0]
  let iy = oldY - solved2[1]
  const cap = joint.maxForce * ctx.h
  const lengthSquared = ix * ix + iy * iy
  if (!(lengthSquared <= cap * cap)) {
    const scale = lengthSquared < Number.POSITIVE_INFINITY ? cap / Math.sqrt(lengthSquared) : 0
    ix = scale > 0 ? ix * scale : 0
    iy = scale > 0 ? iy * scale : 0
  }
  joint.linearImpulseX = ix
  joint.linearImpulseY = iy
  const dx = ix - oldX
  const dy = iy - oldY
  state[oA + VX] -= mA * dx
  state[oA + VY] -= mA * dy
  state[oA + W] -= iA * (rAx * dy - rAy * dx)
  state[oB + VX] += mB * dx
  state[oB + VY] += mB * dy
}
