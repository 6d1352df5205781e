/*
 * A byte delta: `target` written as copy and literal runs against a `base` the reader already has
 * (the replay log stores a keyframe's saved world this way, against the previous keyframe's).
 *
 * Encoding (docs/replay-format.md, "Delta worlds"): a varint target length, then runs until the
 * target is complete, each a varint `n << 1 | kind`:
 *   kind 0, literal: the next n bytes are copied to the output;
 *   kind 1, copy: a zigzag varint d follows; n bytes are copied from base offset `expected + d`,
 *   where `expected` is the base offset that the current output position maps to under the
 *   previous copy's shift (0 before the first copy), so a copy that continues the layout costs d = 0.
 * Varints are unsigned LEB128 (7 bits a byte, low first), zigzag maps 0, -1, 1, -2 to 0, 1, 2, 3.
 *
 * The encoder (rsync-style): every BLOCK-aligned BLOCK bytes of the base are hashed into a table;
 * at each output position it first tries the continued shift, then the table, verifies the bytes,
 * extends the match backwards into the pending literal and forwards as far as bytes agree. Bodies
 * or contacts added or removed only move the shift; a changed number is a short literal.
 */

import { ByteWriter } from '../protocol/index.ts'

/** Bytes per hashed base block (one f64). */
const BLOCK = 8

/** A delta that does not decode against its base; the message names the problem. */
export class ByteDeltaError extends Error {}

const unzigzag = (z: number): number => (z % 2 === 0 ? z / 2 : -(z + 1) / 2)

function hashAt(bytes: Uint8Array, at: number, bits: number): number {
  const a = bytes[at] | (bytes[at + 1] << 8) | (bytes[at + 2] << 16) | (bytes[at + 3] << 24)
  const b = bytes[at + 4] | (bytes[at + 5] << 8) | (bytes[at + 6] << 16) | (bytes[at + 7] << 24)
  return (Math.imul(a, 0x9e3779b1) ^ Math.imul(b ^ (a >>> 15), 0x85ebca77)) >>> (32 - bits)
}

function equalBlock(x: Uint8Array, i: number, y: Uint8Array, j: number): boolean {
  for (let k = 0; k < BLOCK; k++) if (x[i + k] !== y[j + k]) return false
  return true
}

/** Index of the base's aligned blocks: table[hash] = offset + 1 of the first block with that hash. */
function indexBlocks(base: Uint8Array): { table: Int32Array; bits: number } {
  const blocks = Math.floor(base.length / BLOCK)
  let bits = 4
  while (1 << bits < blocks * 2) bits++
  const table = new Int32Array(1 << bits)
  for (let j = (blocks - 1) * BLOCK; j >= 0; j -= BLOCK) table[hashAt(base, j, bits)] = j + 1
  return { table, bits }
}

/** Encode `target` as copy and literal runs against `base` (see the file comment). */
export function encodeByteDelta(base: Uint8Array, target: Uint8Array): Uint8Array {
  const out = new ByteWriter(256)
  out.writeVarint(target.length)
  const { table, bits } = indexBlocks(base)
  const n = target.length
  let i = 0
  let literalStart = 0
  let shift = 0
  while (i + BLOCK <= n) {
    let p = i + shift
    if (p < 0 || p + BLOCK > base.length || !equalBlock(target, i, base, p)) {
      const candidate = base.length >= BLOCK ? table[hashAt(target, i, bits)] - 1 : -1
      p = candidate >= 0 && equalBlock(target, i, base, candidate) ? candidate : -1
    }
    if (p < 0) {
      i++
      continue
    }
    while (i > literalStart && p > 0 && target[i - 1] === base[p - 1]) {
      i--
      p--
    }
    let end = i + BLOCK
    let q = p + BLOCK
    while (end < n && q < base.length && target[end] === base[q]) {
      end++
      q++
    }
    if (i > literalStart) {
      out.writeVarint((i - literalStart) * 2)
      out.writeBytes(target, literalStart, i)
    }
    out.writeVarint((end - i) * 2 + 1)
    out.writeZigzag(p - (i + shift))
    shift = p - i
    i = end
    literalStart = end
  }
  if (n > literalStart) {
    out.writeVarint((n - literalStart) * 2)
    out.writeBytes(target, literalStart, n)
  }
  return out.toBytes()
}

/** Rebuild the target from `base` and a delta; throws ByteDeltaError for a delta that does not fit. */
export function decodeByteDelta(base: Uint8Array, delta: Uint8Array): Uint8Array {
  let at = 0
  const varint = (what: string): number => {
    let v = 0
    let scale = 1
    for (;;) {
      if (at >= delta.length) throw new ByteDeltaError(`delta ends inside a ${what} at byte ${at}`)
      const b = delta[at++]
      v += (b & 0x7f) * scale
      if (b < 0x80) return v
      scale *= 0x80
      if (scale > 2 ** 49) throw new ByteDeltaError(`${what} varint too long at byte ${at}`)
    }
  }
  const length = varint('target length')
  if (length > 64 * 1024 * 1024) throw new ByteDeltaError(`delta target length ${length} is too large`)
  const out = new Uint8Array(length)
  let i = 0
  let shift = 0
  while (i < length) {
    const run = varint('run')
    const n = Math.floor(run / 2)
    if (n === 0 || i + n > length)
      throw new ByteDeltaError(`run of ${n} bytes at output ${i} does not fit a ${length}-byte target`)
    if (run % 2 === 0) {
      if (at + n > delta.length) throw new ByteDeltaError(`literal of ${n} bytes runs past the delta's end`)
      out.set(delta.subarray(at, at + n), i)
      at += n
    } else {
      const p = i + shift + unzigzag(varint('copy offset'))
      if (p < 0 || p + n > base.length)
        throw new ByteDeltaError(
          `copy of ${n} bytes from base offset ${p} is outside the ${base.length}-byte base`,
        )
      out.set(base.subarray(p, p + n), i)
      shift = p - i
    }
    i += n
  }
  if (at !== delta.length) throw new ByteDeltaError(`${delta.length - at} bytes after the delta's last run`)
  return out
}
