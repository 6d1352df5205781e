/*
 * box2d3-wasm (Box2D v3, Erin Catto's current solver, compiled to WebAssembly) as a benchmark peer,
 * in either of the package's two builds (see Box2D3Build).
 *
 * The package's entry picks its 'deluxe' build (SIMD and pthreads) where SIMD validates and, in a
 * browser, the page is cross-origin isolated; otherwise its 'compat' build. The 'box2d3-wasm-compat'
 * peer loads the compat build's module directly, so in Node the two peers compare Box2D v3 with and
 * without WebAssembly SIMD (the deluxe build is also the threaded one: shared memory and atomics).
 * In a page that is not cross-origin isolated both peers run the compat build. Either way the
 * world keeps Box2D v3's default workerCount (0: one thread), so it is compared single-threaded
 * like every other engine here. The deluxe thread pool is sized from navigator.hardwareConcurrency,
 * which Node 20 lacks, so we supply it from os.cpus() as the package's own integration test does.
 *
 * Bodies carry the blueprint's type, origin, angle, velocities, damping and flags, and one shape
 * with the same geometry (b2MakeBox for boxes, b2ComputeHull + b2MakePolygon for other polygons,
 * radius 0), density (default 1), friction (default 0.6) and restitution (default 0). Revolute
 * joints pin the two bodies at the blueprint's world anchor, with the joint angle zero at creation;
 * a joint to the world (bodyA null) uses one static body at the origin. The world steps 1/60 s
 * with 4 sub-steps (Box2D v3's documented default) and every other world setting at its default.
 * Embind handles we create are deleted as soon as Box2D has copied them.
 */
import type { BodyDef, JointDef, SceneBlueprint } from '../../engine/index.ts'
import type { PeerWorld } from '../stats.ts'
import { inNode, wasmLocator } from './wasm-location.ts'

/** Box2D v3 sub-steps per 1/60 s step (its documented default). */
export const BOX2D3_SUB_STEPS = 4

const STEP = 1 / 60

/** The module factory (the package's typings export it with `export =`). */
type Box2D3Factory = typeof import('box2d3-wasm')
type Box2D3 = Awaited<ReturnType<Box2D3Factory>>
type BodyId = ReturnType<Box2D3['b2CreateBody']>
type WorldId = ReturnType<Box2D3['b2CreateWorld']>

/**
 * Which build a peer runs: 'entry' is the package entry's choice (deluxe in Node: SIMD, pthreads),
 * 'compat' its build without SIMD or threads, loaded directly.
 */
export type Box2D3Build = 'entry' | 'compat'

/** The peer's engine name for each build. */
export const BOX2D3_ENGINES = { entry: 'box2d3-wasm', compat: 'box2d3-wasm-compat' } as const

const modules = new Map<Box2D3Build, Promise<Box2D3>>()

/** The build's module factory. */
async function factoryOf(build: Box2D3Build): Promise<Box2D3Factory> {
  if (build === 'entry') return (await import('box2d3-wasm')).default
  // The package exports only its entry, so the compat module is imported by its path. Node loads
  // the package's own file, found beside the entry Node resolves (a copy inside a bench bundle
  // would look for its .wasm beside the bundle). A page loads it by a literal path that esbuild
  // bundles (TypeScript pairs a .mjs only with a .d.mts; Box2D.compat.d.ts matches the entry's).
  const compat: { default: Box2D3Factory } = inNode()
    ? await import(new URL('./compat/Box2D.compat.mjs', import.meta.resolve('box2d3-wasm')).href)
    : // @ts-expect-error TS7016: no .d.mts beside Box2D.compat.mjs
      await import('../../node_modules/box2d3-wasm/build/dist/es/compat/Box2D.compat.mjs')
  return compat.default
}

