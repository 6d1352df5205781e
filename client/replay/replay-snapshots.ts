/*
 * The replay player's own snapshots: the state at a tick (ReplayRunner.save(): the simulation's
 * state, its saved world and the delta base, plus the index of the first record after that tick),
 * taken while the player moves forward through a log, so that a seek back starts from the nearest
 * of (log keyframe, snapshot) at or before its target instead of only from the log's keyframes,
 * which may be far apart (the recorder's keyframe budget) or absent. A log does not change once
 * read, so a snapshot stays valid for the player's life: a seek back and forward again reuses it.
 *
 * Where: at room ticks that are multiples of SNAPSHOT_TICKS (one grid for every path through the
 * log, so a second pass over a stretch finds its snapshots already there and takes none), and only
 * where no log keyframe (the header counts) or snapshot lies in the SNAPSHOT_TICKS ticks up to and
 * including the tick. So with no keyframes near, a seek replays fewer than SNAPSHOT_TICKS ticks;
 * after a keyframe that is off the grid (a server room starts at a tick below 60, so the header
 * usually is) the next snapshot may be up to 2 * SNAPSHOT_TICKS - 1 ticks from it.
 *
 * How much: every snapshot's saved world, a rough figure for its state, and each delta base once
 * (bases are decoded log keyframes, shared by the snapshots after them) count against a byte
 * budget. Over it, the snapshot whose neighbours (snapshots, log keyframes, the log's end) are
 * closest goes: the rest stay spread, and the longest stretch a seek may have to replay grows as
 * little as it can. On an even grid with no keyframes that drops every other snapshot. Log
 * keyframes are never dropped (they live in the log anyway).
 */
import type { RunnerSnapshot } from '../../shared/index.ts'

/**
 * Room ticks between the player's snapshots: 600 (10 s at 60 Hz), the recorder's default keyframe
 * interval, so a log that kept its keyframes needs none. A snapshot of a 1,000-body pile is about
 * 375 KB and a few ms of world.save(); 600 ticks of that pile take far longer to replay, so taking
 * them costs forward play little, and a seek back replays at most 10 s of room time.
 */
export const SNAPSHOT_TICKS = 600

/**
 * Bytes all of a player's snapshots may hold together: 64 MB. That is 170 snapshots of a 1,000-body
 * pile (28 minutes of such a room at one per SNAPSHOT_TICKS, before any is dropped) and thousands of
 * a small room, next to a log held in memory that is itself tens of MB.
 */
export const SNAPSHOT_BUDGET_BYTES = 64 * 1024 * 1024

/** A rough figure for a snapshot's state (room fields, players, user joints): bytes. */
const STATE_BYTES = 512
const STATE_BYTES_PER_ITEM = 128

/** The state at `tick` as the player left it: the runner's snapshot and where to resume reading. */
export interface PlayerSnapshot extends RunnerSnapshot {
  tick: number
  /** Index of the first record with a tick after `tick`. */
  next: number
}

/** Index of the last element of a sorted sequence at or before `tick`, or -1. */
function lastAtOrBefore(count: number, tickAt: (i: number) => number, tick: number): number {
  let lo = 0
  let hi = count
  while (lo < hi) {
    const mid = (lo + hi) >> 1
    if (tickAt(mid) <= tick) lo = mid + 1
    else hi = mid
  }
  return lo - 1
}

/** Bytes a snapshot holds besides its delta base. */
function ownBytes(s: PlayerSnapshot): number {
  return (
    s.world.byteLength +
    STATE_BYTES +
    STATE_BYTES_PER_ITEM * (s.state.players.length + s.state.userJoints.length)
  )
}

/** The snapshots of one log, in tick order, within a byte budget (see the file comment). */
export class SnapshotStore {
  private readonly list: PlayerSnapshot[] = []
  /** Delta bases held by snapshots, with how many hold each. */
  private readonly bases = new Map<Uint8Array, number>()
  private held = 0

  /**
   * `keyframeTicks` are the log's header and keyframe ticks in order, `lastTick` its end; with a
   * budget of 0 none are taken.
   */
  constructor(
    private readonly keyframeTicks: readonly number[],
    private readonly lastTick: number,
    readonly budget: number = SNAPSHOT_BUDGET_BYTES,
  ) {}

  /** Ticks of the snapshots held, in order. */
  get ticks(): number[] {
    return this.list.map((s) => s.tick)
  }

  /** Bytes the snapshots hold (as counted against the budget). */
  get bytes(): number {
    return this.held
  }

  /** Whether the state at `tick` should be taken: on the grid, and no start point near before it. */
  wants(tick: number): boolean {
    if (this.budget <= 0 || tick % SNAPSHOT_TICKS !== 0) return false
    return this.startBefore(tick) <= tick - SNAPSHOT_TICKS
  }

  /** The newest snapshot at or before `tick`, or null. */
  before(tick: number): PlayerSnapshot | null {
    return this.list[lastAtOrBefore(this.list.length, (i) => this.list[i].tick, tick)] ?? null
  }

  /** Keep a snapshot, dropping others (or it) while over the budget. */
  add(snapshot: PlayerSnapshot): void {
    const at = lastAtOrBefore(this.list.length, (i) => this.list[i].tick, snapshot.tick) + 1
    this.list.splice(at, 0, snapshot)
    this.held += ownBytes(snapshot)
    this.holdBase(snapshot.base, 1)
    while (this.held > this.budget && this.list.length > 0) this.drop(this.crowded())
  }

  /** Tick of the newest start point (log keyframe or snapshot) at or before `tick`, or -Infinity. */
  private startBefore(tick: number): number {
    const k = lastAtOrBefore(this.keyframeTicks.length, (i) => this.keyframeTicks[i], tick)
    const s = this.before(tick)
    return Math.max(
      k < 0 ? Number.NEGATIVE_INFINITY : this.keyframeTicks[k],
      s ? s.tick : Number.NEGATIVE_INFINITY,
    )
  }

  /** Index of the snapshot whose removal leaves the shortest stretch between start points (the first such). */
  private crowded(): number {
    let best = 0
    let shortest = Number.POSITIVE_INFINITY
    for (let i = 0; i < this.list.length; i++) {
      const tick = this.list[i].tick
      const k = lastAtOrBefore(this.keyframeTicks.length, (j) => this.keyframeTicks[j], tick - 1)
      const previous = Math.max(
        this.list[i - 1]?.tick ?? Number.NEGATIVE_INFINITY,
        this.keyframeTicks[k] ?? Number.NEGATIVE_INFINITY,
      )
      const kn =
        this.keyframeTicks[lastAtOrBefore(this.keyframeTicks.length, (j) => this.keyframeTicks[j], tick) + 1]
      const following = Math.min(this.list[i + 1]?.tick ?? this.lastTick, kn ?? this.lastTick)
      if (following - previous < shortest) {
        shortest = following - previous
        best = i
      }
    }
    return best
  }

  private drop(i: number): void {
    const [gone] = this.list.splice(i, 1)
    this.held -= ownBytes(gone)
    this.holdBase(gone.base, -1)
  }

  /** Count a delta base once, however many snapshots hold it. */
  private holdBase(base: Uint8Array | null, change: 1 | -1): void {
    if (!base) return
    const count = (this.bases.get(base) ?? 0) + change
    if (count === 1 && change === 1) this.held += base.byteLength
    if (count === 0) {
      this.bases.delete(base)
      this.held -= base.byteLength
    } else this.bases.set(base, count)
  }
}
