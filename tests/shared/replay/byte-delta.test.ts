import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { ByteDeltaError, decodeByteDelta, encodeByteDelta } from '../../../shared/replay/byte-delta.ts'

/** A target made from a base by random edits: insertions, deletions, in-place changes of 1-16 bytes. */
const baseAndEdited = fc
  .tuple(
    fc.uint8Array({ maxLength: 2000 }),
    fc.array(
      fc.record({
        at: fc.nat(),
        kind: fc.constantFrom('insert', 'delete', 'change'),
        bytes: fc.uint8Array({ minLength: 1, maxLength: 16 }),
      }),
      { maxLength: 30 },
    ),
  )
  .map(([base, edits]) => {
    const target = Array.from(base)
    for (const e of edits) {
      const at = target.length === 0 ? 0 : e.at % target.length
      if (e.kind === 'insert') target.splice(at, 0, ...e.bytes)
      else if (e.kind === 'delete') target.splice(at, e.bytes.length)
      else target.splice(at, e.bytes.length, ...e.bytes)
    }
    return { base, target: new Uint8Array(target) }
  })

/** Apply a delta by a second, independent reading of the format (docs/replay-format.md). */
function applyByHand(base: Uint8Array, delta: Uint8Array): number[] {
  let at = 0
  const varint = (): number => {
    let v = 0
    for (let shift = 0; ; shift += 7) {
      const b = delta[at++]
      v += (b & 127) * 2 ** shift
      if (b < 128) return v
    }
  }
  const length = varint()
  const out: number[] = []
  let shift = 0
  while (out.length < length) {
    const run = varint()
    const n = run >> 1
    if ((run & 1) === 0) for (let k = 0; k < n; k++) out.push(delta[at++])
    else {
      const z = varint()
      const start = out.length + shift + (z & 1 ? -(z + 1) / 2 : z / 2)
      for (let k = 0; k < n; k++) out.push(base[start + k])
      shift = start - (out.length - n)
    }
  }
  return out
}

describe('byte delta', () => {
  it('decode(base, encode(base, target)) is the target for random bases and random insertions, deletions and changes', () => {
    fc.assert(
      fc.property(baseAndEdited, ({ base, target }) => {
        const delta = encodeByteDelta(base, target)
        expect(Buffer.from(decodeByteDelta(base, delta))).toEqual(Buffer.from(target))
        expect(applyByHand(base, delta)).toEqual(Array.from(target))
      }),
      { numRuns: 500 },
    )
  })

  it('works against unrelated or empty bases', () => {
    fc.assert(
      fc.property(fc.uint8Array({ maxLength: 500 }), fc.uint8Array({ maxLength: 500 }), (base, target) => {
        expect(Buffer.from(decodeByteDelta(base, encodeByteDelta(base, target)))).toEqual(Buffer.from(target))
      }),
    )
  })

  it('costs a few bytes for a 100 KB target equal to its base except for one inserted and one changed f64', () => {
    const base = new Uint8Array(100_000)
    let seed = 2463534242
    for (let i = 0; i < base.length; i++) {
      seed ^= seed << 13
      seed ^= seed >>> 17
      seed ^= seed << 5
      base[i] = seed & 255
    }
    const target = new Uint8Array(base.length + 8)
    target.set(base.subarray(0, 40_000))
    target.set([1, 2, 3, 4, 5, 6, 7, 8], 40_000)
    target.set(base.subarray(40_000), 40_008)
    target.set([9, 9, 9, 9, 9, 9, 9, 9], 80_000)
    const delta = encodeByteDelta(base, target)
    // 2 literals of 8 bytes plus about 3 runs of a few bytes each.
    expect(delta.length).toBeLessThan(40)
    expect(Buffer.compare(decodeByteDelta(base, delta), target)).toBe(0)
  })

  it('refuses deltas that do not fit their base with a ByteDeltaError naming the problem', () => {
    const base = new Uint8Array([1, 2, 3, 4])
    expect(() => decodeByteDelta(base, new Uint8Array([4, 9, 2]))).toThrow(
      /copy of 4 bytes from base offset 1 is outside/,
    )
    expect(() => decodeByteDelta(base, new Uint8Array([2, 4, 1]))).toThrow(/literal of 2 bytes runs past/)
    expect(() => decodeByteDelta(base, new Uint8Array([1, 2, 7, 5]))).toThrow(/1 bytes after/)
    expect(() => decodeByteDelta(base, new Uint8Array([2, 6, 0]))).toThrow(/run of 3 bytes at output 0/)
    fc.assert(
      fc.property(fc.uint8Array({ maxLength: 30 }), (junk) => {
        try {
          decodeByteDelta(base, junk)
        } catch (error) {
          expect(error).toBeInstanceOf(ByteDeltaError)
        }
      }),
    )
  })
})