/** Loads one build of the box2d3-wasm module once (later calls share it). */
export function loadBox2D3(build: Box2D3Build = 'entry'): Promise<Box2D3> {
  let loading = modules.get(build)
  if (loading === undefined) {
    loading = (async () => {
      const scope = globalThis as { navigator?: { hardwareConcurrency?: number } }
      if (inNode()) {
        const { cpus } = await import('node:os')
        scope.navigator ??= {}
        scope.navigator.hardwareConcurrency ??= cpus().length
      }
      const factory = await factoryOf(build)
      const locate = wasmLocator()
      return factory(locate && !inNode() ? { locateFile: (file: string) => locate(file) } : {})
    })()
    modules.set(build, loading)
  }
  return loading
}

function bodyType(b2: Box2D3, def: BodyDef) {
  const type = def.type ?? 'dynamic'
  if (type === 'static') return b2.b2BodyType.b2_staticBody
  if (type === 'kinematic') return b2.b2BodyType.b2_kinematicBody
  return b2.b2BodyType.b2_dynamicBody
}

function createBody(b2: Box2D3, world: WorldId, def: BodyDef, enableSleep: boolean): BodyId {
  const bd = b2.b2DefaultBodyDef()
  const position = new b2.b2Vec2(def.position?.x ?? 0, def.position?.y ?? 0)
  const velocity = new b2.b2Vec2(def.linearVelocity?.x ?? 0, def.linearVelocity?.y ?? 0)
  const rotation = b2.b2MakeRot(def.angle ?? 0)
  bd.type = bodyType(b2, def)
  bd.position = position
  bd.rotation = rotation
  bd.linearVelocity = velocity
  bd.angularVelocity = def.angularVelocity ?? 0
  bd.linearDamping = def.linearDamping ?? 0
  bd.angularDamping = def.angularDamping ?? 0
  bd.gravityScale = def.gravityScale ?? 1
  bd.isBullet = def.bullet ?? false
  bd.isAwake = def.awake ?? true
  bd.enableSleep = enableSleep && (def.enableSleep ?? true)
  if (def.fixedRotation) {
    const locks = bd.motionLocks
    locks.angularZ = true
    bd.motionLocks = locks
    locks.delete()
  }
  const body = b2.b2CreateBody(world, bd)
  for (const handle of [bd, position, velocity, rotation]) handle.delete()

  const sd = b2.b2DefaultShapeDef()
  const material = sd.material
  material.friction = def.friction ?? 0.6
  material.restitution = def.restitution ?? 0
  sd.material = material
  material.delete()
  sd.density = def.density ?? 1
  const shape = def.shape
  if (shape.type === 'circle') {
    const c = new b2.b2Circle()
    const center = new b2.b2Vec2(0, 0)
    c.center = center
    c.radius = shape.radius
    b2.b2CreateCircleShape(body, sd, c)
    center.delete()
    c.delete()
  } else {
    let polygon: ReturnType<Box2D3['b2MakeBox']>
    if (shape.box) {
      polygon = b2.b2MakeBox(shape.box.halfWidth, shape.box.halfHeight)
    } else {
      const points = shape.vertices.map((v) => new b2.b2Vec2(v.x, v.y))
      const hull = b2.b2ComputeHull(points)
      for (const p of points) p.delete()
      if (hull.count !== shape.vertices.length) {
        throw new Error(`box2d3-wasm hull kept ${hull.count} of ${shape.vertices.length} vertices`)
      }
      polygon = b2.b2MakePolygon(hull, 0)
      hull.delete()
    }
    b2.b2CreatePolygonShape(body, sd, polygon)
    polygon.delete()
  }
  sd.delete()
  return body
}

/** A box2d3-wasm world (either build) holding the blueprint, sleeping on or off. Build with `create`. */
export class Box2D3WasmPeer implements PeerWorld {
  readonly engine: (typeof BOX2D3_ENGINES)[Box2D3Build]
  private readonly bodies: BodyId[] = []
  private world: WorldId | null
  private ground: BodyId | null = null

