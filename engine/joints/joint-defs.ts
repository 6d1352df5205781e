/*
 * Joints from their public definitions, and joints back to their public read-back (JointInfo).
 * Every value of a definition is checked here, with a RangeError naming it, before the joint
 * reaches the solver. Anchors are given in world space at creation and stored in each body's frame.
 */

import { angle, finite, finiteVec, inRange } from '../def-checks.ts'
import type { Body } from '../dynamics/index.ts'
import { atan2, type Vec2 } from '../math.ts'
import type { BodyId, JointDef, JointFrames, JointInfo, JointReaction } from '../types.ts'
import { Joint } from './joint.ts'
import {
  DISTANCE,
  JOINT_TYPE_NAMES,
  MOTOR,
  MOUSE,
  PRISMATIC,
  REVOLUTE,
  relativeAngle,
  unwind,
  WELD,
  WHEEL,
} from './joint-math.ts'

/**
 * Builds joint `id` from a definition. `bodyOf` resolves (or rejects) body ids, `ground` is the
 * fixed world frame for `bodyA: null`, and `gravity` (m/s^2) scales the mouse joint's default
 * force cap (1000 m |g|).
 */
export function buildJoint(
  def: JointDef,
  id: number,
  bodyOf: (id: BodyId) => Body,
  ground: Body,
  gravity: number,
): Joint {
  if (def.type === 'mouse') {
    const b = bodyOf(def.body)
    const target = finiteVec('target', def.target)
    const joint = new Joint(id, MOUSE, ground, b)
    configureBreak(joint, def)
    const local = reach(
      'localAnchor',
      b,
      def.localAnchor ? finiteVec('localAnchor', def.localAnchor) : localPoint(b, target),
    )
    joint.localAnchorBx = local.x
    joint.localAnchorBy = local.y
    joint.targetX = target.x
    joint.targetY = target.y
    joint.maxForce = inRange('maxForce', def.maxForce ?? 1000 * b.mass * gravity, 0, 1e12)
    joint.hertz = inRange('hertz', def.hertz ?? 5, 0, 1000)
    joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? 0.7, 0, 1000)
    return joint
  }
  const a = def.bodyA === null ? ground : bodyOf(def.bodyA)
  const b = bodyOf(def.bodyB)
  if (a === b) throw new RangeError(`a joint needs two different bodies, got ${b.id} twice`)
  const joint = new Joint(id, KIND_CODES[def.type], a, b)
  configureBreak(joint, def)
  if (def.type === 'motor') {
    configureMotor(joint, def)
    return joint
  }
  const anchorA = finiteVec('anchor', def.type === 'distance' ? def.anchorA : def.anchor)
  const anchorB = def.type === 'distance' ? finiteVec('anchorB', def.anchorB) : anchorA
  // A pin, weld or slider usually lies inside both bodies, so they must not collide; a rope, rod
  // or spring keeps its bodies apart only along its axis, so they collide like any two bodies.
  joint.collideConnected = flag('collideConnected', def.collideConnected, def.type === 'distance')
  const nameA = def.type === 'distance' ? 'anchorA' : 'anchor'
  const la = reach(nameA, a, localPoint(a, anchorA))
  const lb = reach(def.type === 'distance' ? 'anchorB' : 'anchor', b, localPoint(b, anchorB))
  joint.localAnchorAx = la.x
  joint.localAnchorAy = la.y
  joint.localAnchorBx = lb.x
  joint.localAnchorBy = lb.y
  // angleB - angleA now; a distance joint has none (its saved field stays 0).
  if (def.type !== 'distance') joint.referenceAngle = atan2(b.s * a.c - b.c * a.s, b.c * a.c + b.s * a.s)
  if (def.type === 'revolute') configureRevolute(joint, def)
  else if (def.type === 'distance') configureDistance(joint, def, anchorA, anchorB)
  else if (def.type === 'weld') configureWeld(joint, def)
  else configureSlider(joint, def)
  if (def.frames !== undefined) applyFrames(joint, def.frames, a, b)
  return joint
}

