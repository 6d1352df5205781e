/*
 * The engine's public definitions: what callers pass in (definitions with defaults, like Box2D's
 * b2DefaultBodyDef) and what they read back. The World class implements these.
 */

import type { ChainShape, Shape } from './collision/index.ts'
import type { Vec2 } from './math.ts'

/** Opaque body id: handed out in creation order from 1, never reused within a world. */
export type BodyId = number
/** Opaque joint id: handed out in creation order from 1, never reused within a world. */
export type JointId = number
/** Opaque shape id: handed out in creation order from 1, never reused within a world. */
export type ShapeId = number

/**
 * Box2D's collision filter: two shapes of the same non-zero group collide if the group is positive
 * and never if it is negative; otherwise they collide when each one's category is in the other's mask.
 */
export interface Filter {
  /** The categories this shape is in: an unsigned 32-bit mask, usually 1. */
  categoryBits: number
  /** The categories this shape collides with: an unsigned 32-bit mask, usually 0xffffffff (all). */
  maskBits: number
  /**
   * Shapes of the same non-zero group always collide (positive) or never collide (negative),
   * whatever their masks; usually 0 (no group). An integer in [-2^31, 2^31).
   */
  groupIndex: number
}

/** A shape to attach to a body, with its material, filter and flags; only `shape` is required. */
export interface ShapeDef {
  /**
   * The geometry in the body's frame: circle(), box(), polygon(), capsule(), segment(), or chain()
   * (static bodies only; one shape per segment, with consecutive ids, all with this definition's
   * material, filter and flags).
   */
  shape: Shape | ChainShape
  /** Density (kg/m^2), usually 1 (the body definition's `density` if given). */
  density?: number
  /** Coulomb friction, usually 0.6 (the body definition's if given); pairs mix by sqrt(a b). */
  friction?: number
  /** Restitution 0..1, usually 0 (the body definition's if given); pairs mix by max(a, b). */
  restitution?: number
  /**
   * Rolling resistance (non-dimensional, Box2D v3.1), usually 0: a pair resists relative spin with a
   * torque of at most max(a, b) x the larger shape radius x the normal force.
   */
  rollingResistance?: number
  /**
   * Surface speed (m/s) along the right perpendicular of the outward normal, Box2D's convention
   * (clockwise round the outline: on a box's top face +x): a conveyor belt; usually 0. Friction
   * drives the pair to the sum of the two shapes' speeds.
   */
  tangentSpeed?: number
  /** Collision filter; usually category 1, every mask bit, group 0. */
  filter?: Filter
  /** Detects overlap (sensorEvents) and never pushes, usually false. */
  sensor?: boolean
  /** Whether sensors see this shape, usually true. */
  enableSensorEvents?: boolean
  /** Begin and end contact events for this shape, usually true. */
  enableContactEvents?: boolean
  /** Hit events (impacts faster than 1 m/s) for this shape, usually false. */
  enableHitEvents?: boolean
}

/** How a body moves: static never moves, kinematic moves by its velocity only, dynamic by forces. */
export type BodyType = 'static' | 'kinematic' | 'dynamic'

/** World settings; every field has a default (see DEFAULT_WORLD_DEF). */
export interface WorldDef {
  /** Gravity (m/s^2), usually (0, -10). */
  gravity?: Vec2
  /** Solver sub-steps per 1/60 s step, usually 4. */
  subSteps?: number
  /** Allow islands to fall asleep, usually true. */
  enableSleep?: boolean
  /** Continuous collision for bullets and fast bodies, usually true. */
  enableContinuous?: boolean
  /** Contact stiffness (Hz), usually 30; clamped to a quarter of the sub-step rate. */
  contactHertz?: number
  /** Contact damping ratio (non-dimensional), usually 10. */
  contactDampingRatio?: number
  /** Fastest speed at which overlap is pushed apart (m/s), usually 3. */
  maxContactPushSpeed?: number
  /** Relative normal speed below which restitution is ignored (m/s), usually 1. */
  restitutionThreshold?: number
  /** Speed below which a body counts as resting (m/s), usually 0.05. */
  sleepThreshold?: number
  /** How long an island must rest before it sleeps (s), usually 0.5. */
  timeToSleep?: number
}

