/*
 * Helpers every joint kind shares: kind codes, impulse caps and accumulation, angles, the 2x2 and
 * 3x3 solves. They live here, apart from joint.ts (which dispatches to the kinds) so that the kind
 * files import them without a run-time import cycle (joint.ts -> weld-joint.ts -> joint.ts).
 */

import { DQC, DQS, type Softness, type StepContext, softnessInput } from '../dynamics/index.ts'
import { atan2, PI, TWO_PI } from '../math.ts'
import type { Joint } from './joint.ts'

/** Joint kind codes. */
export const REVOLUTE = 0
export const DISTANCE = 1
export const MOUSE = 2
export const WELD = 3
export const PRISMATIC = 4
export const WHEEL = 5
export const MOTOR = 6
/** Kind names in code order. */
export const JOINT_TYPE_NAMES = [
  'revolute',
  'distance',
  'mouse',
  'weld',
  'prismatic',
  'wheel',
  'motor',
] as const

/** Per-step values the joints read (the solver's StepContext). */
export type JointStepContext = StepContext

/** `impulse` within [-cap, cap]; NaN (which no finite input should produce) becomes 0. */
export function clampImpulse(impulse: number, cap: number): number {
  if (impulse > cap) return cap
  if (impulse < -cap) return -cap
  return Number.isNaN(impulse) ? 0 : impulse
}

/** Adds `impulse` to the accumulated x impulse within the joint's cap; returns what was added. */
export function accumulateX(joint: Joint, impulse: number): number {
  const old = joint.linearImpulseX
  const sum = old + impulse
  if (Math.abs(sum) <= joint.maxImpulse) {
    joint.linearImpulseX = sum
    return impulse
  }
  joint.linearImpulseX = clampImpulse(sum, joint.maxImpulse)
  return joint.linearImpulseX - old
}

/** Adds `impulse` to the accumulated y impulse within the joint's cap; returns what was added. */
export function accumulateY(joint: Joint, impulse: number): number {
  const old = joint.linearImpulseY
  const sum = old + impulse
  if (Math.abs(sum) <= joint.maxImpulse) {
    joint.linearImpulseY = sum
    return impulse
  }
  joint.linearImpulseY = clampImpulse(sum, joint.maxImpulse)
  return joint.linearImpulseY - old
}

/** Adds `impulse` to the accumulated angular impulse within the angular cap; returns what was added. */
export function accumulateAngular(joint: Joint, impulse: number): number {
  const old = joint.angularImpulse
  const sum = old + impulse
  if (Math.abs(sum) <= joint.maxAngularImpulse) {
    joint.angularImpulse = sum
    return impulse
  }
  joint.angularImpulse = clampImpulse(sum, joint.maxAngularImpulse)
  return joint.angularImpulse - old
}

/** Adds `impulse` to the accumulated spring impulse within the linear cap; returns what was added. */
export function accumulateSpring(joint: Joint, impulse: number, cap: number): number {
  const old = joint.springImpulse
  const sum = old + impulse
  if (Math.abs(sum) <= cap) {
    joint.springImpulse = sum
    return impulse
  }
  joint.springImpulse = clampImpulse(sum, cap)
  return joint.springImpulse - old
}

/**
 * soft = the softness of the joint's spring (hertz, dampingRatio) at the sub-step ctx.h. Objects
 * in, no doubles: a call V8 does not inline boxes each double argument, and prepareJoints, into
 * which the kinds' prepare functions are inlined, can run out of its inlining budget before
 * Softness.set (the machines scene, 2026-11-28).
 */
export function setSpringSoftness(soft: Softness, joint: Joint, ctx: JointStepContext): void {
  softnessInput[0] = joint.hertz
  softnessInput[1] = joint.dampingRatio
  softnessInput[2] = ctx.h
  soft.setFromInput()
}

/** soft = the softness of a weld's angular spring (angularHertz, angularDampingRatio) at ctx.h. */
export function setAngularSoftness(soft: Softness, joint: Joint, ctx: JointStepContext): void {
  softnessInput[0] = joint.angularHertz
  softnessInput[1] = joint.angularDampingRatio
  softnessInput[2] = ctx.h
  soft.setFromInput()
}

/** Relative angle of rotation b with respect to rotation a, in [-pi, pi] (rad). */
export function relativeAngle(bc: number, bs: number, ac: number, as: number): number {
  return atan2(bs * ac - bc * as, bc * ac + bs * as)
}

