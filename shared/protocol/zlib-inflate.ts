/*
 * A synchronous zlib inflater (RFC 1950 wrapper around RFC 1951 DEFLATE), pure and browser-safe.
 * Browsers only inflate asynchronously (DecompressionStream); the replay log reader is a
 * synchronous stream parser and must open a log's deflated record blocks while it reads them, in
 * Node and in a page alike. Blocks are small (one writer flush, a few KB), so a compact canonical
 * Huffman decoder (count and symbol tables, one bit at a time, as in Joergen Ibsen's tinf) is fast
 * enough; big saved worlds still go through the platform's inflate.
 *
 * Every malformed input throws an InflateError naming the problem; output beyond `maxOutput`
 * bytes throws too (a small stream cannot blow up memory).
 */

/** A stream that is not valid zlib data, or inflates past its bound. */
export class InflateError extends Error {}

interface Huffman {
  /** counts[len]: codes of each bit length 0..15. */
  counts: Uint16Array
  /** Symbols in canonical order. */
  symbols: Uint16Array
}

const LENGTH_BASE = [
  3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195,
  227, 258,
]
const LENGTH_EXTRA = [0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0]
const DIST_BASE = [
  1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097,
  6145, 8193, 12289, 16385, 24577,
]
const DIST_EXTRA = [
  0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13,
]
/** Order of the code length code lengths in a dynamic block header (RFC 1951 3.2.7). */
const CLEN_ORDER = [16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15]

function buildHuffman(lengths: ArrayLike<number>, from: number, n: number): Huffman {
  const counts = new Uint16Array(16)
  for (let i = 0; i < n; i++) counts[lengths[from + i]]++
  counts[0] = 0
  let left = 1
  for (let len = 1; len < 16; len++) {
    left = left * 2 - counts[len]
    if (left < 0) throw new InflateError('over-subscribed Huffman code lengths')
  }
  const offsets = new Uint16Array(16)
  for (let len = 1; len < 15; len++) offsets[len + 1] = offsets[len] + counts[len]
  const symbols = new Uint16Array(n)
  for (let i = 0; i < n; i++) if (lengths[from + i] !== 0) symbols[offsets[lengths[from + i]]++] = i
  return { counts, symbols }
}

const FIXED = ((): { lit: Huffman; dist: Huffman } => {
  const lengths = new Uint8Array(288 + 30)
  for (let i = 0; i < 288; i++) lengths[i] = i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8
  lengths.fill(5, 288)
  return { lit: buildHuffman(lengths, 0, 288), dist: buildHuffman(lengths, 288, 30) }
})()

class Inflater {
  private at = 0
  private bitBuffer = 0
  private bitCount = 0
  out: Uint8Array
  length = 0

  constructor(
    private readonly data: Uint8Array,
    private readonly maxOutput: number,
  ) {
    this.at = 2
    this.out = new Uint8Array(Math.min(maxOutput, Math.max(1024, data.length * 4)))
  }

  bits(n: number): number {
    while (this.bitCount < n) {
      if (this.at >= this.data.length) throw new InflateError('zlib stream ends early')
      this.bitBuffer |= this.data[this.at++] << this.bitCount
      this.bitCount += 8
    }
    const v = this.bitBuffer & ((1 << n) - 1)
    this.bitBuffer >>>= n
    this.bitCount -= n
    return v
  }

  symbol(h: Huffman): number {
    let code = 0
    let first = 0
    let index = 0
    for (let len = 1; len < 16; len++) {
      code |= this.bits(1)
      const count = h.counts[len]
      if (code - first < count) return h.symbols[index + code - first]
      index += count
      first = (first + count) * 2
      code *= 2
    }
    throw new InflateError('invalid Huffman code')
  }

  private reserve(n: number): void {
    if (this.length + n <= this.out.length) return
    if (this.length + n > this.maxOutput)
      throw new InflateError(`inflates to more than ${this.maxOutput} bytes`)
    const next = new Uint8Array(Math.min(this.maxOutput, Math.max(this.out.length * 2, this.length + n)))
    next.set(this.out.subarray(0, this.length))
    this.out = next
  }

  stored(): void {
    this.bitBuffer = 0
    this.bitCount = 0
    if (this.at + 4 > this.data.length) throw new InflateError('zlib stream ends early')
    const len = this.data[this.at] | (this.data[this.at + 1] << 8)
    const nlen = this.data[this.at + 2] | (this.data[this.at + 3] << 8)
    this.at += 4
    if ((len ^ 0xffff) !== nlen) throw new InflateError('stored block length check fails')
    if (this.at + len > this.data.length) throw new InflateError('zlib stream ends early')
    this.reserve(len)
    this.out.set(this.data.subarray(this.at, this.at + len), this.length)
    this.length += len
    this.at += len
  }