/**
 * A body definition with one shape; everything but `shape` is optional. CompoundBodyDef gives
 * `shapes` instead.
 */
export interface BodyDef {
  /** Usually 'dynamic'. */
  type?: BodyType
  /** World position of the body origin (m). */
  position?: Vec2
  /** Rotation (rad). */
  angle?: number
  /**
   * The rotation as its exact (cos, sin) pair, which wins over `angle` (Box2D v3.1's b2Rot in
   * b2BodyDef): getBodyDef reads it back, so a body saved and recreated has the very same rotation
   * (atan2 and cos/sin do not round-trip bit for bit). Its length must be 1 within 1e-6.
   */
  rotation?: { c: number; s: number }
  /** Velocity of the centre of mass (m/s). */
  linearVelocity?: Vec2
  /** Angular velocity (rad/s). */
  angularVelocity?: number
  /** The body's one shape (shorthand for `shapes: [{ shape, density, friction, restitution }]`); a chain goes in `shapes`. */
  shape: Shape
  /** Density (kg/m^2) of the shapes that give none, usually 1. */
  density?: number
  /** Coulomb friction coefficient of the shapes that give none, usually 0.6; pairs mix by sqrt(a*b). */
  friction?: number
  /** Restitution (bounciness) 0..1 of the shapes that give none, usually 0; pairs mix by max(a, b). */
  restitution?: number
  /** Linear damping (1/s), usually 0. */
  linearDamping?: number
  /** Angular damping (1/s), usually 0. */
  angularDamping?: number
  /** Multiplier on world gravity, usually 1. */
  gravityScale?: number
  /** Continuous collision against dynamic bodies as well as static ones, usually false. */
  bullet?: boolean
  /** Start awake, usually true. */
  awake?: boolean
  /** May this body sleep, usually true. */
  enableSleep?: boolean
  /** Never rotates (infinite inertia), usually false. */
  fixedRotation?: boolean
}

/**
 * A joint's frames exactly as the engine keeps them: each anchor in its body's frame (m, from the
 * body origin; the world frame for a null body), angleB - angleA at creation (rad), and for
 * prismatic and wheel joints the axis in A's frame (unit). Given in a definition, they win over the
 * world anchors, the current angle and the world axis, so getJointDef's read-back recreates a joint
 * bit for bit on bodies posed as they are now, whatever has moved since the joint was made.
 */
export interface JointFrames {
  localAnchorA: Vec2
  localAnchorB: Vec2
  /** Revolute, weld, prismatic, wheel; 0 (ignored) for distance joints. */
  referenceAngle: number
  /** Prismatic, wheel: the axis in body A's frame, unit length within 1e-6. */
  localAxisA?: Vec2
}

/** Settings every joint definition has. */
export interface JointBreakDef {
  /** Reaction force (N) above which the joint breaks after a step; usually Infinity (never). */
  breakForce?: number
  /** Reaction torque (N m) above which the joint breaks after a step; usually Infinity (never). */
  breakTorque?: number
}

/**
 * A body definition with any number of shapes (a compound body): BodyDef with `shapes` in place of
 * `shape`. Its `density`, `friction` and `restitution` are the defaults of shapes that give none.
 */
export interface CompoundBodyDef extends Omit<BodyDef, 'shape'> {
  shape?: undefined
  /** The body's shapes, in order (their ids are handed out in this order), 1 to 1,024. */
  shapes: ShapeDef[]
}

/** An explosion for World.explode (Box2D v3.1's b2ExplosionDef). */
export interface ExplosionDef {
  /** Centre (world, m). */
  position: Vec2
  /** Shapes within this distance get the full impulse (m). */
  radius: number
  /** Beyond the radius the impulse falls linearly to 0 over this distance (m), usually 0. */
  falloff?: number
  /** Impulse per metre of a shape's width across the blast direction (N s/m); negative pulls in. */
  impulsePerLength: number
  /** Categories affected (unsigned 32-bit), usually all. */
  maskBits?: number
}

