/*
 * The solver state of the awake bodies: one Float64Array, STATE_STRIDE numbers per body (Box2D v3's
 * b2BodyState): velocity (VX, VY, W) and the sub-step deltas of position (DPX, DPY) and rotation as a
 * unit pair (DQC, DQS). A body's record starts at stateOffset(body): awake bodies have solverIndex
 * 0..n-1 for this step and records 1..n; static bodies (solverIndex -1) share record 0, which never
 * moves and has zero velocity, so constraint code reads and writes both bodies without branching.
 *
 * Contacts and joints read and write these records by offset; the Body fields vx, vy, w hold the
 * velocity only between steps (finalizeBodies copies it back). The integrators here run once per
 * sub-step (b2IntegrateVelocities, b2IntegratePositions) and enforce the speed limits.
 */

import { MAX_LINEAR_SPEED, MAX_ROTATION } from '../constants.ts'
import { type Body, DYNAMIC } from './body.ts'
import type { StepContext } from './step-context.ts'

/** Linear velocity x (m/s). */
export const VX = 0
/** Linear velocity y (m/s). */
export const VY = 1
/** Angular velocity (rad/s). */
export const W = 2
/** Position delta of the centre of mass since the step began, x (m). */
export const DPX = 3
/** Position delta, y (m). */
export const DPY = 4
/** Rotation delta since the step began, cosine. */
export const DQC = 5
/** Rotation delta, sine. */
export const DQS = 6
/** Numbers per body record (one spare keeps records 64-byte aligned). */
export const STATE_STRIDE = 8

/** Offset of a body's record in the state array: record 0 (static, never moving) for a body not being solved. */
export function stateOffset(b: Body): number {
  return (b.solverIndex + 1) * STATE_STRIDE
}

/** Copies awake bodies' velocities into the solver state (grown if needed) with zero deltas. */
export function loadSolverStates(awake: Body[], n: number, state: Float64Array): Float64Array {
  if (state.length < (n + 1) * STATE_STRIDE) state = new Float64Array((n + 1) * 2 * STATE_STRIDE)
  state.fill(0, 0, STATE_STRIDE)
  state[DQC] = 1
  for (let i = 0; i < n; i++) {
    const b = awake[i]
    const o = (i + 1) * STATE_STRIDE
    state[o + VX] = b.vx
    state[o + VY] = b.vy
    state[o + W] = b.w
    state[o + DPX] = 0
    state[o + DPY] = 0
    state[o + DQC] = 1
    state[o + DQS] = 0
  }
  return state
}

/**
 * Gravity and damping for awake dynamic bodies over one sub-step (semi-implicit Euler), then the
 * speed limits (see clampSpeed).
 */
export function integrateVelocities(awake: Body[], n: number, state: Float64Array, ctx: StepContext): void {
  const h = ctx.h
  const gx = ctx.gravityX * h
  const gy = ctx.gravityY * h
  const maxAngularSpeed = MAX_ROTATION * ctx.invH
  for (let i = 0; i < n; i++) {
    const b = awake[i]
    if (b.type !== DYNAMIC) continue
    const o = (i + 1) * STATE_STRIDE
    let vx = state[o + VX]
    let vy = state[o + VY]
    let w = state[o + W]
    if (b.linearDamping > 0) {
      const damp = 1 / (1 + h * b.linearDamping)
      vx *= damp
      vy *= damp
    }
    if (b.angularDamping > 0) w *= 1 / (1 + h * b.angularDamping)
    state[o + VX] = vx + b.gravityScale * gx
    state[o + VY] = vy + b.gravityScale * gy
    state[o + W] = w
    clampSpeed(state, o, maxAngularSpeed)
  }
}

/**
 * The speed limits of the record at offset `o` (Box2D v3 b2IntegratePositions): linear speed at most
 * MAX_LINEAR_SPEED, angular speed at most `maxAngularSpeed` (MAX_ROTATION per sub-step). Applied
 * after gravity and again before each position update (after contacts and joints), so neither
 * forces nor impulses can push a body past them.
 */
function clampSpeed(state: Float64Array, o: number, maxAngularSpeed: number): void {
  const vx = state[o + VX]
  const vy = state[o + VY]
  const speedSquared = vx * vx + vy * vy
  if (speedSquared > MAX_LINEAR_SPEED * MAX_LINEAR_SPEED) {
    const scale = MAX_LINEAR_SPEED / Math.sqrt(speedSquared)
    state[o + VX] = vx * scale
    state[o + VY] = vy * scale
  }
  const w = state[o + W]
  if (w > maxAngularSpeed) state[o + W] = maxAngularSpeed
  else if (w < -maxAngularSpeed) state[o + W] = -maxAngularSpeed
}

/** Clamps the speeds, then accumulates the sub-step position and rotation deltas of n awake bodies. */
export function integratePositions(state: Float64Array, n: number, ctx: StepContext): void {
  const h = ctx.h
  const maxAngularSpeed = MAX_ROTATION * ctx.invH
  const end = (n + 1) * STATE_STRIDE
  for (let o = STATE_STRIDE; o < end; o += STATE_STRIDE) {
    clampSpeed(state, o, maxAngularSpeed)
    state[o + DPX] += h * state[o + VX]
    state[o + DPY] += h * state[o + VY]
    // Integrate the rotation and renormalize (Box2D v3 b2IntegrateRotation).
    const da = h * state[o + W]
    const c = state[o + DQC]
    const s = state[o + DQS]
    const qc = c - da * s
    const qs = s + da * c
    const mag = Math.sqrt(qc * qc + qs * qs)
    const inv = mag > 0 ? 1 / mag : 0
    state[o + DQC] = qc * inv
    state[o + DQS] = qs * inv
  }
}

/**
 * Brings a body's velocity within the limits after an outside change (an impulse, a set velocity):
 * the direction is kept, a non-finite angular velocity (an impulse of infinite torque both ways)
 * becomes 0. Inputs are finite, but their products with a body's inverse mass may overflow.
 */
export function limitBodyVelocity(b: Body, maxAngularSpeed: number): void {
  let vx = b.vx
  let vy = b.vy
  const big = Math.max(Math.abs(vx), Math.abs(vy))
  if (big > MAX_LINEAR_SPEED) {
    // Normalize by the largest component first so that squaring cannot overflow.
    if (big === Number.POSITIVE_INFINITY) {
      vx = Math.abs(vx) === big ? Math.sign(vx) : 0
      vy = Math.abs(vy) === big ? Math.sign(vy) : 0
    } else {
      vx /= big
      vy /= big
    }
    const scale = MAX_LINEAR_SPEED / Math.sqrt(vx * vx + vy * vy)
    b.vx = vx * scale
    b.vy = vy * scale
  }
  const w = b.w
  if (Number.isNaN(w)) b.w = 0
  else b.w = Math.max(-maxAngularSpeed, Math.min(w, maxAngularSpeed))
}

/** Copies a body's solver state into its fields (static bodies have none). */
export function stateToBody(state: Float64Array, b: Body): void {
  if (b.solverIndex < 0) return
  const o = stateOffset(b)
  b.vx = state[o + VX]
  b.vy = state[o + VY]
  b.w = state[o + W]
  b.dpx = state[o + DPX]
  b.dpy = state[o + DPY]
  b.dqc = state[o + DQC]
  b.dqs = state[o + DQS]
}
