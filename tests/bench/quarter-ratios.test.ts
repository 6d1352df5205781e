/*
 * The benchmark page's spread (issue 31, fix 12): Concord's time over another engine's in each
 * quarter of the run, lowest and highest. Checked against hand-made step times, and against the
 * mediant inequality: the whole run's ratio (sum over sum) always lies between the quarters' lowest
 * and highest.
 */
import { describe, expect, it } from 'vitest'
import { quarterRatios } from '../../bench/summary.ts'

describe('quarterRatios', () => {
  it('reads each quarter by hand', () => {
    // Eight steps, two per quarter: Concord 1 ms throughout; the other 2, 2, 1, 1, 4, 4, 1, 3 ms.
    const concord = [1, 1, 1, 1, 1, 1, 1, 1]
    const other = [2, 2, 1, 1, 4, 4, 1, 3]
    // Quarters: 2/4 = 0.5, 2/2 = 1, 2/8 = 0.25, 2/4 = 0.5.
    expect(quarterRatios(concord, other)).toEqual({ low: 0.25, high: 1 })
  })

  it('brackets the whole run ratio, for any step times', () => {
    let seed = 7
    const next = (): number => {
      seed = (seed * 1103515245 + 12345) % 2147483648
      return 0.05 + (seed / 2147483648) * 3
    }
    for (let trial = 0; trial < 200; trial++) {
      const n = 4 + (trial % 37)
      const concord = Array.from({ length: n }, next)
      const other = Array.from({ length: n }, next)
      const whole = concord.reduce((a, b) => a + b) / other.reduce((a, b) => a + b)
      const range = quarterRatios(concord, other)!
      expect(range.low).toBeLessThanOrEqual(whole * (1 + 1e-12))
      expect(range.high).toBeGreaterThanOrEqual(whole * (1 - 1e-12))
    }
  })

  it('is null with fewer than four steps or a quarter that reads 0 ms (a coarse timer)', () => {
    expect(quarterRatios([1, 1, 1], [1, 1, 1])).toBeNull()
    expect(quarterRatios([1, 1, 1, 1], [1, 0, 1, 1])).toBeNull()
  })
})
