/*
 * Distance joint (Box2D v3 distance_joint.c): keeps the anchors `length` apart.
 * - Rod: hertz = 0 and minLength = maxLength = length: a rigid, softly corrected axial constraint.
 * - Rope: hertz = 0 and minLength < maxLength: only the limits act. With minLength = 0 the lower
 *   limit is not solved at all, so a rope pulls and never pushes, not even speculatively.
 * - Spring: hertz > 0: a soft spring toward `length` (implicit, stable at any stiffness), plus the
 *   min/max limits when minLength < maxLength (the defaults, min = max = length, mean no limits).
 * - Motor (enableMotor): drives the length's rate of change toward motorSpeed (m/s) with at most
 *   maxMotorForce (N), on a spring or a rope (a rod's rigid constraint overrides it).
 * Limits are speculative (close at most the remaining gap) and soft once violated, like contacts.
 *
 * The spring is the physics, not an error correction, so it acts in the relax pass as well. Its
 * equilibrium is exact: at rest the accumulated impulse P per sub-step balances the load, and the
 * update is zero when massScale * k * biasRate * C = -impulseScale * P, which with Catto's
 * coefficients gives C = -P / (h * m * omega^2), i.e. the static deflection g / omega^2.
 *
 * The oscillation is not exact: each sub-step is a linear map of (position, velocity, impulse)
 * (warm start, biased solve, integrate, relax solve), and its complex eigenvalue turns by less
 * than h * omega per sub-step. The frequency comes out low by about 0.45 (h omega)^2 (h = 1/240 s:
 * -0.03 % at 1 Hz, -0.8 % at 5 Hz, -3 % at 10 Hz, -20 % at 30 Hz; measured and predicted agree to
 * 0.1 %), and the implicit spring loses energy like a damping ratio of about h omega even when the
 * user asks for 0. That is the price of being stable at any stiffness.
 */
import { DPX, DPY, DQC, DQS, Softness, VX, VY, W } from '../dynamics/index.ts'
import type { Joint } from './joint.ts'
import { clampImpulse, type JointStepContext, setSpringSoftness } from './joint-math.ts'

const springSoftness = new Softness()

// Current axis, length and arms from the sub-step deltas, set by computeAxis (a typed array: a
// module-level double would allocate a heap number on every write in V8).
const geometry = new Float64Array(10)
const AXIS_X = 0
const AXIS_Y = 1
const LENGTH = 2
const RA_X = 3
const RA_Y = 4
const RB_X = 5
const RB_Y = 6
// Values passed through the array instead of as call arguments or results (V8 boxes a double
// crossing a call it does not inline: a heap allocation per call).
const SPEED = 7
const IMPULSE = 8
const LIMIT_C = 9

function computeAxis(joint: Joint, state: Float64Array): void {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const g = geometry
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  g[RA_X] = rAx
  g[RA_Y] = rAy
  g[RB_X] = rBx
  g[RB_Y] = rBy
  const dx = state[oB + DPX] - state[oA + DPX] + joint.deltaCenterX + rBx - rAx
  const dy = state[oB + DPY] - state[oA + DPY] + joint.deltaCenterY + rBy - rAy
  const length = Math.sqrt(dx * dx + dy * dy)
  g[LENGTH] = length
  if (length > 1e-12) {
    g[AXIS_X] = dx / length
    g[AXIS_Y] = dy / length
  } else {
    g[AXIS_X] = 1
    g[AXIS_Y] = 0
  }
}

/** Per-step preparation of a distance joint. */
export function prepareDistance(joint: Joint, state: Float64Array, ctx: JointStepContext): void {
  // The sub-step deltas are the identity before the sub-steps: this is the step-start geometry.
  computeAxis(joint, state)
  const a = joint.bodyA
  const b = joint.bodyB
  const g = geometry
  const crA = g[RA_X] * g[AXIS_Y] - g[RA_Y] * g[AXIS_X]
  const crB = g[RB_X] * g[AXIS_Y] - g[RB_Y] * g[AXIS_X]
  const k = a.invMass + b.invMass + a.invInertia * crA * crA + b.invInertia * crB * crB
  joint.axialMass = k > 0 ? 1 / k : 0
  setSpringSoftness(springSoftness, joint, ctx)
  joint.springBiasRate = springSoftness.biasRate
  joint.springMassScale = springSoftness.massScale
  joint.springImpulseScale = springSoftness.impulseScale
  if (!hasLimits(joint)) {
    joint.lowerImpulse = 0
    joint.upperImpulse = 0
  }
  if (joint.hertz === 0 && joint.minLength < joint.maxLength) joint.impulse = 0
  if (!joint.enableMotor) joint.motorImpulse = 0
}

/** Whether the min/max limits act: only when they span a range (a rod is rigid instead). */
function hasLimits(joint: Joint): boolean {
  return joint.minLength < joint.maxLength
}

