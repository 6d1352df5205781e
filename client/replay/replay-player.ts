/*
 * The replay player's timeline: a whole log read into memory, indexed by its keyframes, and a
 * ReplayRunner (shared/replay/replay-runner.ts, the same code the CLI verifies with) that plays it.
 *
 * "The state at tick T" is the simulation with its room tick at T and every record of ticks up to
 * and including T applied: exactly what the room held after its commands at T, before the step to
 * T + 1. Seeking to T starts from the newest of: the log's keyframes at or before T (the header is
 * the first one; a delta keyframe is decoded through its chain from the last whole one, see
 * deltaChain), the player's own snapshots at or before T, and the current tick when T is ahead of
 * it; then it applies the records after that. The recorder's keyframe budget skips keyframes in
 * busy rooms, and a log from untrusted hands may have none, so the player takes its own snapshots
 * (replay-snapshots.ts: the state at every SNAPSHOT_TICKS-th tick it passes with no keyframe or
 * snapshot in the SNAPSHOT_TICKS ticks before, within a byte budget) and keeps them for the log's
 * life. A seek costs the ticks from where it starts to T: once the player has passed T's stretch
 * of the log, fewer than 2 * SNAPSHOT_TICKS (fewer than SNAPSHOT_TICKS where no keyframe is near,
 * more where the budget has thinned the snapshots). The first pass is not bounded: a first seek to
 * the end of a keyframe-free log of a million ticks replays all of them (taking snapshots on the
 * way), and a seek back to near its end then replays fewer than SNAPSHOT_TICKS.
 *
 * So every move through the log (a seek, or playing forward) runs in slices: a slice goes tick by
 * tick (the records of a tick, then the step to the next) until the target or until SLICE_MS have
 * passed, then the move yields to the event loop (a macrotask) before the next slice, so the page
 * keeps painting and taking input. The clock is checked after every tick (the cost of a tick
 * ranges from microseconds in a resting world to milliseconds in a busy one, and can change a
 * hundredfold within a log, so a tick count sized from past slices could block for seconds); it
 * decides only where a slice ends, and every slice ends at "the state at" some tick, so where
 * slices fall changes nothing in the world.
 *
 * Moves run one at a time, in the order asked (never two on the one runner at once). A seek
 * supersedes every move asked before it: a running one stops at its next slice boundary, a waiting
 * one never starts, and each resolves false; the world then goes on from wherever the older one
 * stopped, which is always the state at some tick. Playing forward applies the same records in
 * the same order as seeking, and a snapshot is a keyframe the player made (World.save(), which
 * loads into a world that steps bit-identically), so a seek, a superseded seek followed by
 * another, and a play-through reach bit-identical worlds at the same tick (the hash check below
 * is on in all of them). A snapshot is taken at the start of a slice (see runSlice).
 *
 * The hash check: every hash record met while playing or seeking is compared with the replayed
 * world (the runner does it); the first mismatch is kept, with its tick, for the indicator.
 */

import {
  type Divergence,
  deltaChain,
  type HeaderRecord,
  type Inflate,
  incompatibility,
  type KeyframeRecord,
  PREAMBLE_BYTES,
  type Preamble,
  type ReadStatus,
  ReplayLogReader,
  type ReplayRecord,
  ReplayRunner,
  type RoomSimulation,
  type SimulationListener,
} from '../../shared/index.ts'
import { findClientGame } from '../modes/index.ts'
import { SNAPSHOT_BUDGET_BYTES, SnapshotStore } from './replay-snapshots.ts'

/** A log read whole: its records after the header and where its keyframes are. */
export interface LoadedLog {
  preamble: Preamble
  header: HeaderRecord
  /** Every intact record after the header, in log order. */
  records: ReplayRecord[]
  /** Indices into `records` of the keyframes, in tick order. */
  keyframes: number[]
  /** How reading ended: 'end' for a whole log, 'torn' or 'corrupt' when only a prefix was kept. */
  status: ReadStatus
  /** Room tick of the header and of the last intact record. */
  firstTick: number
  lastTick: number
}

/** Why a file cannot be played; the message names the problem in one line. */
export class ReplayLoadError extends Error {}

