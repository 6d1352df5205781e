/*
 * Joints as they travel: a WireJoint is built from the joint definition the world was given (scene
 * joints from a scene's blueprint, players' joints from their commands), right when the joint is
 * created, so that anchors and axes can be turned into each body's local frame and the reference
 * angle read. The definition's defaults are resolved here exactly as the engine resolves them
 * (engine/joints/joint-defs.ts): a distance joint's length is the anchors' distance, a rope (only
 * maxLength given) has minLength 0, a spring damps at 0.7, a weld is rigid (damping ratios 1), a
 * wheel's suspension is on at 1 Hz, a motor joint's offsets are the pose b has now (force and
 * torque 1, correction 0.3); bodies joined by a distance joint collide while the others do not.
 */
import {
  buildScene,
  type DistanceJointDef,
  type JointDef,
  type JointId,
  type JointInfo,
  type MotorJointDef,
  type PrismaticJointDef,
  type RevoluteJointDef,
  type SceneBlueprint,
  type Vec2,
  type WeldJointDef,
  type WheelJointDef,
  type World,
} from '../../engine/index.ts'
import type { WireJoint, WireJointForce, WireJointForceKind, WireJointKind } from './messages.ts'

/** A definition of a joint that travels (mouse joints are grabs: they travel as cursors). */
export type WireJointDef =
  | RevoluteJointDef
  | DistanceJointDef
  | WeldJointDef
  | PrismaticJointDef
  | WheelJointDef
  | MotorJointDef

/** Every joint kind that travels, in PROTOCOL.md's order. */
export const WIRE_JOINT_KINDS: readonly WireJointKind[] = [
  'pin',
  'rod',
  'rope',
  'spring',
  'weld',
  'slider',
  'wheel',
  'motor',
]

/** Whether a joint's bodies collide when the definition does not say: distance joints yes, the others no. */
export function defaultCollide(type: WireJointDef['type']): boolean {
  return type === 'distance'
}

/** The drawn kind of a distance joint with these parameters: spring, rod or rope. */
export function distanceKind(min: number, max: number, hz: number): WireJointKind {
  if (hz > 0) return 'spring'
  return min >= max ? 'rod' : 'rope'
}

/** A break threshold as it travels: 0 for never (Infinity, the engine's default, is not sent). */
const threshold = (value: number | undefined): number =>
  value !== undefined && Number.isFinite(value) ? value : 0

/** The anchors of a definition (world m): a's and b's (the same point but for distance joints). */
function anchorsOf(world: World, def: WireJointDef): [Vec2, Vec2] {
  if (def.type === 'distance') return [def.anchorA, def.anchorB]
  if (def.type !== 'motor') return [def.anchor, def.anchor]
  // A motor joint: a's anchor is the offset target (in a's frame), b's its centre of mass.
  const centre = world.getWorldCenter(def.bodyB)
  const a = def.bodyA ?? 0
  const target =
    def.linearOffset === undefined
      ? centre
      : a === 0
        ? def.linearOffset
        : world.getWorldPoint(a, def.linearOffset)
  return [target, centre]
}