  dynamicTables(): { lit: Huffman; dist: Huffman } {
    const hlit = this.bits(5) + 257
    const hdist = this.bits(5) + 1
    const hclen = this.bits(4) + 4
    const clen = new Uint8Array(19)
    for (let i = 0; i < hclen; i++) clen[CLEN_ORDER[i]] = this.bits(3)
    const codeLengths = buildHuffman(clen, 0, 19)
    const lengths = new Uint8Array(hlit + hdist)
    for (let i = 0; i < hlit + hdist; ) {
      const sym = this.symbol(codeLengths)
      if (sym < 16) {
        lengths[i++] = sym
        continue
      }
      let repeat: number
      let value = 0
      if (sym === 16) {
        if (i === 0) throw new InflateError('repeat of a code length before the first')
        value = lengths[i - 1]
        repeat = 3 + this.bits(2)
      } else if (sym === 17) repeat = 3 + this.bits(3)
      else repeat = 11 + this.bits(7)
      if (i + repeat > hlit + hdist) throw new InflateError('code lengths overflow their table')
      lengths.fill(value, i, i + repeat)
      i += repeat
    }
    if (lengths[256] === 0) throw new InflateError('no end-of-block code')
    return { lit: buildHuffman(lengths, 0, hlit), dist: buildHuffman(lengths, hlit, hdist) }
  }

  compressed(lit: Huffman, dist: Huffman): void {
    for (;;) {
      const sym = this.symbol(lit)
      if (sym < 256) {
        this.reserve(1)
        this.out[this.length++] = sym
        continue
      }
      if (sym === 256) return
      const l = sym - 257
      if (l >= 29) throw new InflateError(`invalid length symbol ${sym}`)
      const length = LENGTH_BASE[l] + this.bits(LENGTH_EXTRA[l])
      const d = this.symbol(dist)
      if (d >= 30) throw new InflateError(`invalid distance symbol ${d}`)
      const distance = DIST_BASE[d] + this.bits(DIST_EXTRA[d])
      if (distance > this.length) throw new InflateError(`distance ${distance} reaches before the output`)
      this.reserve(length)
      for (let k = 0; k < length; k++, this.length++) this.out[this.length] = this.out[this.length - distance]
    }
  }

  /** Byte offset after the last block (the Adler-32 trailer starts there). */
  get end(): number {
    return this.at
  }
}

function adler32(bytes: Uint8Array, length: number): number {
  let a = 1
  let b = 0
  for (let i = 0; i < length; ) {
    const stop = Math.min(length, i + 5552)
    for (; i < stop; i++) {
      a += bytes[i]
      b += a
    }
    a %= 65521
    b %= 65521
  }
  return (b * 65536 + a) >>> 0
}

/** Inflate a zlib stream (RFC 1950) into at most `maxOutput` bytes; throws InflateError. */
export function inflateZlibSync(data: Uint8Array, maxOutput: number): Uint8Array {
  if (data.length < 6) throw new InflateError(`zlib stream too short (${data.length} bytes)`)
  const cmf = data[0]
  const flg = data[1]
  if ((cmf & 0x0f) !== 8 || cmf >> 4 > 7 || (cmf * 256 + flg) % 31 !== 0)
    throw new InflateError('not a zlib stream (bad header)')
  if (flg & 0x20) throw new InflateError('zlib preset dictionaries are not supported')
  const z = new Inflater(data, maxOutput)
  for (let last = 0; !last; ) {
    last = z.bits(1)
    const type = z.bits(2)
    if (type === 0) z.stored()
    else if (type === 1) z.compressed(FIXED.lit, FIXED.dist)
    else if (type === 2) {
      const tables = z.dynamicTables()
      z.compressed(tables.lit, tables.dist)
    } else throw new InflateError('invalid DEFLATE block type 3')
  }
  const at = z.end
  if (at + 4 !== data.length)
    throw new InflateError(
      `${data.length - at - 4} bytes after the zlib stream's end (expected 4 for Adler-32)`,
    )
  const stored = ((data[at] << 24) | (data[at + 1] << 16) | (data[at + 2] << 8) | data[at + 3]) >>> 0
  if (adler32(z.out, z.length) !== stored) throw new InflateError('Adler-32 mismatch')
  return z.out.slice(0, z.length)
}