/** Main-thread time a slice of a move runs for (ms, plus at most one tick); the page paints between. */
const SLICE_MS = 12

/**
 * Resolve in a new task: a MessageChannel message. A resolved promise would not let the page
 * paint (microtasks run before it), and nested setTimeout(0)s are clamped to 4 ms each.
 */
function nextTask(): Promise<void> {
  return new Promise((resolve) => {
    const channel = new MessageChannel()
    channel.port1.onmessage = () => {
      channel.port1.close()
      resolve()
    }
    channel.port2.postMessage(null)
  })
}

/** Bytes of whole records handed to the reader at a time while reading a log. */
const READ_CHUNK_BYTES = 256 * 1024

/**
 * Read a whole log; rejects with ReplayLoadError for a file that is not a playable log. A log is
 * read in slices like a seek (about SLICE_MS of main thread, then a new task), so opening a big
 * file (a 60 MB log of 3 million small records took 3.3 s to parse in Node) leaves the page live;
 * `progress` gets the fraction of the bytes read after each slice. The reader gets whole records,
 * many at a time, never a record cut in two (its buffer would copy a large record once per chunk).
 */
export async function readLog(bytes: Uint8Array, progress?: (fraction: number) => void): Promise<LoadedLog> {
  const reader = new ReplayLogReader()
  let header: ReplayRecord | null = null
  const records: ReplayRecord[] = []
  const keyframes: number[] = []
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  let at = 0
  let deadline = performance.now() + SLICE_MS
  while (at < bytes.length && reader.current.state === 'reading') {
    // Whole frames (u32 length, length bytes, u32 CRC) from `at` to about READ_CHUNK_BYTES on; the
    // preamble goes with the first chunk. A length running past the end takes the rest: the reader
    // tells a torn tail or a corrupt length from there.
    let end = at === 0 ? Math.min(PREAMBLE_BYTES, bytes.length) : at
    while (end < bytes.length && end - at < READ_CHUNK_BYTES) {
      if (bytes.length - end < 4) {
        end = bytes.length
        break
      }
      end = Math.min(bytes.length, end + 8 + view.getUint32(end, true))
    }
    for (const r of reader.push(bytes.subarray(at, end))) {
      if (header === null) header = r
      else {
        if (r.type === 'keyframe') keyframes.push(records.length)
        records.push(r)
      }
    }
    at = end
    if (performance.now() >= deadline && at < bytes.length) {
      progress?.(at / bytes.length)
      await nextTask()
      deadline = performance.now() + SLICE_MS
    }
  }
  const status = reader.finish()
  if (status.state === 'invalid') throw new ReplayLoadError(`not a replay log: ${status.reason}`)
  const preamble = reader.preamble
  if (!preamble || !header || header.type !== 'header')
    throw new ReplayLoadError('not a replay log: no header')
  const problem = incompatibility(preamble)
  if (problem) throw new ReplayLoadError(problem)
  return { preamble, header, records, keyframes, status, firstTick: header.tick, lastTick: status.lastTick }
}

/** A player joined in the log: its name and colour. */
export interface ReplayPerson {
  name: string
  color: string
}

/** A seek under way: where its replay started (after any keyframe restore) and where it is going. */
export interface SeekProgress {
  from: number
  target: number
}

/** How a player is set up besides its log. */
export interface PlayerOptions {
  /** Bytes its own snapshots may hold (SNAPSHOT_BUDGET_BYTES unless given); 0 takes none. */
  snapshotBudget?: number
}