/** Exact frames from a definition (JointFrames: getJointDef's read-back) over the computed ones. */
function applyFrames(joint: Joint, frames: JointFrames, a: Body, b: Body): void {
  if (frames === null || typeof frames !== 'object')
    throw new RangeError(`frames must be an object, got ${frames}`)
  const la = reach('frames.localAnchorA', a, finiteVec('frames.localAnchorA', frames.localAnchorA))
  const lb = reach('frames.localAnchorB', b, finiteVec('frames.localAnchorB', frames.localAnchorB))
  joint.localAnchorAx = la.x
  joint.localAnchorAy = la.y
  joint.localAnchorBx = lb.x
  joint.localAnchorBy = lb.y
  if (joint.type !== DISTANCE) joint.referenceAngle = angle('frames.referenceAngle', frames.referenceAngle)
  if (joint.type !== PRISMATIC && joint.type !== WHEEL) return
  if (frames.localAxisA === undefined) return
  const axis = finiteVec('frames.localAxisA', frames.localAxisA)
  if (!(Math.abs(axis.x * axis.x + axis.y * axis.y - 1) <= 1e-6))
    throw new RangeError(`frames.localAxisA must be a unit vector, got (${axis.x}, ${axis.y})`)
  joint.localAxisAx = axis.x
  joint.localAxisAy = axis.y
}

/**
 * A joint's definition as it stands (settings changed since creation included), with its exact
 * frames: createJoint of it, on bodies posed as they are now, makes the same joint bit for bit.
 * Break thresholds that never break (Infinity) are left out.
 */
export function jointDef(j: Joint): JointDef {
  const type = JOINT_TYPE_NAMES[j.type] as JointDef['type']
  const bodyA = j.bodyA.id === 0 ? null : j.bodyA.id
  const bodyB = j.bodyB.id
  const anchorA = worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
  const anchorB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
  const frames: JointFrames = {
    localAnchorA: { x: j.localAnchorAx, y: j.localAnchorAy },
    localAnchorB: { x: j.localAnchorBx, y: j.localAnchorBy },
    referenceAngle: j.referenceAngle,
  }
  const brk: { breakForce?: number; breakTorque?: number } = {}
  if (j.breakForce !== Number.POSITIVE_INFINITY) brk.breakForce = j.breakForce
  if (j.breakTorque !== Number.POSITIVE_INFINITY) brk.breakTorque = j.breakTorque
  const collideConnected = j.collideConnected
  switch (type) {
    case 'revolute':
      return {
        type,
        bodyA,
        bodyB,
        anchor: anchorB,
        frames,
        collideConnected,
        enableLimit: j.enableLimit,
        lowerAngle: j.lowerAngle,
        upperAngle: j.upperAngle,
        enableMotor: j.enableMotor,
        motorSpeed: j.motorSpeed,
        maxMotorTorque: j.maxMotorTorque,
        enableSpring: j.enableSpring,
        hertz: j.hertz,
        dampingRatio: j.dampingRatio,
        targetAngle: j.springTarget,
        ...brk,
      }
    case 'distance':
      return {
        type,
        bodyA,
        bodyB,
        anchorA,
        anchorB,
        frames,
        collideConnected,
        length: j.length,
        minLength: j.minLength,
        maxLength: j.maxLength,
        hertz: j.hertz,
        dampingRatio: j.dampingRatio,
        enableMotor: j.enableMotor,
        motorSpeed: j.motorSpeed,
        maxMotorForce: j.maxMotorForce,
        ...brk,
      }
    case 'weld':
      return {
        type,
        bodyA,
        bodyB,
        anchor: anchorB,
        frames,
        collideConnected,
        linearHertz: j.hertz,
        angularHertz: j.angularHertz,
        linearDampingRatio: j.dampingRatio,
        angularDampingRatio: j.angularDampingRatio,
        ...brk,
      }
    case 'prismatic':
    case 'wheel': {
      frames.localAxisA = { x: j.localAxisAx, y: j.localAxisAy }
      const axis = worldAxis(j)
      const common = {
        bodyA,
        bodyB,
        anchor: anchorB,
        axis,
        frames,
        collideConnected,
        enableLimit: j.enableLimit,
        lower: j.lowerTranslation,
        upper: j.upperTranslation,
        enableMotor: j.enableMotor,
        motorSpeed: j.motorSpeed,
        enableSpring: j.enableSpring,
        hertz: j.hertz,
        dampingRatio: j.dampingRatio,
        ...brk,
      }
      return type === 'wheel'
        ? { type, ...common, maxMotorTorque: j.maxMotorTorque }
        : { type, ...common, maxMotorForce: j.maxMotorForce, targetTranslation: j.springTarget }
    }
    case 'motor':
      return {
        type,
        bodyA,
        bodyB,
        collideConnected,
        linearOffset: { x: j.linearOffsetX, y: j.linearOffsetY },
        angularOffset: j.angularOffset,
        maxForce: j.maxForce,
        maxTorque: j.maxTorque,
        correctionFactor: j.correctionFactor,
        ...brk,
      }
    default:
      return {
        type: 'mouse',
        body: bodyB,
        target: { x: j.targetX, y: j.targetY },
        localAnchor: { x: j.localAnchorBx, y: j.localAnchorBy },
        maxForce: j.maxForce,
        hertz: j.hertz,
        dampingRatio: j.dampingRatio,
        ...brk,
      }
  }
}

