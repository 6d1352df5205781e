/*
 * The playout clock against hand-computed schedules: a steady 60 Hz stream plays 2 ticks behind,
 * a server at 4x is followed, jitter raises the delay by 1.5 times the lateness peak (which then
 * decays), the target never passes the newest tick, and falling far behind asks for a resync.
 */
import { describe, expect, it } from 'vitest'
import { PlayoutClock } from '../../../shared/sim/lockstep-playout.ts'

const TICK_MS = 1000 / 60

describe('playout clock', () => {
  it('plays a steady 60 Hz stream at the minimum delay of 2 ticks', () => {
    const c = new PlayoutClock()
    c.reset(100, 0)
    for (let t = 101; t <= 400; t += 2) c.arrive(t, (t - 100) * TICK_MS)
    const now = 300 * TICK_MS
    expect(c.delay).toBeCloseTo(2, 6)
    expect(c.rate * 1000).toBeCloseTo(60, 1)
    // The estimate is 400 at that moment; 2 ticks behind is 398 (397 when rounding leaves the
    // measured rate or delay a hair off).
    expect(c.target(now)).toBeGreaterThanOrEqual(397)
    expect(c.target(now)).toBeLessThanOrEqual(398)
  })

  it('follows a server running 4 times faster than real time', () => {
    const c = new PlayoutClock()
    c.reset(0, 0)
    for (let t = 2; t <= 4000; t += 2) c.arrive(t, (t * TICK_MS) / 4)
    expect(c.rate * 1000).toBeCloseTo(240, -1)
    expect(c.target((4000 * TICK_MS) / 4)).toBeGreaterThanOrEqual(3997)
  })

  it('raises the delay by 1.5 times a late burst, never targets past the newest tick, then relaxes', () => {
    const c = new PlayoutClock()
    c.reset(0, 0)
    for (let t = 1; t <= 120; t++) c.arrive(t, t * TICK_MS)
    // Ticks 121..130 arrive together, 10 ticks late.
    for (let t = 121; t <= 130; t++) c.arrive(t, 140 * TICK_MS)
    // Tick 121 was due at 121 and came at 140: at most 19 ticks late against the estimate (less
    // because the burst itself lowers the measured rate), and at least the 10 ticks it waited.
    expect(c.latenessPeak).toBeGreaterThanOrEqual(10)
    expect(c.latenessPeak).toBeLessThanOrEqual(19)
    expect(c.delay).toBeCloseTo(2 + 1.5 * c.latenessPeak, 6)
    expect(c.target(200 * TICK_MS)).toBeLessThanOrEqual(130)
    for (let t = 131; t <= 700; t++) c.arrive(t, (t + 10) * TICK_MS)
    expect(c.delay).toBeLessThan(4)
  })

  it('asks for a resync only beyond the behind limit', () => {
    const c = new PlayoutClock({ behindLimit: 600 })
    c.reset(0, 0)
    c.arrive(700, 1000)
    expect(c.tooFarBehind(100)).toBe(false)
    expect(c.tooFarBehind(99)).toBe(true)
  })
})
