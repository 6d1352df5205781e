/*
 * The replay player's timeline: a whole log read into memory, indexed by its keyframes, and a
 * ReplayRunner (shared/replay-runner.ts, the same code the CLI verifies with) that plays it.
 *
 * "The state at tick T" is the simulation with its room tick at T and every record of ticks up to
 * and including T applied: exactly what the room held after its commands at T, before the step to
 * T + 1. Seeking to T restores the newest keyframe at or before T (the header is the first one;
 * a delta keyframe is decoded through its chain from the last whole one, see deltaChain) and
 * applies the records after it, so a seek costs at most one keyframe interval of simulation.
 * Playing forward applies the same records in the same order, so a seek and a play-through reach
 * bit-identical worlds (the hash check below is on in both).
 *
 * The hash check: every hash record met while playing or seeking is compared with the replayed
 * world (the runner does it); the first mismatch is kept, with its tick, for the indicator.
 */
import type { Preamble, ReplayRecord } from '../shared/replay-log.ts'
import { type ReadStatus, ReplayLogReader } from '../shared/replay-log-reader.ts'
import {
  type Divergence,
  deltaChain,
  type HeaderRecord,
  type Inflate,
  incompatibility,
  type KeyframeRecord,
  ReplayRunner,
} from '../shared/replay-runner.ts'
import type { RoomSimulation, SimulationListener } from '../shared/room-simulation.ts'

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

/** Read a whole log; throws ReplayLoadError for a file that is not a playable log. */
export function readLog(bytes: Uint8Array): LoadedLog {
  const reader = new ReplayLogReader()
  const all = reader.push(bytes)
  const status = reader.finish()
  if (status.state === 'invalid') throw new ReplayLoadError(`not a replay log: ${status.reason}`)
  const preamble = reader.preamble
  const header = all[0]
  if (!preamble || !header || header.type !== 'header')
    throw new ReplayLoadError('not a replay log: no header')
  const problem = incompatibility(preamble)
  if (problem) throw new ReplayLoadError(problem)
  const records = all.slice(1)
  const keyframes: number[] = []
  records.forEach((r, i) => {
    if (r.type === 'keyframe') keyframes.push(i)
  })
  return { preamble, header, records, keyframes, status, firstTick: header.tick, lastTick: status.lastTick }
}

/** A player joined in the log: its name and colour. */
export interface ReplayPerson {
  name: string
  color: string
}

/** Plays a loaded log: seek, step and run forward, with the hash check. */
export class ReplayPlayer {
  /** Players seen so far in the log, by id (names stay known after they leave). */
  readonly people = new Map<number, ReplayPerson>()
  /** The player whose record is being applied (for spawn flashes), or 0. */
  actingPlayer = 0
  /** Hash checkpoints compared so far (since the last seek back counts them again). */
  checked = 0
  /** The first hash (or refused command) that did not match the log, kept across seeks. */
  mismatch: Divergence | null = null
  private next = 0
  /** The header, then every keyframe, in log order (what deltaChain walks). */
  private readonly stored: Array<HeaderRecord | KeyframeRecord>

  private constructor(
    readonly log: LoadedLog,
    private readonly runner: ReplayRunner,
  ) {
    this.stored = [log.header, ...log.keyframes.map((i) => log.records[i] as KeyframeRecord)]
  }

  /** A player at the log's first tick. */
  static async open(log: LoadedLog, inflate: Inflate, listener?: SimulationListener): Promise<ReplayPlayer> {
    const runner = await ReplayRunner.start(log.preamble, log.header, { inflate, listener })
    const player = new ReplayPlayer(log, runner)
    player.collectPeople(log.records.length)
    return player
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

  /** Play forward to `tick` (clamped to the log's end), applying every record up to it. */
  async forwardTo(tick: number): Promise<void> {
    const target = Math.min(Math.max(tick, this.tick), this.log.lastTick)
    const records = this.log.records
    while (this.next < records.length && records[this.next].tick <= target) {
      const r = records[this.next++]
      this.actingPlayer = r.type === 'command' ? r.player : 0
      await this.runner.apply(r)
      this.actingPlayer = 0
      if (r.type === 'hash') this.checked++
      this.noteDivergence()
    }
    this.runner.advanceTo(target)
  }

  /** Jump to any tick: through the newest keyframe at or before it, then forward. */
  async seek(tick: number): Promise<void> {
    const target = Math.min(Math.max(tick, this.log.firstTick), this.log.lastTick)
    if (target >= this.tick && this.keyframeBefore(target) <= this.next - 1) {
      await this.forwardTo(target)
      return
    }
    const k = this.keyframeBefore(target)
    await this.runner.restore(deltaChain(this.stored, k < 0 ? 0 : this.log.keyframes.indexOf(k) + 1))
    this.next = k + 1
    await this.forwardTo(target)
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
