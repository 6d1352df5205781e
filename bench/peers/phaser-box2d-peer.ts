/*
 * phaser-box2d (Phaser Studio's JavaScript port of Box2D v3.0) as a benchmark peer.
 *
 * The npm package names a main file it does not ship, so we import its ES module bundle
 * (dist/PhaserBox2D.js) directly; it runs in Node and in browsers. Built like the box2d3-wasm
 * peer through the same C-style API: the blueprint's type, origin, angle, velocities, damping and
 * flags, one shape (b2MakeBox, or b2ComputeHull + b2MakePolygon, or a b2Circle), density (default
 * 1), friction (default 0.6) and restitution (default 0; the port's own default is 0.1). Revolute
 * joints use Box2D v3.0's local anchors and reference angle; a joint to the world uses one static
 * body with no shape. The world steps b2World_Step(1/60, 4 sub-steps), Box2D v3's default, with
 * lengths in metres (its b2_lengthUnitsPerMeter stays 1).
 */
import {
  b2Body_GetLinearVelocity,
  b2Body_GetLocalPoint,
  b2Body_GetPosition,
  b2Body_GetRotation,
  b2Body_IsAwake,
  type b2BodyId,
  b2BodyType,
  b2Circle,
  b2ComputeHull,
  b2CreateBody,
  b2CreateCircleShape,
  b2CreatePolygonShape,
  b2CreateRevoluteJoint,
  b2DefaultBodyDef,
  b2DefaultRevoluteJointDef,
  b2DefaultShapeDef,
  b2DefaultWorldDef,
  b2DestroyWorld,
  b2MakeBox,
  b2MakePolygon,
  b2MakeRot,
  b2Rot_GetAngle,
  b2Vec2,
  b2World_Step,
  type b2WorldId,
  CreateWorld,
} from 'phaser-box2d/dist/PhaserBox2D.js'
import type { BodyDef, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

const STEP = 1 / 60
const SUB_STEPS = 4

const BODY_TYPES = {
  static: b2BodyType.b2_staticBody,
  kinematic: b2BodyType.b2_kinematicBody,
  dynamic: b2BodyType.b2_dynamicBody,
} as const

/** A phaser-box2d world holding the blueprint, sleeping on or off. */
export class PhaserBox2DPeer implements PeerWorld {
  readonly engine = 'phaser-box2d'
  private readonly bodies: b2BodyId[] = []
  private world: b2WorldId | null
  private ground: b2BodyId | null = null

  constructor(
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
  ) {
    const worldDef = b2DefaultWorldDef()
    worldDef.gravity = new b2Vec2(blueprint.gravity.x, blueprint.gravity.y)
    worldDef.enableSleep = enableSleep
    this.world = CreateWorld({ worldDef }).worldId
    for (const def of blueprint.bodies) this.addBody(def)
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Builds the blueprint (the same signature as the wasm peers' create). */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<PhaserBox2DPeer> {
    return new PhaserBox2DPeer(blueprint, enableSleep)
  }

  private live(): b2WorldId {
    if (this.world === null) throw new Error('phaser-box2d world used after dispose')
    return this.world
  }

  addBody(def: BodyDef): void {
    const bd = b2DefaultBodyDef()
    bd.type = BODY_TYPES[def.type ?? 'dynamic']
    bd.position = new b2Vec2(def.position?.x ?? 0, def.position?.y ?? 0)
    bd.rotation = b2MakeRot(def.angle ?? 0)
    bd.linearVelocity = new b2Vec2(def.linearVelocity?.x ?? 0, def.linearVelocity?.y ?? 0)
    bd.angularVelocity = def.angularVelocity ?? 0
    bd.linearDamping = def.linearDamping ?? 0
    bd.angularDamping = def.angularDamping ?? 0
    bd.gravityScale = def.gravityScale ?? 1
    bd.isBullet = def.bullet ?? false
    bd.isAwake = def.awake ?? true
    bd.enableSleep = this.enableSleep && (def.enableSleep ?? true)
    bd.fixedRotation = def.fixedRotation ?? false
    const body = b2CreateBody(this.live(), bd)
    const sd = b2DefaultShapeDef()
    sd.density = def.density ?? 1
    sd.friction = def.friction ?? 0.6
    sd.restitution = def.restitution ?? 0
    const shape = def.shape
    if (shape.type === 'circle') {
      b2CreateCircleShape(body, sd, new b2Circle(new b2Vec2(0, 0), shape.radius))
    } else if (shape.box) {
      b2CreatePolygonShape(body, sd, b2MakeBox(shape.box.halfWidth, shape.box.halfHeight))
    } else {
      const points = shape.vertices.map((v) => new b2Vec2(v.x, v.y))
      const polygon = b2MakePolygon(b2ComputeHull(points, points.length), 0)
      if (polygon === null || polygon.count !== points.length) {
        throw new Error(`phaser-box2d hull rejected a polygon of ${points.length} vertices`)
      }
      b2CreatePolygonShape(body, sd, polygon)
    }
    this.bodies.push(body)
  }

  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute')
      throw new Error(`phaser-box2d peer builds revolute joints only, got ${def.type}`)
    if (this.ground === null) {
      const bd = b2DefaultBodyDef()
      this.ground = b2CreateBody(this.live(), bd)
    }
    const a = def.bodyA === null ? this.ground : this.bodies[def.bodyA]
    const b = this.bodies[def.bodyB]
    const anchor = new b2Vec2(def.anchor.x, def.anchor.y)
    const jd = b2DefaultRevoluteJointDef()
    jd.bodyIdA = a
    jd.bodyIdB = b
    jd.localAnchorA = b2Body_GetLocalPoint(a, anchor)
    jd.localAnchorB = b2Body_GetLocalPoint(b, anchor)
    jd.referenceAngle = b2Rot_GetAngle(b2Body_GetRotation(b)) - b2Rot_GetAngle(b2Body_GetRotation(a))
    jd.enableLimit = def.enableLimit ?? false
    jd.lowerAngle = def.lowerAngle ?? 0
    jd.upperAngle = def.upperAngle ?? 0
    jd.enableMotor = def.enableMotor ?? false
    jd.motorSpeed = def.motorSpeed ?? 0
    jd.maxMotorTorque = def.maxMotorTorque ?? 0
    b2CreateRevoluteJoint(this.live(), jd)
  }

  step(): void {
    b2World_Step(this.live(), STEP, SUB_STEPS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = b2Body_GetPosition(body)
      const v = b2Body_GetLinearVelocity(body)
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (b2Body_IsAwake(body)) awake++
    return awake
  }

  dispose(): void {
    if (this.world === null) return
    b2DestroyWorld(this.world)
    this.world = null
    this.bodies.length = 0
  }
}
