/*
 * Saving, loading and hashing a world.
 *
 * The saved bytes hold everything that influences future steps: settings, id counters, every
 * body (damping, flags, transform, velocity, sleep timer, step-start pose) with its shapes (geometry,
 * material, filter, flags, fat AABB), every contact (by shape ids) with its manifold and accumulated
 * impulses (warm starting), and every joint with
 * its accumulated impulses. The broadphase tree is rebuilt from the saved fat AABBs: the pairs it
 * reports are sorted and depend only on the boxes, so its shape does not matter. A world loaded
 * from these bytes steps bit-identically to the original. The container (header, checksum) is in
 * save-format.ts.
 *
 * The hash is FNV-1a of the payload: it covers exactly the state that a save captures.
 */

import { box, capsule, chainSegmentShape, circle, polygon, type Shape, segment } from '../collision/index.ts'
import {
  Body,
  BodyShape,
  CONTACT_POINT_FIELDS,
  Contact,
  type ContactStore,
  DYNAMIC,
  NORMAL_X,
  POINT_0,
  POINT_FIELDS as RECORD_POINT_FIELDS,
  ROLLING_IMPULSE,
  STATIC,
  updateMassData,
} from '../dynamics/index.ts'
import { JOINT_TYPE_NAMES, Joint } from '../joints/index.ts'
import type { WorldDef } from '../types.ts'
import {
  type ByteReader,
  type ByteWriter,
  beginSave,
  fnv1a,
  HEADER_BYTES,
  openSave,
  sealSave,
  WorldLoadError,
} from './save-format.ts'
import { SensorState } from './sensor.ts'
import { type ResolvedWorldDef, resolveWorldDef, SETTINGS_NUMBERS, type WorldStore } from './world-store.ts'

/** Numbers of one writer call, written with one ByteWriter.f64s (see the writers below). */
const staged = new Float64Array(32)

/**
 * Writes a shape: a kind byte, then its numbers. Kinds: 0 circle at the origin (radius), 1 box
 * (half extents), 2 polygon (count, vertices), 3 circle off the origin (radius, centre), 4 rounded
 * polygon (count, vertices, radius), 5 capsule (centres, radius), 6 segment (points), 7 chain
 * segment (ghost1, point1, point2, ghost2). Kind 7 came with chains inside format 3: a save without
 * chains is byte for byte what it was, and an engine from before chains refuses one with a chain
 * ("unknown shape kind 7").
 */
function writeShape(w: ByteWriter, shape: Shape): void {
  const n = staged
  if (shape.type === 'circle') {
    const c = shape.centroid
    const centred = c.x === 0 && c.y === 0
    w.u8(centred ? 0 : 3)
    n[0] = shape.radius
    n[1] = c.x
    n[2] = c.y
    w.f64s(n, 0, centred ? 1 : 3)
  } else if (shape.type === 'chainSegment') {
    w.u8(7)
    n[0] = shape.ghost1.x
    n[1] = shape.ghost1.y
    n[2] = shape.vertices[0].x
    n[3] = shape.vertices[0].y
    n[4] = shape.vertices[1].x
    n[5] = shape.vertices[1].y
    n[6] = shape.ghost2.x
    n[7] = shape.ghost2.y
    w.f64s(n, 0, 8)
  } else if (shape.type === 'capsule' || shape.type === 'segment') {
    const capsule = shape.type === 'capsule'
    w.u8(capsule ? 5 : 6)
    n[0] = shape.vertices[0].x
    n[1] = shape.vertices[0].y
    n[2] = shape.vertices[1].x
    n[3] = shape.vertices[1].y
    n[4] = shape.radius
    w.f64s(n, 0, capsule ? 5 : 4)
  } else if (shape.radius > 0) {
    w.u8(4)
    w.u8(shape.count)
    for (let i = 0; i < shape.count; i++) {
      n[2 * i] = shape.vertices[i].x
      n[2 * i + 1] = shape.vertices[i].y
    }
    n[2 * shape.count] = shape.radius
    w.f64s(n, 0, 2 * shape.count + 1)
  } else if (shape.box !== null) {
    w.u8(1)
    n[0] = shape.box.halfWidth
    n[1] = shape.box.halfHeight
    w.f64s(n, 0, 2)
  } else {
    w.u8(2)
    w.u8(shape.count)
    for (let i = 0; i < shape.count; i++) {
      n[2 * i] = shape.vertices[i].x
      n[2 * i + 1] = shape.vertices[i].y
    }
    w.f64s(n, 0, 2 * shape.count)
  }
}

