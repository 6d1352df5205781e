/*
 * The byte container of a saved world: a growable writer, a bounds-checked reader, the header
 * and the checksum. world-state.ts writes and reads the payload.
 *
 * Format (little-endian): "CNCW" magic, u16 format version, u16 reserved, u32 payload length,
 * u32 FNV-1a checksum of the payload, then the payload. Truncated, corrupted or other-version
 * bytes throw a WorldLoadError naming what is wrong; nothing half-built is returned.
 */
/**
 * Bumped whenever the payload layout changes, or the way a saved world goes on from its bytes (a
 * world saved by one version must continue bit for bit in a build of that version, and logs of
 * other versions are refused rather than replayed differently). 2 was used by two branches with
 * different layouts (issue 27: shapes saved per body with their own ids, material, filter and
 * flags, contacts naming their shapes, a sensor section and pending forces; issue 28: the new joint
 * kinds' fields behind joint flag bit 3); 3 is their merged layout, with both. 4 has 3's layout;
 * slender shapes' contacts get extra solver sweeps (constants.ts SLENDER_RATIO), so a world with a
 * slender shape goes on differently than in a build of 3.
 */
export const SAVE_FORMAT_VERSION = 4
const MAGIC = 0x57434e43 // "CNCW" little-endian
/** Bytes before the payload. */
export const HEADER_BYTES = 16

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

  /**
   * Writes src[start .. start + count) as f64s. Writers pass doubles this way when they can: V8
   * boxes a double argument of a call it does not inline (a heap number per f64 call).
   */
  f64s(src: Float64Array, start: number, count: number): void {
    this.reserve(8 * count)
    const view = this.view
    let at = this.length
    for (let i = start; i < start + count; i++) {
      view.setFloat64(at, src[i], true)
      at += 8
    }
    this.length = at
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
