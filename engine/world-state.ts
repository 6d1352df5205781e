/*
 * Saving, loading and hashing a world.
 *
 * The saved bytes hold everything that influences future steps: settings, id counters, every
 * body (shape, material, flags, transform, velocity, sleep timer, step-start pose, fat AABB),
 * every contact with its manifold and accumulated impulses (warm starting), and every joint with
 * its accumulated impulses. The broadphase tree is rebuilt from the saved fat AABBs: the pairs it
 * reports are sorted and depend only on the boxes, so its shape does not matter. A world loaded
 * from these bytes steps bit-identically to the original.
 *
 * Format (little-endian): "CNCW" magic, u16 format version, u16 reserved, u32 payload length,
 * u32 FNV-1a checksum of the payload, then the payload. Truncated, corrupted or other-version
 * bytes throw a WorldLoadError naming what is wrong; nothing half-built is returned.
 *
 * The hash is FNV-1a of the payload: it covers exactly the state that a save captures.
 */
import { Body } from './body.ts'
import { CONTACT_POINT_FIELDS, Contact } from './contact.ts'
import { Joint } from './joint.ts'
import { box, circle, polygon, type Shape } from './shapes.ts'

/** Bumped whenever the payload layout changes. */
export const SAVE_FORMAT_VERSION = 1
const MAGIC = 0x57434e43 // "CNCW" little-endian
const HEADER_BYTES = 16

/** Thrown by loadWorld for bytes that are not a valid saved world of this version. */
export class WorldLoadError extends Error {
  override name = 'WorldLoadError'
}

/** A growable little-endian byte writer. */
export class ByteWriter {
  bytes = new Uint8Array(1024)
  view = new DataView(this.bytes.buffer)
  length = 0

  private reserve(n: number): void {
    if (this.length + n <= this.bytes.length) return
    let size = this.bytes.length * 2
    while (size < this.length + n) size *= 2
    const next = new Uint8Array(size)
    next.set(this.bytes.subarray(0, this.length))
    this.bytes = next
    this.view = new DataView(next.buffer)
  }

  f64(v: number): void {
    this.reserve(8)
    this.view.setFloat64(this.length, v, true)
    this.length += 8
  }

  u32(v: number): void {
    this.reserve(4)
    this.view.setUint32(this.length, v, true)
    this.length += 4
  }

  u8(v: number): void {
    this.reserve(1)
    this.view.setUint8(this.length, v)
    this.length += 1
  }
}

/** A bounds-checked little-endian reader that names what it was reading when bytes run out. */
export class ByteReader {
  private readonly view: DataView
  private offset: number
  private readonly end: number

  constructor(bytes: Uint8Array, offset: number, end: number) {
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
    this.offset = offset
    this.end = end
  }

  private need(n: number, what: string): void {
    if (this.offset + n > this.end) throw new WorldLoadError(`saved world is truncated while reading ${what}`)
  }

  f64(what: string): number {
    this.need(8, what)
    const v = this.view.getFloat64(this.offset, true)
    this.offset += 8
    return v
  }

  /** A finite f64. */
  num(what: string): number {
    const v = this.f64(what)
    if (!Number.isFinite(v)) throw new WorldLoadError(`saved world has a non-finite ${what}: ${v}`)
    return v
  }

  u32(what: string): number {
    this.need(4, what)
    const v = this.view.getUint32(this.offset, true)
    this.offset += 4
    return v
  }

  u8(what: string): number {
    this.need(1, what)
    const v = this.view.getUint8(this.offset)
    this.offset += 1
    return v
  }

  /** Throws unless every byte was consumed. */
  finish(): void {
    if (this.offset !== this.end)
      throw new WorldLoadError(`saved world has ${this.end - this.offset} unexpected trailing bytes`)
  }
}

/** FNV-1a over bytes [start, end). */
export function fnv1a(bytes: Uint8Array, start: number, end: number): number {
  let h = 0x811c9dc5
  for (let i = start; i < end; i++) {
    h ^= bytes[i]
    h = Math.imul(h, 0x01000193)
  }
  return h >>> 0
}

