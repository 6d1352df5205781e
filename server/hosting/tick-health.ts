/*
 * Liveness of the tick loops: every loop (the in-process clock, or each room worker) reports a beat
 * as it ticks; a loop whose last beat is older than the stall limit makes /healthz fail, so an
 * orchestrator restarts a server whose simulation has wedged while its HTTP side still answers.
 * The Agones health pings are sent only while every loop is healthy, for the same reason.
 */
import { performance } from 'node:perf_hooks'

/** One stalled loop: its name and how long since it last ticked (ms). */
export interface StalledLoop {
  loop: string
  sinceMs: number
}

/** Last-beat bookkeeping for every tick loop of the process. */
export class TickHealth {
  private readonly last = new Map<string, number>()

  constructor(
    /** A loop silent for longer than this is stalled (ms); usually a few seconds. */
    readonly stallMs: number,
    private readonly now: () => number = () => performance.now(),
  ) {}

  /** The loop ran a tick now. */
  beat(loop: string): void {
    this.last.set(loop, this.now())
  }

  /** Forget a loop (it was stopped on purpose). */
  remove(loop: string): void {
    this.last.delete(loop)
  }

  /** Loops silent for longer than the stall limit, longest first. */
  stalled(): StalledLoop[] {
    const now = this.now()
    const out: StalledLoop[] = []
    for (const [loop, at] of this.last) if (now - at > this.stallMs) out.push({ loop, sinceMs: now - at })
    return out.sort((a, b) => b.sinceMs - a.sinceMs)
  }

  /** Null when every loop ticks; otherwise a one-line reason naming the stalled loops. */
  problem(): string | null {
    const stalled = this.stalled()
    if (stalled.length === 0) return null
    return `tick loop stalled: ${stalled.map((s) => `${s.loop} silent for ${Math.round(s.sinceMs)} ms`).join(', ')}`
  }
}
