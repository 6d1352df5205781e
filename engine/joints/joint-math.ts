/*
 * What every joint kind shares, and nothing that depends on a kind: the kind codes, the clamped
 * accumulation of impulses, a 2x2 solve and the relative angle. The kinds (revolute-joint.ts,
 * distance-joint.ts, mouse-joint.ts), the joint tree (joint-tree.ts) and the dispatcher (joint.ts)
 * import it; it imports none of them, so the joint files form no import cycle.
 */
import { atan2 } from '../math.ts'
import type { Joint } from './joint.ts'

/** Joint kind codes. */
export const REVOLUTE = 0
export const DISTANCE = 1
export const MOUSE = 2
/** Kind names in code order. */
export const JOINT_TYPE_NAMES = ['revolute', 'distance', 'mouse'] as const

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

/** Relative angle of rotation b with respect to rotation a, in [-pi, pi] (rad). */
export function relativeAngle(bc: number, bs: number, ac: number, as: number): number {
  return atan2(bs * ac - bc * as, bc * ac + bs * as)
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
