/*
 * Weld joint (Box2D v3 weld_joint.c): B is glued to A at the anchor, keeping the angle it had at
 * creation. Two soft constraints: an angular one (angleB - angleA - referenceAngle = 0, with
 * `angularHertz`, `angularDampingRatio`) and a 2D point one (the anchors coincide, with `hertz`,
 * `dampingRatio` as its linear spring). 0 Hz means rigid: solved with the joint softness in the
 * biased pass and rigidly in the relax pass; a spring (hertz > 0) is physics, so it acts in the
 * relax pass too. A weld that is rigid both ways and belongs to a tree of welds and pins is solved
 * exactly by the direct solver (joint-tree.ts, as a 3-row block), which is what lets a cantilever
 * of light boxes hold its shape; Gauss-Seidel alone lets it sag metres (Box2D v3: 2.89 m for ten
 * 1 m boxes after 10 s).
 */
import { DPX, DPY, DQC, DQS, Softness, VX, VY, W } from '../dynamics/index.ts'
import { PI, TWO_PI } from '../math.ts'
import type { Joint } from './joint.ts'
import {
  angleOut,
  bodiesAngle,
  type JointStepContext,
  relativeDeltaAngle,
  setAngularSoftness,
  setSpringSoftness,
  solve22,
  solved2,
  system22,
} from './joint-math.ts'

const softness = new Softness()

/** Per-step preparation of a weld joint. */
export function prepareWeld(joint: Joint, ctx: JointStepContext): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const k = a.invInertia + b.invInertia
  joint.axialMass = k > 0 ? 1 / k : 0
  bodiesAngle(joint)
  // unwind, written out: no double argument or result (see joint-math.ts setSpringSoftness).
  let deltaAngle = angleOut[0] - joint.referenceAngle
  if (deltaAngle < -PI) deltaAngle += TWO_PI
  else if (deltaAngle > PI) deltaAngle -= TWO_PI
  joint.deltaAngle = deltaAngle
  let linear = ctx.jointSoftness
  if (joint.hertz !== 0) {
    setSpringSoftness(softness, joint, ctx)
    linear = softness
  }
  joint.springBiasRate = linear.biasRate
  joint.springMassScale = linear.massScale
  joint.springImpulseScale = linear.impulseScale
  let angular = ctx.jointSoftness
  if (joint.angularHertz !== 0) {
    setAngularSoftness(softness, joint, ctx)
    angular = softness
  }
  joint.angularBiasRate = angular.biasRate
  joint.angularMassScale = angular.massScale
  joint.angularImpulseScale = angular.impulseScale
}

/** Whether the weld is rigid both ways (then a tree of such welds is solved directly). */
export function isRigidWeld(joint: Joint): boolean {
  return joint.hertz === 0 && joint.angularHertz === 0
}

/** Applies the accumulated impulses of a weld joint. */
export function warmStartWeld(joint: Joint, state: Float64Array): void {
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
  const l = joint.angularImpulse
  state[oA + VX] -= a.invMass * px
  state[oA + VY] -= a.invMass * py
  state[oA + W] -= a.invInertia * (rAx * py - rAy * px + l)
  state[oB + VX] += b.invMass * px
  state[oB + VY] += b.invMass * py
  state[oB + W] += b.invInertia * (rBx * py - rBy * px + l)
}