/** Revolute (pin) joint: bodies share a world anchor point and rotate about it. */
export interface RevoluteJointDef extends JointBreakDef {
  type: 'revolute'
  /** First body, or null for the fixed world frame. */
  bodyA: BodyId | null
  bodyB: BodyId
  /** Exact frames (getJointDef's read-back); when given they win over the world anchors and axis. */
  frames?: JointFrames
  /** World anchor at creation (m). */
  anchor: Vec2
  /** Whether the two bodies collide with each other, usually false (the pin lies inside both). */
  collideConnected?: boolean
  enableLimit?: boolean
  /** Lower and upper limits of angleB - angleA relative to creation (rad). */
  lowerAngle?: number
  upperAngle?: number
  enableMotor?: boolean
  /** Target relative angular speed (rad/s). */
  motorSpeed?: number
  /** Largest torque the motor applies (N m). */
  maxMotorTorque?: number
  /** A rotational spring toward targetAngle, usually false. */
  enableSpring?: boolean
  /** Spring stiffness (Hz) against the joint's angular mass, and damping ratio (usually 0.7). */
  hertz?: number
  dampingRatio?: number
  /** Angle the spring pulls toward (rad, relative to creation), usually 0. */
  targetAngle?: number
}

/** Distance joint: a rod, a rope (minLength 0), or a soft spring (hertz > 0). */
export interface DistanceJointDef extends JointBreakDef {
  type: 'distance'
  bodyA: BodyId | null
  bodyB: BodyId
  /** Exact frames (getJointDef's read-back); when given they win over the world anchors and axis. */
  frames?: JointFrames
  /** World anchors at creation (m). */
  anchorA: Vec2
  anchorB: Vec2
  /** Whether the two bodies collide with each other, usually true (a rope never lets them pass through). */
  collideConnected?: boolean
  /** Rest length (m); defaults to the anchors' current distance. */
  length?: number
  /** Limits on the length (m); a rope is minLength 0, maxLength = length. */
  minLength?: number
  maxLength?: number
  /** Spring stiffness (Hz); 0 means rigid. */
  hertz?: number
  /** Spring damping ratio, usually 0.7 when hertz > 0. */
  dampingRatio?: number
  /** A motor along the axis (on a spring or a rope), usually false. */
  enableMotor?: boolean
  /** Target rate of change of the length (m/s). */
  motorSpeed?: number
  /** Largest force the motor applies (N). */
  maxMotorForce?: number
}

/** Mouse (grab) joint: pulls a point on a body toward a moving target with a capped force. */
export interface MouseJointDef extends JointBreakDef {
  type: 'mouse'
  body: BodyId
  /** World target (m). */
  target: Vec2
  /** Grabbed point in the body's local frame (m); defaults to the target's local point. */
  localAnchor?: Vec2
  /** Largest force (N); defaults to 1000 * mass * |gravity or 10|. */
  maxForce?: number
  /** Stiffness (Hz), usually 5. */
  hertz?: number
  /** Damping ratio, usually 0.7. */
  dampingRatio?: number
}

/** Weld joint: B is glued to A at the anchor (rigid at 0 Hz, a spring otherwise). */
export interface WeldJointDef extends JointBreakDef {
  type: 'weld'
  bodyA: BodyId | null
  bodyB: BodyId
  /** Exact frames (getJointDef's read-back); when given they win over the world anchors and axis. */
  frames?: JointFrames
  /** World anchor at creation (m). */
  anchor: Vec2
  /** Usually false. */
  collideConnected?: boolean
  /** Stiffness of the point (linear) and angle (angular) constraints (Hz), usually 0 = rigid. */
  linearHertz?: number
  angularHertz?: number
  /** Damping ratios of the two springs, usually 1. */
  linearDampingRatio?: number
  angularDampingRatio?: number
}