/** Writes the header in front of a payload written at [HEADER_BYTES, length). */
export function sealSave(w: ByteWriter): Uint8Array {
  const payloadLength = w.length - HEADER_BYTES
  w.view.setUint32(0, MAGIC, true)
  w.view.setUint16(4, SAVE_FORMAT_VERSION, true)
  w.view.setUint16(6, 0, true)
  w.view.setUint32(8, payloadLength, true)
  w.view.setUint32(12, fnv1a(w.bytes, HEADER_BYTES, w.length), true)
  return w.bytes.slice(0, w.length)
}

/** Starts a save: reserves the header. */
export function beginSave(w: ByteWriter): void {
  w.length = 0
  w.u32(0)
  w.u32(0)
  w.u32(0)
  w.u32(0)
}

/** Checks the header and checksum; returns a reader over the payload. */
export function openSave(bytes: Uint8Array): ByteReader {
  if (!(bytes instanceof Uint8Array)) throw new WorldLoadError('saved world must be a Uint8Array')
  if (bytes.length < HEADER_BYTES)
    throw new WorldLoadError(`saved world is truncated: ${bytes.length} bytes, header needs ${HEADER_BYTES}`)
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  if (view.getUint32(0, true) !== MAGIC)
    throw new WorldLoadError('bytes are not a saved Concord world (bad magic)')
  const version = view.getUint16(4, true)
  if (version !== SAVE_FORMAT_VERSION) {
    throw new WorldLoadError(
      `saved world has format version ${version}; this engine reads version ${SAVE_FORMAT_VERSION}`,
    )
  }
  if (view.getUint16(6, true) !== 0)
    throw new WorldLoadError('saved world header is corrupted: reserved bytes are not zero')
  const length = view.getUint32(8, true)
  if (HEADER_BYTES + length > bytes.length) {
    throw new WorldLoadError(
      `saved world is truncated: payload needs ${length} bytes, ${bytes.length - HEADER_BYTES} present`,
    )
  }
  if (HEADER_BYTES + length < bytes.length) {
    throw new WorldLoadError(
      `saved world has ${bytes.length - HEADER_BYTES - length} trailing bytes after the payload`,
    )
  }
  const checksum = view.getUint32(12, true)
  if (fnv1a(bytes, HEADER_BYTES, HEADER_BYTES + length) !== checksum) {
    throw new WorldLoadError('saved world is corrupted: checksum mismatch')
  }
  return new ByteReader(bytes, HEADER_BYTES, HEADER_BYTES + length)
}

/** Writes a shape. */
export function writeShape(w: ByteWriter, shape: Shape): void {
  if (shape.type === 'circle') {
    w.u8(0)
    w.f64(shape.radius)
  } else if (shape.box !== null) {
    w.u8(1)
    w.f64(shape.box.halfWidth)
    w.f64(shape.box.halfHeight)
  } else {
    w.u8(2)
    w.u8(shape.count)
    for (const v of shape.vertices) {
      w.f64(v.x)
      w.f64(v.y)
    }
  }
}

/** Reads a shape, rebuilding it with the same constructors (so the same validation applies). */
export function readShape(r: ByteReader): Shape {
  const kind = r.u8('shape kind')
  try {
    if (kind === 0) return circle(r.num('circle radius'))
    if (kind === 1) return box(r.num('box half width'), r.num('box half height'))
    if (kind === 2) {
      const n = r.u8('polygon vertex count')
      const points = []
      for (let i = 0; i < n; i++) points.push({ x: r.num('polygon vertex'), y: r.num('polygon vertex') })
      return polygon(points)
    }
  } catch (e) {
    if (e instanceof WorldLoadError) throw e
    throw new WorldLoadError(`saved world has an invalid shape: ${(e as Error).message}`)
  }
  throw new WorldLoadError(`saved world has an unknown shape kind ${kind}`)
}

