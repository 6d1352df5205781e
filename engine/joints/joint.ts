/*
 * Joints: constraints between two bodies (or a body and the fixed world), solved in the same
 * soft-step stages as contacts (Box2D v3 joint.c): prepare once per step, then in each sub-step
 * warm start, solve with bias, and relax without bias.
 *
 * One Joint class holds the fields of every kind so that all joints share one hidden class; the
 * kind-specific math lives in revolute-joint.ts, distance-joint.ts, mouse-joint.ts, weld-joint.ts,
 * prismatic-joint.ts, wheel-joint.ts and motor-joint.ts, and the helpers they share in
 * joint-math.ts (which imports no kind, so no run-time import cycle remains). Anchors are
 * stored relative to each body's origin in the body frame (localAnchorA/B); each step they are
 * rotated into world-oriented arms from the centre of mass (anchorA/B), and the sub-step deltas of
 * the bodies update the constraint error without running any geometry again.
 */

import { MAX_LINEAR_SPEED, MAX_ROTATION } from '../constants.ts'
import { type Body, stateOffset } from '../dynamics/index.ts'
import { prepareDistance, solveDistance, warmStartDistance } from './distance-joint.ts'
import { DISTANCE, type JointStepContext, MOTOR, MOUSE, PRISMATIC, REVOLUTE, WELD } from './joint-math.ts'
import { prepareMotor, solveMotor, warmStartMotor } from './motor-joint.ts'
import { prepareMouse, solveMouse, warmStartMouse } from './mouse-joint.ts'
import { preparePrismatic, solvePrismatic, warmStartPrismatic } from './prismatic-joint.ts'
import { prepareRevolute, solveRevolute, warmStartRevolute } from './revolute-joint.ts'
import { prepareWeld, solveWeld, warmStartWeld } from './weld-joint.ts'
import { prepareWheel, solveWheel, warmStartWheel } from './wheel-joint.ts'

export {
  accumulateX,
  accumulateY,
  clampImpulse,
  DISTANCE,
  JOINT_TYPE_NAMES,
  type JointStepContext,
  MOTOR,
  MOUSE,
  PRISMATIC,
  REVOLUTE,
  relativeAngle,
  solve22,
  solved2,
  system22,
  WELD,
  WHEEL,
} from './joint-math.ts'

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
  // Mouse settings (maxForce is also the motor joint's force cap)
  targetX = 0
  targetY = 0
  maxForce = 0
  // Weld: angular spring (hertz, dampingRatio are its linear spring; 0 Hz = rigid)
  angularHertz = 0
  angularDampingRatio = 0
  // Prismatic and wheel: the axis in body A's frame (unit), translation limits (m), motor force
  localAxisAx = 1
  localAxisAy = 0
  lowerTranslation = 0
  upperTranslation = 0
  maxMotorForce = 0
  /** Spring on the joint's free coordinate (revolute, prismatic, wheel; a distance spring is hertz > 0). */
  enableSpring = false
  /** Where the spring rests: prismatic translation (m) or revolute angle (rad). */
  springTarget = 0
  // Motor joint: B's origin in A's frame (m), B's angle relative to A (rad), torque cap, correction
  linearOffsetX = 0
  linearOffsetY = 0
  angularOffset = 0
  maxTorque = 0
  correctionFactor = 0
  /** Motor joint: the offsets at the previous step, whose change gives the offset's velocity. */
  lastOffsetX = 0
  lastOffsetY = 0
  lastAngularOffset = 0
  /** Reaction force (N) and torque (N m) above which the joint breaks after a step. */
  breakForce = Number.POSITIVE_INFINITY
  breakTorque = Number.POSITIVE_INFINITY

  // Accumulated impulses (warm started across steps)
  linearImpulseX = 0
  linearImpulseY = 0
  /** Distance joint: rigid/spring axial impulse (N s). */
  impulse = 0
  lowerImpulse = 0
  upperImpulse = 0
  motorImpulse = 0
  /** Weld, prismatic, motor joint: angular impulse (N m s). */
  angularImpulse = 0
  /** Spring impulse of a revolute (N m s), prismatic or wheel (N s) spring. */
  springImpulse = 0

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
  /** Angular softness (weld). */
  angularBiasRate = 0
  angularMassScale = 1
  angularImpulseScale = 0
  /** Prismatic, wheel: the axis in world orientation at the step start (unit). */
  axisX = 1
  axisY = 0
  /** Wheel: motor mass; motor joint: angular mass (kg m^2). */
  angularMass = 0
  /** Motor joint: velocity of the target point (world, m/s) and of the target angle (rad/s) this step. */
  offsetVelocityX = 0
  offsetVelocityY = 0
  offsetAngularVelocity = 0
  /** Motor joint: sub-steps warm started so far this step. */
  subStep = 0

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
      joint.angularImpulse = 0
      joint.springImpulse = 0
    }
    const type = joint.type
    if (type === REVOLUTE) prepareRevolute(joint, ctx)
    else if (type === DISTANCE) prepareDistance(joint, state, ctx)
    else if (type === MOUSE) prepareMouse(joint, ctx)
    else if (type === WELD) prepareWeld(joint, ctx)
    else if (type === PRISMATIC) preparePrismatic(joint, ctx)
    else if (type === MOTOR) prepareMotor(joint)
    else prepareWheel(joint, ctx)
  }
}

/** Applies every joint's accumulated impulses to the solver state. */
export function warmStartJoints(joints: Joint[], count: number, state: Float64Array): void {
  for (let i = 0; i < count; i++) {
    const joint = joints[i]
    const type = joint.type
    if (type === REVOLUTE) warmStartRevolute(joint, state)
    else if (type === DISTANCE) warmStartDistance(joint, state)
    else if (type === MOUSE) warmStartMouse(joint, state)
    else if (type === WELD) warmStartWeld(joint, state)
    else if (type === PRISMATIC) warmStartPrismatic(joint, state)
    else if (type === MOTOR) warmStartMotor(joint, state)
    else warmStartWheel(joint, state)
  }
}

/**
 * One iteration over the joints; `useBias` corrects position error, false is the relax pass.
 * Gauss-Seidel in id order, then the pins of the joint tree all at once (joint-tree.ts).
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
    const type = joint.type
    if (type === REVOLUTE) solveRevolute(joint, state, ctx, useBias)
    else if (type === DISTANCE) solveDistance(joint, state, ctx, useBias)
    else if (type === MOUSE) solveMouse(joint, state, ctx)
    else if (type === WELD) solveWeld(joint, state, useBias)
    else if (type === PRISMATIC) solvePrismatic(joint, state, ctx, useBias)
    else if (type === MOTOR) solveMotor(joint, state, ctx, useBias)
    else solveWheel(joint, state, ctx, useBias)
  }
}
