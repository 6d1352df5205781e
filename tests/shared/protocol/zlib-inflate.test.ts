import { constants, deflateSync } from 'node:zlib'
import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { InflateError, inflateZlibSync } from '../../../shared/protocol/zlib-inflate.ts'

/** Bytes that deflate finds matches in: runs, repeats of earlier pieces and noise. */
const compressible = fc
  .array(
    fc.oneof(
      fc.uint8Array({ maxLength: 40 }),
      fc
        .record({ byte: fc.integer({ min: 0, max: 255 }), n: fc.integer({ min: 1, max: 400 }) })
        .map(({ byte, n }) => new Uint8Array(n).fill(byte)),
      fc.constant(new TextEncoder().encode('{"k":"move","x":1.25,"y":6.5}')),
    ),
    { maxLength: 60 },
  )
  .map((parts) => new Uint8Array(Buffer.concat(parts)))

describe('inflateZlibSync', () => {
  it("inflates exactly what Node's zlib deflated, at every level and strategy (stored, fixed and dynamic Huffman blocks)", () => {
    fc.assert(
      fc.property(
        compressible,
        fc.integer({ min: 0, max: 9 }),
        fc.constantFrom(
          constants.Z_DEFAULT_STRATEGY,
          constants.Z_FIXED,
          constants.Z_HUFFMAN_ONLY,
          constants.Z_RLE,
        ),
        (bytes, level, strategy) => {
          const z = new Uint8Array(deflateSync(bytes, { level, strategy }))
          expect(Buffer.from(inflateZlibSync(z, bytes.length))).toEqual(Buffer.from(bytes))
        },
      ),
      { numRuns: 400 },
    )
  })

  it('inflates a 300 KB stream of mixed data (long distances, many blocks)', () => {
    const bytes = new Uint8Array(300_000)
    let seed = 12345
    for (let i = 0; i < bytes.length; i++) {
      seed = (Math.imul(seed, 1103515245) + 12345) >>> 0
      bytes[i] = i % 1000 < 500 ? seed >>> 24 : bytes[i - 20_000 > 0 ? i - 20_000 : 0]
    }
    const z = new Uint8Array(deflateSync(bytes))
    expect(Buffer.from(inflateZlibSync(z, bytes.length))).toEqual(Buffer.from(bytes))
  })

  it('refuses output beyond its bound, a bad header, a truncated stream, a wrong Adler-32 and trailing bytes', () => {
    const bytes = new Uint8Array(1000).fill(7)
    const z = new Uint8Array(deflateSync(bytes))
    expect(() => inflateZlibSync(z, 999)).toThrow(/more than 999 bytes/)
    expect(() =>
      inflateZlibSync(
        z.map((b, i) => (i === 0 ? 0x79 : b)),
        1000,
      ),
    ).toThrow(/bad header/)
    expect(() => inflateZlibSync(z.subarray(0, z.length - 5), 1000)).toThrow(InflateError)
    const badSum = z.slice()
    badSum[badSum.length - 1] ^= 1
    expect(() => inflateZlibSync(badSum, 1000)).toThrow(/Adler-32/)
    expect(() => inflateZlibSync(new Uint8Array([...z, 0]), 1000)).toThrow(/after the zlib stream/)
  })

  it('never throws anything but an InflateError on random or bit-flipped input', () => {
    const z = new Uint8Array(
      deflateSync(new TextEncoder().encode('hash record, command, join, leave '.repeat(20))),
    )
    fc.assert(
      fc.property(
        fc.integer({ min: 0, max: z.length * 8 - 1 }),
        fc.uint8Array({ maxLength: 64 }),
        (bit, noise) => {
          const flipped = z.slice()
          flipped[bit >> 3] ^= 1 << (bit & 7)
          for (const input of [flipped, noise]) {
            try {
              inflateZlibSync(input, 4096)
            } catch (error) {
              expect(error).toBeInstanceOf(InflateError)
            }
          }
        },
      ),
      { numRuns: 500 },
    )
  })
})