const BODY_STATE_FIELDS = [
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
] as const
const BODY_MATERIAL_FIELDS = [
  'density',
  'friction',
  'restitution',
  'linearDamping',
  'angularDamping',
  'gravityScale',
] as const
const POINT_FIELDS = [
  CONTACT_POINT_FIELDS.map((f) => `${f}0` as const),
  CONTACT_POINT_FIELDS.map((f) => `${f}1` as const),
]
const JOINT_FIELDS = [
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

/** Writes a body's definition and state (fat AABB comes separately). */
export function writeBody(w: ByteWriter, b: Body): void {
  w.f64(b.id)
  w.u8(b.type)
  writeShape(w, b.shape)
  for (const f of BODY_MATERIAL_FIELDS) w.f64(b[f])
  w.u8((b.bullet ? 1 : 0) | (b.enableSleep ? 2 : 0) | (b.fixedRotation ? 4 : 0) | (b.awake ? 8 : 0))
  for (const f of BODY_STATE_FIELDS) w.f64(b[f])
}

/** Reads a body written by writeBody (mass properties are recomputed by the caller). */
export function readBody(r: ByteReader): Body {
  const id = r.num('body id')
  const type = r.u8('body type')
  if (type > 2) throw new WorldLoadError(`saved world has body ${id} of unknown type ${type}`)
  const body = new Body(id, type, readShape(r))
  for (const f of BODY_MATERIAL_FIELDS) body[f] = r.num(`body ${id} ${f}`)
  const flags = r.u8('body flags')
  body.bullet = (flags & 1) !== 0
  body.enableSleep = (flags & 2) !== 0
  body.fixedRotation = (flags & 4) !== 0
  body.awake = (flags & 8) !== 0
  for (const f of BODY_STATE_FIELDS) body[f] = r.num(`body ${id} ${f}`)
  return body
}

/** Writes a contact (bodies by id). */
export function writeContact(w: ByteWriter, c: Contact): void {
  w.f64(c.bodyA.id)
  w.f64(c.bodyB.id)
  w.u8(c.touching ? 1 : 0)
  w.u8(c.pointCount)
  w.f64(c.normalX)
  w.f64(c.normalY)
  for (let j = 0; j < c.pointCount; j++) {
    for (const f of POINT_FIELDS[j]) w.f64(c[f])
  }
}

/** Reads a contact written by writeContact. */
export function readContact(r: ByteReader, lookup: (id: number) => Body): Contact {
  const a = lookup(r.num('contact body A'))
  const b = lookup(r.num('contact body B'))
  if (a.id >= b.id)
    throw new WorldLoadError(`saved world has a contact with bodies out of order (${a.id}, ${b.id})`)
  const c = new Contact(a, b)
  c.touching = r.u8('contact touching') === 1
  c.pointCount = r.u8('contact point count')
  if (c.pointCount > 2) throw new WorldLoadError(`saved world has a contact with ${c.pointCount} points`)
  c.normalX = r.num('contact normal')
  c.normalY = r.num('contact normal')
  for (let j = 0; j < c.pointCount; j++) {
    for (const f of POINT_FIELDS[j]) c[f] = r.num(`contact point ${f}`)
  }
  return c
}

/** Writes a joint (bodies by id; the world frame is id 0). */
export function writeJoint(w: ByteWriter, j: Joint): void {
  w.f64(j.id)
  w.u8(j.type)
  w.f64(j.bodyA.id)
  w.f64(j.bodyB.id)
  w.u8((j.enableLimit ? 1 : 0) | (j.enableMotor ? 2 : 0) | (j.collideConnected ? 4 : 0))
  for (const f of JOINT_FIELDS) w.f64(j[f])
}

/** Reads a joint written by writeJoint. */
export function readJoint(r: ByteReader, lookup: (id: number) => Body): Joint {
  const id = r.num('joint id')
  const type = r.u8('joint type')
  if (type > 2) throw new WorldLoadError(`saved world has joint ${id} of unknown type ${type}`)
  const a = lookup(r.num('joint body A'))
  const b = lookup(r.num('joint body B'))
  const j = new Joint(id, type, a, b)
  const flags = r.u8('joint flags')
  j.enableLimit = (flags & 1) !== 0
  j.enableMotor = (flags & 2) !== 0
  j.collideConnected = (flags & 4) !== 0
  for (const f of JOINT_FIELDS) j[f] = r.num(`joint ${id} ${f}`)
  return j
}