const KIND_CODES = {
  revolute: REVOLUTE,
  distance: DISTANCE,
  mouse: MOUSE,
  weld: WELD,
  prismatic: PRISMATIC,
  wheel: WHEEL,
  motor: MOTOR,
} as const

function configureBreak(joint: Joint, def: JointDef): void {
  joint.breakForce = threshold('breakForce', def.breakForce)
  joint.breakTorque = threshold('breakTorque', def.breakTorque)
}

/** A break threshold: a number >= 0, Infinity (never) by default. */
function threshold(name: string, value: number | undefined): number {
  if (value === undefined) return Number.POSITIVE_INFINITY
  if (typeof value !== 'number' || !(value >= 0))
    throw new RangeError(`${name} must be a number >= 0 (Infinity: never breaks), got ${value}`)
  return value
}

function configureWeld(joint: Joint, def: Extract<JointDef, { type: 'weld' }>): void {
  joint.hertz = inRange('linearHertz', def.linearHertz ?? 0, 0, 1e6)
  joint.angularHertz = inRange('angularHertz', def.angularHertz ?? 0, 0, 1e6)
  joint.dampingRatio = inRange('linearDampingRatio', def.linearDampingRatio ?? 1, 0, 1e6)
  joint.angularDampingRatio = inRange('angularDampingRatio', def.angularDampingRatio ?? 1, 0, 1e6)
}

/** Prismatic and wheel joints: the axis, limits, motor and spring. */
function configureSlider(joint: Joint, def: Extract<JointDef, { type: 'prismatic' | 'wheel' }>): void {
  const axis = finiteVec('axis', def.axis)
  const length = Math.sqrt(axis.x * axis.x + axis.y * axis.y)
  if (!(length > 1e-9) || !Number.isFinite(length))
    throw new RangeError(`axis must be a non-zero direction, got (${axis.x}, ${axis.y})`)
  const ux = axis.x / length
  const uy = axis.y / length
  const a = joint.bodyA
  joint.localAxisAx = a.c * ux + a.s * uy
  joint.localAxisAy = -a.s * ux + a.c * uy
  joint.enableLimit = flag('enableLimit', def.enableLimit, false)
  joint.lowerTranslation = inRange('lower', def.lower ?? 0, -MAX_JOINT_REACH, MAX_JOINT_REACH)
  joint.upperTranslation = inRange('upper', def.upper ?? 0, joint.lowerTranslation, MAX_JOINT_REACH)
  joint.enableMotor = flag('enableMotor', def.enableMotor, false)
  joint.motorSpeed = finite('motorSpeed', def.motorSpeed ?? 0)
  const wheel = def.type === 'wheel'
  joint.enableSpring = flag('enableSpring', def.enableSpring, wheel)
  joint.hertz = inRange('hertz', def.hertz ?? (wheel ? 1 : 0), 0, 1e6)
  joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? 0.7, 0, 1e6)
  if (def.type === 'wheel') joint.maxMotorTorque = inRange('maxMotorTorque', def.maxMotorTorque ?? 0, 0, 1e12)
  else {
    joint.maxMotorForce = inRange('maxMotorForce', def.maxMotorForce ?? 0, 0, 1e12)
    joint.springTarget = inRange(
      'targetTranslation',
      def.targetTranslation ?? 0,
      -MAX_JOINT_REACH,
      MAX_JOINT_REACH,
    )
  }
}

