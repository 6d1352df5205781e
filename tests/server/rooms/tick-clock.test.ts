import { performance } from 'node:perf_hooks'
import { describe, expect, it } from 'vitest'
import { MAX_CATCH_UP, TickClock } from '../../../server/rooms/tick-clock.ts'
import { FLUSH_LEAD_MS, flushDelay } from '../../../server/workers/worker-link.ts'

const STEP = 1 / 60

describe('the fixed-step tick clock (driven with made-up times)', () => {
  it('turns wall time into whole 1/60 s ticks and carries the remainder', () => {
    let ticks = 0
    const clock = new TickClock(STEP, () => ticks++)
    clock.reset(0)
    let now = 0
    for (let frame = 0; frame < 600; frame++) {
      now += 7.3 // 7.3 ms frames: ticks do not line up with wakes
      clock.pump(now)
    }
    // 4.38 s of wall time is 262.8 ticks: 262 whole ones, whatever the wake pattern.
    expect(ticks).toBe(262)
    expect(clock.overruns).toBe(0)
  })

  it('after a stall it runs at most MAX_CATCH_UP ticks and counts the rest as overruns', () => {
    let ticks = 0
    const dropped: number[] = []
    const clock = new TickClock(
      STEP,
      () => ticks++,
      (n) => dropped.push(n),
    )
    clock.reset(1000)
    expect(clock.pump(1000 + 1000)).toBe(MAX_CATCH_UP)
    expect(ticks).toBe(MAX_CATCH_UP)
    expect(clock.overruns).toBe(60 - MAX_CATCH_UP)
    expect(dropped).toEqual([60 - MAX_CATCH_UP])
    // Back to normal: the next frame runs its one tick, no backlog.
    expect(clock.pump(2000 + 1000 / 60 + 0.01)).toBe(1)
  })

  it('with a phase, ticks fall that fraction of a step past the process-wide grid of steps', () => {
    // Pumped every 0.01 ms, a clock reports each tick within 0.01 ms of when it falls due. Where it
    // falls is read against the process's time (timeOrigin + now), which every thread shares.
    const stepMs = STEP * 1000
    const dueAt = (phase: number, startMs: number): number[] => {
      const due: number[] = []
      const clock = new TickClock(STEP, () => due.push(now))
      let now = startMs
      clock.reset(now, phase)
      while (due.length < 5) clock.pump((now += 0.01))
      return due
    }
    for (const phase of [0, 0.25, 0.5, 0.75]) {
      for (const startMs of [1000, 1003.7, 1016.6]) {
        const due = dueAt(phase, startMs)
        // The first tick comes within one step of the start, at the next point of its grid.
        expect(due[0] - startMs).toBeLessThanOrEqual(stepMs + 0.01)
        for (const t of due) {
          const into = (performance.timeOrigin + t - phase * stepMs) % stepMs
          expect(Math.min(into, stepMs - into)).toBeLessThan(0.011)
        }
      }
    }
    // Clocks started at different times with phases 0 and 1/2 tick half a step apart.
    const a = dueAt(0, 1000)
    const b = dueAt(0.5, 1011)
    const gap = (((b[0] - a[0]) % stepMs) + stepMs) % stepMs
    expect(gap).toBeCloseTo(stepMs / 2, 1)
  })

  it("inputs for a worker wait until FLUSH_LEAD_MS before that worker's next tick", () => {
    const stepMs = 1000 / 60
    // 0.01 ms after a whole number of steps since the epoch (at 1.7e12 ms a double resolves 0.0002 ms).
    const grid = Math.ceil(1.7e12 / stepMs) * stepMs + 0.01
    for (const phase of [0, 0.5]) {
      // Just after this worker's tick fell due (the grid of TickClock.start(phase)).
      const tick = grid + phase * stepMs
      expect(flushDelay(tick, phase)).toBeCloseTo(stepMs - FLUSH_LEAD_MS - 0.01, 2)
      expect(flushDelay(tick + 5, phase)).toBeCloseTo(stepMs - FLUSH_LEAD_MS - 5.01, 2)
      // Inside the last FLUSH_LEAD_MS: send now.
      expect(flushDelay(tick + stepMs - 1, phase)).toBeLessThanOrEqual(0)
      expect(flushDelay(tick - 1, phase)).toBeLessThanOrEqual(0)
    }
    // The other worker's tick is half a step away: the same moment waits differently.
    expect(flushDelay(grid, 0.5)).toBeCloseTo(stepMs / 2 - FLUSH_LEAD_MS - 0.01, 2)
  })
})
