/*
 * Revolute (pin) joint: the anchors of A and B coincide; optional angle limits and a motor
 * (Box2D v3 revolute_joint.c). The point constraint is a soft 2x2 block; the limits are speculative
 * (they let the joint close exactly the remaining gap) and soft once violated; the motor's
 * accumulated impulse is clamped to maxMotorTorque * h so its torque never exceeds the cap, and its
 * target speed is clamped by the limits so that no motor torque can push the joint through them.
 */

import { type Joint, type JointStepContext, relativeAngle, solve22, solved2 } from './joint.ts'
import { PI, TWO_PI } from './math.ts'

/** Unwinds an angle into [-pi, pi]. */
function unwind(angle: number): number {
  if (angle < -PI) return angle + TWO_PI
  if (angle > PI) return angle - TWO_PI
  return angle
}

/** Per-step preparation of a revolute joint. */
export function prepareRevolute(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const k = a.invInertia + b.invInertia
  joint.axialMass = k > 0 ? 1 / k : 0
  joint.deltaAngle = unwind(relativeAngle(b.c, b.s, a.c, a.s) - joint.referenceAngle)
  if (!joint.enableMotor) joint.motorImpulse = 0
  if (!joint.enableLimit) {
    joint.lowerImpulse = 0
    joint.upperImpulse = 0
  }
}

/** Applies the accumulated impulses of a revolute joint. */
export function warmStartRevolute(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const rAx = a.dqc * joint.anchorAx - a.dqs * joint.anchorAy
  const rAy = a.dqs * joint.anchorAx + a.dqc * joint.anchorAy
  const rBx = b.dqc * joint.anchorBx - b.dqs * joint.anchorBy
  const rBy = b.dqs * joint.anchorBx + b.dqc * joint.anchorBy
  const px = joint.linearImpulseX
  const py = joint.linearImpulseY
  const axial = joint.motorImpulse + joint.lowerImpulse - joint.upperImpulse
  a.vx -= a.invMass * px
  a.vy -= a.invMass * py
  a.w -= a.invInertia * (rAx * py - rAy * px + axial)
  b.vx += b.invMass * px
  b.vy += b.invMass * py
  b.w += b.invInertia * (rBx * py - rBy * px + axial)
}

/** Solves the limits of a revolute joint (speculative, then soft when violated). */
function solveLimits(joint: Joint, ctx: JointStepContext, useBias: boolean): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const jointAngle = unwind(joint.deltaAngle + relativeAngle(b.dqc, b.dqs, a.dqc, a.dqs))
  solveLimit(joint, ctx, useBias, jointAngle - joint.lowerAngle, 1)
  // Upper limit: the sign of everything flips.
  solveLimit(joint, ctx, useBias, joint.upperAngle - jointAngle, -1)
}

/** One-sided angle limit with error C (rad, positive = inside); sign +1 is the lower, -1 the upper. */
function solveLimit(joint: Joint, ctx: JointStepContext, useBias: boolean, C: number, sign: number): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const soft = ctx.jointSoftness
  let bias = 0
  let massScale = 1
  let impulseScale = 0
  if (C > 0) bias = C * ctx.invH
  else if (useBias) {
    bias = soft.biasRate * C
    massScale = soft.massScale
    impulseScale = soft.impulseScale
  }
  const accumulated = sign > 0 ? joint.lowerImpulse : joint.upperImpulse
  const cdot = sign * (b.w - a.w)
  let impulse = -joint.axialMass * massScale * (cdot + bias) - impulseScale * accumulated
  const newImpulse = Math.max(accumulated + impulse, 0)
  impulse = newImpulse - accumulated
  if (sign > 0) joint.lowerImpulse = newImpulse
  else joint.upperImpulse = newImpulse
  a.w -= a.invInertia * (sign * impulse)
  b.w += b.invInertia * (sign * impulse)
}

