import { describe, expect, it } from 'vitest'
import { MAX_CATCH_UP, TickClock } from '../../server/tick-clock.ts'

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
})
