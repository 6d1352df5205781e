/*
 * @box2d/core (Lusito's TypeScript port of Box2D 2.4) as a benchmark peer.
 *
 * Built like the planck peer: the blueprint's type, origin, angle, velocities, damping and flags,
 * one fixture with the same shape (SetAsBox for boxes, Set for other polygons, b2CircleShape),
 * density (default 1), friction (default 0.6) and restitution (default 0). Revolute joints are
 * b2RevoluteJointDef.Initialize at the world anchor (angle zero at creation, as in Concord); a
 * joint to the world uses one static body with no fixture. The world steps 1/60 s with 8 velocity
 * and 3 position iterations (Box2D 2.4's testbed values, as for planck and box2d-wasm).
 */
import {
  type b2Body,
  b2BodyType,
  b2CircleShape,
  b2PolygonShape,
  b2RevoluteJointDef,
  type b2Shape,
  b2World,
} from '@box2d/core'
import type { BodyDef, Shape as ConcordShape, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

const STEP = 1 / 60
const ITERATIONS = { velocityIterations: 8, positionIterations: 3 }

function toShape(shape: ConcordShape): b2Shape {
  if (shape.type === 'circle') return new b2CircleShape(shape.radius)
  const polygon = new b2PolygonShape()
  if (shape.box) polygon.SetAsBox(shape.box.halfWidth, shape.box.halfHeight)
  else polygon.Set(shape.vertices.map((v) => ({ x: v.x, y: v.y })))
  return polygon
}

const BODY_TYPES = {
  static: b2BodyType.b2_staticBody,
  kinematic: b2BodyType.b2_kinematicBody,
  dynamic: b2BodyType.b2_dynamicBody,
} as const

/** An @box2d/core world holding the blueprint, sleeping on or off. */
export class Box2DCorePeer implements PeerWorld {
  readonly engine = '@box2d/core'
  private readonly world: b2World
  private readonly bodies: b2Body[] = []
  private ground: b2Body | null = null

  constructor(
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
  ) {
    this.world = b2World.Create({ x: blueprint.gravity.x, y: blueprint.gravity.y })
    this.world.SetAllowSleeping(enableSleep)
    for (const def of blueprint.bodies) this.addBody(def)
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Builds the blueprint (the same signature as the wasm peers' create). */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<Box2DCorePeer> {
    return new Box2DCorePeer(blueprint, enableSleep)
  }

  addBody(def: BodyDef): void {
    const body = this.world.CreateBody({
      type: BODY_TYPES[def.type ?? 'dynamic'],
      position: { x: def.position?.x ?? 0, y: def.position?.y ?? 0 },
      angle: def.angle ?? 0,
      linearVelocity: { x: def.linearVelocity?.x ?? 0, y: def.linearVelocity?.y ?? 0 },
      angularVelocity: def.angularVelocity ?? 0,
      linearDamping: def.linearDamping ?? 0,
      angularDamping: def.angularDamping ?? 0,
      gravityScale: def.gravityScale ?? 1,
      bullet: def.bullet ?? false,
      awake: def.awake ?? true,
      allowSleep: this.enableSleep && (def.enableSleep ?? true),
      fixedRotation: def.fixedRotation ?? false,
    })
    body.CreateFixture({
      shape: toShape(def.shape),
      density: def.density ?? 1,
      friction: def.friction ?? 0.6,
      restitution: def.restitution ?? 0,
    })
    this.bodies.push(body)
  }

  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute')
      throw new Error(`@box2d/core peer builds revolute joints only, got ${def.type}`)
    this.ground ??= this.world.CreateBody()
    const jd = new b2RevoluteJointDef()
    jd.Initialize(
      def.bodyA === null ? this.ground : this.bodies[def.bodyA],
      this.bodies[def.bodyB],
      def.anchor,
    )
    jd.enableLimit = def.enableLimit ?? false
    jd.lowerAngle = def.lowerAngle ?? 0
    jd.upperAngle = def.upperAngle ?? 0
    jd.enableMotor = def.enableMotor ?? false
    jd.motorSpeed = def.motorSpeed ?? 0
    jd.maxMotorTorque = def.maxMotorTorque ?? 0
    this.world.CreateJoint(jd)
  }

  step(): void {
    this.world.Step(STEP, ITERATIONS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = body.GetPosition()
      const v = body.GetLinearVelocity()
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (body.GetType() !== b2BodyType.b2_staticBody && body.IsAwake()) awake++
    return awake
  }

  dispose(): void {
    for (const body of this.bodies) this.world.DestroyBody(body)
    this.bodies.length = 0
  }
}
