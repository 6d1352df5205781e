/*
 * box2d-wasm (Box2D 2.4.1 compiled to WebAssembly by Emscripten) as a benchmark peer.
 *
 * The module is loaded once and shared by every world. Its Node loader tries to fetch() the .wasm
 * by file path, which Node 20's fetch rejects, so in Node we read the binary ourselves and hand it
 * over as `wasmBinary`, picking the SIMD build exactly when the package's own entry would (the same
 * WebAssembly.validate probe); in a browser the page's wasm locator says where the file is.
 *
 * Bodies are built like the planck peer: same type, origin, angle, velocities, damping and flags,
 * one fixture with the same shape, density (default 1), friction (default 0.6) and restitution
 * (default 0). Boxes use SetAsBox; other polygons go through b2PolygonShape.Set with a b2Vec2
 * array allocated on the wasm heap. Every definition, shape and vector we allocate is destroyed
 * as soon as Box2D has copied it; body wrappers are released from Emscripten's cache on dispose.
 * The world steps 1/60 s with 8 velocity and 3 position iterations (Box2D 2.4's testbed values).
 */

import type {
  BodyDef,
  BodyType,
  Shape as ConcordShape,
  JointDef,
  SceneBlueprint,
} from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'
import { inNode, wasmLocator } from './wasm-location.ts'

/** Box2D 2.4 velocity iterations per step. */
export const BOX2D_VELOCITY_ITERATIONS = 8
/** Box2D 2.4 position iterations per step. */
export const BOX2D_POSITION_ITERATIONS = 3

const STEP = 1 / 60

type Box2DModule = typeof Box2D & EmscriptenModule

// wasm-feature-detect's SIMD probe, as used by box2d-wasm's entry.js.
const SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0, 10, 10, 1, 8, 0, 65, 0, 253, 15, 253, 98,
  11,
])

/** Which wasm build the module runs: 'simd' or 'baseline'. */
export const BOX2D_WASM_BUILD = WebAssembly.validate(SIMD_PROBE) ? 'simd' : 'baseline'

let modulePromise: Promise<Box2DModule> | null = null

/** Loads the box2d-wasm module once (later calls share it). */
export function loadBox2D(): Promise<Box2DModule> {
  modulePromise ??= (async () => {
    const factory = (await import('box2d-wasm')).default
    const locate = wasmLocator()
    if (!inNode()) return factory(locate ? { locateFile: (file: string) => locate(file) } : {})
    const { readFileSync } = await import('node:fs')
    const { createRequire } = await import('node:module')
    const { dirname, join } = await import('node:path')
    const entry = createRequire(import.meta.url).resolve('box2d-wasm')
    const file = BOX2D_WASM_BUILD === 'simd' ? 'Box2D.simd.wasm' : 'Box2D.wasm'
    const bytes = readFileSync(join(dirname(entry), file))
    const wasmBinary = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength)
    return factory({ wasmBinary })
  })()
  return modulePromise
}

function bodyTypeOf(b2: Box2DModule, type: BodyType): number {
  if (type === 'static') return b2.b2_staticBody
  if (type === 'kinematic') return b2.b2_kinematicBody
  return b2.b2_dynamicBody
}

function createShape(b2: Box2DModule, shape: ConcordShape): Box2D.b2Shape {
  if (shape.type === 'circle') {
    const circle = new b2.b2CircleShape()
    circle.set_m_radius(shape.radius)
    return circle
  }
  const polygon = new b2.b2PolygonShape()
  if (shape.box) {
    polygon.SetAsBox(shape.box.halfWidth, shape.box.halfHeight)
  } else {
    const [vertices, free] = b2.pointsToVec2Array(shape.vertices.map((v) => ({ x: v.x, y: v.y })))
    polygon.Set(vertices, shape.vertices.length)
    free()
  }
  return polygon
}

