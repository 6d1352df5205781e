/*
 * CPU time of a synchronous stretch of this thread's work (a loop tick), in ms. Node 20 has no
 * per-thread CPU clock, so it comes from Linux's per-thread scheduler statistics,
 * /proc/thread-self/schedstat: "time on a CPU, time waiting for a CPU, timeslices" in ns. The
 * first field is brought up to date only at scheduler ticks and switches (every 4 ms on the
 * machine this was measured on), so a 5 ms tick read from it shows as 4 or 8 ms. The second is
 * brought up to date each time the thread gets a CPU back, and a thread reading it is running, so
 * any wait inside the stretch is counted in full when the stretch ends. For a stretch that never
 * sleeps (synchronous JavaScript), wall time less the wait is the time it ran, to the microsecond.
 * Checked here: 400 busy stretches of 1-5 ms read p50 3.07 ms, and their sum (1,246 ms) agrees with
 * the first field over the whole run (1,264 ms, which also counts the gaps between stretches);
 * beside 3 busy processes on 2 cores, the sum fell to the CPU the thread got (930 / 963 ms).
 */
import { closeSync, openSync, readFileSync, readSync } from 'node:fs'
import { performance } from 'node:perf_hooks'

const SCHEDSTAT = '/proc/thread-self/schedstat'
const SPACE = 0x20
const DIGIT_0 = 0x30
const DIGIT_9 = 0x39

/** Times stretches of this thread's work: start(), then stop() returns the CPU ms it ran. */
export class StretchTimer {
  /**
   * This thread's schedstat, opened once (thread-self names the opening thread) and re-read with
   * pread at offset 0 into a kept buffer: 3 us a read against 19 us for readFileSync's open, read,
   * close and string split, four or more times per loop tick, and nothing allocated.
   */
  private fd = -1
  private readonly buffer = new Uint8Array(128)
  private wallStart = 0
  private waitStart = 0

  /** Whether this system has per-thread scheduler statistics (Linux). */
  static available(): boolean {
    try {
      readFileSync(SCHEDSTAT, 'utf8')
      return true
    } catch {
      return false
    }
  }

  /** Start a stretch. */
  start(): void {
    this.read()
    this.wallStart = this.wallAt
    this.waitStart = this.waitAt
  }

  /** Close this thread's schedstat (a thread's exit does not close it: file descriptors belong to the process). */
  close(): void {
    if (this.fd >= 0) closeSync(this.fd)
    this.fd = -1
  }

  /** End the stretch: its wall time less the time the thread waited for a CPU in it (ms). */
  stop(): number {
    this.read()
    return Math.max(0, this.wallAt - this.wallStart - (this.waitAt - this.waitStart))
  }

  private wallAt = 0
  private waitAt = 0

  /**
   * The wall clock and the wait at one instant: the wait read before and after the clock agree, so
   * the thread did not wait between them (a wait there, e.g. when the read's system call returns
   * to a busy CPU, would otherwise count on one side only). At most 5 tries; then the last.
   */
  private read(): void {
    let before = this.waitMs()
    for (let tries = 0; ; tries++) {
      this.wallAt = performance.now()
      const after = this.waitMs()
      this.waitAt = after
      if (after === before || tries === 4) return
      before = after
    }
  }

  /** Time this thread has waited for a CPU so far (ms): the second decimal field of schedstat. */
  private waitMs(): number {
    if (this.fd < 0) this.fd = openSync(SCHEDSTAT, 'r')
    const n = readSync(this.fd, this.buffer, 0, this.buffer.length, 0)
    return schedstatWaitNs(this.buffer, n) / 1e6
  }
}

/** The second field (time waiting for a CPU, ns) of schedstat's text in bytes[0 .. length), without making a string. */
export function schedstatWaitNs(bytes: Uint8Array, length: number): number {
  let i = 0
  while (i < length && bytes[i] !== SPACE) i++
  let ns = 0
  for (i++; i < length && bytes[i] >= DIGIT_0 && bytes[i] <= DIGIT_9; i++) ns = ns * 10 + (bytes[i] - DIGIT_0)
  return ns
}