/** The wire form of joint `id`, just created in `world` from `def` by player `owner` (0: a scene). */
export function wireJoint(world: World, id: JointId, def: WireJointDef, owner = 0): WireJoint {
  const a = def.bodyA ?? 0
  const local = (body: number, p: Vec2): Vec2 =>
    body === 0 ? { x: p.x, y: p.y } : world.getLocalPoint(body, p)
  const [anchorA, anchorB] = anchorsOf(world, def)
  const la = local(a, anchorA)
  const lb = local(def.bodyB, anchorB)
  const joint: WireJoint = {
    id,
    kind: 'pin',
    a,
    b: def.bodyB,
    ax: la.x,
    ay: la.y,
    bx: lb.x,
    by: lb.y,
    length: 0,
    min: 0,
    max: 0,
    hz: 0,
    damping: 0,
    ref: 0,
    limit: false,
    lower: 0,
    upper: 0,
    motor: false,
    speed: 0,
    torque: 0,
    collide: def.collideConnected ?? defaultCollide(def.type),
    force: 0,
    ux: 0,
    uy: 0,
    spring: false,
    target: 0,
    ahz: 0,
    adamping: 0,
    correction: 0,
    breakForce: threshold(def.breakForce),
    breakTorque: threshold(def.breakTorque),
    owner,
  }
  if (def.type !== 'distance' && def.type !== 'motor') {
    let ref = world.getAngle(def.bodyB) - (a === 0 ? 0 : world.getAngle(a))
    if (ref > Math.PI) ref -= 2 * Math.PI
    else if (ref <= -Math.PI) ref += 2 * Math.PI
    joint.ref = ref
  }
  switch (def.type) {
    case 'revolute':
      joint.limit = def.enableLimit === true
      joint.lower = def.lowerAngle ?? 0
      joint.upper = def.upperAngle ?? 0
      joint.motor = def.enableMotor === true
      joint.speed = def.motorSpeed ?? 0
      joint.torque = def.maxMotorTorque ?? 0
      joint.spring = def.enableSpring === true
      joint.hz = def.hertz ?? 0
      joint.damping = def.dampingRatio ?? (joint.spring ? 0.7 : 0)
      joint.target = def.targetAngle ?? 0
      return joint
    case 'distance':
      return distanceJoint(joint, def)
    case 'weld':
      joint.kind = 'weld'
      joint.hz = def.linearHertz ?? 0
      joint.damping = def.linearDampingRatio ?? 1
      joint.ahz = def.angularHertz ?? 0
      joint.adamping = def.angularDampingRatio ?? 1
      return joint
    case 'prismatic':
    case 'wheel': {
      const wheel = def.type === 'wheel'
      joint.kind = wheel ? 'wheel' : 'slider'
      const tip = { x: def.anchor.x + def.axis.x, y: def.anchor.y + def.axis.y }
      const lt = local(a, tip)
      const dx = lt.x - la.x
      const dy = lt.y - la.y
      const n = Math.sqrt(dx * dx + dy * dy)
      joint.ux = dx / n
      joint.uy = dy / n
      joint.limit = def.enableLimit === true
      joint.lower = def.lower ?? 0
      joint.upper = def.upper ?? 0
      joint.motor = def.enableMotor === true
      joint.speed = def.motorSpeed ?? 0
      joint.spring = def.enableSpring ?? wheel
      joint.hz = def.hertz ?? (wheel ? 1 : 0)
      joint.damping = def.dampingRatio ?? 0.7
      if (def.type === 'wheel') joint.torque = def.maxMotorTorque ?? 0
      else {
        joint.force = def.maxMotorForce ?? 0
        joint.target = def.targetTranslation ?? 0
      }
      return joint
    }
    case 'motor': {
      joint.kind = 'motor'
      const angleA = a === 0 ? 0 : world.getAngle(a)
      joint.target = def.angularOffset ?? world.getAngle(def.bodyB) - angleA
      joint.force = def.maxForce ?? 1
      joint.torque = def.maxTorque ?? 1
      joint.correction = def.correctionFactor ?? 0.3
      return joint
    }
  }
}

/**
 * A wire joint with its settings taken from the joint's definition as it now stands (World
 * getJointDef, after World.setJointSettings): limits, motor, spring, lengths, weld springs, the
 * motor joint's caps and the break thresholds (Infinity travels as 0). The anchors, axis,
 * reference angle, collide flag and owner are kept. A new object; a distance joint's drawn kind
 * follows its new range and hertz.
 */
