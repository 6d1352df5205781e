/*
 * Snapshot interpolation (Valve's entity interpolation, Glenn Fiedler's "Snapshot Interpolation").
 *
 * The server sends a snapshot every few ticks; the client keeps the last few full states (copies of
 * the decoded quantized frames) and draws the world as it was `delay` ticks ago, between the two
 * snapshots around that moment, so motion is smooth even though states arrive in bursts.
 *
 * The timeline is the server's tick as it reaches this client: every snapshot arrival gives one
 * sample `tick - arrivalMs * rate`; the largest sample is the least-delayed path through the
 * network, so "now" on the server-as-seen-here is `nowMs * rate + offset`. The maximum is taken
 * over the last OFFSET_WINDOW_MS of arrivals only, so a server whose clock stepped back (an
 * overloaded host dropping ticks) or a path that got slower is followed within a second or two
 * instead of being outrun. The render time is that
 * minus an adaptive delay: two measured snapshot intervals plus a margin that grows with jitter
 * (how late snapshots arrive compared with the fastest one), i.e. about 2-3 intervals by default.
 * With a delay of at least two intervals, one lost snapshot still leaves a pair to interpolate
 * between: no freeze. The playback clock never jumps: it runs at real speed and is nudged up to
 * 10 % faster or slower toward its target, so changes of offset or delay are absorbed without a
 * pop (it only snaps after a stall of many ticks, e.g. a background tab).
 *
 * When the render time passes the newest snapshot (a late or lost packet beyond the margin),
 * bodies are extrapolated along their last velocity for at most MAX_EXTRAPOLATION ticks, then held.
 * Positions are linear; angles take the shortest arc, computed on quantized angles (one turn =
 * 65536) so a wrap from +pi to -pi turns the short way.
 */
import {
  ANGLE_STEPS,
  angleDelta,
  dequantizeAngle,
  dequantizePosition,
  FRAME_AWAKE,
  QuantizedFrame,
  TICK_RATE,
} from '../shared/index.ts'

/** Frames kept (about half a second at 30 Hz snapshots). */
const CAPACITY = 24
/** Arrivals considered for the clock offset (ms). */
const OFFSET_WINDOW_MS = 1500
/** Longest extrapolation past the newest snapshot (ticks): 100 ms. */
export const MAX_EXTRAPOLATION = 6
/** Playback speed is corrected by at most this fraction of real time. */
const MAX_SLEW = 0.1
/** A playback clock further than this from its target (ticks) snaps instead of slewing. */
const SNAP_TICKS = 30
const TICKS_PER_MS = TICK_RATE / 1000

/** An interpolated pose. */
export interface Pose {
  x: number
  y: number
  angle: number
  awake: boolean
}

interface TimedFrame {
  tick: number
  frame: QuantizedFrame
}

/** Buffer of recent snapshots, an estimate of the server clock, and pose sampling. */
export class SnapshotTimeline {
  private readonly frames: TimedFrame[] = []
  private readonly spare: QuantizedFrame[] = []
  private offset = Number.NaN
  private readonly samples: Array<{ value: number; at: number }> = []
  /** Measured snapshot interval (ticks), smoothed. */
  intervalTicks: number
  /** Mean lateness of arrivals behind the fastest one (ticks), smoothed. */
  jitterTicks = 0
  /** Current interpolation delay (ticks). */
  delayTicks: number
  /** The tick being drawn (fractional). */
  renderTick = Number.NaN
  private lastNow = Number.NaN

  /** The room's announced snapshot interval (ticks), e.g. 2 at 30 Hz. */
  nominalInterval: number

  /** nominalInterval: the expected snapshot interval (ticks), e.g. 2 at 30 Hz. */
  constructor(nominalInterval = 2) {
    this.nominalInterval = nominalInterval
    this.intervalTicks = nominalInterval
    this.delayTicks = this.targetDelay()
  }

  /** Forget every frame (a new world epoch) but keep the clock estimate. */
  clear(): void {
    for (const f of this.frames) this.spare.push(f.frame)
    this.frames.length = 0
  }

  /** Record the full state at `tick` that arrived at `arrivalMs`; frames must come in tick order. */
  push(tick: number, frame: QuantizedFrame, arrivalMs: number): void {
    const newest = this.frames[this.frames.length - 1]
    if (newest && tick <= newest.tick) return
    // Gaps much longer than announced are a quiet room (nothing to send), not the network.
    const gap = newest ? tick - newest.tick : 0
    if (gap > 0 && gap <= 3 * this.nominalInterval) this.intervalTicks += (gap - this.intervalTicks) * 0.1
    const copy = this.spare.pop() ?? new QuantizedFrame()
    copy.copyFrom(frame)
    this.frames.push({ tick, frame: copy })
    if (this.frames.length > CAPACITY) this.spare.push(this.frames.shift()!.frame)
    this.observeArrival(tick - arrivalMs * TICKS_PER_MS, arrivalMs)
  }