/** Reads a shape, rebuilding it with the same constructors (so the same validation applies). */
function readShape(r: ByteReader): Shape {
  const kind = r.u8('shape kind')
  try {
    if (kind === 0) return circle(r.num('circle radius'))
    if (kind === 1) return box(r.num('box half width'), r.num('box half height'))
    if (kind === 2 || kind === 4) {
      const n = r.u8('polygon vertex count')
      const points = []
      for (let i = 0; i < n; i++) points.push({ x: r.num('polygon vertex'), y: r.num('polygon vertex') })
      return kind === 2 ? polygon(points) : polygon(points, r.num('polygon radius'))
    }
    if (kind === 3) {
      const radius = r.num('circle radius')
      return circle(radius, { x: r.num('circle center'), y: r.num('circle center') })
    }
    if (kind === 5 || kind === 6) {
      const p1 = { x: r.num('segment point'), y: r.num('segment point') }
      const p2 = { x: r.num('segment point'), y: r.num('segment point') }
      return kind === 5 ? capsule(p1, p2, r.num('capsule radius')) : segment(p1, p2)
    }
    if (kind === 7) {
      const points = []
      for (let i = 0; i < 4; i++)
        points.push({ x: r.num('chain segment point'), y: r.num('chain segment point') })
      return chainSegmentShape(points[0], points[1], points[2], points[3])
    }
  } catch (e) {
    if (e instanceof WorldLoadError) throw e
    throw new WorldLoadError(`saved world has an invalid shape: ${(e as Error).message}`)
  }
  throw new WorldLoadError(`saved world has an unknown shape kind ${kind}`)
}

/** Body state fields in saved order (after the flags byte). */
export const BODY_STATE_FIELDS = [
  'x',
  'y',
  'cx',
  'cy',
  'c',
  's',
  'vx',
  'vy',
  'w',
  'sleepTime',
  'c0x',
  'c0y',
  'q0c',
  'q0s',
  'fx',
  'fy',
  'torque',
] as const
/** Body material fields in saved order (after the type). */
export const BODY_MATERIAL_FIELDS = ['linearDamping', 'angularDamping', 'gravityScale'] as const
/** Shape fields in saved order (after the geometry). */
export const SHAPE_FIELDS = [
  'density',
  'friction',
  'restitution',
  'rollingResistance',
  'tangentSpeed',
  'categoryBits',
  'maskBits',
  'groupIndex',
] as const
/** Contact point fields in saved order, for point 0 and point 1. */
export const POINT_FIELDS = [
  CONTACT_POINT_FIELDS.map((f) => `${f}0` as const),
  CONTACT_POINT_FIELDS.map((f) => `${f}1` as const),
]
/** Joint fields in saved order (after the flags byte). */
export const JOINT_FIELDS = [
  'localAnchorAx',
  'localAnchorAy',
  'localAnchorBx',
  'localAnchorBy',
  'referenceAngle',
  'lowerAngle',
  'upperAngle',
  'motorSpeed',
  'maxMotorTorque',
  'length',
  'minLength',
  'maxLength',
  'hertz',
  'dampingRatio',
  'targetX',
  'targetY',
  'maxForce',
  'linearImpulseX',
  'linearImpulseY',
  'impulse',
  'lowerImpulse',
  'upperImpulse',
  'motorImpulse',
] as const
/**
 * Joint fields of the kinds and settings added in save format 2 (weld, prismatic, wheel, motor
 * joints; springs on revolute joints, motors on distance joints, break thresholds), in saved order.
 * A joint writes them (flags bit 3) only when it is a new kind or one of them differs from its
 * default, so a world of the first three kinds saves, and hashes, exactly as in format 1.
 */