function configureMotor(joint: Joint, def: Extract<JointDef, { type: 'motor' }>): void {
  const a = joint.bodyA
  const b = joint.bodyB
  joint.collideConnected = flag('collideConnected', def.collideConnected, false)
  // Default offsets: the pose B has relative to A now (centre of mass in A's frame, from A's origin).
  const here = localPoint(a, { x: b.cx, y: b.cy })
  const offset = def.linearOffset === undefined ? here : finiteVec('linearOffset', def.linearOffset)
  const local = reach('linearOffset', a, offset)
  joint.linearOffsetX = local.x
  joint.linearOffsetY = local.y
  joint.localAnchorAx = local.x
  joint.localAnchorAy = local.y
  joint.localAnchorBx = b.localCenterX
  joint.localAnchorBy = b.localCenterY
  const current = atan2(b.s * a.c - b.c * a.s, b.c * a.c + b.s * a.s)
  joint.angularOffset = def.angularOffset === undefined ? current : angle('angularOffset', def.angularOffset)
  joint.maxForce = inRange('maxForce', def.maxForce ?? 1, 0, 1e12)
  joint.maxTorque = inRange('maxTorque', def.maxTorque ?? 1, 0, 1e12)
  joint.correctionFactor = inRange('correctionFactor', def.correctionFactor ?? 0.3, 0, 1)
  joint.lastOffsetX = joint.linearOffsetX
  joint.lastOffsetY = joint.linearOffsetY
  joint.lastAngularOffset = joint.angularOffset
}

function configureRevolute(joint: Joint, def: Extract<JointDef, { type: 'revolute' }>): void {
  joint.enableLimit = def.enableLimit === true
  joint.lowerAngle = inRange('lowerAngle', def.lowerAngle ?? 0, -Math.PI, Math.PI)
  joint.upperAngle = inRange('upperAngle', def.upperAngle ?? 0, joint.lowerAngle, Math.PI)
  joint.enableMotor = def.enableMotor === true
  joint.motorSpeed = finite('motorSpeed', def.motorSpeed ?? 0)
  joint.maxMotorTorque = inRange('maxMotorTorque', def.maxMotorTorque ?? 0, 0, 1e12)
  joint.enableSpring = flag('enableSpring', def.enableSpring, false)
  joint.hertz = inRange('hertz', def.hertz ?? 0, 0, 1e6)
  // 0.7 with a spring; 0 without (the saved field keeps its format-1 value for plain pins).
  joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? (joint.enableSpring ? 0.7 : 0), 0, 1e6)
  joint.springTarget = inRange('targetAngle', def.targetAngle ?? 0, -Math.PI, Math.PI)
}

function configureDistance(
  joint: Joint,
  def: Extract<JointDef, { type: 'distance' }>,
  pa: Vec2,
  pb: Vec2,
): void {
  const dx = pb.x - pa.x
  const dy = pb.y - pa.y
  const current = Math.sqrt(dx * dx + dy * dy)
  // Coincident anchors make a rod of the shortest length rather than an error.
  joint.length = inRange(
    'length',
    def.length ?? Math.max(current, MIN_JOINT_LENGTH),
    MIN_JOINT_LENGTH,
    MAX_JOINT_REACH,
  )
  // A def that gives only maxLength (and no spring) is a rope: it must never push.
  const ropeDefault = def.maxLength !== undefined && def.hertz === undefined ? 0 : joint.length
  joint.minLength = inRange('minLength', def.minLength ?? ropeDefault, 0, joint.length)
  joint.maxLength = inRange('maxLength', def.maxLength ?? joint.length, joint.length, MAX_JOINT_REACH)
  joint.hertz = inRange('hertz', def.hertz ?? 0, 0, 1e6)
  joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? (joint.hertz > 0 ? 0.7 : 0), 0, 1e6)
  joint.enableMotor = flag('enableMotor', def.enableMotor, false)
  joint.motorSpeed = finite('motorSpeed', def.motorSpeed ?? 0)
  joint.maxMotorForce = inRange('maxMotorForce', def.maxMotorForce ?? 0, 0, 1e12)
}

/** Shortest distance joint (m). */
const MIN_JOINT_LENGTH = 0.001
/**
 * Farthest an anchor may lie from its body's origin, and longest distance joint (m). Far beyond any
 * sensible world, it only keeps the lever arms' products (r^2 / I) finite: with anchors at 1e300 m
 * they overflowed to Infinity and the bodies became NaN.
 */
