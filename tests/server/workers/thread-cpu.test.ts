/*
 * server/workers/thread-cpu.ts against the kernel's own count: the CPU time of back-to-back stretches of
 * work, summed, equals the thread's time on a CPU over the same window (the first field of
 * /proc/thread-self/schedstat, which is up to one scheduler tick stale at each end), and no
 * stretch reads more than its wall time, and a stretch with more work reads more in proportion (to
 * well under a millisecond, not a scheduler tick). These hold however loaded the machine is: waiting for a
 * CPU lengthens the wall time and is left out of both counts.
 */
import { readFileSync } from 'node:fs'
import { performance } from 'node:perf_hooks'
import { describe, expect, it } from 'vitest'
import { StretchTimer, schedstatWaitNs } from '../../../server/workers/thread-cpu.ts'

const runMs = (): number => Number(readFileSync('/proc/thread-self/schedstat', 'utf8').split(' ')[0]) / 1e6

/** About a millisecond of arithmetic. */
function work(n: number): number {
  let x = 0
  for (let i = 0; i < n; i++) x = (x + Math.sqrt(i)) % 1e9
  return x
}

describe('the CPU time of a stretch of this thread', () => {
  it.runIf(StretchTimer.available())(
    'sums to the kernel count of the thread on a CPU, and never exceeds the wall time',
    () => {
      const timer = new StretchTimer()
      work(200_000)
      const cpus: number[] = []
      const walls: number[] = []
      let sink = 0
      const before = runMs()
      const loop0 = performance.now()
      for (let k = 0; k < 200; k++) {
        const wall0 = performance.now()
        timer.start()
        sink += work(100_000 + 20_000 * (k % 5))
        cpus.push(timer.stop())
        walls.push(performance.now() - wall0)
      }
      const loopWall = performance.now() - loop0
      const kernel = runMs() - before
      expect(sink).toBeGreaterThan(0)
      for (let k = 0; k < cpus.length; k++) {
        expect(cpus[k]).toBeGreaterThanOrEqual(0)
        expect(cpus[k]).toBeLessThanOrEqual(walls[k])
      }
      // Resolution: the stretches with 1.8 times the work take about 1.8 times the CPU (read from
      // the kernel's on-CPU field, a few-millisecond stretch reads as 0 or one scheduler tick).
      const median = (xs: number[]): number => [...xs].sort((a, b) => a - b)[xs.length >> 1]
      const ratio = median(cpus.filter((_, k) => k % 5 === 4)) / median(cpus.filter((_, k) => k % 5 === 0))
      expect(ratio).toBeGreaterThan(1.4)
      expect(ratio).toBeLessThan(2.3)
      const sum = cpus.reduce((a, b) => a + b, 0)
      // The kernel's count also holds the loop's own work between stretches (reading the
      // statistics, the clock), which took at most the wall time between them; and it is up to
      // one scheduler tick (4 ms at 250 Hz, 10 ms at 100 Hz) stale at each end.
      const between = loopWall - walls.reduce((a, b) => a + b, 0)
      const stale = 20
      expect(sum).toBeGreaterThan(50)
      expect(sum).toBeLessThanOrEqual(kernel + stale)
      expect(kernel - sum).toBeLessThanOrEqual(between + stale)
    },
  )

  it('reads the wait field of schedstat text as String.split would', () => {
    const lines = ['135101073 46830539 40\n', '0 0 0\n', '9007199254740991 123456789012345 7\n', '1 2 3']
    if (StretchTimer.available()) lines.push(readFileSync('/proc/thread-self/schedstat', 'utf8'))
    for (const line of lines) {
      const bytes = new TextEncoder().encode(line)
      expect(schedstatWaitNs(bytes, bytes.length), line).toBe(Number(line.split(' ')[1]))
    }
  })
})
