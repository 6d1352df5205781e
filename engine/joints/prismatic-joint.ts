/*
 * Prismatic (slider) joint (Box2D v3 prismatic_joint.c): B slides along an axis fixed in A and
 * keeps its angle relative to A. The translation is the anchors' separation along the axis (m,
 * zero at creation). Solved in Box2D's order: spring (toward `springTarget`, the target
 * translation; physics, so also in the relax pass), motor (speed along the axis, force capped at
 * maxMotorForce h per sub-step), lower and upper limits (speculative, soft once violated), then the
 * 2-row constraint: no motion across the axis and no relative rotation (soft in the biased pass).
 */
import { DPX, DPY, DQC, DQS, Softness, VX, VY, W } from '../dynamics/index.ts'
import { PI, TWO_PI } from '../math.ts'
import type { Joint } from './joint.ts'
import {
  angleOut,
  bodiesAngle,
  type JointStepContext,
  relativeDeltaAngle,
  setSpringSoftness,
} from './joint-math.ts'

const springSoftness = new Softness()

/**
 * Current geometry from the sub-step deltas (computeFrame): the axis (unit, world), the anchors'
 * separation d, the arms, and along-axis and across-axis lever terms. A typed array, as in
 * distance-joint.ts.
 */
const frame = new Float64Array(18)
const AX = 0
const AY = 1
const DX = 2
const DY = 3
const RAX = 4
const RAY = 5
const RBX = 6
const RBY = 7
const A1 = 8
const A2 = 9
const S1 = 10
const S2 = 11
/** Results and arguments passed through the typed array (V8 boxes doubles across calls it does not inline). */
const SPEED = 12
const PX = 13
const PY = 14
const LA = 15
const LB = 16
const LIMIT_C = 17

/** Fills `frame` for a prismatic or wheel joint at the current sub-step. */
export function computeFrame(joint: Joint, state: Float64Array): void {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const f = frame
  const qAc = state[oA + DQC]
  const qAs = state[oA + DQS]
  const rAx = qAc * joint.anchorAx - qAs * joint.anchorAy
  const rAy = qAs * joint.anchorAx + qAc * joint.anchorAy
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  const ax = qAc * joint.axisX - qAs * joint.axisY
  const ay = qAs * joint.axisX + qAc * joint.axisY
  const dx = state[oB + DPX] - state[oA + DPX] + joint.deltaCenterX + rBx - rAx
  const dy = state[oB + DPY] - state[oA + DPY] + joint.deltaCenterY + rBy - rAy
  f[AX] = ax
  f[AY] = ay
  f[DX] = dx
  f[DY] = dy
  f[RAX] = rAx
  f[RAY] = rAy
  f[RBX] = rBx
  f[RBY] = rBy
  // a1 = (d + rA) x axis, a2 = rB x axis; s1, s2 the same with the perpendicular (-ay, ax).
  f[A1] = (dx + rAx) * ay - (dy + rAy) * ax
  f[A2] = rBx * ay - rBy * ax
  f[S1] = (dx + rAx) * ax + (dy + rAy) * ay
  f[S2] = rBx * ax + rBy * ay
}

/** The frame the last computeFrame filled (read by wheel-joint.ts). */
export const jointFrame = frame
export { A1, A2, AX, AY, DX, DY, LA, LB, LIMIT_C, PX, PY, S1, S2, SPEED }

/** Applies the linear impulse frame[PX, PY] and angular impulses frame[LA] (on A), frame[LB] (on B). */
export function applyFrameImpulse(joint: Joint, state: Float64Array): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const px = frame[PX]
  const py = frame[PY]
  state[oA + VX] -= a.invMass * px
  state[oA + VY] -= a.invMass * py
  state[oA + W] -= a.invInertia * frame[LA]
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * frame[LB]
}

/** Axis (world) at the step start and the axial mass; shared with the wheel joint. */
export function prepareAxis(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  joint.axisX = a.c * joint.localAxisAx - a.s * joint.localAxisAy
  joint.axisY = a.s * joint.localAxisAx + a.c * joint.localAxisAy
  const dx = joint.deltaCenterX + joint.anchorBx - joint.anchorAx
  const dy = joint.deltaCenterY + joint.anchorBy - joint.anchorAy
  const a1 = (dx + joint.anchorAx) * joint.axisY - (dy + joint.anchorAy) * joint.axisX
  const a2 = joint.anchorBx * joint.axisY - joint.anchorBy * joint.axisX
  const k = a.invMass + b.invMass + a.invInertia * a1 * a1 + b.invInertia * a2 * a2
  joint.axialMass = k > 0 ? 1 / k : 0
}