/** One iteration of a weld joint: the angle, then the point (Box2D's order). */
export function solveWeld(joint: Joint, state: Float64Array, useBias: boolean): void {
  if (joint.inTree) return // solved directly (joint-tree.ts)
  const a = joint.bodyA
  const b = joint.bodyB
  const oA = joint.offsetA
  const oB = joint.offsetB
  const mA = a.invMass
  const mB = b.invMass
  const iA = a.invInertia
  const iB = b.invInertia
  {
    let bias = 0
    let massScale = 1
    let impulseScale = 0
    if (useBias || joint.angularHertz > 0) {
      relativeDeltaAngle(joint, state)
      const C = angleOut[0] + joint.deltaAngle
      bias = joint.angularBiasRate * C
      massScale = joint.angularMassScale
      impulseScale = joint.angularImpulseScale
    }
    const cdot = state[oB + W] - state[oA + W]
    // joint-math.ts accumulateAngular, written out: a call V8 does not inline boxes its double
    // argument and result (a heap number each; the README's allocation notes).
    let impulse = -massScale * joint.axialMass * (cdot + bias) - impulseScale * joint.angularImpulse
    const old = joint.angularImpulse
    const cap = joint.maxAngularImpulse
    let sum = old + impulse
    if (!(Math.abs(sum) <= cap)) {
      if (sum > cap) sum = cap
      else if (sum < -cap) sum = -cap
      else if (Number.isNaN(sum)) sum = 0
      impulse = sum - old
    }
    joint.angularImpulse = sum
    state[oA + W] -= iA * impulse
    state[oB + W] += iB * impulse
  }
  const rAx = state[oA + DQC] * joint.anchorAx - state[oA + DQS] * joint.anchorAy
  const rAy = state[oA + DQS] * joint.anchorAx + state[oA + DQC] * joint.anchorAy
  const rBx = state[oB + DQC] * joint.anchorBx - state[oB + DQS] * joint.anchorBy
  const rBy = state[oB + DQS] * joint.anchorBx + state[oB + DQC] * joint.anchorBy
  let biasX = 0
  let biasY = 0
  let massScale = 1
  let impulseScale = 0
  if (useBias || joint.hertz > 0) {
    const sepX = state[oB + DPX] - state[oA + DPX] + (rBx - rAx) + joint.deltaCenterX
    const sepY = state[oB + DPY] - state[oA + DPY] + (rBy - rAy) + joint.deltaCenterY
    biasX = joint.springBiasRate * sepX
    biasY = joint.springBiasRate * sepY
    massScale = joint.springMassScale
    impulseScale = joint.springImpulseScale
  }
  const wA = state[oA + W]
  const wB = state[oB + W]
  system22[0] = mA + mB + rAy * rAy * iA + rBy * rBy * iB
  system22[1] = -rAy * rAx * iA - rBy * rBx * iB
  system22[2] = mA + mB + rAx * rAx * iA + rBx * rBx * iB
  system22[3] = state[oB + VX] - wB * rBy - (state[oA + VX] - wA * rAy) + biasX
  system22[4] = state[oB + VY] + wB * rBx - (state[oA + VY] + wA * rAx) + biasY
  solve22()
  // joint-math.ts accumulateX and accumulateY, written out (as the angle's above).
  const cap = joint.maxImpulse
  let ix = -massScale * solved2[0] - impulseScale * joint.linearImpulseX
  const oldX = joint.linearImpulseX
  let sumX = oldX + ix
  if (!(Math.abs(sumX) <= cap)) {
    if (sumX > cap) sumX = cap
    else if (sumX < -cap) sumX = -cap
    else if (Number.isNaN(sumX)) sumX = 0
    ix = sumX - oldX
  }
  joint.linearImpulseX = sumX
  let iy = -massScale * solved2[1] - impulseScale * joint.linearImpulseY
  const oldY = joint.linearImpulseY
  let sumY = oldY + iy
  if (!(Math.abs(sumY) <= cap)) {
    if (sumY > cap) sumY = cap
    else if (sumY < -cap) sumY = -cap
    else if (Number.isNaN(sumY)) sumY = 0
    iy = sumY - oldY
  }
  joint.linearImpulseY = sumY
  state[oA + VX] -= mA * ix
  state[oA + VY] -= mA * iy
  state[oA + W] -= iA * (rAx * iy - rAy * ix)
  state[oB + VX] += mB * ix
  state[oB + VY] += mB * iy
  state[oB + W] += iB * (rBx * iy - rBy * ix)
}
