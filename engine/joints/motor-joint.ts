/*
 * Motor joint (Box2D v3.0 motor_joint.c, with two changes): drives B toward a pose relative to A:
 * B's centre of mass at `linearOffset` in A's frame (m) and B's angle at angleA + `angularOffset`
 * (rad), with a force of at most `maxForce` (N) and a torque of at most `maxTorque` (N m). Used to
 * move a platform or a character along a path while it still collides like a dynamic body.
 *
 * Each sub-step it asks for the offset's own velocity (feed-forward: the change of the offsets
 * since the last step, so a target moved every step at a steady speed is followed with no lag,
 * where Box2D v3.0 lags by v h / correctionFactor) plus a correction of `correctionFactor` (0..1)
 * of the error per sub-step, capped at sqrt(2 a |C|) with a = maxForce (1/mA + 1/mB) the largest
 * acceleration the force allows (the angular part likewise): the speed from which the capped
 * force can still brake to a stop at the target. Without that cap (Box2D v3.0) a force-limited
 * body overshoots a distant target by as much as it had to cover and swings about it for ever
 * (x'' = -a sign(x) has no damping); with it, it arrives at the time-optimal (bang-bang) instant.
 */

import { STEP_SECONDS } from '../constants.ts'
import { DPX, DPY, DQC, DQS, VX, VY, W } from '../dynamics/index.ts'
import { PI, TWO_PI } from '../math.ts'
import type { Joint } from './joint.ts'
import {
  angleOut,
  bodiesAngle,
  type JointStepContext,
  relativeDeltaAngle,
  solve22,
  solved2,
  system22,
} from './joint-math.ts'

/** Per-step preparation of a motor joint: arms to the offset point and B's centre. */
export function prepareMotor(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  // A's arm reaches the target point (linearOffset in A's frame, from A's centre of mass); B's arm
  // is zero (B's centre of mass is driven there).
  // The target at the step's start (last step's offset); it moves at the offset velocity below.
  const lx = joint.lastOffsetX - a.localCenterX
  const ly = joint.lastOffsetY - a.localCenterY
  joint.anchorAx = a.c * lx - a.s * ly
  joint.anchorAy = a.s * lx + a.c * ly
  joint.anchorBx = 0
  joint.anchorBy = 0
  bodiesAngle(joint)
  // unwind, written out: no double argument or result (see joint-math.ts setSpringSoftness).
  let deltaAngle = angleOut[0] - joint.lastAngularOffset
  if (deltaAngle < -PI) deltaAngle += TWO_PI
  else if (deltaAngle > PI) deltaAngle -= TWO_PI
  joint.deltaAngle = deltaAngle
  joint.subStep = 0
  const k = a.invInertia + b.invInertia
  joint.angularMass = k > 0 ? 1 / k : 0
  // The offsets' velocity since the last step (in A's frame, turned to world orientation).
  const inverseStep = 1 / STEP_SECONDS
  const vx = (joint.linearOffsetX - joint.lastOffsetX) * inverseStep
  const vy = (joint.linearOffsetY - joint.lastOffsetY) * inverseStep
  joint.offsetVelocityX = a.c * vx - a.s * vy
  joint.offsetVelocityY = a.s * vx + a.c * vy
  joint.offsetAngularVelocity = (joint.angularOffset - joint.lastAngularOffset) * inverseStep
  joint.lastOffsetX = joint.linearOffsetX
  joint.lastOffsetY = joint.linearOffsetY
  joint.lastAngularOffset = joint.angularOffset
}

/** Applies the accumulated impulses of a motor joint. */
export function warmStartMotor(joint: Joint, state: Float64Array): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  joint.subStep++
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

/**
 * One iteration of a motor joint (the same in both passes: the correction is its purpose). The
 * target has moved at the offset velocity for the sub-steps integrated so far: k - 1 in the biased
 * pass of sub-step k, k in its relax pass (after the positions moved).
 */
export function solveMotor(joint: Joint, state: Float64Array, ctx: JointStepContext, useBias: boolean): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  const rate = joint.correctionFactor * ctx.invH
  const elapsed = (useBias ? joint.subStep - 1 : joint.subStep) * ctx.h
  {
    relativeDeltaAngle(joint, state)
    const C = angleOut[0] + joint.deltaAngle - joint.offsetAngularVelocity * elapsed
    const cdot = state[oB + W] - state[oA + W] - joint.offsetAngularVelocity
    let bias = rate * C
    const brake = Math.sqrt(2 * joint.maxTorque * (iA + iB) * Math.abs(C))
    if (Math.abs(bias) > brake) bias = bias > 0 ? brake : -brake
    const old = joint.angularImpulse
    const cap = joint.maxTorque * ctx.h
    let sum = old - joint.angularMass * (cdot + bias)
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
  const cx = state[oB + DPX] - state[oA + DPX] - rAx + joint.deltaCenterX - joint.offsetVelocityX * elapsed
  const cy = state[oB + DPY] - state[oA + DPY] - rAy + joint.deltaCenterY - joint.offsetVelocityY * elapsed
  let biasX = rate * cx
  let biasY = rate * cy
  const error = Math.sqrt(cx * cx + cy * cy)
  const brake = Math.sqrt(2 * joint.maxForce * (mA + mB) * error)
  const bias = rate * error
  if (bias > brake) {
    biasX *= brake / bias
    biasY *= brake / bias
  }
  system22[0] = mA + mB + rAy * rAy * iA
  system22[1] = -rAy * rAx * iA
  system22[2] = mA + mB + rAx * rAx * iA
  system22[3] = state[oB + VX] - (state[oA + VX] - wA * rAy) - joint.offsetVelocityX + biasX
  system22[4] = state[oB + VY] - (state[oA + VY] + wA * rAx) - joint.offsetVelocityY + biasY
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
