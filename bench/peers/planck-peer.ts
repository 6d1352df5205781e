/*
 * planck.js (the most used Box2D 2.x port in JavaScript) as a benchmark peer.
 *
 * The blueprint's bodies are created in order with the same type, origin, angle, velocities,
 * damping and flags, and one fixture with the same shape, density (default 1), friction (default
 * 0.6) and restitution (default 0). Boxes made by box() become planck's box (the same four
 * vertices); other polygons pass their counter-clockwise vertices. The world steps 1/60 s with
 * planck's default 8 velocity and 3 position iterations, warm starting and continuous collision on,
 * as in Box2D 2.4; sleeping is switched per run.
 */
import { type Body, BoxShape, CircleShape, PolygonShape, RevoluteJoint, type Shape, World } from 'planck'
import type { BodyDef, Shape as ConcordShape, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

/** Box2D 2.x velocity iterations per step (planck's default). */
export const PLANCK_VELOCITY_ITERATIONS = 8
/** Box2D 2.x position iterations per step (planck's default). */
export const PLANCK_POSITION_ITERATIONS = 3

const STEP = 1 / 60

function toPlanckShape(shape: ConcordShape): Shape {
  if (shape.type === 'circle') return new CircleShape(shape.radius)
  if (shape.box) return new BoxShape(shape.box.halfWidth, shape.box.halfHeight)
  return new PolygonShape(shape.vertices.map((v) => ({ x: v.x, y: v.y })))
}

function createBody(world: World, def: BodyDef, enableSleep: boolean): Body {
  const body = world.createBody({
    type: def.type ?? 'dynamic',
    position: { x: def.position?.x ?? 0, y: def.position?.y ?? 0 },
    angle: def.angle ?? 0,
    linearVelocity: { x: def.linearVelocity?.x ?? 0, y: def.linearVelocity?.y ?? 0 },
    angularVelocity: def.angularVelocity ?? 0,
    linearDamping: def.linearDamping ?? 0,
    angularDamping: def.angularDamping ?? 0,
    gravityScale: def.gravityScale ?? 1,
    bullet: def.bullet ?? false,
    awake: def.awake ?? true,
    allowSleep: enableSleep && (def.enableSleep ?? true),
    fixedRotation: def.fixedRotation ?? false,
  })
  body.createFixture(toPlanckShape(def.shape), {
    density: def.density ?? 1,
    friction: def.friction ?? 0.6,
    restitution: def.restitution ?? 0,
  })
  return body
}

/** A planck world holding the blueprint, sleeping on or off. */
export class PlanckPeer implements PeerWorld {
  readonly engine = 'planck'
  private readonly world: World
  private readonly bodies: Body[]
  private ground: Body | null = null

  constructor(
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
  ) {
    this.world = new World({
      gravity: { x: blueprint.gravity.x, y: blueprint.gravity.y },
      allowSleep: enableSleep,
    })
    this.bodies = blueprint.bodies.map((def) => createBody(this.world, def, enableSleep))
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Builds the blueprint (the same signature as the wasm peers' create). */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<PlanckPeer> {
    return new PlanckPeer(blueprint, enableSleep)
  }

  addBody(def: BodyDef): void {
    this.bodies.push(createBody(this.world, def, this.enableSleep))
  }

  /** A revolute joint at the world anchor (angle zero at creation); the world frame is a static body. */
  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute') throw new Error(`planck peer builds revolute joints only, got ${def.type}`)
    this.ground ??= this.world.createBody()
    const a = def.bodyA === null ? this.ground : this.bodies[def.bodyA]
    const joint = new RevoluteJoint(
      {
        enableLimit: def.enableLimit ?? false,
        lowerAngle: def.lowerAngle ?? 0,
        upperAngle: def.upperAngle ?? 0,
        enableMotor: def.enableMotor ?? false,
        motorSpeed: def.motorSpeed ?? 0,
        maxMotorTorque: def.maxMotorTorque ?? 0,
      },
      a,
      this.bodies[def.bodyB],
      { x: def.anchor.x, y: def.anchor.y },
    )
    this.world.createJoint(joint)
  }

  step(): void {
    this.world.step(STEP, PLANCK_VELOCITY_ITERATIONS, PLANCK_POSITION_ITERATIONS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = body.getPosition()
      const v = body.getLinearVelocity()
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (!body.isStatic() && body.isAwake()) awake++
    return awake
  }

  dispose(): void {
    for (const body of this.bodies) this.world.destroyBody(body)
    this.bodies.length = 0
  }
}
