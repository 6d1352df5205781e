/*
 * matter-js (the most used 2D engine written for the web; position-based, not a Box2D descendant)
 * as a benchmark peer.
 *
 * matter-js works in pixels with y pointing down and milliseconds. Its defaults are tuned for
 * bodies tens of pixels across, so we map 1 m to 100 px and flip y; its default gravity (y = 1,
 * scale 0.001 px/ms^2 = 1,000 px/s^2) is then exactly the blueprint's 10 m/s^2, and a 1 m box is
 * 100 px, in the range its examples use. Bodies carry the same shape (Bodies.circle, rectangle, or
 * the polygon's vertices about its centroid, which is the body origin in every benchmark scene),
 * friction (default 0.6; matter's own default is 0.1), density (scaled by its default 0.001 so
 * masses keep their ratios), angle and velocities; restitution 0. Revolute joints are matter
 * constraints of length 0 between the anchor points (a pin, at matter's default stiffness for
 * pins, 0.7). The engine steps
 * Engine.update(engine, 1000 / 60) with its default 6 position, 4 velocity and 2 constraint
 * iterations; sleeping is engine.enableSleeping.
 */
import Matter from 'matter-js'
import type { BodyDef, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'

/** Pixels per metre in the matter-js world. */
export const MATTER_PIXELS_PER_METRE = 100
const S = MATTER_PIXELS_PER_METRE
/** matter-js's default body density (mass per px^2), our density 1. */
const DENSITY_SCALE = 0.001
const STEP_MS = 1000 / 60

function createBody(def: BodyDef): Matter.Body {
  const x = (def.position?.x ?? 0) * S
  const y = -(def.position?.y ?? 0) * S
  const options: Matter.IChamferableBodyDefinition = {
    isStatic: (def.type ?? 'dynamic') !== 'dynamic',
    angle: -(def.angle ?? 0),
    friction: def.friction ?? 0.6,
    restitution: def.restitution ?? 0,
    density: (def.density ?? 1) * DENSITY_SCALE,
  }
  const shape = def.shape
  let body: Matter.Body
  if (shape.type === 'circle') body = Matter.Bodies.circle(x, y, shape.radius * S, options)
  else if (shape.box) {
    body = Matter.Bodies.rectangle(x, y, shape.box.halfWidth * 2 * S, shape.box.halfHeight * 2 * S, options)
  } else {
    if (Math.abs(shape.centroid.x) > 1e-9 || Math.abs(shape.centroid.y) > 1e-9) {
      throw new Error(
        `matter peer needs polygons centred on the body origin, got centroid ${JSON.stringify(shape.centroid)}`,
      )
    }
    const points = shape.vertices.map((v) => ({ x: v.x * S, y: -v.y * S }))
    body = Matter.Bodies.fromVertices(x, y, [Matter.Vertices.clockwiseSort(points)], options)
  }
  if (def.linearVelocity) {
    Matter.Body.setVelocity(body, { x: (def.linearVelocity.x * S) / 60, y: (-def.linearVelocity.y * S) / 60 })
  }
  if (def.angularVelocity) Matter.Body.setAngularVelocity(body, -def.angularVelocity / 60)
  return body
}

/** A matter-js engine holding the blueprint, sleeping on or off. */
export class MatterPeer implements PeerWorld {
  readonly engine = 'matter-js'
  private readonly matter: Matter.Engine
  private readonly bodies: Matter.Body[] = []

  constructor(blueprint: SceneBlueprint, enableSleep: boolean) {
    this.matter = Matter.Engine.create({ enableSleeping: enableSleep })
    if (blueprint.gravity.x !== 0 || blueprint.gravity.y !== -10) {
      throw new Error(`matter peer expects gravity (0, -10), got ${JSON.stringify(blueprint.gravity)}`)
    }
    for (const def of blueprint.bodies) this.addBody(def)
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Builds the blueprint (the same signature as the wasm peers' create). */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<MatterPeer> {
    return new MatterPeer(blueprint, enableSleep)
  }

  addBody(def: BodyDef): void {
    const body = createBody(def)
    this.bodies.push(body)
    Matter.Composite.add(this.matter.world, body)
  }

  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute') throw new Error(`matter peer builds revolute joints only, got ${def.type}`)
    const anchor = { x: def.anchor.x * S, y: -def.anchor.y * S }
    const b = this.bodies[def.bodyB]
    const a = def.bodyA === null ? undefined : this.bodies[def.bodyA]
    const local = (body: Matter.Body) => Matter.Vector.sub(anchor, body.position)
    const constraint = Matter.Constraint.create({
      bodyA: a,
      pointA: a ? local(a) : anchor,
      bodyB: b,
      pointB: local(b),
      length: 0,
    })
    Matter.Composite.add(this.matter.world, constraint)
  }

  step(): void {
    Matter.Engine.update(this.matter, STEP_MS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      out.set(
        [body.position.x / S, -body.position.y / S, (body.velocity.x * 60) / S, (-body.velocity.y * 60) / S],
        i * 4,
      )
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (!body.isStatic && !body.isSleeping) awake++
    return awake
  }

  dispose(): void {
    Matter.Composite.clear(this.matter.world, false, true)
    Matter.Engine.clear(this.matter)
    this.bodies.length = 0
  }
}
