/*
 * Joints from their public definitions, and joints back to their public read-back (JointInfo).
 * Every value of a definition is checked here, with a RangeError naming it, before the joint
 * reaches the solver. Anchors are given in world space at creation and stored in each body's frame.
 */

import { finite, finiteVec, inRange } from '../def-checks.ts'
import type { Body } from '../dynamics/index.ts'
import { atan2, type Vec2 } from '../math.ts'
import type { BodyId, JointDef, JointInfo, JointReaction } from '../types.ts'
import { Joint } from './joint.ts'
import { DISTANCE, JOINT_TYPE_NAMES, MOUSE, REVOLUTE } from './joint-math.ts'

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
  const anchorA = finiteVec('anchor', def.type === 'revolute' ? def.anchor : def.anchorA)
  const anchorB = def.type === 'revolute' ? anchorA : finiteVec('anchorB', def.anchorB)
  const joint = new Joint(id, def.type === 'revolute' ? REVOLUTE : DISTANCE, a, b)
  // A pin usually lies inside both bodies, so they must not collide; a rope, rod or spring keeps
  // its bodies apart only along its axis, so they collide like any two bodies.
  joint.collideConnected = flag('collideConnected', def.collideConnected, def.type === 'distance')
  const la = reach(def.type === 'revolute' ? 'anchor' : 'anchorA', a, localPoint(a, anchorA))
  const lb = reach(def.type === 'revolute' ? 'anchor' : 'anchorB', b, localPoint(b, anchorB))
  joint.localAnchorAx = la.x
  joint.localAnchorAy = la.y
  joint.localAnchorBx = lb.x
  joint.localAnchorBy = lb.y
  if (def.type === 'revolute') configureRevolute(joint, def)
  else configureDistance(joint, def, anchorA, anchorB)
  return joint
}

function configureRevolute(joint: Joint, def: Extract<JointDef, { type: 'revolute' }>): void {
  joint.referenceAngle = atan2(
    joint.bodyB.s * joint.bodyA.c - joint.bodyB.c * joint.bodyA.s,
    joint.bodyB.c * joint.bodyA.c + joint.bodyB.s * joint.bodyA.s,
  )
  joint.enableLimit = def.enableLimit === true
  joint.lowerAngle = inRange('lowerAngle', def.lowerAngle ?? 0, -Math.PI, Math.PI)
  joint.upperAngle = inRange('upperAngle', def.upperAngle ?? 0, joint.lowerAngle, Math.PI)
  joint.enableMotor = def.enableMotor === true
  joint.motorSpeed = finite('motorSpeed', def.motorSpeed ?? 0)
  joint.maxMotorTorque = inRange('maxMotorTorque', def.maxMotorTorque ?? 0, 0, 1e12)
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

/**
 * A joint's reaction over the last step: the force on body B at its anchor (N) and the pure torque
 * on B (N m); body A gets the opposite. `impulseToForce` is sub-steps per second: the impulses are
 * accumulated per sub-step, so impulse / h is the mean force of the last sub-step.
 */
export function jointReaction(j: Joint, impulseToForce: number): JointReaction {
  let fx = j.linearImpulseX
  let fy = j.linearImpulseY
  if (j.type === DISTANCE) {
    const anchorA = worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
    const anchorB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
    const dx = anchorB.x - anchorA.x
    const dy = anchorB.y - anchorA.y
    const len = Math.sqrt(dx * dx + dy * dy)
    // The solver pushes along +x when the anchors coincide (distance-joint.ts computeAxis).
    const ux = len > 1e-12 ? dx / len : 1
    const uy = len > 1e-12 ? dy / len : 0
    const axial = j.impulse + j.lowerImpulse - j.upperImpulse
    fx = axial * ux
    fy = axial * uy
  }
  const torque = j.type === REVOLUTE ? j.motorImpulse + j.lowerImpulse - j.upperImpulse : 0
  return { force: { x: fx * impulseToForce, y: fy * impulseToForce }, torque: torque * impulseToForce }
}

/** A joint's read-back; `impulseToForce` is sub-steps per second (see jointReaction). */
export function jointInfo(j: Joint, impulseToForce: number): JointInfo {
  const anchorB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
  const anchorA =
    j.type === MOUSE ? { x: j.targetX, y: j.targetY } : worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
  const { force, torque } = jointReaction(j, impulseToForce)
  return {
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
}
