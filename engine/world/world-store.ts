/*
 * The world's storage: settings, bodies, contacts and joints in id order, lookups by id, the
 * broadphase proxies, and the scratch arrays of the step. World (world.ts) adds the step and
 * WorldApi (world-api.ts) the public methods; this layer only keeps the containers consistent.
 */

import { BroadPhase, PairBuffer, PairMap, type Shape, VERTEX_X, VERTEX_Y } from '../collision/index.ts'
import { SPECULATIVE_DISTANCE, STEP_SECONDS } from '../constants.ts'
import {
  Body,
  type BodyShape,
  type Contact,
  ContactStore,
  IslandBuilder,
  Softness,
  STATIC,
  StepContext,
} from '../dynamics/index.ts'
import type { Joint } from '../joints/index.ts'
import type { WorldDef } from '../types.ts'
import { EventBuffers } from './events.ts'
import type { SensorState } from './sensor.ts'

/** WorldDef with every field set. */
export type ResolvedWorldDef = Required<WorldDef>

/**
 * The defaults of every world setting. contactHertz is 45, not Box2D's 30: at 30 Hz a 15-box stack
 * dropped with 10 cm gaps leans over and falls within 20 s with sleeping off (top box 0.40 m off at
 * 10 s, 17.8 m at 20 s); at 45 Hz it stands (0.016 m at 10 s, before column contacts) and every other
 * stacking target still holds (see engine/README.md). 45 Hz stays under the clamp of a quarter of the
 * sub-step rate (60 Hz).
 */
export const DEFAULT_WORLD_DEF: Readonly<ResolvedWorldDef> = {
  gravity: { x: 0, y: -10 },
  subSteps: 4,
  enableSleep: true,
  enableContinuous: true,
  contactHertz: 45,
  contactDampingRatio: 10,
  maxContactPushSpeed: 3,
  restitutionThreshold: 1,
  sleepThreshold: 0.05,
  timeToSleep: 0.5,
}

/** The numeric settings, in save order. */
export const SETTINGS_NUMBERS = [
  'contactHertz',
  'contactDampingRatio',
  'maxContactPushSpeed',
  'restitutionThreshold',
  'sleepThreshold',
  'timeToSleep',
] as const

/** Validates a WorldDef and fills in the defaults; throws a RangeError naming a bad value. */
export function resolveWorldDef(def: WorldDef): ResolvedWorldDef {
  const d = { ...DEFAULT_WORLD_DEF, ...def }
  const g = d.gravity
  if (!g || !Number.isFinite(g.x) || !Number.isFinite(g.y))
    throw new RangeError(`gravity must be a finite vector, got ${JSON.stringify(g)}`)
  if (!Number.isInteger(d.subSteps) || d.subSteps < 1 || d.subSteps > 64) {
    throw new RangeError(`subSteps must be an integer in [1, 64], got ${d.subSteps}`)
  }
  for (const key of SETTINGS_NUMBERS) {
    const v = d[key]
    if (typeof v !== 'number' || !Number.isFinite(v) || v < 0)
      throw new RangeError(`${key} must be a finite number >= 0, got ${v}`)
  }
  return {
    ...d,
    gravity: { x: g.x, y: g.y },
    enableSleep: d.enableSleep !== false,
    enableContinuous: d.enableContinuous !== false,
  }
}

/**
 * Storage shared by the world's layers. Its fields are engine-internal (world-state.ts saves and
 * loads them); code outside engine/ uses the World methods.
 */
export class WorldStore {
  readonly settings: ResolvedWorldDef
  gravityX: number
  gravityY: number
  tickCount = 0
  /**
   * Bumped by every step and every public method that changes the world (World.hash() is cached
   * until it changes: a room and its recorder hash the same tick).
   */
  revision = 0
  nextBodyId = 1
  nextJointId = 1
  nextShapeId = 1