export const JOINT_EXTRA_FIELDS = [
  'angularHertz',
  'angularDampingRatio',
  'localAxisAx',
  'localAxisAy',
  'lowerTranslation',
  'upperTranslation',
  'maxMotorForce',
  'springTarget',
  'linearOffsetX',
  'linearOffsetY',
  'angularOffset',
  'maxTorque',
  'correctionFactor',
  'lastOffsetX',
  'lastOffsetY',
  'lastAngularOffset',
  'breakForce',
  'breakTorque',
  'angularImpulse',
  'springImpulse',
] as const
/** Highest joint kind code (joint-math.ts MOTOR). */
const LAST_JOINT_TYPE = 6

/*
 * The writers below name every field (in the order of the lists above) instead of looping over the
 * lists: a loop reads `b[f]` with a changing key, which V8 cannot specialize, and a save or hash
 * then costs 3x as much (a room hashes its world every second). The readers loop over the lists;
 * tests/engine/save-writers.test.ts checks that the writers follow the lists. The numbers are
 * staged in a Float64Array and written with one f64s call per run: a double passed to a ByteWriter
 * call that V8 did not inline was a heap number each (about 3 KB per hash of a 100-body pile).
 */

/** Writes a body's definition and state (its shapes come after it). */
export function writeBody(w: ByteWriter, b: Body): void {
  const n = staged
  w.f64(b.id)
  w.u8(b.type)
  n[0] = b.linearDamping
  n[1] = b.angularDamping
  n[2] = b.gravityScale
  w.f64s(n, 0, 3)
  w.u8((b.bullet ? 1 : 0) | (b.enableSleep ? 2 : 0) | (b.fixedRotation ? 4 : 0) | (b.awake ? 8 : 0))
  n[0] = b.x
  n[1] = b.y
  n[2] = b.cx
  n[3] = b.cy
  n[4] = b.c
  n[5] = b.s
  n[6] = b.vx
  n[7] = b.vy
  n[8] = b.w
  n[9] = b.sleepTime
  n[10] = b.c0x
  n[11] = b.c0y
  n[12] = b.q0c
  n[13] = b.q0s
  n[14] = b.fx
  n[15] = b.fy
  n[16] = b.torque
  w.f64s(n, 0, 17)
}

/** Writes a shape on a body (its fat AABB comes separately). */
export function writeBodyShape(w: ByteWriter, s: BodyShape): void {
  const n = staged
  w.f64(s.id)
  writeShape(w, s.shape)
  n[0] = s.density
  n[1] = s.friction
  n[2] = s.restitution
  n[3] = s.rollingResistance
  n[4] = s.tangentSpeed
  n[5] = s.categoryBits
  n[6] = s.maskBits
  n[7] = s.groupIndex
  w.f64s(n, 0, 8)
  w.u8(
    (s.sensor ? 1 : 0) |
      (s.enableSensorEvents ? 2 : 0) |
      (s.enableContactEvents ? 4 : 0) |
      (s.enableHitEvents ? 8 : 0),
  )
}

/** Reads a shape written by writeBodyShape, for `body`. */
function readBodyShape(r: ByteReader, body: Body): BodyShape {
  const id = r.num('shape id')
  const s = new BodyShape(id, body, readShape(r))
  for (const f of SHAPE_FIELDS) s[f] = r.num(`shape ${id} ${f}`)
  const flags = r.u8('shape flags')
  s.sensor = (flags & 1) !== 0
  s.enableSensorEvents = (flags & 2) !== 0
  s.enableContactEvents = (flags & 4) !== 0
  s.enableHitEvents = (flags & 8) !== 0
  if (s.sensor && s.shape.type === 'chainSegment')
    throw new WorldLoadError(`saved world has chain segment ${id} as a sensor`)
  return s
}