/** Prismatic (slider) joint: B slides along an axis fixed in A and keeps its angle to A. */
export interface PrismaticJointDef extends JointBreakDef {
  type: 'prismatic'
  bodyA: BodyId | null
  bodyB: BodyId
  /** Exact frames (getJointDef's read-back); when given they win over the world anchors and axis. */
  frames?: JointFrames
  /** World anchor at creation (m): translation 0 is where the bodies are now. */
  anchor: Vec2
  /** World direction of the axis at creation (any length but zero); fixed in A's frame. */
  axis: Vec2
  /** Usually false. */
  collideConnected?: boolean
  enableLimit?: boolean
  /** Limits on the translation along the axis (m), lower <= 0 <= upper usually. */
  lower?: number
  upper?: number
  enableMotor?: boolean
  /** Target speed along the axis (m/s). */
  motorSpeed?: number
  /** Largest motor force (N). */
  maxMotorForce?: number
  /** A spring along the axis toward targetTranslation, usually false. */
  enableSpring?: boolean
  /** Spring stiffness (Hz, against the joint's axial mass), damping ratio (usually 0.7). */
  hertz?: number
  dampingRatio?: number
  /** Translation the spring pulls toward (m), usually 0. */
  targetTranslation?: number
}

/** Wheel joint: B slides on a sprung axis fixed in A (suspension) and spins freely (motor). */
export interface WheelJointDef extends JointBreakDef {
  type: 'wheel'
  bodyA: BodyId | null
  bodyB: BodyId
  /** Exact frames (getJointDef's read-back); when given they win over the world anchors and axis. */
  frames?: JointFrames
  /** World anchor at creation (m), usually the wheel's centre. */
  anchor: Vec2
  /** World direction of the suspension axis at creation, usually up (0, 1). */
  axis: Vec2
  /** Usually false. */
  collideConnected?: boolean
  /** Suspension spring, usually true, 1 Hz, damping ratio 0.7 (stiffness against the axial mass). */
  enableSpring?: boolean
  hertz?: number
  dampingRatio?: number
  enableLimit?: boolean
  /** Limits on the suspension travel (m). */
  lower?: number
  upper?: number
  enableMotor?: boolean
  /** Target spin of B relative to A (rad/s). */
  motorSpeed?: number
  /** Largest motor torque (N m). */
  maxMotorTorque?: number
}

/** Motor joint: drives B toward an offset pose relative to A with a capped force and torque. */
export interface MotorJointDef extends JointBreakDef {
  type: 'motor'
  bodyA: BodyId | null
  bodyB: BodyId
  /** Target position of B's centre of mass in A's frame (m); defaults to where it is now. */
  linearOffset?: Vec2
  /** Target angle of B relative to A (rad); defaults to the current one. */
  angularOffset?: number
  /** Largest force (N), usually 1; and torque (N m), usually 1. */
  maxForce?: number
  maxTorque?: number
  /** Fraction of the error closed per sub-step (0..1), usually 0.3. */
  correctionFactor?: number
  /** Usually false. */
  collideConnected?: boolean
}

/** Every joint definition. */
export type JointDef =
  | RevoluteJointDef
  | DistanceJointDef
  | MouseJointDef
  | WeldJointDef
  | PrismaticJointDef
  | WheelJointDef
  | MotorJointDef

/**
 * Settings World.setJointSettings changes on an existing joint, by the names its definition uses;
 * each kind takes only its own (RangeError naming any other): revolute enableLimit, lowerAngle,
 * upperAngle, enableMotor, motorSpeed, maxMotorTorque, enableSpring, hertz, dampingRatio,
 * targetAngle; distance length, minLength, maxLength, hertz, dampingRatio, enableMotor, motorSpeed,
 * maxMotorForce; weld linearHertz, angularHertz, linearDampingRatio, angularDampingRatio;
 * prismatic enableLimit, lower, upper, enableMotor, motorSpeed, maxMotorForce, enableSpring, hertz,
 * dampingRatio, targetTranslation; wheel the same with maxMotorTorque for maxMotorForce and no
 * targetTranslation; motor maxForce, maxTorque, correctionFactor; mouse maxForce, hertz,
 * dampingRatio; every kind breakForce and breakTorque. Units and ranges as in the definitions.
 */