/**
 * Angles of rotations without a call that allocates: V8 does not inline engine/math.ts's atan2
 * (the fdlibm kernel, exact to 1 ulp), and a double passed to or returned from a call it does not
 * inline is a heap allocation; the solver needs a joint's angle per joint per iteration. So the
 * functions below take objects, read the rotation, and leave the angle in angleOut[0] (rad, in
 * (-pi, pi]). The kernel uses + - * / sqrt only: two half-angle reductions bring the argument
 * within tan(pi/8) and a series to the 21st power gives atan there to about 1e-10 rad: plenty for
 * a constraint's error (the saved state never holds it).
 */
export const angleOut = new Float64Array(3)

/** angleOut[0] = the angle of the unit rotation (angleOut[1], angleOut[2]) = (c, s). */
function angleOfRotation(): void {
  const c = angleOut[1]
  const s = angleOut[2]
  // Half-angle: theta = 2 atan(s / (1 + c)) for c >= 0; for c < 0 turn by pi first.
  let base = 0
  let t: number
  if (c >= 0) t = s / (1 + c)
  else {
    base = s >= 0 ? PI : -PI
    t = -s / (1 - c)
  }
  // |t| <= 1; once more: atan t = 2 atan(t / (1 + sqrt(1 + t^2))), |u| <= tan(pi/8).
  const u = t / (1 + Math.sqrt(1 + t * t))
  const u2 = u * u
  const series =
    u *
    (1 -
      u2 *
        (1 / 3 -
          u2 *
            (1 / 5 -
              u2 *
                (1 / 7 -
                  u2 *
                    (1 / 9 -
                      u2 *
                        (1 / 11 -
                          u2 * (1 / 13 - u2 * (1 / 15 - u2 * (1 / 17 - u2 * (1 / 19 - u2 / 21))))))))))
  angleOut[0] = base + 4 * series
}

/** angleOut[0] = the bodies' relative rotation during this step so far (rad): B's sub-step delta less A's. */
export function relativeDeltaAngle(joint: Joint, state: Float64Array): void {
  const oA = joint.offsetA
  const oB = joint.offsetB
  const ac = state[oA + DQC]
  const as = state[oA + DQS]
  const bc = state[oB + DQC]
  const bs = state[oB + DQS]
  angleOut[1] = bc * ac + bs * as
  angleOut[2] = bs * ac - bc * as
  angleOfRotation()
}

/** angleOut[0] = angleB - angleA now (rad, (-pi, pi]), from the bodies' rotations. */
export function bodiesAngle(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  angleOut[1] = b.c * a.c + b.s * a.s
  angleOut[2] = b.s * a.c - b.c * a.s
  angleOfRotation()
}

/** Unwinds an angle into [-pi, pi]. */
export function unwind(angle: number): number {
  if (angle < -PI) return angle + TWO_PI
  if (angle > PI) return angle - TWO_PI
  return angle
}

/**
 * Solves the symmetric 2x2 system [k11 k12; k12 k22] x = (bx, by), given in system22 as
 * [k11, k12, k22, bx, by], into `solved2` (Cramer's rule). Typed arrays both ways: V8 boxes the
 * double arguments of a call it does not inline (the room's mouse joints call this 40 times a step).
 */
export function solve22(): void {
  const k11 = system22[0]
  const k12 = system22[1]
  const k22 = system22[2]
  const bx = system22[3]
  const by = system22[4]
  let det = k11 * k22 - k12 * k12
  if (det !== 0) det = 1 / det
  solved2[0] = det * (k22 * bx - k12 * by)
  solved2[1] = det * (k11 * by - k12 * bx)
}
/** Input of solve22: k11, k12, k22, bx, by. */
export const system22 = new Float64Array(5)
/** Output of solve22 (a typed array: a module-level double would allocate on every write in V8). */
export const solved2 = new Float64Array(2)

/**
 * Inverts the symmetric 3x3 matrix in `sym3` (xx, xy, xw, yy, yw, ww) into `inverse3` (same
 * layout), by cofactors; a singular matrix gives zeros.
 */
export function invert33(): void {
  const a = sym3[0]
  const b = sym3[1]
  const c = sym3[2]
  const d = sym3[3]
  const e = sym3[4]
  const f = sym3[5]
  const c00 = d * f - e * e
  const c01 = c * e - b * f
  const c02 = b * e - c * d
  let det = a * c00 + b * c01 + c * c02
  det = det !== 0 ? 1 / det : 0
  inverse3[0] = det * c00
  inverse3[1] = det * c01
  inverse3[2] = det * c02
  inverse3[3] = det * (a * f - c * c)
  inverse3[4] = det * (b * c - a * e)
  inverse3[5] = det * (a * d - b * b)
}
/** Input of invert33: xx, xy, xw, yy, yw, ww. */
export const sym3 = new Float64Array(6)
/** Output of invert33, same layout. */
export const inverse3 = new Float64Array(6)