/** Reads a body written by writeBody (its shapes and mass properties are added by the caller). */
function readBody(r: ByteReader): Body {
  const id = r.num('body id')
  const type = r.u8('body type')
  if (type > 2) throw new WorldLoadError(`saved world has body ${id} of unknown type ${type}`)
  const body = new Body(id, type)
  for (const f of BODY_MATERIAL_FIELDS) body[f] = r.num(`body ${id} ${f}`)
  const flags = r.u8('body flags')
  body.bullet = (flags & 1) !== 0
  body.enableSleep = (flags & 2) !== 0
  body.fixedRotation = (flags & 4) !== 0
  body.awake = (flags & 8) !== 0
  for (const f of BODY_STATE_FIELDS) body[f] = r.num(`body ${id} ${f}`)
  return body
}

/** Writes a contact (shapes by id). */
export function writeContact(w: ByteWriter, c: Contact): void {
  // The record holds the normal and each point's fields in save order (contact-record.ts).
  const d = c.store.data
  const o = c.base
  w.f64(c.shapeA.id)
  w.f64(c.shapeB.id)
  // Bit 1: touching; bit 2: a rolling impulse follows (only then, so that worlds without rolling
  // resistance save, and hash, exactly as before it existed).
  const rolling = d[o + ROLLING_IMPULSE]
  w.u8((c.touching ? 1 : 0) | (rolling !== 0 ? 2 : 0))
  w.u8(c.pointCount)
  w.f64s(d, o + NORMAL_X, 2)
  if (c.pointCount > 0) w.f64s(d, o + POINT_0, RECORD_POINT_FIELDS)
  if (c.pointCount > 1) w.f64s(d, o + POINT_0 + RECORD_POINT_FIELDS, RECORD_POINT_FIELDS)
  if (rolling !== 0) w.f64(rolling)
}

/** Reads a contact written by writeContact. */
function readContact(r: ByteReader, shapes: Map<number, BodyShape>, store: ContactStore): Contact {
  const idA = r.num('contact shape A')
  const idB = r.num('contact shape B')
  const a = shapes.get(idA)
  const b = shapes.get(idB)
  if (a === undefined || b === undefined)
    throw new WorldLoadError(`saved world has a contact of missing shape ${a === undefined ? idA : idB}`)
  if (a.id >= b.id)
    throw new WorldLoadError(`saved world has a contact with shapes out of order (${a.id}, ${b.id})`)
  if (a.body === b.body)
    throw new WorldLoadError(`saved world has a contact between shapes of one body ${a.body.id}`)
  const c = new Contact(a, b, store)
  const flags = r.u8('contact flags')
  if (flags > 3) throw new WorldLoadError(`saved world has a contact with flags ${flags}`)
  c.touching = (flags & 1) !== 0
  c.pointCount = r.u8('contact point count')
  if (c.pointCount > 2) throw new WorldLoadError(`saved world has a contact with ${c.pointCount} points`)
  c.normalX = r.num('contact normal')
  c.normalY = r.num('contact normal')
  for (let j = 0; j < c.pointCount; j++) {
    for (const f of POINT_FIELDS[j]) c[f] = r.num(`contact point ${f}`)
  }
  if ((flags & 2) !== 0) c.rollingImpulse = r.num('contact rolling impulse')
  return c
}