  /** Bodies in ascending id order. */
  readonly bodies: Body[] = []
  readonly bodyMap = new Map<number, Body>()
  /** Every body's shapes by id. */
  readonly shapeMap = new Map<number, BodyShape>()
  /** Sensor shapes and what overlaps them, in shape-id order. */
  readonly sensors: SensorState[] = []
  /** The last step's contact and sensor events. */
  readonly events = new EventBuffers()
  /** Bodies with a force or torque to apply at the next step (each once). */
  readonly forced: Body[] = []
  /** Shapes that asked for hit events (the step looks for hits only when some did). */
  hitEventShapes = 0
  /** Contacts in ascending pair-key order. */
  readonly contactArray: Contact[] = []
  /** Contacts by shape-id pair (lower id first). */
  readonly contactMap = new PairMap<Contact>()
  /** The contacts' numbers (contact-record.ts). */
  readonly contactStore = new ContactStore()
  /** Destroyed contacts kept for reuse with their records (a record is never freed). */
  protected readonly contactPool: Contact[] = []
  /** Joints in ascending id order. */
  readonly jointList: Joint[] = []
  readonly jointMap = new Map<number, Joint>()
  /** The fixed world frame that joints with `bodyA: null` attach to (id 0, never in the broadphase). */
  readonly ground = new Body(0, STATIC)

  // Solver sets of the current step, in id order
  protected readonly awake: Body[] = []
  protected awakeCount = 0
  protected readonly activeContacts: Contact[] = []
  protected activeContactCount = 0
  protected readonly activeJoints: Joint[] = []
  protected activeJointCount = 0

  readonly broadPhase = new BroadPhase()
  protected readonly islands = new IslandBuilder()
  protected readonly pairBuffer = new PairBuffer()
  protected readonly contactSoftness = new Softness()
  protected readonly staticSoftness = new Softness()
  /** The solver's per-step scalars (joints read them too). */
  protected readonly stepContext = new StepContext()
  /** Tight AABB scratch: minX, minY, maxX, maxY, then the step's displacement dx, dy. */
  protected readonly aabb = new Float64Array(6)

  constructor(settings: ResolvedWorldDef) {
    this.settings = settings
    this.gravityX = settings.gravity.x
    this.gravityY = settings.gravity.y
    this.ground.awake = false
    this.configureSolver()
  }

  /**
   * Sets the per-step solver scalars and softness from the settings, once: the settings never
   * change, and recomputing them each step would box doubles in calls V8 does not inline.
   */
  private configureSolver(): void {
    const s = this.settings
    const ctx = this.stepContext
    const h = STEP_SECONDS / s.subSteps
    ctx.h = h
    ctx.invH = 1 / h
    ctx.maxPushSpeed = s.maxContactPushSpeed
    ctx.restitutionThreshold = s.restitutionThreshold
    ctx.sleepThreshold = s.sleepThreshold
    // Contact stiffness is clamped to a quarter of the sub-step rate; static contacts are twice as stiff.
    const contactHertz = Math.min(s.contactHertz, 0.25 * ctx.invH)
    this.contactSoftness.set(contactHertz, s.contactDampingRatio, h)
    this.staticSoftness.set(2 * contactHertz, s.contactDampingRatio, h)
    ctx.jointSoftness.set(2 * contactHertz, 2, h)
    ctx.columnStiffness.set(contactHertz, s.contactDampingRatio, h)
  }

  /**
   * Computes a shape's tight AABB on its body, plus the speculative margin if `speculative` (moving
   * bodies), into `aabb`. The margin is chosen here, not passed: a double argument of a call V8 does
   * not inline is a heap number per call (measured: 9 KB per step in the compound scene).
   */
  protected computeAABB(bs: BodyShape, speculative: boolean): void {
    this.computeShapeAABB(bs.body, bs.shape, bs.geometry, speculative)
  }

  /** computeAABB with the shape's body, geometry and layout given (the one-shape path reads them from the body). */
  protected computeShapeAABB(b: Body, shape: Shape, g: Float64Array, speculative: boolean): void {
    const margin = speculative ? SPECULATIVE_DISTANCE : 0
    const out = this.aabb
    let minX = Number.POSITIVE_INFINITY
    let minY = Number.POSITIVE_INFINITY
    let maxX = Number.NEGATIVE_INFINITY
    let maxY = Number.NEGATIVE_INFINITY
    const bx = b.x
    const by = b.y
    const c = b.c
    const s = b.s
    if (shape.type === 'circle') {
      // The centre, from the layout (empty for a circle on the body origin, polygon-geometry.ts);
      // the radius is added below with the margin, as for rounded polygons. One exit for both kinds
      // keeps this function under V8's inlining size (460 bytes of bytecode), so it is inlined
      // into the per-body broadphase pass.
      minX = bx
      minY = by
      if (g.length !== 0) {
        minX += c * g[0] - s * g[1]
        minY += s * g[0] + c * g[1]
      }
      maxX = minX
      maxY = minY
    }
    for (let i = 0; i < shape.count; i++) {
      const vx = g[VERTEX_X + i]
      const vy = g[VERTEX_Y + i]
      const x = bx + c * vx - s * vy
      const y = by + s * vx + c * vy
      if (x < minX) minX = x
      if (y < minY) minY = y
      if (x > maxX) maxX = x
      if (y > maxY) maxY = y
    }
    // A circle, rounded polygon or capsule reaches its radius beyond its centre or vertices (0 for
    // sharp shapes).
    const reach = margin + shape.radius
    out[0] = minX - reach
    out[1] = minY - reach
    out[2] = maxX + reach
    out[3] = maxY + reach
  }

