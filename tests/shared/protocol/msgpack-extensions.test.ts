import { ExtData, encode } from '@msgpack/msgpack'
import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { decodeClientMessage } from '../../../shared/protocol/codec.ts'
import { findNonStandard } from '../../../shared/protocol/msgpack-extensions.ts'

/** Plain MessagePack values: JSON values plus byte strings, long strings and big arrays. */
const plain = fc.oneof(
  fc.jsonValue(),
  fc.uint8Array({ maxLength: 300 }),
  fc.string({ minLength: 200, maxLength: 70_000, unit: 'binary' }),
  fc.array(fc.integer(), { minLength: 16, maxLength: 70 }),
  fc.dictionary(fc.string(), fc.double(), { minKeys: 16, maxKeys: 40 }),
)

describe('findNonStandard', () => {
  it('finds nothing in values encoded by an independent encoder (@msgpack/msgpack)', () => {
    fc.assert(fc.property(plain, (v) => findNonStandard(encode(v)) === -1))
  })

  it('finds an extension right after any plain value, at the offset the layout gives by hand', () => {
    const ext = fc
      .tuple(fc.integer({ min: 0, max: 127 }), fc.uint8Array({ maxLength: 300 }))
      .map(([type, data]) => new ExtData(type, data))
    fc.assert(
      fc.property(plain, ext, (v, e) => {
        // [v, e]: the fixarray header 0x92, then v's bytes, then the extension.
        expect(findNonStandard(encode([v, e]))).toBe(1 + encode(v).length)
        // {k: v, z: e}: the fixmap header, "k" (2 bytes), v, "z" (2 bytes), then the extension.
        expect(findNonStandard(encode({ k: v, z: e }))).toBe(1 + 2 + encode(v).length + 2)
      }),
    )
  })

  it('finds a timestamp and the never-used 0xc1, and the client decoder refuses both as malformed', () => {
    const withDate = encode({ t: 'input', seq: 1, cmd: { k: 'move', x: new Date(0), y: 0 } })
    expect(findNonStandard(withDate)).toBeGreaterThan(0)
    expect(findNonStandard(new Uint8Array([0x91, 0xc1]))).toBe(1)
    for (const bytes of [withDate, new Uint8Array([0xc1]), new Uint8Array([0xd4, 0x00, 0x00])]) {
      const result = decodeClientMessage(bytes)
      expect(result.ok ? 'ok' : result.code).toBe('malformed')
    }
  })
})