export function withJointSettings(wire: WireJoint, def: JointDef): WireJoint {
  const j: WireJoint = {
    ...wire,
    breakForce: threshold(def.breakForce),
    breakTorque: threshold(def.breakTorque),
  }
  switch (def.type) {
    case 'revolute':
      j.limit = def.enableLimit === true
      j.lower = def.lowerAngle ?? 0
      j.upper = def.upperAngle ?? 0
      j.motor = def.enableMotor === true
      j.speed = def.motorSpeed ?? 0
      j.torque = def.maxMotorTorque ?? 0
      j.spring = def.enableSpring === true
      j.hz = def.hertz ?? 0
      j.damping = def.dampingRatio ?? 0
      j.target = def.targetAngle ?? 0
      break
    case 'distance':
      j.length = def.length ?? j.length
      j.min = def.minLength ?? j.min
      j.max = def.maxLength ?? j.max
      j.hz = def.hertz ?? 0
      j.damping = def.dampingRatio ?? 0
      j.kind = distanceKind(j.min, j.max, j.hz)
      j.motor = def.enableMotor === true
      j.speed = def.motorSpeed ?? 0
      j.force = def.maxMotorForce ?? 0
      break
    case 'weld':
      j.hz = def.linearHertz ?? 0
      j.damping = def.linearDampingRatio ?? 0
      j.ahz = def.angularHertz ?? 0
      j.adamping = def.angularDampingRatio ?? 0
      break
    case 'prismatic':
    case 'wheel':
      j.limit = def.enableLimit === true
      j.lower = def.lower ?? 0
      j.upper = def.upper ?? 0
      j.motor = def.enableMotor === true
      j.speed = def.motorSpeed ?? 0
      j.spring = def.enableSpring === true
      j.hz = def.hertz ?? 0
      j.damping = def.dampingRatio ?? 0
      if (def.type === 'wheel') j.torque = def.maxMotorTorque ?? 0
      else {
        j.force = def.maxMotorForce ?? 0
        j.target = def.targetTranslation ?? 0
      }
      break
    case 'motor':
      j.force = def.maxForce ?? 0
      j.torque = def.maxTorque ?? 0
      j.correction = def.correctionFactor ?? 0
      break
  }
  return j
}

/** The distance joint's fields: length, range, spring and motor, and its drawn kind. */
function distanceJoint(joint: WireJoint, def: DistanceJointDef): WireJoint {
  const dx = def.anchorB.x - def.anchorA.x
  const dy = def.anchorB.y - def.anchorA.y
  const length = def.length ?? Math.max(Math.sqrt(dx * dx + dy * dy), 0.001)
  const ropeDefault = def.maxLength !== undefined && def.hertz === undefined ? 0 : length
  joint.length = length
  joint.min = def.minLength ?? ropeDefault
  joint.max = def.maxLength ?? length
  joint.hz = def.hertz ?? 0
  joint.damping = def.dampingRatio ?? (joint.hz > 0 ? 0.7 : 0)
  joint.kind = distanceKind(joint.min, joint.max, joint.hz)
  joint.motor = def.enableMotor === true
  joint.speed = def.motorSpeed ?? 0
  joint.force = def.maxMotorForce ?? 0
  return joint
}

/**
 * Build a scene's bodies and joints in a fresh world and return its joints in wire form (in
 * creation order, so their ids are the world's joint ids 1, 2, 3 ...).
 */
export function buildSceneJoints(world: World, scene: SceneBlueprint): WireJoint[] {
  const before = new Set(world.jointIds())
  const ids = buildScene(world, scene)
  const created = world.jointIds().filter((id) => !before.has(id))
  const out: WireJoint[] = []
  const defs = scene.joints ?? []
  for (let i = 0; i < defs.length; i++) {
    const def = defs[i]
    // Mouse joints are grabs: they travel as cursors (no scene has one).
    if (def.type === 'mouse') continue
    const bodyA = def.bodyA === null ? null : ids[def.bodyA]
    out.push(wireJoint(world, created[i], { ...def, bodyA, bodyB: ids[def.bodyB] } as WireJointDef))
  }
  return out
}

/** A joint's force on `body`, one of its two bodies (body a feels the opposite of b), as it travels. */
export function jointForceOn(body: number, j: JointInfo, kind: WireJointForceKind): WireJointForce {
  const onB = j.bodyB === body
  const sign = onB ? 1 : -1
  const at = onB ? j.anchorB : j.anchorA
  return {
    id: j.id,
    kind,
    x: at.x,
    y: at.y,
    fx: sign * j.force.x,
    fy: sign * j.force.y,
    torque: sign * j.torque,
  }
}
