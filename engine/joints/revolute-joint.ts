/*
 * Revolute (pin) joint: the anchors of A and B coincide; an optional rotational spring toward
 * `springTarget` (targetAngle), angle limits and a motor (Box2D v3 revolute_joint.c). The point constraint is a soft 2x2 block; the limits are speculative
 * (they let the joint close exactly the remaining gap) and soft once violated; the motor's
 * accumulated impulse is clamped to maxMotorTorque * h so its torque never exceeds the cap, and its
 * target speed is clamped by the limits so that no motor torque can push the joint through them.
 */

import { DPX, DPY, DQC, DQS, Softness, VX, VY, W } from '../dynamics/index.ts'
import { atan2InPlace } from '../math.ts'
import type { Joint } from './joint.ts'
import {
  accumulateX,
  accumulateY,
  angleOut,
  clampImpulse,
  type JointStepContext,
  relativeDeltaAngle,
  setSpringSoftness,
  solve22,
  solved2,
  system22,
  unwind,
} from './joint-math.ts'

const springSoftness = new Softness()
/** atan2InPlace's argument and result. */
const atanIO = new Float64Array(2)

/** Per-step preparation of a revolute joint. */
export function prepareRevolute(joint: Joint, ctx: JointStepContext): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const k = a.invInertia + b.invInertia
  joint.axialMass = k > 0 ? 1 / k : 0
  // relativeAngle(b.c, b.s, a.c, a.s), without a call that allocates (atan2InPlace).
  atanIO[0] = b.s * a.c - b.c * a.s
  atanIO[1] = b.c * a.c + b.s * a.s
  atan2InPlace(atanIO)
  joint.deltaAngle = unwind(atanIO[0] - joint.referenceAngle)
  if (!joint.enableMotor) joint.motorImpulse = 0
  if (joint.enableSpring) {
    setSpringSoftness(springSoftness, joint, ctx)
    joint.springBiasRate = springSoftness.biasRate
    joint.springMassScale = springSoftness.massScale
    joint.springImpulseScale = springSoftness.impulseScale
  } else joint.springImpulse = 0
  if (!joint.enableLimit) {
    joint.lowerImpulse = 0
    joint.upperImpulse = 0
  }
}

/** Applies the accumulated impulses of a revolute joint. */
export function warmStartRevolute(joint: Joint, state: Float64Array): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  const px = joint.linearImpulseX
  const py = joint.linearImpulseY
  // The spring impulse is +0 when the spring is off, so adding it changes nothing then.
  const axial = joint.motorImpulse + joint.lowerImpulse - joint.upperImpulse + joint.springImpulse
  state[oA + VX] -= a.invMass * px
  state[oA + VY] -= a.invMass * py
  state[oA + W] -= a.invInertia * (rAx * py - rAy * px + axial)
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * (rBx * py - rBy * px + axial)
}

/** The joint angle now (rad): the step-start angle plus the sub-step rotations, unwound. */
function jointAngle(joint: Joint, state: Float64Array): number {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const bc = state[oB + DQC]
  const bs = state[oB + DQS]
  const ac = state[oA + DQC]
  const as = state[oA + DQS]
  // relativeAngle(bc, bs, ac, as), without a call that allocates (atan2InPlace).
  atanIO[0] = bs * ac - bc * as
  atanIO[1] = bc * ac + bs * as
  atan2InPlace(atanIO)
  return unwind(joint.deltaAngle + atanIO[0])
}

/** Solves the limits of a revolute joint (speculative, then soft when violated). */
function solveLimits(joint: Joint, state: Float64Array, ctx: JointStepContext, useBias: boolean): void {
  const angle = jointAngle(joint, state)
  solveLimit(joint, state, ctx, useBias, angle - joint.lowerAngle, 1)
  // Upper limit: the sign of everything flips.
  solveLimit(joint, state, ctx, useBias, joint.upperAngle - angle, -1)
}

/** One-sided angle limit with error C (rad, positive = inside); sign +1 is the lower, -1 the upper. */
function solveLimit(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
  C: number,
  sign: number,
): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
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
  const cdot = sign * (state[oB + W] - state[oA + W])
  let impulse = -joint.axialMass * massScale * (cdot + bias) - impulseScale * accumulated
  const newImpulse = Math.max(clampImpulse(accumulated + impulse, joint.maxAngularImpulse), 0)
  impulse = newImpulse - accumulated
  if (sign > 0) joint.lowerImpulse = newImpulse
  else joint.upperImpulse = newImpulse
  state[oA + W] -= a.invInertia * (sign * impulse)
  state[oB + W] += b.invInertia * (sign * impulse)
}

