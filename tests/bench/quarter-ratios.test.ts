/*
 * The benchmark page's ratio and spread (issue 31, fix 12): the median over rounds of Concord's
 * round time over another engine's, and that median in each quarter of the run, lowest and
 * highest. Checked against hand-made step times, and for the property that makes it the page's
 * number: slowing a few rounds (a burst of load on the machine) leaves it unchanged, where the ratio
 * of means moves.
 */
import { describe, expect, it } from 'vitest'
import { medianRoundRatio, quarterRatios } from '../../bench/summary.ts'

describe('medianRoundRatio and quarterRatios', () => {
  it('read rounds and quarters by hand', () => {
    // Eight rounds of two steps. Concord 1 ms a step; the other engine's rounds take 4, 2, 8, 4,
    // 2, 4, 4, 2 ms, so the round ratios are 0.5, 1, 0.25, 0.5, 1, 0.5, 0.5, 1.
    const concord = Array(16).fill(1)
    const other = [2, 2, 1, 1, 4, 4, 2, 2, 1, 1, 2, 2, 2, 2, 1, 1]
    // Sorted: 0.25, 0.5, 0.5, 0.5, 0.5, 1, 1, 1: median (0.5 + 0.5) / 2.
    expect(medianRoundRatio(concord, other, 2)).toBe(0.5)
    // Quarters of two rounds: (0.5, 1) -> 0.75, (0.25, 0.5) -> 0.375, (1, 0.5) -> 0.75, (0.5, 1) -> 0.75.
    expect(quarterRatios(concord, other, 2)).toEqual({ low: 0.375, high: 0.75 })
  })

  it('a burst of load on a few rounds moves the ratio of means but not the median', () => {
    const concord = Array(100).fill(1)
    const other = Array(100).fill(2)
    expect(medianRoundRatio(concord, other, 5)).toBe(0.5)
    // Rounds 3 and 11 of Concord ran while the machine was busy: 10 times slower.
    for (const i of [15, 16, 17, 18, 19, 55, 56, 57, 58, 59]) concord[i] = 10
    const meanRatio = concord.reduce((a, b) => a + b) / other.reduce((a, b) => a + b)
    expect(meanRatio).toBeCloseTo(0.95, 12)
    expect(medianRoundRatio(concord, other, 5)).toBe(0.5)
    expect(quarterRatios(concord, other, 5)).toEqual({ low: 0.5, high: 0.5 })
  })

  it('is null with too few rounds, or with rounds that read 0 ms (a coarse timer)', () => {
    expect(quarterRatios([1, 1, 1], [1, 1, 1], 1)).toBeNull()
    expect(medianRoundRatio([0, 0], [1, 1], 1)).toBeNull()
    expect(quarterRatios([1, 1, 1, 0], [1, 1, 1, 1], 1)).toBeNull()
  })
})
