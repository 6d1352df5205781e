/*
 * Byte-level readers and writers for the snapshot payload: unsigned LEB128 varints (7 bits per
 * byte, low groups first, high bit = more) and ZigZag for signed values (0, -1, 1, -2 ... ->
 * 0, 1, 2, 3 ...), as in Protocol Buffers. Arithmetic instead of bit operators keeps values up to
 * 2^53 exact. The writer grows its buffer and is reused across snapshots.
 */

/** A growable byte buffer, reused between encodes (call reset()). */
export class ByteWriter {
  bytes: Uint8Array
  length = 0

  constructor(capacity = 1024) {
    this.bytes = new Uint8Array(capacity)
  }

  /** Forget the content, keep the memory. */
  reset(): void {
    this.length = 0
  }

  private ensure(extra: number): void {
    if (this.length + extra <= this.bytes.length) return
    const grown = new Uint8Array(Math.max(this.bytes.length * 2, this.length + extra))
    grown.set(this.bytes.subarray(0, this.length))
    this.bytes = grown
  }

  /** Append one byte (0..255). */
  writeByte(b: number): void {
    this.ensure(1)
    this.bytes[this.length++] = b
  }

  /** Append an unsigned integer (0..2^53) as a LEB128 varint. */
  writeVarint(u: number): void {
    this.ensure(8)
    while (u >= 128) {
      this.bytes[this.length++] = (u % 128) + 128
      u = Math.floor(u / 128)
    }
    this.bytes[this.length++] = u
  }

  /** Append bytes source[from, to). */
  writeBytes(source: Uint8Array, from: number, to: number): void {
    this.ensure(to - from)
    this.bytes.set(source.subarray(from, to), this.length)
    this.length += to - from
  }

  /** Append a signed integer as a ZigZag varint. */
  writeZigzag(i: number): void {
    this.writeVarint(i >= 0 ? i * 2 : -i * 2 - 1)
  }

  /** A copy of the written bytes. */
  toBytes(): Uint8Array {
    return this.bytes.slice(0, this.length)
  }
}

/** Bytes a LEB128 varint of u takes. */
export function varintSize(u: number): number {
  let n = 1
  while (u >= 128) {
    u = Math.floor(u / 128)
    n++
  }
  return n
}

/** Bytes a ZigZag varint of i takes. */
export function zigzagSize(i: number): number {
  return varintSize(i >= 0 ? i * 2 : -i * 2 - 1)
}

/** Reads what ByteWriter wrote; throws RangeError on truncated or overlong input. */
export class ByteReader {
  private offset = 0

  constructor(private readonly bytes: Uint8Array) {}

  /** True when every byte has been read. */
  get done(): boolean {
    return this.offset >= this.bytes.length
  }

  /** Next byte. */
  readByte(): number {
    if (this.offset >= this.bytes.length) throw new RangeError('snapshot data truncated')
    return this.bytes[this.offset++]
  }

  /** Next unsigned varint (at most 8 bytes). */
  readVarint(): number {
    let value = 0
    let scale = 1
    for (let i = 0; i < 8; i++) {
      const b = this.readByte()
      value += (b % 128) * scale
      if (b < 128) return value
      scale *= 128
    }
    throw new RangeError('varint longer than 8 bytes')
  }

  /** Next ZigZag varint. */
  readZigzag(): number {
    const u = this.readVarint()
    return u % 2 === 0 ? u / 2 : -(u + 1) / 2
  }
}
