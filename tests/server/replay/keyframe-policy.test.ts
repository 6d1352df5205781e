import { describe, expect, it } from 'vitest'
import { FULL_BUDGET_BYTES, KeyframePolicy, MAX_CHAIN } from '../../../server/replay/keyframe-policy.ts'

/** Run a policy for `ticks` ticks with fixed keyframe sizes; returns [tick, kind] of each keyframe. */
function run(policy: KeyframePolicy, ticks: number, full: number, delta: number): Array<[number, string]> {
  const out: Array<[number, string]> = []
  for (let t = 1; t <= ticks; t++) {
    const kind = policy.decide(t)
    if (kind === 'none') continue
    out.push([t, kind])
    policy.record(kind, kind === 'full' ? full : delta)
  }
  return out
}

describe('keyframe policy', () => {
  it('without a budget: a keyframe at every multiple of the interval, never between', () => {
    const policy = new KeyframePolicy(600, 0, 60)
    policy.reset(0, true, 1000)
    const written = run(policy, 36_000, 400_000, 400_000)
    expect(written.map(([t]) => t)).toEqual(Array.from({ length: 60 }, (_, i) => (i + 1) * 600))
  })

  it('with a budget: the k-th keyframe waits for the first multiple of 600 where budget x age covers k keyframes', () => {
    // 12 MB/h at 60 ticks/s is 55.56 bytes per tick; 100 KB keyframes (under FULL_BUDGET_BYTES:
    // the whole budget).
    const policy = new KeyframePolicy(600, 12_000_000, 60)
    policy.reset(0, true, 100_000)
    const written = run(policy, 216_000, 100_000, 100_000)
    // By hand: before the k-th keyframe (k from 0) k x 100,000 bytes are written, and at tick t
    // t x 12e6 / 216,000 are allowed: k = 0 goes at the first chance (600), k >= 1 once
    // t >= 1,800 k (a multiple of 600), up to k = 120 at 216,000.
    expect(written.map(([t]) => t)).toEqual([600, ...Array.from({ length: 120 }, (_, k) => 1_800 * (k + 1))])
    // So an hour's keyframes exceed the budget by at most one keyframe.
    expect(written.length * 100_000).toBeLessThanOrEqual(12_000_000 + 100_000)
  })

  it('a world over FULL_BUDGET_BYTES gets the budget scaled by FULL_BUDGET_BYTES / its keyframe size', () => {
    expect(FULL_BUDGET_BYTES).toBe(128_000)
    // 24 MB/h and 400 KB keyframes (a busy pile): 24e6 x 128,000 / 400,000 = 7.68e6 bytes per
    // hour, 35.56 per tick; the k-th keyframe (k >= 1) once t x 7.68e6 / 216,000 >= 400,000 k,
    // i.e. t >= 11,250 k, at the next multiple of 600.
    const policy = new KeyframePolicy(600, 24_000_000, 60)
    policy.reset(0, true, 400_000)
    const written = run(policy, 216_000, 400_000, 400_000)
    const byHand = Array.from({ length: 19 }, (_, k) => Math.ceil((11_250 * (k + 1)) / 600) * 600)
    expect(written.map(([t]) => t)).toEqual([600, ...byHand])
    expect(written.length * 400_000).toBeLessThanOrEqual(7_680_000 + 400_000)
  })

  it('a log that started at a later tick (rotation, recovery) measures its budget from there', () => {
    const policy = new KeyframePolicy(600, 12_000_000, 60)
    policy.reset(90_000, true, 100_000)
    expect(policy.decide(90_600)).toBe('delta')
    policy.record('delta', 100_000)
    expect(policy.decide(91_200)).toBe('none')
    expect(policy.decide(90_000 + 1_800)).not.toBe('none')
  })

  it('deltas while they and the next one stay under one whole keyframe, at most MAX_CHAIN of them', () => {
    const quarter = new KeyframePolicy(60, 0, 60)
    quarter.reset(0, true, 1000)
    // Deltas of 250 bytes against 1,000-byte whole keyframes: 0 + 0, 250 + 250, 500 + 250 < 1000,
    // then 750 + 250 is not: whole. The header counts as the first whole one.
    expect(run(quarter, 60 * 8, 1000, 250).map(([, k]) => k)).toEqual([
      'delta',
      'delta',
      'delta',
      'full',
      'delta',
      'delta',
      'delta',
      'full',
    ])
    const tiny = new KeyframePolicy(60, 0, 60)
    tiny.reset(0, true, 100_000)
    const kinds = run(tiny, 60 * (2 * MAX_CHAIN + 2), 100_000, 30).map(([, k]) => k)
    expect(kinds.indexOf('full')).toBe(MAX_CHAIN)
    expect(kinds.lastIndexOf('full')).toBe(2 * MAX_CHAIN + 1)
    expect(kinds.filter((k) => k === 'full')).toHaveLength(2)
  })

  it('without a base (a resumed log) the first keyframe is whole', () => {
    const policy = new KeyframePolicy(60, 0, 60)
    policy.reset(120, false, 0)
    expect(policy.decide(180)).toBe('full')
  })
})