/** Writes a joint (bodies by id; the world frame is id 0). */
export function writeJoint(w: ByteWriter, j: Joint): void {
  const n = staged
  w.f64(j.id)
  w.u8(j.type)
  w.f64(j.bodyA.id)
  w.f64(j.bodyB.id)
  const extra = hasExtraFields(j)
  w.u8(
    (j.enableLimit ? 1 : 0) |
      (j.enableMotor ? 2 : 0) |
      (j.collideConnected ? 4 : 0) |
      (extra ? 8 : 0) |
      (j.enableSpring ? 16 : 0),
  )
  n[0] = j.localAnchorAx
  n[1] = j.localAnchorAy
  n[2] = j.localAnchorBx
  n[3] = j.localAnchorBy
  n[4] = j.referenceAngle
  n[5] = j.lowerAngle
  n[6] = j.upperAngle
  n[7] = j.motorSpeed
  n[8] = j.maxMotorTorque
  n[9] = j.length
  n[10] = j.minLength
  n[11] = j.maxLength
  n[12] = j.hertz
  n[13] = j.dampingRatio
  n[14] = j.targetX
  n[15] = j.targetY
  n[16] = j.maxForce
  n[17] = j.linearImpulseX
  n[18] = j.linearImpulseY
  n[19] = j.impulse
  n[20] = j.lowerImpulse
  n[21] = j.upperImpulse
  n[22] = j.motorImpulse
  w.f64s(n, 0, 23)
  if (!extra) return
  // Explicit reads in JOINT_EXTRA_FIELDS order: a keyed read (j[name]) boxes each double.
  n[0] = j.angularHertz
  n[1] = j.angularDampingRatio
  n[2] = j.localAxisAx
  n[3] = j.localAxisAy
  n[4] = j.lowerTranslation
  n[5] = j.upperTranslation
  n[6] = j.maxMotorForce
  n[7] = j.springTarget
  n[8] = j.linearOffsetX
  n[9] = j.linearOffsetY
  n[10] = j.angularOffset
  n[11] = j.maxTorque
  n[12] = j.correctionFactor
  n[13] = j.lastOffsetX
  n[14] = j.lastOffsetY
  n[15] = j.lastAngularOffset
  n[16] = j.breakForce
  n[17] = j.breakTorque
  n[18] = j.angularImpulse
  n[19] = j.springImpulse
  w.f64s(n, 0, JOINT_EXTRA_FIELDS.length)
}

/** Whether a joint needs the format-2 fields: a new kind, a spring, or any of them not at its default. */
function hasExtraFields(j: Joint): boolean {
  return (
    j.type > 2 ||
    j.enableSpring ||
    j.angularHertz !== 0 ||
    j.angularDampingRatio !== 0 ||
    j.localAxisAx !== 1 ||
    j.localAxisAy !== 0 ||
    j.lowerTranslation !== 0 ||
    j.upperTranslation !== 0 ||
    j.maxMotorForce !== 0 ||
    j.springTarget !== 0 ||
    j.linearOffsetX !== 0 ||
    j.linearOffsetY !== 0 ||
    j.angularOffset !== 0 ||
    j.maxTorque !== 0 ||
    j.correctionFactor !== 0 ||
    j.lastOffsetX !== 0 ||
    j.lastOffsetY !== 0 ||
    j.lastAngularOffset !== 0 ||
    j.breakForce !== Number.POSITIVE_INFINITY ||
    j.breakTorque !== Number.POSITIVE_INFINITY ||
    j.angularImpulse !== 0 ||
    j.springImpulse !== 0
  )
}

/** Reads a joint written by writeJoint. */
function readJoint(r: ByteReader, lookup: (id: number) => Body): Joint {
  const id = r.num('joint id')
  const type = r.u8('joint type')
  if (type > LAST_JOINT_TYPE) throw new WorldLoadError(`saved world has joint ${id} of unknown type ${type}`)
  const a = lookup(r.num('joint body A'))
  const b = lookup(r.num('joint body B'))
  const j = new Joint(id, type, a, b)
  const flags = r.u8('joint flags')
  j.enableLimit = (flags & 1) !== 0
  j.enableMotor = (flags & 2) !== 0
  j.collideConnected = (flags & 4) !== 0
  j.enableSpring = (flags & 16) !== 0
  for (const f of JOINT_FIELDS) j[f] = r.num(`joint ${id} ${f}`)
  if ((flags & 8) !== 0) {
    for (const f of JOINT_EXTRA_FIELDS) {
      const what = `joint ${id} ${f}`
      // Break thresholds are +Infinity by default (never); everything else is finite.
      const v = f === 'breakForce' || f === 'breakTorque' ? r.f64(what) : r.num(what)
      if (!(v >= 0 || (f !== 'breakForce' && f !== 'breakTorque')))
        throw new WorldLoadError(`saved world has a negative or NaN ${what}: ${v}`)
      j[f] = v
    }
  } else if (type > 2)
    throw new WorldLoadError(`saved world has ${JOINT_TYPE_NAMES[type]} joint ${id} without its fields`)
  return j
}

