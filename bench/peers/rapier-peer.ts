/*
 * Rapier (@dimforge/rapier2d-compat: the Rust engine compiled to WebAssembly, the binary inlined as
 * base64 so one import works in Node and in browsers) as a benchmark peer.
 *
 * Bodies carry the blueprint's type, origin, angle, velocities, damping and flags, with one
 * collider of the same geometry (ball, cuboid, or the convex hull of the polygon's vertices),
 * density (default 1), friction (default 0.6: both sides equal, so Rapier's default averaging
 * combine gives the same pair friction as Box2D's geometric mean) and restitution (default 0).
 * Revolute joints pin the two bodies at the blueprint's world anchor; limits are shifted so the
 * joint angle is zero at creation as in Concord; a joint to the world uses one fixed body with no
 * collider. The world keeps Rapier's defaults: a 1/60 s time step, 4 solver iterations, 1 stabilization
 * iteration; sleeping is switched per body with setCanSleep.
 */
import type RAPIER_TYPES from '@dimforge/rapier2d-compat'
import type { BodyDef, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

type Rapier = typeof RAPIER_TYPES
type RigidBody = InstanceType<Rapier['RigidBody']>
type World = InstanceType<Rapier['World']>

let modulePromise: Promise<Rapier> | null = null

/** Loads and initialises Rapier once (later calls share it). */
export function loadRapier(): Promise<Rapier> {
  modulePromise ??= (async () => {
    const rapier = (await import('@dimforge/rapier2d-compat')).default
    await rapier.init()
    return rapier
  })()
  return modulePromise
}

/** Rapier's version string, once loaded (for the results file). */
export async function rapierVersion(): Promise<string> {
  return (await loadRapier()).version()
}

function createBody(R: Rapier, world: World, def: BodyDef, enableSleep: boolean): RigidBody {
  const type = def.type ?? 'dynamic'
  const desc =
    type === 'static'
      ? R.RigidBodyDesc.fixed()
      : type === 'kinematic'
        ? R.RigidBodyDesc.kinematicVelocityBased()
        : R.RigidBodyDesc.dynamic()
  desc
    .setTranslation(def.position?.x ?? 0, def.position?.y ?? 0)
    .setRotation(def.angle ?? 0)
    .setLinvel(def.linearVelocity?.x ?? 0, def.linearVelocity?.y ?? 0)
    .setAngvel(def.angularVelocity ?? 0)
    .setLinearDamping(def.linearDamping ?? 0)
    .setAngularDamping(def.angularDamping ?? 0)
    .setGravityScale(def.gravityScale ?? 1)
    .setCcdEnabled(def.bullet ?? false)
    .setCanSleep(enableSleep && (def.enableSleep ?? true))
    .setSleeping(def.awake === false)
  if (def.fixedRotation) desc.lockRotations()
  const body = world.createRigidBody(desc)
  const shape = def.shape
  let collider: InstanceType<Rapier['ColliderDesc']> | null
  if (shape.type === 'circle') collider = R.ColliderDesc.ball(shape.radius)
  else if (shape.box) collider = R.ColliderDesc.cuboid(shape.box.halfWidth, shape.box.halfHeight)
  else collider = R.ColliderDesc.convexHull(new Float32Array(shape.vertices.flatMap((v) => [v.x, v.y])))
  if (collider === null) throw new Error(`rapier could not build a convex hull of ${shape.count} vertices`)
  collider
    .setDensity(def.density ?? 1)
    .setFriction(def.friction ?? 0.6)
    .setRestitution(def.restitution ?? 0)
  world.createCollider(collider, body)
  return body
}

/** A Rapier world holding the blueprint, sleeping on or off. Build with `create`. */
export class RapierPeer implements PeerWorld {
  readonly engine = 'rapier'
  private readonly bodies: RigidBody[] = []
  private world: World | null
  private ground: RigidBody | null = null

  private constructor(
    private readonly R: Rapier,
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
  ) {
    this.world = new R.World({ x: blueprint.gravity.x, y: blueprint.gravity.y })
    for (const def of blueprint.bodies) this.addBody(def)
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Loads Rapier if needed and builds the blueprint in a new world. */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<RapierPeer> {
    return new RapierPeer(await loadRapier(), blueprint, enableSleep)
  }

  private live(): World {
    if (this.world === null) throw new Error('rapier world used after dispose')
    return this.world
  }

  addBody(def: BodyDef): void {
    this.bodies.push(createBody(this.R, this.live(), def, this.enableSleep))
  }

  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute') throw new Error(`rapier peer builds revolute joints only, got ${def.type}`)
    this.ground ??= this.live().createRigidBody(this.R.RigidBodyDesc.fixed())
    const a = def.bodyA === null ? this.ground : this.bodies[def.bodyA]
    const b = this.bodies[def.bodyB]
    const local = (body: RigidBody) => {
      const p = body.translation()
      const angle = body.rotation()
      const dx = def.anchor.x - p.x
      const dy = def.anchor.y - p.y
      const c = Math.cos(angle)
      const s = Math.sin(angle)
      return { x: c * dx + s * dy, y: -s * dx + c * dy }
    }
    const data = this.R.JointData.revolute(local(a), local(b))
    const joint = this.live().createImpulseJoint(data, a, b, true) as InstanceType<
      Rapier['RevoluteImpulseJoint']
    >
    // Box2D and Concord never collide two bodies a joint links; Rapier does unless told.
    joint.setContactsEnabled(false)
    const offset = b.rotation() - a.rotation()
    if (def.enableLimit) joint.setLimits((def.lowerAngle ?? 0) + offset, (def.upperAngle ?? 0) + offset)
    if (def.enableMotor) {
      joint.configureMotorVelocity(def.motorSpeed ?? 0, 1)
      joint.setMotorMaxForce(def.maxMotorTorque ?? 0)
    }
  }

  step(): void {
    this.live().step()
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = body.translation()
      const v = body.linvel()
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (!body.isFixed() && !body.isSleeping()) awake++
    return awake
  }

  dispose(): void {
    this.world?.free()
    this.world = null
    this.bodies.length = 0
  }
}
