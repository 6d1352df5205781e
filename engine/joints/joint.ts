/*
 * Joints: constraints between two bodies (or a body and the fixed world), solved in the same
 * soft-step stages as contacts (Box2D v3 joint.c): prepare once per step, then in each sub-step
 * warm start, solve with bias, and relax without bias.
 *
 * One Joint class holds the fields of every kind so that all joints share one hidden class; the
 * kind-specific math lives in revolute-joint.ts, distance-joint.ts and mouse-joint.ts. Anchors are
 * stored relative to each body's origin in the body frame (localAnchorA/B); each step they are
 * rotated into world-oriented arms from the centre of mass (anchorA/B), and the sub-step deltas of
 * the bodies update the constraint error without running any geometry again.
 */

import { MAX_LINEAR_SPEED, MAX_ROTATION } from '../constants.ts'
import { type Body, type StepContext, stateOffset } from '../dynamics/index.ts'
import { prepareDistance, solveDistance, warmStartDistance } from './distance-joint.ts'
import { DISTANCE, REVOLUTE } from './joint-math.ts'
import { prepareMouse, solveMouse, warmStartMouse } from './mouse-joint.ts'
import { prepareRevolute, solveRevolute, warmStartRevolute } from './revolute-joint.ts'

/** Per-step values the joints read (the solver's StepContext). */
export type JointStepContext = StepContext

/** A joint. Engine-internal; the public API addresses joints by id. */
export class Joint {
  readonly id: number
  readonly type: number
  readonly bodyA: Body
  readonly bodyB: Body
  /** Anchors in each body's frame, relative to the body origin (m). */
  localAnchorAx = 0
  localAnchorAy = 0
  localAnchorBx = 0
  localAnchorBy = 0
  /** Whether this step's direct tree solver handles the point constraint (joint-tree.ts). */
  inTree = false
  /** Whether the two bodies collide with each other (Box2D's collideConnected). */
  collideConnected = false
  /** Revolute: angleB - angleA at creation (rad). */
  referenceAngle = 0
  // Revolute settings
  enableLimit = false
  lowerAngle = 0
  upperAngle = 0
  enableMotor = false
  motorSpeed = 0
  maxMotorTorque = 0
  // Distance settings
  length = 0
  minLength = 0
  maxLength = 0
  hertz = 0
  dampingRatio = 0
  // Mouse settings
  targetX = 0
  targetY = 0
  maxForce = 0

  // Accumulated impulses (warm started across steps)
  linearImpulseX = 0
  linearImpulseY = 0
  /** Distance joint: rigid/spring axial impulse (N s). */
  impulse = 0
  lowerImpulse = 0
  upperImpulse = 0
  motorImpulse = 0

  // Per-step solver data
  /** Offsets of the bodies' records in the solver state (record 0 for a fixed body). */
  offsetA = 0
  offsetB = 0
  /** Caps on the accumulated linear (N s) and angular (N m s) impulses (see jointImpulseCaps). */
  maxImpulse = 0
  maxAngularImpulse = 0
  anchorAx = 0
  anchorAy = 0
  anchorBx = 0
  anchorBy = 0
  deltaCenterX = 0
  deltaCenterY = 0
  deltaAngle = 0
  axialMass = 0
  /** Spring softness (distance spring, mouse). */
  springBiasRate = 0
  springMassScale = 1
  springImpulseScale = 0

  constructor(id: number, type: number, bodyA: Body, bodyB: Body) {
    this.id = id
    this.type = type
    this.bodyA = bodyA
    this.bodyB = bodyB
  }

  /** The other body of the joint. */
  other(body: Body): Body {
    return body === this.bodyA ? this.bodyB : this.bodyA
  }
}

/** Computes world arms from the centres of mass and the step-start centre offset. */
export function prepareAnchors(joint: Joint): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const lax = joint.localAnchorAx - a.localCenterX
  const lay = joint.localAnchorAy - a.localCenterY
  const lbx = joint.localAnchorBx - b.localCenterX
  const lby = joint.localAnchorBy - b.localCenterY
  joint.anchorAx = a.c * lax - a.s * lay
  joint.anchorAy = a.s * lax + a.c * lay
  joint.anchorBx = b.c * lbx - b.s * lby
  joint.anchorBy = b.s * lbx + b.c * lby
  joint.deltaCenterX = b.cx - a.cx
  joint.deltaCenterY = b.cy - a.cy
}

/**
 * Caps on a joint's accumulated impulses, so that no request (anchors hundreds of metres away,
 * constraints that fight each other, a rod that cannot reach) can wind an impulse up without bound
 * until it overflows: an impulse that would change both bodies' velocities by twice the speed
 * limit is never needed (2 MAX_LINEAR_SPEED (mA + mB); the same about the bodies' extents, plus
 * twice the spin limit for the inertias, for angular impulses). A joint holding a load sees
 * m g h per sub-step: the cap is 19,200 times the two bodies' mass, far above any load a joint can
 * carry stably (the chain blows up above about 2,000:1, see joint-tree.ts).
 */
function jointImpulseCaps(joint: Joint, ctx: JointStepContext): void {
  const a = joint.bodyA
  const b = joint.bodyB
  const mass = (a.invMass > 0 ? a.mass : 0) + (b.invMass > 0 ? b.mass : 0)
  const inertia = (a.invInertia > 0 ? a.inertia : 0) + (b.invInertia > 0 ? b.inertia : 0)
  joint.maxImpulse = 2 * MAX_LINEAR_SPEED * mass
  joint.maxAngularImpulse =
    joint.maxImpulse * (a.maxExtent + b.maxExtent) + 2 * MAX_ROTATION * ctx.invH * inertia
}

/** Prepares every joint for the step (after the solver state is loaded: it records offsets). */
export function prepareJoints(
  joints: Joint[],
  count: number,
  state: Float64Array,
  ctx: JointStepContext,
): void {
  for (let i = 0; i < count; i++) {
    const joint = joints[i]
    prepareAnchors(joint)
    joint.offsetA = stateOffset(joint.bodyA)
    joint.offsetB = stateOffset(joint.bodyB)
    jointImpulseCaps(joint, ctx)
    if (!ctx.enableWarmStarting) {
      joint.linearImpulseX = 0
      joint.linearImpulseY = 0
      joint.impulse = 0
      joint.lowerImpulse = 0
      joint.upperImpulse = 0
      joint.motorImpulse = 0
    }
    if (joint.type === REVOLUTE) prepareRevolute(joint)
    else if (joint.type === DISTANCE) prepareDistance(joint, state, ctx)
    else prepareMouse(joint, ctx)
  }
}

/** Applies every joint's accumulated impulses to the solver state. */
export function warmStartJoints(joints: Joint[], count: number, state: Float64Array): void {
  for (let i = 0; i < count; i++) {
    const joint = joints[i]
    if (joint.type === REVOLUTE) warmStartRevolute(joint, state)
    else if (joint.type === DISTANCE) warmStartDistance(joint, state)
    else warmStartMouse(joint, state)
  }
}

/**
 * One iteration over the joints; `useBias` corrects position error, false is the relax pass.
 * Gauss-Seidel in id order; the pins of the joint tree are then solved at once (joint-tree.ts).
 */
export function solveJoints(
  joints: Joint[],
  count: number,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
): void {
  for (let i = 0; i < count; i++) {
    const joint = joints[i]
    if (joint.type === REVOLUTE) solveRevolute(joint, state, ctx, useBias)
    else if (joint.type === DISTANCE) solveDistance(joint, state, ctx, useBias)
    else solveMouse(joint, state, ctx)
  }
}
