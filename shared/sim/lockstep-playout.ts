/*
 * The playout clock of a lockstep client: which tick to simulate up to at a given moment.
 *
 * The server streams ticks as it runs them; they arrive in bursts (batching, the network, the
 * event loop). Playing each tick the moment it arrives would make the world stutter with that
 * jitter, so the client plays behind the newest tick it has by a delay that absorbs it, like an
 * audio jitter buffer:
 *
 *   - a smooth estimate of the server's tick at local time t: anchor + (t - anchorTime) * rate,
 *     where rate (ticks per ms) is measured from arrivals over half-second windows (so a server
 *     that runs faster than 60 Hz, as the tests make it, is followed too);
 *   - every arrival moves the anchor: forward at once when the stream is ahead of the estimate,
 *     back slowly when it is late; how late it was (in ticks) feeds a peak that decays over about
 *     two seconds;
 *   - the delay is 2 ticks plus 1.5 times that peak, within [minDelay, maxDelay];
 *   - the target tick is estimate - delay, never past the newest tick received, and the clock
 *     asks for a resync when the simulation is more than `behindLimit` ticks behind the newest.
 *
 * All inputs are explicit (arrival times, now): no wall clock is read here, so tests drive it.
 */

/** Tunables of the playout clock. */
export interface PlayoutOptions {
  /** Nominal server rate (ticks per second), 60. */
  tickRate: number
  /** Smallest playout delay (ticks), 2. */
  minDelay: number
  /** Largest playout delay (ticks), 30 (half a second). */
  maxDelay: number
  /** Ticks behind the newest received at which a resync is better than catching up, 600 (10 s). */
  behindLimit: number
}

/** Default tunables. */
export const DEFAULT_PLAYOUT: PlayoutOptions = { tickRate: 60, minDelay: 2, maxDelay: 30, behindLimit: 600 }

/** Window over which the arrival rate is measured (ms). */
const RATE_WINDOW_MS = 500
/** Time constant of the lateness peak's decay (ms). */
const PEAK_DECAY_MS = 2000

/** Adaptive playout delay over a stream of ticks. */
export class PlayoutClock {
  /** Newest tick received. */
  newest = -1
  /** Estimated server rate (ticks per ms). */
  rate: number
  /** Current playout delay (ticks). */
  delay: number
  /** Largest recent lateness of an arrival against the smooth estimate (ticks). */
  latenessPeak = 0
  private anchorTick = 0
  private anchorTime = 0
  private rateTick = 0
  private rateTime = 0
  private lastArrival = 0
  private readonly options: PlayoutOptions

  constructor(options: Partial<PlayoutOptions> = {}) {
    this.options = { ...DEFAULT_PLAYOUT, ...options }
    this.rate = this.options.tickRate / 1000
    this.delay = this.options.minDelay
  }

  /** Start over at `tick` (a fresh sync), keeping the measured rate. */
  reset(tick: number, nowMs: number): void {
    this.newest = tick
    this.anchorTick = tick
    this.anchorTime = nowMs
    this.rateTick = tick
    this.rateTime = nowMs
    this.lastArrival = nowMs
    this.latenessPeak = 0
    this.delay = this.options.minDelay
  }

  /** The smooth estimate of the server's tick at `nowMs`. */
  estimate(nowMs: number): number {
    return this.anchorTick + (nowMs - this.anchorTime) * this.rate
  }

  /** Ticks up to `tick` have arrived at `nowMs`. */
  arrive(tick: number, nowMs: number): void {
    if (tick <= this.newest) return
    this.newest = tick
    const elapsed = nowMs - this.rateTime
    if (elapsed >= RATE_WINDOW_MS) {
      const measured = (tick - this.rateTick) / elapsed
      this.rate = this.rate * 0.7 + measured * 0.3
      this.rateTick = tick
      this.rateTime = nowMs
    }
    const expected = this.estimate(nowMs)
    const ahead = tick - expected
    this.latenessPeak *= Math.max(0, 1 - (nowMs - this.lastArrival) / PEAK_DECAY_MS)
    this.lastArrival = nowMs
    if (ahead >= 0) {
      this.anchorTick = tick
    } else {
      this.latenessPeak = Math.max(this.latenessPeak, -ahead)
      this.anchorTick = expected + ahead * 0.05
    }
    this.anchorTime = nowMs
    const { minDelay, maxDelay } = this.options
    this.delay = Math.min(maxDelay, Math.max(minDelay, 2 + 1.5 * this.latenessPeak))
  }

  /** The whole tick to have simulated by `nowMs`: estimate - delay, at most the newest received. */
  target(nowMs: number): number {
    return Math.min(this.newest, Math.floor(this.estimate(nowMs) - this.delay))
  }

  /** Whether a simulation at `simTick` is so far behind that a resync beats catching up. */
  tooFarBehind(simTick: number): boolean {
    return this.newest - simTick > this.options.behindLimit
  }
}
