/*
 * The solver state of awake bodies: velocities and sub-step deltas packed in one Float64Array
 * (STATE_STRIDE numbers per body; slot 0 is a static, never-moving state shared by static bodies),
 * and the sub-step integrators that run over it (Box2D v3's b2BodyState and b2IntegrateVelocities /
 * b2IntegratePositions). Joints work on Body fields, so the states of jointed bodies are copied
 * into their Body objects around each joint stage; that costs a few numbers per joint.
 */
import { type Body, DYNAMIC } from './body.ts'
import { STATE_STRIDE } from './contact-solver.ts'
import type { Joint } from './joint.ts'
import type { StepContext } from './step-context.ts'
import { MAX_LINEAR_SPEED } from './world-store.ts'

/** Copies awake bodies' velocities into the solver state (grown if needed) with zero deltas. */
export function loadSolverStates(awake: Body[], n: number, state: Float64Array): Float64Array {
  if (state.length < (n + 1) * STATE_STRIDE) state = new Float64Array((n + 1) * 2 * STATE_STRIDE)
  state.fill(0, 0, STATE_STRIDE)
  state[5] = 1
  for (let i = 0; i < n; i++) {
    const b = awake[i]
    const o = (i + 1) * STATE_STRIDE
    state[o] = b.vx
    state[o + 1] = b.vy
    state[o + 2] = b.w
    state[o + 3] = 0
    state[o + 4] = 0
    state[o + 5] = 1
    state[o + 6] = 0
  }
  return state
}

/** Copies the solver state of the jointed awake bodies into their Body fields. */
export function statesToJointBodies(state: Float64Array, joints: Joint[], count: number): void {
  for (let i = 0; i < count; i++) {
    stateToBody(state, joints[i].bodyA)
    stateToBody(state, joints[i].bodyB)
  }
}

/** Copies the jointed bodies' Body fields back into the solver state. */
export function jointBodiesToStates(state: Float64Array, joints: Joint[], count: number): void {
  for (let i = 0; i < count; i++) {
    bodyToState(state, joints[i].bodyA)
    bodyToState(state, joints[i].bodyB)
  }
}

/** Gravity and damping for awake dynamic bodies over one sub-step, semi-implicit Euler. */
export function integrateVelocities(awake: Body[], n: number, state: Float64Array, ctx: StepContext): void {
  const h = ctx.h
  const gx = ctx.gravityX * h
  const gy = ctx.gravityY * h
  const maxAngularSpeed = (0.25 * Math.PI) / h
  for (let i = 0; i < n; i++) {
    const b = awake[i]
    if (b.type !== DYNAMIC) continue
    const o = (i + 1) * STATE_STRIDE
    let vx = state[o]
    let vy = state[o + 1]
    let w = state[o + 2]
    if (b.linearDamping > 0) {
      const damp = 1 / (1 + h * b.linearDamping)
      vx *= damp
      vy *= damp
    }
    if (b.angularDamping > 0) w *= 1 / (1 + h * b.angularDamping)
    vx += b.gravityScale * gx
    vy += b.gravityScale * gy
    const speedSquared = vx * vx + vy * vy
    if (speedSquared > MAX_LINEAR_SPEED * MAX_LINEAR_SPEED) {
      const scale = MAX_LINEAR_SPEED / Math.sqrt(speedSquared)
      vx *= scale
      vy *= scale
    }
    if (w * w > maxAngularSpeed * maxAngularSpeed) w = w > 0 ? maxAngularSpeed : -maxAngularSpeed
    state[o] = vx
    state[o + 1] = vy
    state[o + 2] = w
  }
}

/** Accumulates the sub-step position and rotation deltas of n awake bodies. */
export function integratePositions(state: Float64Array, n: number, ctx: StepContext): void {
  const h = ctx.h
  const end = (n + 1) * STATE_STRIDE
  for (let o = STATE_STRIDE; o < end; o += STATE_STRIDE) {
    state[o + 3] += h * state[o]
    state[o + 4] += h * state[o + 1]
    // Integrate the rotation and renormalize (Box2D v3 b2IntegrateRotation).
    const da = h * state[o + 2]
    const c = state[o + 5]
    const s = state[o + 6]
    const qc = c - da * s
    const qs = s + da * c
    const mag = Math.sqrt(qc * qc + qs * qs)
    const inv = mag > 0 ? 1 / mag : 0
    state[o + 5] = qc * inv
    state[o + 6] = qs * inv
  }
}

/** Copies a body's solver state into its fields (static bodies have none). */
export function stateToBody(state: Float64Array, b: Body): void {
  if (b.solverIndex < 0) return
  const o = (b.solverIndex + 1) * STATE_STRIDE
  b.vx = state[o]
  b.vy = state[o + 1]
  b.w = state[o + 2]
  b.dpx = state[o + 3]
  b.dpy = state[o + 4]
  b.dqc = state[o + 5]
  b.dqs = state[o + 6]
}

/** Copies a body's fields into its solver state. */
export function bodyToState(state: Float64Array, b: Body): void {
  if (b.solverIndex < 0) return
  const o = (b.solverIndex + 1) * STATE_STRIDE
  state[o] = b.vx
  state[o + 1] = b.vy
  state[o + 2] = b.w
  state[o + 3] = b.dpx
  state[o + 4] = b.dpy
  state[o + 5] = b.dqc
  state[o + 6] = b.dqs
}