/** Per-step preparation of a prismatic joint. */
export function preparePrismatic(joint: Joint, ctx: JointStepContext): void {
  prepareAxis(joint)
  bodiesAngle(joint)
  // unwind, written out: no double argument or result (see joint-math.ts setSpringSoftness).
  let deltaAngle = angleOut[0] - joint.referenceAngle
  if (deltaAngle < -PI) deltaAngle += TWO_PI
  else if (deltaAngle > PI) deltaAngle -= TWO_PI
  joint.deltaAngle = deltaAngle
  setSpringSoftness(springSoftness, joint, ctx)
  joint.springBiasRate = springSoftness.biasRate
  joint.springMassScale = springSoftness.massScale
  joint.springImpulseScale = springSoftness.impulseScale
  if (!joint.enableSpring) joint.springImpulse = 0
  if (!joint.enableMotor) joint.motorImpulse = 0
  if (!joint.enableLimit) {
    joint.lowerImpulse = 0
    joint.upperImpulse = 0
  }
}

/** Applies the accumulated impulses of a prismatic joint. */
export function warmStartPrismatic(joint: Joint, state: Float64Array): void {
  computeFrame(joint, state)
  const f = frame
  const axial = joint.motorImpulse + joint.springImpulse + joint.lowerImpulse - joint.upperImpulse
  const perp = joint.linearImpulseX
  const l = joint.angularImpulse
  // P = axial axis + perp perpendicular, perpendicular = (-ay, ax).
  const px = axial * f[AX] - perp * f[AY]
  const py = axial * f[AY] + perp * f[AX]
  f[PX] = px
  f[PY] = py
  f[LA] = axial * f[A1] + perp * f[S1] + l
  f[LB] = axial * f[A2] + perp * f[S2] + l
  applyFrameImpulse(joint, state)
}

/** Relative speed of the anchors along the axis (m/s), into frame[SPEED]. */
export function axialSpeed(joint: Joint, state: Float64Array): void {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const f = frame
  f[SPEED] =
    (state[oB + VX] - state[oA + VX]) * f[AX] +
    (state[oB + VY] - state[oA + VY]) * f[AY] +
    f[A2] * state[oB + W] -
    f[A1] * state[oA + W]
}

/** Applies an impulse along the axis, given in frame[PX] (m: N s). */
export function applyAxialImpulse(joint: Joint, state: Float64Array): void {
  const f = frame
  const impulse = f[PX]
  f[PY] = impulse * f[AY]
  f[LA] = impulse * f[A1]
  f[LB] = impulse * f[A2]
  f[PX] = impulse * f[AX]
  applyFrameImpulse(joint, state)
}

/** A one-sided translation limit with error frame[LIMIT_C] (m, positive = inside); sign +1 lower, -1 upper. */
export function solveAxialLimit(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
  sign: number,
): void {
  const C = frame[LIMIT_C]
  let bias = 0
  let massScale = 1
  let impulseScale = 0
  if (C > 0) bias = C * ctx.invH
  else if (useBias) {
    bias = ctx.jointSoftness.biasRate * C
    massScale = ctx.jointSoftness.massScale
    impulseScale = ctx.jointSoftness.impulseScale
  }
  const accumulated = sign > 0 ? joint.lowerImpulse : joint.upperImpulse
  axialSpeed(joint, state)
  const cdot = sign * frame[SPEED]
  const impulse = -joint.axialMass * massScale * (cdot + bias) - impulseScale * accumulated
  const cap = joint.maxImpulse
  let sum = accumulated + impulse
  if (sum > cap) sum = cap
  else if (sum < -cap) sum = -cap
  else if (Number.isNaN(sum)) sum = 0
  const newImpulse = Math.max(sum, 0)
  if (sign > 0) joint.lowerImpulse = newImpulse
  else joint.upperImpulse = newImpulse
  frame[PX] = sign * (newImpulse - accumulated)
  applyAxialImpulse(joint, state)
}