const MAX_JOINT_REACH = 1e6

/** A local anchor, checked to lie within MAX_JOINT_REACH of the body's origin. */
function reach(name: string, b: Body, local: Vec2): Vec2 {
  if (Math.abs(local.x) > MAX_JOINT_REACH || Math.abs(local.y) > MAX_JOINT_REACH) {
    const where = b.id === 0 ? 'the world origin' : `body ${b.id}`
    throw new RangeError(
      `${name} must lie within ${MAX_JOINT_REACH} m of ${where}, got (${local.x}, ${local.y}) from it`,
    )
  }
  return local
}

function flag(name: string, value: boolean | undefined, fallback: boolean): boolean {
  if (value === undefined) return fallback
  if (typeof value !== 'boolean') throw new RangeError(`${name} must be a boolean, got ${String(value)}`)
  return value
}

/** A world point in a body's frame, relative to its origin (m). */
export function localPoint(b: Body, p: Vec2): Vec2 {
  const dx = p.x - b.x
  const dy = p.y - b.y
  return { x: b.c * dx + b.s * dy, y: -b.s * dx + b.c * dy }
}

function worldPoint(b: Body, lx: number, ly: number): Vec2 {
  return { x: b.x + b.c * lx - b.s * ly, y: b.y + b.s * lx + b.c * ly }
}

/** Output of reactionInto: force x, y (N) on B at its anchor, torque (N m) on B. */
export const reactionOut = new Float64Array(3)

/**
 * A joint's reaction over the last step into `reactionOut`, without allocating (the step's break
 * check and getJointReaction both read it): the force on body B at its anchor (N) and the pure
 * torque on B (N m); body A gets the opposite. `impulseToForce` is sub-steps per second: the
 * impulses are accumulated per sub-step, so impulse / h is the mean force of the last sub-step.
 */
export function reactionInto(j: Joint, impulseToForce: number): void {
  let fx = j.linearImpulseX
  let fy = j.linearImpulseY
  let torque = 0
  const type = j.type
  if (type === DISTANCE) {
    const a = j.bodyA
    const b = j.bodyB
    const dx =
      b.x +
      b.c * j.localAnchorBx -
      b.s * j.localAnchorBy -
      (a.x + a.c * j.localAnchorAx - a.s * j.localAnchorAy)
    const dy =
      b.y +
      b.s * j.localAnchorBx +
      b.c * j.localAnchorBy -
      (a.y + a.s * j.localAnchorAx + a.c * j.localAnchorAy)
    const len = Math.sqrt(dx * dx + dy * dy)
    // The solver pushes along +x when the anchors coincide (distance-joint.ts computeAxis).
    const ux = len > 1e-12 ? dx / len : 1
    const uy = len > 1e-12 ? dy / len : 0
    let axial = j.impulse + j.lowerImpulse - j.upperImpulse
    if (j.enableMotor) axial += j.motorImpulse
    fx = axial * ux
    fy = axial * uy
  } else if (type === REVOLUTE) {
    torque = j.motorImpulse + j.lowerImpulse - j.upperImpulse
    if (j.enableSpring) torque += j.springImpulse
  } else if (type === WELD || type === MOTOR) {
    torque = j.angularImpulse
  } else if (type === PRISMATIC || type === WHEEL) {
    const a = j.bodyA
    const ax = a.c * j.localAxisAx - a.s * j.localAxisAy
    const ay = a.s * j.localAxisAx + a.c * j.localAxisAy
    let axial = j.springImpulse + j.lowerImpulse - j.upperImpulse
    if (type === PRISMATIC) axial += j.motorImpulse
    const perp = j.linearImpulseX
    fx = axial * ax - perp * ay
    fy = axial * ay + perp * ax
    torque = type === PRISMATIC ? j.angularImpulse : j.motorImpulse
  }
  reactionOut[0] = fx * impulseToForce
  reactionOut[1] = fy * impulseToForce
  reactionOut[2] = torque * impulseToForce
}

/** A joint's reaction over the last step (see reactionInto). */
export function jointReaction(j: Joint, impulseToForce: number): JointReaction {
  reactionInto(j, impulseToForce)
  return { force: { x: reactionOut[0], y: reactionOut[1] }, torque: reactionOut[2] }
}

