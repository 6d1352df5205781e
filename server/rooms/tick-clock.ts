/*
 * The server's clock: the one place the simulation reads wall-clock time. A fixed-step accumulator
 * turns elapsed real time into whole 1/60 s ticks (Fiedler, "Fix Your Timestep"); the rooms only
 * ever see ticks. When the process falls behind (GC pause, overload), it runs at most
 * MAX_CATCH_UP ticks in a row and drops the rest, counting them as overruns, so a stall never
 * snowballs into a spiral of catch-up work. It never takes a variable step.
 */
import { performance } from 'node:perf_hooks'

/** Ticks run back to back at most when behind. */
export const MAX_CATCH_UP = 4

/** Drives `onTick` at a fixed rate from the wall clock. */
export class TickClock {
  private accumulator = 0
  private last = 0
  private timer: NodeJS.Timeout | null = null
  /** Ticks dropped because the loop fell too far behind. */
  overruns = 0
  /** Ticks run. */
  ticks = 0

  constructor(
    private readonly stepSeconds: number,
    private readonly onTick: () => void,
    private readonly onOverrun: (dropped: number) => void = () => {},
  ) {}

  /**
   * Start ticking. With a phase (a fraction of a tick, 0 <= phase < 1), ticks fall where the
   * process's time (performance.timeOrigin + performance.now(), the same in every thread) is that
   * fraction of a step past a whole number of steps since the epoch, so clocks started in different
   * threads with phases k / N take turns instead of ticking together (worker-pool.ts).
   */
  start(phase?: number): void {
    if (this.timer) return
    this.reset(performance.now(), phase)
    this.schedule()
  }

  /** Stop ticking. */
  stop(): void {
    if (this.timer) clearTimeout(this.timer)
    this.timer = null
  }

  /** Fraction of the next tick elapsed, 0..1 (for clock sync replies). */
  get fraction(): number {
    return Math.min(1, this.accumulator / this.stepSeconds)
  }

  private schedule(): void {
    const wait = Math.max(0, (this.stepSeconds - this.accumulator) * 1000)
    this.timer = setTimeout(() => this.wake(), wait)
  }

  private wake(): void {
    this.pump(performance.now())
    if (this.timer) this.schedule()
  }

  /**
   * Account for wall time up to `nowMs` and run the whole ticks it covers (at most MAX_CATCH_UP;
   * the rest are dropped and counted). Returns the ticks run. Called by the timer; tests call it
   * with made-up times.
   */
  pump(nowMs: number): number {
    this.accumulator += (nowMs - this.last) / 1000
    this.last = nowMs
    let steps = Math.floor(this.accumulator / this.stepSeconds)
    this.accumulator -= steps * this.stepSeconds
    if (steps > MAX_CATCH_UP) {
      this.overruns += steps - MAX_CATCH_UP
      this.onOverrun(steps - MAX_CATCH_UP)
      steps = MAX_CATCH_UP
    }
    for (let i = 0; i < steps; i++) {
      this.ticks++
      this.onTick()
    }
    return steps
  }

  /**
   * Start counting from `nowMs` (performance.now() time) without a timer (tests drive pump()
   * themselves); with a phase, the ticks fall as start(phase) places them.
   */
  reset(nowMs: number, phase?: number): void {
    this.last = nowMs
    this.accumulator =
      phase === undefined ? 0 : phaseAccumulator(this.stepSeconds, phase, performance.timeOrigin + nowMs)
  }
}

/**
 * The accumulator (s) that makes a clock with step `stepSeconds` tick when the time `nowMs` (ms
 * since the epoch) is `phase` steps past a multiple of the step: the time since the last such
 * moment.
 */
export function phaseAccumulator(stepSeconds: number, phase: number, nowMs: number): number {
  const stepMs = stepSeconds * 1000
  const since = (nowMs - phase * stepMs) % stepMs
  return (since < 0 ? since + stepMs : since) / 1000
}