/**
 * The motor's target speed, clamped so that the motor alone never drives the joint past a limit:
 * within one sub-step it may close at most the remaining gap (a speculative target, like the limit
 * itself). Without this a motor with a huge torque cap overpowers the soft limit, whose restoring
 * impulse is only axialMass * h * omega^2 * error per sub-step (60 Hz joint stiffness): a 500 N m
 * motor pushed a 0.1 kg arm 0.4 rad past its stop. With it the limit only carries external loads.
 * The net torque on the bodies is unchanged at rest (the motor holds instead of the stop).
 */
function motorTarget(joint: Joint, ctx: JointStepContext): number {
  let speed = joint.motorSpeed
  if (!joint.enableLimit) return speed
  const a = joint.bodyA
  const b = joint.bodyB
  const jointAngle = unwind(joint.deltaAngle + relativeAngle(b.dqc, b.dqs, a.dqc, a.dqs))
  const maxSpeed = (joint.upperAngle - jointAngle) * ctx.invH
  const minSpeed = (joint.lowerAngle - jointAngle) * ctx.invH
  if (speed > maxSpeed) speed = maxSpeed
  if (speed < minSpeed) speed = minSpeed
  return speed
}

/** One iteration of a revolute joint: motor, limits, then the point constraint. */
export function solveRevolute(joint: Joint, ctx: JointStepContext, useBias: boolean): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  const fixedRotation = iA + iB === 0

  if (joint.enableMotor && !fixedRotation) {
    const cdot = b.w - a.w - motorTarget(joint, ctx)
    let impulse = -joint.axialMass * cdot
    const old = joint.motorImpulse
    const maxImpulse = ctx.h * joint.maxMotorTorque
    joint.motorImpulse = Math.max(-maxImpulse, Math.min(old + impulse, maxImpulse))
    impulse = joint.motorImpulse - old
    a.w -= iA * impulse
    b.w += iB * impulse
  }
  if (joint.enableLimit && !fixedRotation) solveLimits(joint, ctx, useBias)
  if (joint.inTree) return // the point constraint is solved directly (joint-tree.ts)

  // Point-to-point constraint, soft when correcting position error.
  const rAx = a.dqc * joint.anchorAx - a.dqs * joint.anchorAy
  const rAy = a.dqs * joint.anchorAx + a.dqc * joint.anchorAy
  const rBx = b.dqc * joint.anchorBx - b.dqs * joint.anchorBy
  const rBy = b.dqs * joint.anchorBx + b.dqc * joint.anchorBy
  const cdotX = b.vx - b.w * rBy - (a.vx - a.w * rAy)
  const cdotY = b.vy + b.w * rBx - (a.vy + a.w * rAx)
  let biasX = 0
  let biasY = 0
  let massScale = 1
  let impulseScale = 0
  if (useBias) {
    const soft = ctx.jointSoftness
    const sepX = b.dpx - a.dpx + (rBx - rAx) + joint.deltaCenterX
    const sepY = b.dpy - a.dpy + (rBy - rAy) + joint.deltaCenterY
    biasX = soft.biasRate * sepX
    biasY = soft.biasRate * sepY
    massScale = soft.massScale
    impulseScale = soft.impulseScale
  }
  const k11 = mA + mB + rAy * rAy * iA + rBy * rBy * iB
  const k12 = -rAy * rAx * iA - rBy * rBx * iB
  const k22 = mA + mB + rAx * rAx * iA + rBx * rBx * iB
  solve22(k11, k12, k22, cdotX + biasX, cdotY + biasY)
  const ix = -massScale * solved2[0] - impulseScale * joint.linearImpulseX
  const iy = -massScale * solved2[1] - impulseScale * joint.linearImpulseY
  joint.linearImpulseX += ix
  joint.linearImpulseY += iy
  a.vx -= mA * ix
  a.vy -= mA * iy
  a.w -= iA * (rAx * iy - rAy * ix)
  b.vx += mB * ix
  b.vy += mB * iy
  b.w += iB * (rBx * iy - rBy * ix)
}