  private observeArrival(sample: number, arrivalMs: number): void {
    const samples = this.samples
    samples.push({ value: sample, at: arrivalMs })
    while (samples[0].at < arrivalMs - OFFSET_WINDOW_MS) samples.shift()
    let best = -Infinity
    for (const s of samples) if (s.value > best) best = s.value
    this.offset = best
    this.jitterTicks += (best - sample - this.jitterTicks) * 0.1
  }

  private targetDelay(): number {
    const interval = Math.max(1, this.intervalTicks)
    const margin = Math.max(0.5 * interval, 2 * this.jitterTicks)
    return Math.min(2 * interval + margin, 8 * interval, SNAP_TICKS - 1)
  }

  /** Newest tick held, or NaN. */
  get newestTick(): number {
    return this.frames.length ? this.frames[this.frames.length - 1].tick : Number.NaN
  }

  /** Server tick as it reaches this client now (fractional), or NaN before any snapshot. */
  serverTickAt(nowMs: number): number {
    return nowMs * TICKS_PER_MS + this.offset
  }

  /** Advance the playback clock to `nowMs`; returns the tick to draw. */
  advance(nowMs: number): number {
    if (Number.isNaN(this.offset)) return Number.NaN
    this.delayTicks += (this.targetDelay() - this.delayTicks) * 0.05
    const target = this.serverTickAt(nowMs) - this.delayTicks
    const elapsed = Number.isNaN(this.lastNow) ? 0 : (nowMs - this.lastNow) * TICKS_PER_MS
    this.lastNow = nowMs
    if (Number.isNaN(this.renderTick) || Math.abs(target - this.renderTick) > SNAP_TICKS) {
      this.renderTick = target
    } else {
      const error = target - (this.renderTick + elapsed)
      const slew = Math.max(-MAX_SLEW, Math.min(MAX_SLEW, error * 0.5))
      this.renderTick += elapsed * (1 + slew)
    }
    return this.renderTick
  }

  /**
   * The pose of body `id` at `tick`, written to `out`; false when no held frame has it (the
   * caller then uses its latest known pose).
   */
  sample(id: number, tick: number, out: Pose): boolean {
    const frames = this.frames
    const n = frames.length
    if (n === 0) return false
    let i = n - 1
    while (i > 0 && frames[i].tick > tick) i--
    const a = frames[i]
    if (a.tick > tick) return this.write(a.frame, id, out)
    if (i === n - 1) return this.extrapolate(id, tick, out)
    const b = frames[i + 1]
    const hasA = a.frame.has(id)
    if (!b.frame.has(id)) return hasA && this.write(a.frame, id, out)
    if (!hasA) return this.write(b.frame, id, out)
    return this.blend(a.frame, b.frame, id, (tick - a.tick) / (b.tick - a.tick), out)
  }

  private extrapolate(id: number, tick: number, out: Pose): boolean {
    const n = this.frames.length
    const last = this.frames[n - 1]
    if (!last.frame.has(id)) return false
    const prev = n > 1 ? this.frames[n - 2] : null
    if (!prev?.frame.has(id) || (last.frame.flags[id] & FRAME_AWAKE) === 0) {
      return this.write(last.frame, id, out)
    }
    const ahead = Math.min(tick - last.tick, MAX_EXTRAPOLATION)
    return this.blend(prev.frame, last.frame, id, 1 + ahead / (last.tick - prev.tick), out)
  }

  private write(f: QuantizedFrame, id: number, out: Pose): boolean {
    if (!f.has(id)) return false
    out.x = dequantizePosition(f.x[id])
    out.y = dequantizePosition(f.y[id])
    out.angle = dequantizeAngle(f.a[id])
    out.awake = (f.flags[id] & FRAME_AWAKE) !== 0
    return true
  }

  private blend(a: QuantizedFrame, b: QuantizedFrame, id: number, t: number, out: Pose): boolean {
    const ax = a.x[id]
    const ay = a.y[id]
    out.x = dequantizePosition(ax + (b.x[id] - ax) * t)
    out.y = dequantizePosition(ay + (b.y[id] - ay) * t)
    out.angle = dequantizeAngle(a.a[id]) + (angleDelta(a.a[id], b.a[id]) * t * 2 * Math.PI) / ANGLE_STEPS
    out.awake = (b.flags[id] & FRAME_AWAKE) !== 0
    return true
  }
}
