/*
 * One body's (or cursor's) recent authoritative poses, and its pose at any tick drawn from them.
 *
 * A snapshot under the per-client byte budget writes only some of the moving bodies; the others
 * keep their baseline pose in the decoded frame, which is an old pose, not a new one. So a track
 * records a sample only when the server actually wrote the body (or at a full state), and draws:
 *   - between two samples: the straight line between them (interpolation);
 *   - past the newest sample: the newest pose moved along the velocity of the last two samples,
 *     for at most MAX_AHEAD ticks (extrapolation), then held; a sleeping body is held at once;
 *   - before the oldest: the oldest.
 * When a new sample arrives, the pose drawn at the playback tick changes (an extrapolation is
 * replaced by an interpolation toward the new pose): the difference goes into an error offset
 * that is added to what is drawn and decays to zero with time constant BLEND_MS, so the body
 * glides onto the authoritative path instead of popping (Glenn Fiedler's "visual smoothing").
 * Angles are unwrapped as samples arrive, so a turn through +-pi is continuous.
 */

/** Samples kept per track. */
const SAMPLES = 4
/** Longest extrapolation past the newest sample (ticks): 300 ms, longer than a budget-starved body waits. */
export const MAX_AHEAD = 18
/** A velocity from samples further apart than this (ticks) is too old to extrapolate with. */
const MAX_GAP = 30
/** Time constant of the error offset's decay (ms). */
export const BLEND_MS = 90
/** An error larger than this (m) is a teleport, not a correction: drawn at once. */
const SNAP_DISTANCE = 3

/** A pose: position (m), angle (rad), awake. */
export interface TrackPose {
  x: number
  y: number
  angle: number
  awake: boolean
}

/** Recent samples of one body or cursor, with the error offset being blended away. */
export class PoseTrack {
  private readonly ticks = new Float64Array(SAMPLES)
  private readonly xs = new Float64Array(SAMPLES)
  private readonly ys = new Float64Array(SAMPLES)
  private readonly as = new Float64Array(SAMPLES)
  private readonly awakes = new Uint8Array(SAMPLES)
  /** Samples held. */
  count = 0
  errX = 0
  errY = 0
  errA = 0
  private readonly scratch: TrackPose = { x: 0, y: 0, angle: 0, awake: false }

  /** Newest sample's tick, or NaN. */
  get newestTick(): number {
    return this.count ? this.ticks[this.count - 1] : Number.NaN
  }

  /**
   * Add an authoritative sample at `tick` (later than the newest); `at` is the playback tick now
   * (NaN before playback starts): the change this makes to the pose drawn there becomes error.
   */
  add(tick: number, x: number, y: number, angle: number, awake: boolean, at: number): void {
    const n = this.count
    if (n && tick <= this.ticks[n - 1]) return
    const before = this.scratch
    const blend = n > 0 && !Number.isNaN(at) && this.evaluate(at, before)
    const bx = before.x
    const by = before.y
    const ba = before.angle
    let a = angle
    if (n) {
      // Unwrap: the new angle is the one nearest the previous sample's.
      const prev = this.as[n - 1]
      a = prev + remainder(angle - prev)
    }
    if (n === SAMPLES) {
      this.ticks.copyWithin(0, 1)
      this.xs.copyWithin(0, 1)
      this.ys.copyWithin(0, 1)
      this.as.copyWithin(0, 1)
      this.awakes.copyWithin(0, 1)
    }
    const i = Math.min(n, SAMPLES - 1)
    this.ticks[i] = tick
    this.xs[i] = x
    this.ys[i] = y
    this.as[i] = a
    this.awakes[i] = awake ? 1 : 0
    this.count = i + 1
    if (!blend) return
    const after = this.scratch
    this.evaluate(at, after)
    this.errX += bx - after.x
    this.errY += by - after.y
    this.errA += ba - after.angle
    if (Math.abs(this.errX) + Math.abs(this.errY) > SNAP_DISTANCE || Math.abs(this.errA) > Math.PI) {
      this.errX = this.errY = this.errA = 0
    }
  }

  /** Let the error offset decay over `elapsedMs`. */
  decay(elapsedMs: number): void {
    if (this.errX === 0 && this.errY === 0 && this.errA === 0) return
    const k = Math.exp(-elapsedMs / BLEND_MS)
    this.errX *= k
    this.errY *= k
    this.errA *= k
    if (Math.abs(this.errX) + Math.abs(this.errY) + Math.abs(this.errA) < 1e-5)
      this.errX = this.errY = this.errA = 0
  }

  /** The pose to draw at `tick`: the samples' path plus the error offset. False when empty. */
  sample(tick: number, out: TrackPose): boolean {
    if (!this.evaluate(tick, out)) return false
    out.x += this.errX
    out.y += this.errY
    out.angle += this.errA
    return true
  }

  /** The samples' path at `tick` (see the file comment), without the error offset. */
  evaluate(tick: number, out: TrackPose): boolean {
    const n = this.count
    if (n === 0) return false
    const t = this.ticks
    if (tick <= t[0] || n === 1) return this.write(tick <= t[0] ? 0 : n - 1, out)
    const last = n - 1
    if (tick < t[last]) {
      let i = last - 1
      while (t[i] > tick) i--
      return this.lerp(i, i + 1, (tick - t[i]) / (t[i + 1] - t[i]), out)
    }
    const gap = t[last] - t[last - 1]
    if (!this.awakes[last] || gap > MAX_GAP) return this.write(last, out)
    const ahead = Math.min(tick - t[last], MAX_AHEAD)
    return this.lerp(last - 1, last, 1 + ahead / gap, out)
  }

  private write(i: number, out: TrackPose): boolean {
    out.x = this.xs[i]
    out.y = this.ys[i]
    out.angle = this.as[i]
    out.awake = this.awakes[i] === 1
    return true
  }

  private lerp(i: number, j: number, f: number, out: TrackPose): boolean {
    out.x = this.xs[i] + (this.xs[j] - this.xs[i]) * f
    out.y = this.ys[i] + (this.ys[j] - this.ys[i]) * f
    out.angle = this.as[i] + (this.as[j] - this.as[i]) * f
    out.awake = this.awakes[j] === 1
    return true
  }
}

/** An angle difference wrapped into [-pi, pi) (rad). */
function remainder(d: number): number {
  const turns = Math.floor((d + Math.PI) / (2 * Math.PI))
  return d - turns * 2 * Math.PI
}
