/*
 * Wheel joint (Box2D v3 wheel_joint.c): B (the wheel) may slide along an axis fixed in A (the
 * chassis; the suspension travel, m, zero at creation) and spin freely. A spring along the axis
 * (`hertz`, `dampingRatio`, rest at translation 0) is the suspension; limits bound the travel; the
 * motor drives the wheel's spin relative to A (rad/s) with at most maxMotorTorque (N m). The point
 * stays on the line: a 1-row constraint across the axis, soft in the biased pass.
 *
 * Stiffness, as Box2D defines it: the spring's hertz is that of the joint's own axial mass
 * m_axial = 1 / (mA + mB + iA a1^2 + iB a2^2) (a1, a2 the bodies' lever arms about the axis), so
 * its stiffness is k = m_axial (2 pi hertz)^2 and a load F along the axis deflects it F / k.
 */
import { Softness, VX, VY, W } from '../dynamics/index.ts'
import type { Joint } from './joint.ts'
import { type JointStepContext, setSpringSoftness } from './joint-math.ts'
import {
  A1,
  A2,
  AX,
  AY,
  applyAxialImpulse,
  applyFrameImpulse,
  axialSpeed,
  computeFrame,
  DX,
  DY,
  jointFrame,
  LA,
  LB,
  LIMIT_C,
  PX,
  PY,
  prepareAxis,
  S1,
  S2,
  SPEED,
  solveAxialLimit,
} from './prismatic-joint.ts'

const springSoftness = new Softness()

/** Per-step preparation of a wheel joint. */
export function prepareWheel(joint: Joint, ctx: JointStepContext): void {
  prepareAxis(joint)
  const k = joint.bodyA.invInertia + joint.bodyB.invInertia
  joint.angularMass = k > 0 ? 1 / k : 0
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

/** Applies the accumulated impulses of a wheel joint. */
export function warmStartWheel(joint: Joint, state: Float64Array): void {
  computeFrame(joint, state)
  const f = jointFrame
  const axial = joint.springImpulse + joint.lowerImpulse - joint.upperImpulse
  const perp = joint.linearImpulseX
  const px = axial * f[AX] - perp * f[AY]
  const py = axial * f[AY] + perp * f[AX]
  const m = joint.motorImpulse
  f[PX] = px
  f[PY] = py
  f[LA] = axial * f[A1] + perp * f[S1] + m
  f[LB] = axial * f[A2] + perp * f[S2] + m
  applyFrameImpulse(joint, state)
}

/** One iteration of a wheel joint: motor, spring, limits, then the point on the line. */
export function solveWheel(joint: Joint, state: Float64Array, ctx: JointStepContext, useBias: boolean): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const f = jointFrame
  computeFrame(joint, state)
  const translation = f[DX] * f[AX] + f[DY] * f[AY]
  if (joint.enableMotor) {
    const cdot = state[oB + W] - state[oA + W] - joint.motorSpeed
    const old = joint.motorImpulse
    const cap = Math.min(joint.maxMotorTorque * ctx.h, joint.maxAngularImpulse)
    let sum = old - joint.angularMass * cdot
    if (sum > cap) sum = cap
    else if (sum < -cap) sum = -cap
    else if (Number.isNaN(sum)) sum = 0
    joint.motorImpulse = sum
    const impulse = sum - old
    state[oA + W] -= a.invInertia * impulse
    state[oB + W] += b.invInertia * impulse
  }
  if (joint.enableSpring) {
    axialSpeed(joint, state)
    const impulse =
      -joint.springMassScale * joint.axialMass * (f[SPEED] + joint.springBiasRate * translation) -
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
  if (joint.enableLimit) {
    f[LIMIT_C] = translation - joint.lowerTranslation
    solveAxialLimit(joint, state, ctx, useBias, 1)
    f[LIMIT_C] = joint.upperTranslation - translation
    solveAxialLimit(joint, state, ctx, useBias, -1)
  }
  // Point on the line: across the axis only.
  const px = -f[AY]
  const py = f[AX]
  const s1 = f[S1]
  const s2 = f[S2]
  let bias = 0
  let massScale = 1
  let impulseScale = 0
  if (useBias) {
    const soft = ctx.jointSoftness
    bias = soft.biasRate * (f[DX] * px + f[DY] * py)
    massScale = soft.massScale
    impulseScale = soft.impulseScale
  }
  const cdot =
    (state[oB + VX] - state[oA + VX]) * px +
    (state[oB + VY] - state[oA + VY]) * py +
    s2 * state[oB + W] -
    s1 * state[oA + W]
  const k = a.invMass + b.invMass + a.invInertia * s1 * s1 + b.invInertia * s2 * s2
  const perpMass = k > 0 ? 1 / k : 0
  const old = joint.linearImpulseX
  const cap = joint.maxImpulse
  let sum = old - massScale * perpMass * (cdot + bias) - impulseScale * old
  if (sum > cap) sum = cap
  else if (sum < -cap) sum = -cap
  else if (Number.isNaN(sum)) sum = 0
  joint.linearImpulseX = sum
  const i = sum - old
  f[PX] = i * px
  f[PY] = i * py
  f[LA] = i * s1
  f[LB] = i * s2
  applyFrameImpulse(joint, state)
}