/** Applies the axial impulse geometry[IMPULSE]. */
function applyAxial(joint: Joint, state: Float64Array): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const g = geometry
  const impulse = g[IMPULSE]
  const px = impulse * g[AXIS_X]
  const py = impulse * g[AXIS_Y]
  state[oA + VX] -= a.invMass * px
  state[oA + VY] -= a.invMass * py
  state[oA + W] -= a.invInertia * (g[RA_X] * py - g[RA_Y] * px)
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * (g[RB_X] * py - g[RB_Y] * px)
}

/** Applies the accumulated impulses of a distance joint. */
export function warmStartDistance(joint: Joint, state: Float64Array): void {
  computeAxis(joint, state)
  let axial = joint.impulse + joint.lowerImpulse - joint.upperImpulse
  if (joint.enableMotor) axial += joint.motorImpulse
  geometry[IMPULSE] = axial
  applyAxial(joint, state)
}

/** The anchors' relative speed along the axis (m/s), into geometry[SPEED]. */
function axialSpeed(joint: Joint, state: Float64Array): void {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const g = geometry
  const wA = state[oA + W]
  const wB = state[oB + W]
  const vx = state[oB + VX] - wB * g[RB_Y] - (state[oA + VX] - wA * g[RA_Y])
  const vy = state[oB + VY] + wB * g[RB_X] - (state[oA + VY] + wA * g[RA_X])
  g[SPEED] = vx * g[AXIS_X] + vy * g[AXIS_Y]
}

/** Adds geometry[IMPULSE] to the rigid/spring impulse within the joint's cap; leaves what was added there. */
function accumulate(joint: Joint): void {
  const impulse = geometry[IMPULSE]
  const old = joint.impulse
  const sum = old + impulse
  if (Math.abs(sum) <= joint.maxImpulse) {
    joint.impulse = sum
    return
  }
  joint.impulse = clampImpulse(sum, joint.maxImpulse)
  geometry[IMPULSE] = joint.impulse - old
}

/** One iteration of a distance joint. */
export function solveDistance(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
): void {
  computeAxis(joint, state)
  const limits = hasLimits(joint)
  if (joint.hertz > 0) {
    // Soft spring toward the rest length (always biased: the spring is the physics, not correction).
    const C = geometry[LENGTH] - joint.length
    const bias = joint.springBiasRate * C
    axialSpeed(joint, state)
    const cdot = geometry[SPEED]
    geometry[IMPULSE] =
      -joint.springMassScale * joint.axialMass * (cdot + bias) - joint.springImpulseScale * joint.impulse
    accumulate(joint)
    applyAxial(joint, state)
  } else if (!limits) {
    const C = geometry[LENGTH] - joint.length
    let bias = 0
    let massScale = 1
    let impulseScale = 0
    if (useBias) {
      bias = ctx.jointSoftness.biasRate * C
      massScale = ctx.jointSoftness.massScale
      impulseScale = ctx.jointSoftness.impulseScale
    }
    axialSpeed(joint, state)
    const cdot = geometry[SPEED]
    geometry[IMPULSE] = -massScale * joint.axialMass * (cdot + bias) - impulseScale * joint.impulse
    accumulate(joint)
    applyAxial(joint, state)
  }
  if (joint.enableMotor) {
    const old = joint.motorImpulse
    const cap = Math.min(joint.maxMotorForce * ctx.h, joint.maxImpulse)
    axialSpeed(joint, state)
    joint.motorImpulse = clampImpulse(old + joint.axialMass * (joint.motorSpeed - geometry[SPEED]), cap)
    geometry[IMPULSE] = joint.motorImpulse - old
    applyAxial(joint, state)
  }
  if (limits) {
    if (joint.minLength > 0) {
      geometry[LIMIT_C] = geometry[LENGTH] - joint.minLength
      solveLimit(joint, state, ctx, useBias, 1)
    }
    geometry[LIMIT_C] = joint.maxLength - geometry[LENGTH]
    solveLimit(joint, state, ctx, useBias, -1)
  }
}

/**
 * A one-sided length limit with error geometry[LIMIT_C] (m, positive = inside); sign +1 keeps
 * length >= min (pushes), -1 keeps length <= max (pulls).
 */
function solveLimit(
  joint: Joint,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
  sign: number,
): void {
  const C = geometry[LIMIT_C]
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
  const cdot = sign * geometry[SPEED]
  let impulse = -massScale * joint.axialMass * (cdot + bias) - impulseScale * accumulated
  const newImpulse = Math.max(clampImpulse(accumulated + impulse, joint.maxImpulse), 0)
  impulse = newImpulse - accumulated
  if (sign > 0) joint.lowerImpulse = newImpulse
  else joint.upperImpulse = newImpulse
  geometry[IMPULSE] = sign * impulse
  applyAxial(joint, state)
}