  /** Adds a shape's proxy to the broadphase. */
  protected createProxy(bs: BodyShape): void {
    const isStatic = bs.body.type === STATIC
    this.computeAABB(bs, !isStatic)
    const a = this.aabb
    bs.proxy = this.broadPhase.createProxy(a[0], a[1], a[2], a[3], bs.id, isStatic)
  }

  /**
   * Updates the proxies of a body's shapes after it moved; enlarged proxies are paired at the next
   * step. After a step (`predict`), the fat AABBs also reach ahead along the step's displacement.
   */
  protected moveProxy(b: Body, predict: boolean): void {
    const speculative = b.type !== STATIC
    if (b.shapeCount === 1) {
      // One shape (most bodies): read it from the body, as before bodies had several, without
      // touching the shape object (a cache miss per body per step in a 1,000-body pile).
      this.computeShapeAABB(b, b.shape0, b.geometry0, speculative)
      const a = this.aabb
      a[4] = predict ? b.cx - b.c0x : 0
      a[5] = predict ? b.cy - b.c0y : 0
      this.broadPhase.moveProxyPredicted(b.proxy0, a)
      return
    }
    const shapes = b.shapes
    for (let i = 0; i < shapes.length; i++) {
      const bs = shapes[i]
      this.computeAABB(bs, speculative)
      const a = this.aabb
      a[4] = predict ? b.cx - b.c0x : 0
      a[5] = predict ? b.cy - b.c0y : 0
      this.broadPhase.moveProxyPredicted(bs.proxy, a)
    }
  }

  /** Marks every proxy of a body for pairing at the next step. */
  protected touchProxies(b: Body): void {
    for (const bs of b.shapes) if (bs.proxy >= 0) this.broadPhase.touchProxy(bs.proxy)
  }

  /**
   * Records the end of a touching contact that the API destroys between steps (a destroyed body or
   * shape, a changed filter, a joint that forbids the pair): it is reported by the next step.
   */
  protected endContactLater(c: Contact): void {
    if (c.touching && (c.events & 1) !== 0)
      this.events.addEnd(this.events.pendingEnd, c.shapeA.id, c.shapeB.id)
  }

  /** Removes a contact from the pair map and from both bodies' lists (not from `contacts`). */
  protected unlinkContact(c: Contact): void {
    this.contactMap.delete(c.shapeA.id, c.shapeB.id)
    removeItem(c.bodyA.contacts, c)
    removeItem(c.bodyB.contacts, c)
  }

  /** A body by id, or a RangeError naming the id. */
  protected body(id: number): Body {
    const b = this.bodyMap.get(id)
    if (b === undefined) throw new RangeError(`no body with id ${id}`)
    return b
  }

  /** A shape by id, or a RangeError naming the id. */
  protected bodyShape(id: number): BodyShape {
    const s = this.shapeMap.get(id)
    if (s === undefined) throw new RangeError(`no shape with id ${id}`)
    return s
  }

  /** A joint by id, or a RangeError naming the id. */
  protected joint(id: number): Joint {
    const j = this.jointMap.get(id)
    if (j === undefined) throw new RangeError(`no joint with id ${id}`)
    return j
  }
}

/** Removes one item from an unordered list by swapping in the last element. */
export function removeItem<T>(list: T[], item: T): void {
  const i = list.indexOf(item)
  if (i < 0) return
  list[i] = list[list.length - 1]
  list.pop()
}