/** Plays a loaded log: seek, step and run forward in slices, with the hash check. */
export class ReplayPlayer {
  /** Players seen so far in the log, by id (names stay known after they leave). */
  readonly people = new Map<number, ReplayPerson>()
  /** The player whose record is being applied (for spawn flashes), or 0. */
  actingPlayer = 0
  /** Hash checkpoints compared so far (since the last seek back counts them again). */
  checked = 0
  /** The first hash (or refused command) that did not match the log, kept across seeks. */
  mismatch: Divergence | null = null
  /** The seek running now, or null. */
  seeking: SeekProgress | null = null
  /** Room ticks run by moves since the player opened (a seek's cost is what it adds). */
  ticksRun = 0
  private next = 0
  /** The header, then every keyframe, in log order (what deltaChain walks). */
  private readonly stored: Array<HeaderRecord | KeyframeRecord>
  /** Moves asked for so far (each move's ticket is its number), and the newest seek's ticket. */
  private tickets = 0
  private newestSeek = 0
  /** Moves running or waiting, and the last one asked for (the next waits for it). */
  private moves = 0
  private last: Promise<unknown> = Promise.resolve()
  /** The player's own snapshots of the state at ticks it passed (replay-snapshots.ts). */
  private readonly snapshots: SnapshotStore

  private constructor(
    readonly log: LoadedLog,
    private readonly runner: ReplayRunner,
    snapshotBudget: number,
  ) {
    this.stored = [log.header, ...log.keyframes.map((i) => log.records[i] as KeyframeRecord)]
    this.snapshots = new SnapshotStore(
      this.stored.map((k) => k.tick),
      log.lastTick,
      snapshotBudget,
    )
  }

  /** A player at the log's first tick. */
  static async open(
    log: LoadedLog,
    inflate: Inflate,
    listener?: SimulationListener,
    options: PlayerOptions = {},
  ): Promise<ReplayPlayer> {
    const runner = await ReplayRunner.start(log.preamble, log.header, {
      inflate,
      games: findClientGame,
      listener,
    })
    const player = new ReplayPlayer(log, runner, options.snapshotBudget ?? SNAPSHOT_BUDGET_BYTES)
    player.collectPeople(log.records.length)
    return player
  }

  /** Ticks of the player's own snapshots, in order. */
  get snapshotTicks(): number[] {
    return this.snapshots.ticks
  }

  /** Bytes the player's own snapshots hold, as counted against their budget. */
  get snapshotBytes(): number {
    return this.snapshots.bytes
  }

  /** The simulation as of the current tick. */
  get sim(): RoomSimulation {
    return this.runner.sim
  }

  /** Current room tick. */
  get tick(): number {
    return this.runner.sim.tick
  }

  /** Whether the current tick is the last one the log holds. */
  get atEnd(): boolean {
    return this.tick >= this.log.lastTick
  }

  /** Whether a move is running or waiting. */
  get busy(): boolean {
    return this.moves > 0
  }

  /**
   * Play forward to `tick` (clamped to the log's end), applying every record up to it, after the
   * moves asked before. Resolves true there, false when a newer seek superseded it.
   */
  forwardTo(tick: number): Promise<boolean> {
    return this.enqueue(false, (ticket) => this.forward(tick, ticket))
  }

  /** Play `ticks` forward from wherever the moves asked before leave the world (see forwardTo). */
  forwardBy(ticks: number): Promise<boolean> {
    return this.enqueue(false, (ticket) => this.forward(this.tick + ticks, ticket))
  }

  /**
   * Jump to any tick: from the newest log keyframe or own snapshot at or before it (or from the
   * current tick when that is nearer), then forward. Supersedes every move asked before it;
   * resolves true at the tick, false when a newer seek superseded this one.
   */
  seek(tick: number): Promise<boolean> {
    return this.enqueue(true, (ticket) => this.seekNow(tick, ticket))
  }

  /** Stop every move at its next slice boundary (the log is being closed). */
  cancel(): void {
    this.newestSeek = ++this.tickets
  }

  /**
   * Run a move after the ones asked before it. With none under way it starts at once, so a short
   * play-forward has run its ticks when the frame that asked for them draws.
   */
  private enqueue(supersedes: boolean, move: (ticket: number) => Promise<boolean>): Promise<boolean> {
    const ticket = ++this.tickets
    if (supersedes) this.newestSeek = ticket
    const start = (): Promise<boolean> => (this.superseded(ticket) ? Promise.resolve(false) : move(ticket))
    const idle = this.moves === 0
    this.moves++
    const run = (idle ? start() : this.last.then(start)).finally(() => {
      this.moves--
    })
    this.last = run.catch(() => false)
    return run
  }