/** Writes the whole world's payload (after the header) into `w`. */
function writeWorld(w: ByteWriter, world: WorldStore): void {
  beginSave(w)
  const s = world.settings
  w.f64(world.gravityX)
  w.f64(world.gravityY)
  w.u32(s.subSteps)
  w.u8((s.enableSleep ? 1 : 0) | (s.enableContinuous ? 2 : 0))
  for (const key of SETTINGS_NUMBERS) w.f64(s[key])
  w.f64(world.tickCount)
  w.f64(world.nextBodyId)
  w.f64(world.nextJointId)
  w.f64(world.nextShapeId)
  w.u32(world.bodies.length)
  for (const b of world.bodies) {
    writeBody(w, b)
    const shapes = b.shapes
    w.u32(shapes.length)
    for (let i = 0; i < shapes.length; i++) {
      writeBodyShape(w, shapes[i])
      world.broadPhase.getFatAABB(shapes[i].proxy, fatAABB)
      w.f64s(fatAABB, 0, 4)
    }
  }
  w.u32(world.contactArray.length)
  for (const c of world.contactArray) writeContact(w, c)
  w.u32(world.jointList.length)
  for (const j of world.jointList) writeJoint(w, j)
  // What each sensor saw after the last step (the next step's sensor events depend on it).
  w.u32(world.sensors.length)
  for (const state of world.sensors) {
    w.f64(state.shape.id)
    w.u32(state.count)
    for (let i = 0; i < state.count; i++) w.f64(state.visitors[i])
  }
}
const fatAABB = new Float64Array(4)

/** The world's saved bytes: header, checksum and payload. */
export function saveWorld(w: ByteWriter, world: WorldStore): Uint8Array {
  writeWorld(w, world)
  return sealSave(w)
}

/** A 32-bit unsigned FNV-1a hash of the world's payload (what saveWorld writes). */
export function hashWorld(w: ByteWriter, world: WorldStore): number {
  writeWorld(w, world)
  return fnv1a(w.bytes, HEADER_BYTES, w.length)
}

/** Rebuilds a world from saved bytes; `make` creates the empty world from its settings. */
export function loadWorldState<T extends WorldStore>(
  bytes: Uint8Array,
  make: (settings: ResolvedWorldDef) => T,
): T {
  const r = openSave(bytes)
  const gravity = { x: r.num('gravity'), y: r.num('gravity') }
  const subSteps = r.u32('subSteps')
  const flags = r.u8('world flags')
  const def: WorldDef = {
    gravity,
    subSteps,
    enableSleep: (flags & 1) !== 0,
    enableContinuous: (flags & 2) !== 0,
  }
  for (const key of SETTINGS_NUMBERS) def[key] = r.num(key)
  let world: T
  try {
    world = make(resolveWorldDef(def))
  } catch (e) {
    throw new WorldLoadError(`saved world has invalid settings: ${(e as Error).message}`)
  }
  world.tickCount = r.num('tick')
  world.nextBodyId = r.num('next body id')
  world.nextJointId = r.num('next joint id')
  world.nextShapeId = r.num('next shape id')
  readBodies(r, world)
  const lookup = (id: number): Body => {
    const b = id === 0 ? world.ground : world.bodyMap.get(id)
    if (b === undefined) throw new WorldLoadError(`saved world refers to missing body ${id}`)
    return b
  }
  world.sensors.sort((a, b) => a.shape.id - b.shape.id)
  readContacts(r, world)
  readJoints(r, world, lookup)
  readSensors(r, world)
  r.finish()
  return world
}

