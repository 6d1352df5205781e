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
 * Poses are kept per body, not per frame (pose-track.ts): a snapshot under the byte budget writes
 * only some bodies, and only what it wrote is a sample. Between a body's samples it is
 * interpolated; past its newest sample (a body left out of the last snapshots, or a late packet)
 * it is extrapolated along its last velocity for at most MAX_EXTRAPOLATION ticks, then held; and
 * when the next sample corrects the guess, the correction is blended in over about 100 ms instead
 * of popping. Other players' cursors are tracked the same way, on the same delayed timeline.
 */
import {
  dequantizeAngle,
  dequantizePosition,
  FRAME_AWAKE,
  type QuantizedFrame,
  TICK_RATE,
} from '../../shared/index.ts'
import { MAX_AHEAD, PoseTrack } from './pose-track.ts'

/** Arrivals considered for the clock offset (ms). */
const OFFSET_WINDOW_MS = 1500
/** Longest extrapolation past a body's newest sample (ticks): 300 ms. */
export const MAX_EXTRAPOLATION = MAX_AHEAD
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

/** Buffer of recent snapshots, an estimate of the server clock, and pose sampling. */
export class SnapshotTimeline {
  private readonly tracks = new Map<number, PoseTrack>()
  private readonly cursorTracks = new Map<number, PoseTrack>()
  private newest = Number.NaN
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

  /** Forget every body (a new world epoch) but keep the clock estimate. */
  clear(): void {
    this.tracks.clear()
    this.newest = Number.NaN
  }

  /**
   * Record the state at `tick` that arrived at `arrivalMs`; frames must come in tick order.
   * `updated` lists the ids the snapshot wrote (the others only kept their baseline pose); without
   * it (a full state) every body in the frame is a sample. Bodies missing from the frame are dropped.
   */
  push(tick: number, frame: QuantizedFrame, arrivalMs: number, updated?: readonly number[]): void {
    const newest = this.newest
    if (tick <= newest) return
    // Gaps much longer than announced are a quiet room (nothing to send), not the network.
    const gap = Number.isNaN(newest) ? 0 : tick - newest
    if (gap > 0 && gap <= 3 * this.nominalInterval) this.intervalTicks += (gap - this.intervalTicks) * 0.1
    this.newest = tick
    for (const id of this.tracks.keys()) if (!frame.has(id)) this.tracks.delete(id)
    if (updated) {
      for (const id of updated) this.record(frame, id, tick)
      for (let i = 0; i < frame.count; i++)
        if (!this.tracks.has(frame.ids[i])) this.record(frame, frame.ids[i], tick)
    } else {
      for (let i = 0; i < frame.count; i++) this.record(frame, frame.ids[i], tick)
    }
    this.observeArrival(tick - arrivalMs * TICKS_PER_MS, arrivalMs)
  }

  private record(frame: QuantizedFrame, id: number, tick: number): void {
    if (!frame.has(id)) return
    let track = this.tracks.get(id)
    if (!track) {
      track = new PoseTrack()
      this.tracks.set(id, track)
    }
    track.add(
      tick,
      dequantizePosition(frame.x[id]),
      dequantizePosition(frame.y[id]),
      dequantizeAngle(frame.a[id]),
      (frame.flags[id] & FRAME_AWAKE) !== 0,
      this.renderTick,
    )
  }

  /**
   * A player's cursor (m) as of snapshot `tick`. A cursor is sent only when it moves, so after a
   * pause the old position is held until one interval before the new one (no slow slide across
   * the pause).
   */
  pushCursor(player: number, tick: number, x: number, y: number): void {
    let track = this.cursorTracks.get(player)
    if (!track) {
      track = new PoseTrack()
      this.cursorTracks.set(player, track)
    }
    const last = track.newestTick
    const hold = tick - this.intervalTicks
    if (track.count && hold > last) {
      const p = { x: 0, y: 0, angle: 0, awake: false }
      track.evaluate(last, p)
      track.add(hold, p.x, p.y, 0, false, this.renderTick)
    }
    track.add(tick, x, y, 0, false, this.renderTick)
  }

  /** A player's cursor at `tick`, written to `out`; false when none is known. */
  sampleCursor(player: number, tick: number, out: Pose): boolean {
    return this.cursorTracks.get(player)?.sample(tick, out) ?? false
  }

  /**
   * A command put a body somewhere new (events.change: the Edit tool's transform): forget its
   * samples, so it is drawn where it now is (the mirror's pose, then the next snapshot's) instead
   * of being carried on along the jump as if it were a velocity.
   */
  forget(id: number): void {
    this.tracks.delete(id)
  }

  /** Forget a player's cursor (the player left). */
  forgetCursor(player: number): void {
    this.cursorTracks.delete(player)
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
    return this.newest
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
    if (elapsed > 0) {
      const ms = elapsed / TICKS_PER_MS
      for (const t of this.tracks.values()) t.decay(ms)
      for (const t of this.cursorTracks.values()) t.decay(ms)
    }
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
   * The pose of body `id` at `tick`, written to `out`; false when no sample of it is held (the
   * caller then uses its latest known pose).
   */
  sample(id: number, tick: number, out: Pose): boolean {
    return this.tracks.get(id)?.sample(tick, out) ?? false
  }
}