/**
 * The motor's target speed, clamped so that the motor alone never drives the joint past a limit:
 * within one sub-step it may close at most the remaining gap (a speculative target, like the limit
 * itself). Without this a motor with a huge torque cap overpowers the soft limit, whose restoring
 * impulse is only axialMass * h * omega^2 * error per sub-step (60 Hz joint stiffness): a 500 N m
 * motor pushed a 0.1 kg arm 0.4 rad past its stop. With it the limit only carries external loads.
 * The net torque on the bodies is unchanged at rest (the motor holds instead of the stop).
 */
function motorTarget(joint: Joint, state: Float64Array, ctx: JointStepContext): number {
  let speed = joint.motorSpeed
  if (!joint.enableLimit) return speed
  const angle = jointAngle(joint, state)
  const maxSpeed = (joint.upperAngle - angle) * ctx.invH
  const minSpeed = (joint.lowerAngle - angle) * ctx.invH
  if (speed > maxSpeed) speed = maxSpeed
  if (speed < minSpeed) speed = minSpeed
  return speed
}

/** One iteration of a revolute joint: motor, limits, then the point constraint. */
export function solveRevolute(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  const fixedRotation = iA + iB === 0

  if (joint.enableSpring && !fixedRotation) {
    // Soft rotational spring toward the target angle; physics, so it acts in the relax pass too.
    // The joint angle from the step-start angle and this step's rotation (inline: no atan2 call).
    relativeDeltaAngle(joint, state)
    const C = unwind(joint.deltaAngle + angleOut[0]) - joint.springTarget
    const cdot = state[oB + W] - state[oA + W]
    let impulse =
      -joint.springMassScale * joint.axialMass * (cdot + joint.springBiasRate * C) -
      joint.springImpulseScale * joint.springImpulse
    const old = joint.springImpulse
    joint.springImpulse = clampImpulse(old + impulse, joint.maxAngularImpulse)
    impulse = joint.springImpulse - old
    state[oA + W] -= iA * impulse
    state[oB + W] += iB * impulse
  }
  if (joint.enableMotor && !fixedRotation) {
    const cdot = state[oB + W] - state[oA + W] - motorTarget(joint, state, ctx)
    let impulse = -joint.axialMass * cdot
    const old = joint.motorImpulse
    const maxImpulse = ctx.h * joint.maxMotorTorque
    joint.motorImpulse = clampImpulse(old + impulse, Math.min(maxImpulse, joint.maxAngularImpulse))
    impulse = joint.motorImpulse - old
    state[oA + W] -= iA * impulse
    state[oB + W] += iB * impulse
  }
  if (joint.enableLimit && !fixedRotation) solveLimits(joint, state, ctx, useBias)
  if (joint.inTree) return // the point constraint is solved directly (joint-tree.ts)

  // Point-to-point constraint, soft when correcting position error.
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  const wA = state[oA + W]
  const wB = state[oB + W]
  const cdotX = state[oB + VX] - wB * rBy - (state[oA + VX] - wA * rAy)
  const cdotY = state[oB + VY] + wB * rBx - (state[oA + VY] + wA * rAx)
  let biasX = 0
  let biasY = 0
  let massScale = 1
  let impulseScale = 0
  if (useBias) {
    const soft = ctx.jointSoftness
    const sepX = state[oB + DPX] - state[oA + DPX] + (rBx - rAx) + joint.deltaCenterX
    const sepY = state[oB + DPY] - state[oA + DPY] + (rBy - rAy) + joint.deltaCenterY
    biasX = soft.biasRate * sepX
    biasY = soft.biasRate * sepY
    massScale = soft.massScale
    impulseScale = soft.impulseScale
  }
  const k11 = mA + mB + rAy * rAy * iA + rBy * rBy * iB
  const k12 = -rAy * rAx * iA - rBy * rBx * iB
  const k22 = mA + mB + rAx * rAx * iA + rBx * rBx * iB
  system22[0] = k11
  system22[1] = k12
  system22[2] = k22
  system22[3] = cdotX + biasX
  system22[4] = cdotY + biasY
  solve22()
  let ix = -massScale * solved2[0] - impulseScale * joint.linearImpulseX
  let iy = -massScale * solved2[1] - impulseScale * joint.linearImpulseY
  ix = accumulateX(joint, ix)
  iy = accumulateY(joint, iy)
  state[oA + VX] -= mA * ix
  state[oA + VY] -= mA * iy
  state[oA + W] -= iA * (rAx * iy - rAy * ix)
  state[oB + VX] += mB * ix
  state[oB + VY] += mB * iy
  state[oB + W] += iB * (rBx * iy - rBy * ix)
}