/** One iteration of a prismatic joint. */
export function solvePrismatic(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const f = frame
  computeFrame(joint, state)
  const translation = f[DX] * f[AX] + f[DY] * f[AY]
  if (joint.enableSpring) {
    const C = translation - joint.springTarget
    axialSpeed(joint, state)
    const cdot = f[SPEED]
    const impulse =
      -joint.springMassScale * joint.axialMass * (cdot + joint.springBiasRate * C) -
      joint.springImpulseScale * joint.springImpulse
    const old = joint.springImpulse
    const cap = joint.maxImpulse
    let sum = old + impulse
    if (sum > cap) sum = cap
    else if (sum < -cap) sum = -cap
    else if (Number.isNaN(sum)) sum = 0
    joint.springImpulse = sum
    f[PX] = sum - old
    applyAxialImpulse(joint, state)
  }
  if (joint.enableMotor) {
    // The target speed closes at most the remaining gap to a limit per sub-step (as the revolute
    // motor's), so no motor force can drive the slider through its stop.
    let speed = joint.motorSpeed
    if (joint.enableLimit) {
      const t = translation
      speed = Math.max(
        Math.min(speed, (joint.upperTranslation - t) * ctx.invH),
        (joint.lowerTranslation - t) * ctx.invH,
      )
    }
    axialSpeed(joint, state)
    const old = joint.motorImpulse
    const cap = Math.min(joint.maxMotorForce * ctx.h, joint.maxImpulse)
    let sum = old + joint.axialMass * (speed - f[SPEED])
    if (sum > cap) sum = cap
    else if (sum < -cap) sum = -cap
    else if (Number.isNaN(sum)) sum = 0
    joint.motorImpulse = sum
    f[PX] = sum - old
    applyAxialImpulse(joint, state)
  }
  if (joint.enableLimit) {
    f[LIMIT_C] = translation - joint.lowerTranslation
    solveAxialLimit(joint, state, ctx, useBias, 1)
    f[LIMIT_C] = joint.upperTranslation - translation
    solveAxialLimit(joint, state, ctx, useBias, -1)
  }
  // Across the axis and the angle: a 2x2 soft block (Box2D's K = [k11 k12; k12 k22]).
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  const px = -f[AY]
  const py = f[AX]
  const s1 = f[S1]
  const s2 = f[S2]
  const wA = state[oA + W]
  const wB = state[oB + W]
  let c1 = (state[oB + VX] - state[oA + VX]) * px + (state[oB + VY] - state[oA + VY]) * py + s2 * wB - s1 * wA
  let c2 = wB - wA
  let massScale = 1
  let impulseScale = 0
  if (useBias) {
    const soft = ctx.jointSoftness
    relativeDeltaAngle(joint, state)
    const angle = angleOut[0] + joint.deltaAngle
    c1 += soft.biasRate * (f[DX] * px + f[DY] * py)
    c2 += soft.biasRate * angle
    massScale = soft.massScale
    impulseScale = soft.impulseScale
  }
  const k11 = mA + mB + iA * s1 * s1 + iB * s2 * s2
  const k12 = iA * s1 + iB * s2
  let k22 = iA + iB
  if (k22 === 0) k22 = 1 // both rotations fixed: the angular row is moot
  let det = k11 * k22 - k12 * k12
  if (det !== 0) det = 1 / det
  const x1 = det * (k22 * c1 - k12 * c2)
  const x2 = det * (k11 * c2 - k12 * c1)
  const old1 = joint.linearImpulseX
  const old2 = joint.angularImpulse
  const cap1 = joint.maxImpulse
  let sum1 = old1 - massScale * x1 - impulseScale * old1
  if (sum1 > cap1) sum1 = cap1
  else if (sum1 < -cap1) sum1 = -cap1
  else if (Number.isNaN(sum1)) sum1 = 0
  const cap2 = joint.maxAngularImpulse
  let sum2 = old2 - massScale * x2 - impulseScale * old2
  if (sum2 > cap2) sum2 = cap2
  else if (sum2 < -cap2) sum2 = -cap2
  else if (Number.isNaN(sum2)) sum2 = 0
  joint.linearImpulseX = sum1
  joint.angularImpulse = sum2
  const i1 = sum1 - old1
  const i2 = sum2 - old2
  f[PX] = i1 * px
  f[PY] = i1 * py
  f[LA] = i1 * s1 + i2
  f[LB] = i1 * s2 + i2
  applyFrameImpulse(joint, state)
}