  private superseded(ticket: number): boolean {
    return ticket < this.newestSeek
  }

  private async seekNow(tick: number, ticket: number): Promise<boolean> {
    const target = Math.min(Math.max(tick, this.log.firstTick), this.log.lastTick)
    this.seeking = { from: this.tick, target }
    try {
      // Start from the newest of: the current tick (when not past the target), the log keyframe
      // and the own snapshot at or before the target. On a tie the current tick needs no restore.
      const k = this.keyframeBefore(target)
      const keyframeTick = k < 0 ? this.log.firstTick : this.log.records[k].tick
      const snapshot = this.snapshots.before(target)
      const start = Math.max(keyframeTick, snapshot?.tick ?? Number.NEGATIVE_INFINITY)
      if (target < this.tick || start > this.tick || (start === this.tick && k >= this.next)) {
        // A move that stopped on a snapshot tick left the snapshot to the next slice: take it
        // before leaving.
        if (this.snapshots.wants(this.tick)) this.takeSnapshot()
        if (snapshot && snapshot.tick > keyframeTick) {
          this.runner.resume(snapshot)
          this.next = snapshot.next
        } else {
          await this.runner.restore(deltaChain(this.stored, k < 0 ? 0 : this.log.keyframes.indexOf(k) + 1))
          this.next = k + 1
        }
        this.seeking = { from: this.tick, target }
      }
      return await this.forward(target, ticket)
    } finally {
      this.seeking = null
    }
  }

  /** Slice by slice to `tick` (clamped to the log); false when superseded at a slice boundary. */
  private async forward(tick: number, ticket: number): Promise<boolean> {
    const target = Math.min(Math.max(tick, this.tick), this.log.lastTick)
    for (;;) {
      await this.runSlice(target, performance.now() + SLICE_MS)
      if (this.tick >= target) return true
      await nextTask()
      if (this.superseded(ticket)) return false
    }
  }

  /**
   * Tick by tick towards `target` until `deadline` (performance.now() ms) has passed; ends at the
   * state at some tick (every record up to it applied, the room tick at it). The deadline is
   * checked before each step: a slice whose records used up its time ends without one, the next
   * one steps. A snapshot due at a tick is taken only by a slice that has not stepped yet: one
   * that has ends there instead and the next slice starts with it, so a slice pays for SLICE_MS
   * of ticks or a snapshot and the rest of SLICE_MS, never both. A move that ends on a snapshot
   * tick leaves it to the next move: a forward one takes it in its first slice, a seek that
   * restores takes it before it does.
   */
  private async runSlice(target: number, deadline: number): Promise<void> {
    const records = this.log.records
    let stepped = false
    for (;;) {
      while (this.next < records.length && records[this.next].tick <= this.tick) {
        const r = records[this.next++]
        this.actingPlayer = r.type === 'command' ? r.player : 0
        await this.runner.apply(r)
        this.actingPlayer = 0
        if (r.type === 'hash') this.checked++
        this.noteDivergence()
      }
      if (this.snapshots.wants(this.tick)) {
        if (stepped) return
        this.takeSnapshot()
      }
      if (this.tick >= target || performance.now() >= deadline) return
      this.runner.advanceTo(this.tick + 1)
      this.ticksRun++
      stepped = true
    }
  }

  /** Keep the state at the current tick (every record up to it applied) as a snapshot. */
  private takeSnapshot(): void {
    this.snapshots.add({ ...this.runner.save(), tick: this.tick, next: this.next })
  }

  /** Index of the newest keyframe at or before `tick`, or -1 for the header. */
  private keyframeBefore(tick: number): number {
    let found = -1
    for (const i of this.log.keyframes) {
      if (this.log.records[i].tick > tick) break
      found = i
    }
    return found
  }

  private noteDivergence(): void {
    const d = this.runner.divergence
    if (d && (!this.mismatch || d.tick < this.mismatch.tick)) this.mismatch = d
  }

  private collectPeople(upTo: number): void {
    for (let i = 0; i < upTo; i++) {
      const r = this.log.records[i]
      if (r.type === 'join') this.people.set(r.player, { name: r.name, color: r.color })
    }
  }
}