function createBody(b2: Box2DModule, world: Box2D.b2World, def: BodyDef, enableSleep: boolean): Box2D.b2Body {
  const bd = new b2.b2BodyDef()
  const position = new b2.b2Vec2(def.position?.x ?? 0, def.position?.y ?? 0)
  const velocity = new b2.b2Vec2(def.linearVelocity?.x ?? 0, def.linearVelocity?.y ?? 0)
  bd.set_type(bodyTypeOf(b2, def.type ?? 'dynamic'))
  bd.set_position(position)
  bd.set_angle(def.angle ?? 0)
  bd.set_linearVelocity(velocity)
  bd.set_angularVelocity(def.angularVelocity ?? 0)
  bd.set_linearDamping(def.linearDamping ?? 0)
  bd.set_angularDamping(def.angularDamping ?? 0)
  bd.set_gravityScale(def.gravityScale ?? 1)
  bd.set_bullet(def.bullet ?? false)
  bd.set_awake(def.awake ?? true)
  bd.set_allowSleep(enableSleep && (def.enableSleep ?? true))
  bd.set_fixedRotation(def.fixedRotation ?? false)
  const body = world.CreateBody(bd)
  b2.destroy(velocity)
  b2.destroy(position)
  b2.destroy(bd)

  const shape = createShape(b2, def.shape)
  const fd = new b2.b2FixtureDef()
  fd.set_shape(shape)
  fd.set_density(def.density ?? 1)
  fd.set_friction(def.friction ?? 0.6)
  fd.set_restitution(def.restitution ?? 0)
  body.CreateFixture(fd)
  b2.destroy(fd)
  b2.destroy(shape)
  return body
}

/** A box2d-wasm world holding the blueprint, sleeping on or off. Build with `create`. */
export class Box2DWasmPeer implements PeerWorld {
  readonly engine = 'box2d-wasm'
  private readonly leaks: Box2D.LeakMitigator
  private readonly bodies: Box2D.b2Body[]
  private world: Box2D.b2World | null
  private ground: Box2D.b2Body | null = null

  private constructor(
    private readonly b2: Box2DModule,
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
  ) {
    this.leaks = new b2.LeakMitigator()
    const gravity = new b2.b2Vec2(blueprint.gravity.x, blueprint.gravity.y)
    const world = new b2.b2World(gravity)
    b2.destroy(gravity)
    world.SetAllowSleeping(enableSleep)
    this.world = world
    this.bodies = blueprint.bodies.map((def) =>
      this.leaks.recordLeak(createBody(b2, world, def, enableSleep)),
    )
    for (const def of blueprint.joints ?? []) this.addJoint(world, def)
  }

  addBody(def: BodyDef): void {
    if (this.world === null) throw new Error('box2d-wasm world used after dispose')
    this.bodies.push(this.leaks.recordLeak(createBody(this.b2, this.world, def, this.enableSleep)))
  }

  /** A revolute joint at the world anchor (angle zero at creation); the world frame is a static body. */
  private addJoint(world: Box2D.b2World, def: JointDef): void {
    if (def.type !== 'revolute')
      throw new Error(`box2d-wasm peer builds revolute joints only, got ${def.type}`)
    const b2 = this.b2
    if (this.ground === null) {
      const bd = new b2.b2BodyDef()
      this.ground = this.leaks.recordLeak(world.CreateBody(bd))
      b2.destroy(bd)
    }
    const jd = new b2.b2RevoluteJointDef()
    const anchor = new b2.b2Vec2(def.anchor.x, def.anchor.y)
    jd.Initialize(def.bodyA === null ? this.ground : this.bodies[def.bodyA], this.bodies[def.bodyB], anchor)
    jd.set_enableLimit(def.enableLimit ?? false)
    jd.set_lowerAngle(def.lowerAngle ?? 0)
    jd.set_upperAngle(def.upperAngle ?? 0)
    jd.set_enableMotor(def.enableMotor ?? false)
    jd.set_motorSpeed(def.motorSpeed ?? 0)
    jd.set_maxMotorTorque(def.maxMotorTorque ?? 0)
    this.leaks.recordLeak(world.CreateJoint(jd))
    b2.destroy(anchor)
    b2.destroy(jd)
  }

  /** Loads the module if needed and builds the blueprint in a new world. */
  static async create(blueprint: SceneBlueprint, enableSleep: boolean): Promise<Box2DWasmPeer> {
    return new Box2DWasmPeer(await loadBox2D(), blueprint, enableSleep)
  }

  step(): void {
    this.world?.Step(STEP, BOX2D_VELOCITY_ITERATIONS, BOX2D_POSITION_ITERATIONS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = this.leaks.recordLeak(body.GetPosition())
      const v = this.leaks.recordLeak(body.GetLinearVelocity())
      out.set([p.x, p.y, v.x, v.y], i * 4)
    })
    return out
  }

  awakeCount(): number {
    let awake = 0
    for (const body of this.bodies) if (body.GetType() !== this.b2.b2_staticBody && body.IsAwake()) awake++
    return awake
  }

  dispose(): void {
    if (this.world === null) return
    this.b2.destroy(this.world)
    this.world = null
    this.bodies.length = 0
    this.leaks.freeLeaked()
  }
}