function readBodies(r: ByteReader, world: WorldStore): void {
  const count = r.u32('body count')
  let lastId = 0
  // Shape ids rise within a body (a body's shapes are listed in creation order).
  let lastShapeId = 0
  for (let i = 0; i < count; i++) {
    const b = readBody(r)
    if (!(b.id > lastId) || b.id >= world.nextBodyId || !Number.isInteger(b.id)) {
      throw new WorldLoadError(`saved world has an invalid or out-of-order body id ${b.id}`)
    }
    lastId = b.id
    const shapeCount = r.u32('shape count')
    for (let k = 0; k < shapeCount; k++) {
      const s = readBodyShape(r, b)
      if (
        !(s.id > lastShapeId) ||
        s.id >= world.nextShapeId ||
        !Number.isInteger(s.id) ||
        world.shapeMap.has(s.id)
      ) {
        throw new WorldLoadError(`saved world has an invalid, repeated or out-of-order shape id ${s.id}`)
      }
      lastShapeId = s.id
      const box = [r.num('fat AABB'), r.num('fat AABB'), r.num('fat AABB'), r.num('fat AABB')]
      s.proxy = world.broadPhase.createProxyWithFatAABB(
        box[0],
        box[1],
        box[2],
        box[3],
        s.id,
        b.type === STATIC,
      )
      // Every proxy is queried at the next step; pairs that already have a contact are skipped.
      world.broadPhase.touchProxy(s.proxy)
      b.shapes.push(s)
      world.shapeMap.set(s.id, s)
      if (s.enableHitEvents) world.hitEventShapes++
      if (s.sensor) world.sensors.push(new SensorState(s))
    }
    lastShapeId = 0
    b.syncShapes()
    if (b.type === DYNAMIC && !b.shapes.some((s) => s.shape.type !== 'segment'))
      throw new WorldLoadError(`saved world has dynamic body ${b.id} without a shape with mass`)
    if (b.type !== STATIC && b.shapes.some((s) => s.shape.type === 'chainSegment'))
      throw new WorldLoadError(`saved world has a chain on body ${b.id}, which is not static`)
    updateMassData(b)
    if (b.fx !== 0 || b.fy !== 0 || b.torque !== 0) world.forced.push(b)
    world.bodies.push(b)
    world.bodyMap.set(b.id, b)
  }
}

function readContacts(r: ByteReader, world: WorldStore): void {
  const contactCount = r.u32('contact count')
  for (let i = 0; i < contactCount; i++) {
    const c = readContact(r, world.shapeMap, world.contactStore)
    if (world.contactMap.has(c.shapeA.id, c.shapeB.id))
      throw new WorldLoadError(`saved world has a duplicate contact ${c.shapeA.id}-${c.shapeB.id}`)
    if (i > 0 && world.contactArray[i - 1].key > c.key)
      throw new WorldLoadError('saved world has contacts out of order')
    world.contactArray.push(c)
    world.contactMap.set(c.shapeA.id, c.shapeB.id, c)
    c.bodyA.contacts.push(c)
    c.bodyB.contacts.push(c)
  }
}

function readJoints(r: ByteReader, world: WorldStore, lookup: (id: number) => Body): void {
  const jointCount = r.u32('joint count')
  for (let i = 0; i < jointCount; i++) {
    const j = readJoint(r, lookup)
    if (world.jointMap.has(j.id) || j.id >= world.nextJointId)
      throw new WorldLoadError(`saved world has an invalid joint id ${j.id}`)
    world.jointList.push(j)
    world.jointMap.set(j.id, j)
    j.bodyA.joints.push(j)
    j.bodyB.joints.push(j)
  }
}

function readSensors(r: ByteReader, world: WorldStore): void {
  const count = r.u32('sensor count')
  if (count !== world.sensors.length)
    throw new WorldLoadError(`saved world lists ${count} sensors for ${world.sensors.length} sensor shapes`)
  for (const state of world.sensors) {
    const id = r.num('sensor id')
    if (id !== state.shape.id)
      throw new WorldLoadError(`saved world has sensor ${id} where ${state.shape.id} was expected`)
    const n = r.u32('sensor visitor count')
    let last = 0
    for (let i = 0; i < n; i++) {
      const v = r.num('sensor visitor')
      if (!(v > last) || !Number.isInteger(v))
        throw new WorldLoadError(`saved world has sensor ${id} visitor ${v} out of order`)
      last = v
      state.visitors[i] = v
    }
    state.count = n
  }
}