export interface JointSettings {
  enableLimit?: boolean
  /** Revolute limits (rad, in [-pi, pi], lower <= upper). */
  lowerAngle?: number
  upperAngle?: number
  /** Prismatic and wheel limits (m, within 1e6, lower <= upper). */
  lower?: number
  upper?: number
  enableMotor?: boolean
  /** rad/s (revolute, wheel) or m/s (prismatic, distance). */
  motorSpeed?: number
  /** N m, in [0, 1e12] (revolute, wheel). */
  maxMotorTorque?: number
  /** N, in [0, 1e12] (prismatic, distance). */
  maxMotorForce?: number
  enableSpring?: boolean
  /** Spring stiffness (Hz, in [0, 1e6]; mouse [0, 1000]) and damping ratio (same range). */
  hertz?: number
  dampingRatio?: number
  /** Revolute spring target (rad, in [-pi, pi]). */
  targetAngle?: number
  /** Prismatic spring target (m, within 1e6). */
  targetTranslation?: number
  /** Distance: rest length (m, [0.001, 1e6]) and limits (0 <= minLength <= length <= maxLength <= 1e6). */
  length?: number
  minLength?: number
  maxLength?: number
  /** Weld springs (Hz, 0 = rigid) and damping ratios, in [0, 1e6]. */
  linearHertz?: number
  angularHertz?: number
  linearDampingRatio?: number
  angularDampingRatio?: number
  /** Mouse and motor joints: force cap (N); motor joint: torque cap (N m), both in [0, 1e12]. */
  maxForce?: number
  maxTorque?: number
  /** Motor joint: fraction of the error closed per sub-step, in [0, 1]. */
  correctionFactor?: number
  /** Break thresholds (N, N m), >= 0; Infinity never breaks. */
  breakForce?: number
  breakTorque?: number
}

/** What a joint was doing during the last step: which joints broke. */
export interface JointEvents {
  /** Joints that broke in the last step (reaction above breakForce or breakTorque), ascending ids. */
  broken: JointId[]
}

/** A touching contact, for drawing and for the free-body diagram. */
export interface ContactInfo {
  bodyA: BodyId
  bodyB: BodyId
  /** The touching shapes (shapeA on bodyA, shapeB on bodyB; shapeA < shapeB). */
  shapeA: ShapeId
  shapeB: ShapeId
  /** World unit normal from A to B. */
  normal: Vec2
  points: Array<{
    /** World point (m). */
    point: Vec2
    /** Negative when overlapping (m). */
    separation: number
    /** Total normal impulse over the last step, all sub-steps (N s); divided by 1/60 s it is the force (N). */
    normalImpulse: number
    /** Total friction impulse along the tangent (normal.y, -normal.x) over the last step (N s). */
    tangentImpulse: number
  }>
}

/** A joint's state, for drawing. */
export interface JointInfo {
  id: JointId
  type: JointDef['type']
  bodyA: BodyId | null
  bodyB: BodyId
  /** Current world anchors (m); for a mouse joint anchorA is the target. */
  anchorA: Vec2
  anchorB: Vec2
  /** Whether the two bodies collide with each other (a mouse joint's world frame never collides). */
  collideConnected: boolean
  /** Reaction force on body B in the last step, applied at anchorB (N); body A gets -force at anchorA. */
  force: Vec2
  /** Reaction torque on body B in the last step, besides the force's moment (N m); body A gets -torque. */
  torque: number
  /** Prismatic, wheel: the axis now (world, unit). */
  axis?: Vec2
  /** Limits when enabled: translation (m) for prismatic and wheel, angle (rad) for revolute. */
  lower?: number
  upper?: number
  /** Prismatic, wheel: translation along the axis (m); distance: the length (m). */
  translation?: number
  /** Revolute, weld, prismatic, wheel, motor: angleB - angleA relative to the reference (rad). */
  angle?: number
}

/** The force and torque a joint applied over the last step (mean over its sub-steps). */
export interface JointReaction {
  /** Force on body B at anchorB (N); body A gets -force at anchorA. */
  force: Vec2
  /** Pure torque on body B (N m), besides the force's moment; body A gets -torque. */
  torque: number
}
