/*
 * Distance joint (Box2D v3 distance_joint.c): keeps the anchors `length` apart.
 * - Rod: hertz = 0 and minLength = maxLength = length: a rigid, softly corrected axial constraint.
 * - Rope: hertz = 0 and minLength < maxLength: only the limits act. With minLength = 0 the lower
 *   limit is not solved at all, so a rope pulls and never pushes, not even speculatively.
 * - Spring: hertz > 0: a soft spring toward `length` (implicit, stable at any stiffness), plus the
 *   min/max limits when minLength < maxLength (the defaults, min = max = length, mean no limits).
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
import type { Joint, JointStepContext } from './joint.ts'
import { Softness } from './softness.ts'

const springSoftness = new Softness()

// Current axis and length, from the sub-step deltas (set by computeAxis).
let axisX = 0
let axisY = 0
let currentLength = 0
let rAx = 0
let rAy = 0
let rBx = 0
let rBy = 0

function computeAxis(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  rAx = a.dqc * joint.anchorAx - a.dqs * joint.anchorAy
  rAy = a.dqs * joint.anchorAx + a.dqc * joint.anchorAy
  rBx = b.dqc * joint.anchorBx - b.dqs * joint.anchorBy
  rBy = b.dqs * joint.anchorBx + b.dqc * joint.anchorBy
  const dx = b.dpx - a.dpx + joint.deltaCenterX + rBx - rAx
  const dy = b.dpy - a.dpy + joint.deltaCenterY + rBy - rAy
  currentLength = Math.sqrt(dx * dx + dy * dy)
  if (currentLength > 1e-12) {
    axisX = dx / currentLength
    axisY = dy / currentLength
  } else {
    axisX = 1
    axisY = 0
  }
}

/** Per-step preparation of a distance joint. */
export function prepareDistance(joint: Joint, ctx: JointStepContext): void {
  // The sub-step deltas are the identity before the sub-steps: this is the step-start geometry.
  computeAxis(joint)
  const a = joint.bodyA
  const b = joint.bodyB
  const crA = rAx * axisY - rAy * axisX
  const crB = rBx * axisY - rBy * axisX
  const k = a.invMass + b.invMass + a.invInertia * crA * crA + b.invInertia * crB * crB
  joint.axialMass = k > 0 ? 1 / k : 0
  springSoftness.set(joint.hertz, joint.dampingRatio, ctx.h)
  joint.springBiasRate = springSoftness.biasRate
  joint.springMassScale = springSoftness.massScale
  joint.springImpulseScale = springSoftness.impulseScale
  if (!hasLimits(joint)) {
    joint.lowerImpulse = 0
    joint.upperImpulse = 0
  }
  if (joint.hertz === 0 && joint.minLength < joint.maxLength) joint.impulse = 0
}

/** Whether the min/max limits act: only when they span a range (a rod is rigid instead). */
function hasLimits(joint: Joint): boolean {
  return joint.minLength < joint.maxLength
}

function applyAxial(joint: Joint, impulse: number): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const px = impulse * axisX
  const py = impulse * axisY
  a.vx -= a.invMass * px
  a.vy -= a.invMass * py
  a.w -= a.invInertia * (rAx * py - rAy * px)
  b.vx += b.invMass * px
  b.vy += b.invMass * py
  b.w += b.invInertia * (rBx * py - rBy * px)
}

/** Applies the accumulated impulses of a distance joint. */
export function warmStartDistance(joint: Joint): void {
  computeAxis(joint)
  applyAxial(joint, joint.impulse + joint.lowerImpulse - joint.upperImpulse)
}

function axialSpeed(joint: Joint): number {
  const a = joint.bodyA
  const b = joint.bodyB
  const vx = b.vx - b.w * rBy - (a.vx - a.w * rAy)
  const vy = b.vy + b.w * rBx - (a.vy + a.w * rAx)
  return vx * axisX + vy * axisY
}

/** One iteration of a distance joint. */
export function solveDistance(joint: Joint, ctx: JointStepContext, useBias: boolean): void {
  computeAxis(joint)
  const limits = hasLimits(joint)
  if (joint.hertz > 0) {
    // Soft spring toward the rest length (always biased: the spring is the physics, not correction).
    const C = currentLength - joint.length
    const bias = joint.springBiasRate * C
    const cdot = axialSpeed(joint)
    const impulse =
      -joint.springMassScale * joint.axialMass * (cdot + bias) - joint.springImpulseScale * joint.impulse
    joint.impulse += impulse
    applyAxial(joint, impulse)
  } else if (!limits) {
    const C = currentLength - joint.length
    let bias = 0
    let massScale = 1
    let impulseScale = 0
    if (useBias) {
      bias = ctx.jointSoftness.biasRate * C
      massScale = ctx.jointSoftness.massScale
      impulseScale = ctx.jointSoftness.impulseScale
    }
    const cdot = axialSpeed(joint)
    const impulse = -massScale * joint.axialMass * (cdot + bias) - impulseScale * joint.impulse
    joint.impulse += impulse
    applyAxial(joint, impulse)
  }
  if (limits) {
    if (joint.minLength > 0) solveLimit(joint, ctx, useBias, currentLength - joint.minLength, 1)
    solveLimit(joint, ctx, useBias, joint.maxLength - currentLength, -1)
  }
}

/** A one-sided length limit; sign +1 keeps length >= min (pushes), -1 keeps length <= max (pulls). */
function solveLimit(joint: Joint, ctx: JointStepContext, useBias: boolean, C: number, sign: number): void {
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
  const cdot = sign * axialSpeed(joint)
  let impulse = -massScale * joint.axialMass * (cdot + bias) - impulseScale * accumulated
  const newImpulse = Math.max(accumulated + impulse, 0)
  impulse = newImpulse - accumulated
  if (sign > 0) joint.lowerImpulse = newImpulse
  else joint.upperImpulse = newImpulse
  applyAxial(joint, sign * impulse)
}
