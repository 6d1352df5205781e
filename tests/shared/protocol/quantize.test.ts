import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import {
  addAngle,
  angleDelta,
  dequantizeAngle,
  dequantizePosition,
  MAX_ANGLE_ERROR,
  MAX_POSITION_ERROR,
  quantizeAngle,
  quantizePosition,
} from '../../../shared/protocol/quantize.ts'

/** Distance between two angles on the circle, by an independent formula (atan2 of the difference). */
function circularDistance(a: number, b: number): number {
  return Math.abs(Math.atan2(Math.sin(a - b), Math.cos(a - b)))
}

describe('quantization', () => {
  it('positions round-trip within half a millimetre', () => {
    fc.assert(
      fc.property(fc.double({ min: -1000, max: 1000, noNaN: true }), (m) => {
        expect(Math.abs(dequantizePosition(quantizePosition(m)) - m)).toBeLessThanOrEqual(
          MAX_POSITION_ERROR + 1e-12,
        )
      }),
    )
  })

  it('angles round-trip within half of 1/65536 turn, across wrap-around', () => {
    fc.assert(
      fc.property(fc.double({ min: -100, max: 100, noNaN: true }), (rad) => {
        const q = quantizeAngle(rad)
        expect(q).toBeGreaterThanOrEqual(0)
        expect(q).toBeLessThan(65536)
        expect(circularDistance(dequantizeAngle(q), rad)).toBeLessThanOrEqual(MAX_ANGLE_ERROR + 1e-9)
      }),
    )
  })

  it('angle deltas take the short way round and addAngle inverts them', () => {
    expect(angleDelta(65535, 1)).toBe(2)
    expect(angleDelta(1, 65535)).toBe(-2)
    fc.assert(
      fc.property(fc.integer({ min: 0, max: 65535 }), fc.integer({ min: 0, max: 65535 }), (a, b) => {
        const d = angleDelta(a, b)
        expect(Math.abs(d)).toBeLessThanOrEqual(32768)
        expect(addAngle(a, d)).toBe(b)
      }),
    )
  })

  it('huge positions clamp to the int32 range instead of overflowing', () => {
    expect(quantizePosition(1e12)).toBe(2147483647)
    expect(quantizePosition(-1e12)).toBe(-2147483647)
  })
})
