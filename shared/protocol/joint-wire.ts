/*
 * Joints as they travel: a WireJoint is built from the joint definition the world was given (scene
 * joints from a scene's blueprint, players' pins and ropes from their commands), right when the
 * joint is created, so that anchors can be turned into each body's local frame and the pin's
 * reference angle read. The definition's defaults are resolved here exactly as the engine resolves
 * them (engine/joints/joint-defs.ts): a distance joint's length is the anchors' distance, a rope (only
 * maxLength given) has minLength 0, a spring damps at 0.7, and bodies joined by a distance joint
 * collide while pinned bodies do not.
 */
import {
  buildScene,
  type DistanceJointDef,
  type JointId,
  type JointInfo,
  type RevoluteJointDef,
  type SceneBlueprint,
  type Vec2,
  type World,
} from '../../engine/index.ts'
import type { WireJoint, WireJointForce, WireJointForceKind, WireJointKind } from './messages.ts'

/** A definition of a joint that travels (mouse joints are grabs: they travel as cursors). */
export type WireJointDef = RevoluteJointDef | DistanceJointDef

/** Whether a joint's bodies collide when the definition does not say: distance joints yes, pins no. */
export function defaultCollide(type: WireJointDef['type']): boolean {
  return type === 'distance'
}

/** The drawn kind of a distance joint with these parameters: spring, rod or rope. */
export function distanceKind(min: number, max: number, hz: number): WireJointKind {
  if (hz > 0) return 'spring'
  return min >= max ? 'rod' : 'rope'
}

/** The wire form of joint `id`, just created in `world` from `def` (anchors still at their creation points). */
export function wireJoint(world: World, id: JointId, def: WireJointDef): WireJoint {
  const a = def.bodyA ?? 0
  const local = (body: number, p: Vec2): Vec2 =>
    body === 0 ? { x: p.x, y: p.y } : world.getLocalPoint(body, p)
  const anchorA = def.type === 'revolute' ? def.anchor : def.anchorA
  const anchorB = def.type === 'revolute' ? def.anchor : def.anchorB
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
  }
  if (def.type === 'revolute') {
    let ref = world.getAngle(def.bodyB) - (a === 0 ? 0 : world.getAngle(a))
    if (ref > Math.PI) ref -= 2 * Math.PI
    else if (ref <= -Math.PI) ref += 2 * Math.PI
    joint.ref = ref
    joint.limit = def.enableLimit === true
    joint.lower = def.lowerAngle ?? 0
    joint.upper = def.upperAngle ?? 0
    joint.motor = def.enableMotor === true
    joint.speed = def.motorSpeed ?? 0
    joint.torque = def.maxMotorTorque ?? 0
    return joint
  }
  const dx = anchorB.x - anchorA.x
  const dy = anchorB.y - anchorA.y
  const length = def.length ?? Math.sqrt(dx * dx + dy * dy)
  const ropeDefault = def.maxLength !== undefined && def.hertz === undefined ? 0 : length
  joint.length = length
  joint.min = def.minLength ?? ropeDefault
  joint.max = def.maxLength ?? length
  joint.hz = def.hertz ?? 0
  joint.damping = def.dampingRatio ?? (joint.hz > 0 ? 0.7 : 0)
  joint.kind = distanceKind(joint.min, joint.max, joint.hz)
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
    // The wire carries pins and distance joints (the other kinds are not on the wire yet).
    if (def.type !== 'revolute' && def.type !== 'distance') continue
    const body = (index: number): number => ids[index]
    const resolved: WireJointDef =
      def.type === 'revolute'
        ? { ...def, bodyA: def.bodyA === null ? null : body(def.bodyA), bodyB: body(def.bodyB) }
        : { ...def, bodyA: def.bodyA === null ? null : body(def.bodyA), bodyB: body(def.bodyB) }
    out.push(wireJoint(world, created[i], resolved))
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