/** Whether the joint's last reaction exceeds its breakForce or breakTorque. */
export function exceedsBreak(j: Joint, impulseToForce: number): boolean {
  if (j.breakForce === Number.POSITIVE_INFINITY && j.breakTorque === Number.POSITIVE_INFINITY) return false
  reactionInto(j, impulseToForce)
  const fx = reactionOut[0]
  const fy = reactionOut[1]
  return Math.sqrt(fx * fx + fy * fy) > j.breakForce || Math.abs(reactionOut[2]) > j.breakTorque
}

/** The world axis of a prismatic or wheel joint now (unit). */
function worldAxis(j: Joint): Vec2 {
  const a = j.bodyA
  return { x: a.c * j.localAxisAx - a.s * j.localAxisAy, y: a.s * j.localAxisAx + a.c * j.localAxisAy }
}

/** Prismatic, wheel: translation along the axis (m); distance: the anchors' distance (m). */
export function jointTranslation(j: Joint): number {
  const pA = worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
  const pB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
  const dx = pB.x - pA.x
  const dy = pB.y - pA.y
  if (j.type === DISTANCE) return Math.sqrt(dx * dx + dy * dy)
  const axis = worldAxis(j)
  return dx * axis.x + dy * axis.y
}

/** angleB - angleA less the joint's reference angle, in [-pi, pi] (rad). */
export function jointAngle(j: Joint): number {
  const a = j.bodyA
  const b = j.bodyB
  return unwind(relativeAngle(b.c, b.s, a.c, a.s) - j.referenceAngle)
}

/**
 * The rate of the coordinate a joint's motor drives: revolute and wheel wB - wA (rad/s); prismatic
 * d(translation)/dt (m/s); distance d(length)/dt (m/s).
 */
export function jointSpeed(j: Joint): number {
  const a = j.bodyA
  const b = j.bodyB
  if (j.type === REVOLUTE || j.type === WHEEL) return b.w - a.w
  const pA = worldPoint(a, j.localAnchorAx, j.localAnchorAy)
  const pB = worldPoint(b, j.localAnchorBx, j.localAnchorBy)
  // Velocities of the anchor points (centre velocity + w x arm from the centre of mass).
  const vAx = a.vx - a.w * (pA.y - a.cy)
  const vAy = a.vy + a.w * (pA.x - a.cx)
  const vBx = b.vx - b.w * (pB.y - b.cy)
  const vBy = b.vy + b.w * (pB.x - b.cx)
  const dx = pB.x - pA.x
  const dy = pB.y - pA.y
  const rvx = vBx - vAx
  const rvy = vBy - vAy
  if (j.type === DISTANCE) {
    const len = Math.sqrt(dx * dx + dy * dy)
    return len > 1e-12 ? (dx * rvx + dy * rvy) / len : 0
  }
  // Prismatic: d/dt (d . axis) = rv . axis + d . (wA x axis).
  const axis = worldAxis(j)
  return rvx * axis.x + rvy * axis.y + a.w * (dx * -axis.y + dy * axis.x)
}

/** A joint's read-back; `impulseToForce` is sub-steps per second (see jointReaction). */
export function jointInfo(j: Joint, impulseToForce: number): JointInfo {
  const anchorB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
  const anchorA =
    j.type === MOUSE ? { x: j.targetX, y: j.targetY } : worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
  const { force, torque } = jointReaction(j, impulseToForce)
  const info: JointInfo = {
    id: j.id,
    type: JOINT_TYPE_NAMES[j.type],
    bodyA: j.bodyA.id === 0 ? null : j.bodyA.id,
    bodyB: j.bodyB.id,
    anchorA,
    anchorB,
    collideConnected: j.collideConnected,
    force,
    torque,
  }
  const type = j.type
  if (type === PRISMATIC || type === WHEEL) {
    info.axis = worldAxis(j)
    info.translation = jointTranslation(j)
    if (j.enableLimit) {
      info.lower = j.lowerTranslation
      info.upper = j.upperTranslation
    }
  } else if (type === DISTANCE) info.translation = jointTranslation(j)
  else if (type === REVOLUTE && j.enableLimit) {
    info.lower = j.lowerAngle
    info.upper = j.upperAngle
  }
  if (type !== DISTANCE && type !== MOUSE) info.angle = jointAngle(j)
  return info
}