  private constructor(
    private readonly b2: Box2D3,
    blueprint: SceneBlueprint,
    private readonly enableSleep: boolean,
    build: Box2D3Build,
  ) {
    this.engine = BOX2D3_ENGINES[build]
    const wd = b2.b2DefaultWorldDef()
    const gravity = new b2.b2Vec2(blueprint.gravity.x, blueprint.gravity.y)
    wd.gravity = gravity
    wd.enableSleep = enableSleep
    this.world = b2.b2CreateWorld(wd)
    gravity.delete()
    wd.delete()
    for (const def of blueprint.bodies) this.addBody(def)
    for (const def of blueprint.joints ?? []) this.addJoint(def)
  }

  /** Loads the build's module if needed and builds the blueprint in a new world. */
  static async create(
    blueprint: SceneBlueprint,
    enableSleep: boolean,
    build: Box2D3Build = 'entry',
  ): Promise<Box2D3WasmPeer> {
    return new Box2D3WasmPeer(await loadBox2D3(build), blueprint, enableSleep, build)
  }

  private live(): WorldId {
    if (this.world === null) throw new Error(`${this.engine} world used after dispose`)
    return this.world
  }

  addBody(def: BodyDef): void {
    this.bodies.push(createBody(this.b2, this.live(), def, this.enableSleep))
  }

  private worldBody(): BodyId {
    if (this.ground === null) {
      // A static body with no shape: the world frame, colliding with nothing.
      const bd = this.b2.b2DefaultBodyDef()
      this.ground = this.b2.b2CreateBody(this.live(), bd)
      bd.delete()
    }
    return this.ground
  }

  private addJoint(def: JointDef): void {
    if (def.type !== 'revolute')
      throw new Error(`${this.engine} peer builds revolute joints only, got ${def.type}`)
    const b2 = this.b2
    const bodyA = def.bodyA === null ? this.worldBody() : this.bodies[def.bodyA]
    const bodyB = this.bodies[def.bodyB]
    const jd = b2.b2DefaultRevoluteJointDef()
    const base = jd.base
    const anchor = new b2.b2Vec2(def.anchor.x, def.anchor.y)
    for (const [body, side] of [
      [bodyA, 'localFrameA'],
      [bodyB, 'localFrameB'],
    ] as const) {
      const frame = base[side]
      const local = b2.b2Body_GetLocalPoint(body, anchor)
      const q = b2.b2Body_GetRotation(body)
      const inverse = b2.b2MakeRot(-b2.b2Rot_GetAngle(q))
      frame.p = local
      frame.q = inverse
      base[side] = frame
      for (const handle of [frame, local, q, inverse]) handle.delete()
    }
    base.bodyIdA = bodyA
    base.bodyIdB = bodyB
    jd.base = base
    jd.enableLimit = def.enableLimit ?? false
    jd.lowerAngle = def.lowerAngle ?? 0
    jd.upperAngle = def.upperAngle ?? 0
    jd.enableMotor = def.enableMotor ?? false
    jd.motorSpeed = def.motorSpeed ?? 0
    jd.maxMotorTorque = def.maxMotorTorque ?? 0
    b2.b2CreateRevoluteJoint(this.live(), jd)
    base.delete()
    anchor.delete()
    jd.delete()
  }

  step(): void {
    this.b2.b2World_Step(this.live(), STEP, BOX2D3_SUB_STEPS)
  }

  readBodies(): Float64Array {
    const out = new Float64Array(this.bodies.length * 4)
    this.bodies.forEach((body, i) => {
      const p = this.b2.b2Body_GetPosition(body)
      const v = this.b2.b2Body_GetLinearVelocity(body)
      out.set([p.x, p.y, v.x, v.y], i * 4)
      p.delete()
      v.delete()
    })
    return out
  }

  awakeCount(): number {
    return this.b2.b2World_GetAwakeBodyCount(this.live())
  }

  dispose(): void {
    if (this.world === null) return
    this.b2.b2DestroyWorld(this.world)
    this.world = null
    this.bodies.length = 0
  }
}
