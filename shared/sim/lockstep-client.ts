/*
 * A lockstep client: it simulates the room itself from the server's tick stream.
 *
 * The server sends a `sync` (the saved simulation at tick T) and then, in order, every tick's
 * accepted commands, joins and leaves (`ticks`), with the state hash every 60 ticks. This runner
 * keeps the stream in a queue, steps its own RoomSimulation tick by tick up to the playout clock's
 * target (behind the newest tick by an adaptive delay, lockstep-playout.ts), and compares its hash
 * with the server's at every checkpoint:
 *
 *   match      the tick is verified (stats.verifiedTick)
 *   mismatch   a desync: report it (`desync`: tick, both hashes), stop, and wait for the fresh
 *              `sync` the server answers with; stepping resumes from there, no reload
 *   too far behind (playout.tooFarBehind), a gap in the stream, or a sync that does not restore:
 *              ask for a fresh one (`resync`)
 *
 * A `sync` arriving at any time replaces everything: ticks received before it are dropped, the
 * ones after it continue from its tick. It does no I/O of its own: the owner passes in messages and
 * the time and sends what `send` is given, so the same code runs in the page, in Node tests and
 * benchmarks. The predicting client (predict-client.ts) builds on the same stream handling.
 */
import {
  type ClientMessage,
  DEFAULT_HOLD,
  MAX_HOLD,
  type RoomRules,
  type ServerMessage,
  type SyncMessage,
  type TicksMessage,
} from '../protocol/index.ts'
import type { GameCatalog, PlainData } from './game.ts'
import { PlayoutClock, type PlayoutOptions } from './lockstep-playout.ts'
import type { RoomSimulation, SimulationListener } from './room-simulation.ts'
import { inflate, restoreSyncPayload } from './sync-payload.ts'
import { decodeEntries, type StreamEntry } from './tick-stream.ts'

/** What the owner provides. */
export interface LockstepOptions {
  send(message: ClientMessage): void
  /** The games this build knows (games/'s findGame): a sync names its room's game. */
  games: GameCatalog
  playout?: Partial<PlayoutOptions>
  /** Ticks simulated at most per advance() (catching up after a stall), 120. */
  maxStepsPerAdvance?: number
  /**
   * Empty ticks the server may hold back (join.hold, 1-60). Default: the playout's smallest delay,
   * so a held run never makes the newest tick received lag the tick to play (see `hold`).
   */
  hold?: number
  /** Called when a sync has been restored (the view should forget bodies it drew). */
  onRestored?(sim: RoomSimulation): void
  /** The confirmed simulation's listener (e.g. its game events, each once; the SDK's `event`). */
  listener?: SimulationListener
}

/** Where the client is. */
export type LockstepState = 'joining' | 'loading' | 'running' | 'repairing'

/** Counters for the HUD and the tests. */
export interface LockstepStats {
  /** Last tick whose hash matched the server's, or -1. */
  verifiedTick: number
  /** Hash checkpoints compared (matches and mismatches). */
  hashesChecked: number
  desyncs: number
  /** Syncs restored after the first one (repairs after a desync, catch-ups, gaps). */
  resyncs: number
  /** Resyncs asked for (too far behind, gaps, bad syncs). */
  resyncRequests: number
  /** Commands the local simulation refused although the server had accepted them. */
  refused: number
  /** Size of the last sync on the wire and decompressed (bytes). */
  syncWireBytes: number
  syncBytes: number
}

/** The lockstep runner (see the file comment). */
export class LockstepClient {
  sim: RoomSimulation | null = null
  state: LockstepState = 'joining'
  playerId = 0
  rules: RoomRules | null = null
  readonly playout: PlayoutClock
  readonly stats: LockstepStats = {
    verifiedTick: -1,
    hashesChecked: 0,
    desyncs: 0,
    resyncs: 0,
    resyncRequests: 0,
    refused: 0,
    syncWireBytes: 0,
    syncBytes: 0,
  }
  /** The last failure in words (a bad sync or stream entry), for the HUD and logs. */
  lastProblem = ''
  /** Stream entries not yet simulated, ascending ticks (empty ticks have none). */
  protected entries: StreamEntry[] = []
  protected head = 0
  /** Server hashes by tick, not yet compared. */
  protected readonly hashes = new Map<number, number>()
  /** The tick the next `ticks` message must start at. */
  protected expected = -1
  private syncs = 0
  private generation = 0
  private readonly maxSteps: number
  /**
   * What the owner sends as join.hold. A held empty run makes the newest tick received lag the
   * server by up to hold - 1 ticks; the playout plays at least `minDelay` behind the server's
   * tick, so a hold of minDelay keeps the one tick of margin the stream had at the old fixed 2.
   */
  readonly hold: number

  constructor(protected readonly options: LockstepOptions) {
    this.playout = new PlayoutClock(options.playout)
    this.maxSteps = options.maxStepsPerAdvance ?? 120
    const hold = options.hold ?? Math.floor(options.playout?.minDelay ?? DEFAULT_HOLD)
    this.hold = Math.min(MAX_HOLD, Math.max(1, hold))
  }

  /** Newest tick received from the server. */
  get newestTick(): number {
    return this.playout.newest
  }

  /** Take one server message (other types are left to the owner). */
  handle(message: ServerMessage, nowMs: number): void {
    switch (message.t) {
      case 'welcome':
        this.playerId = message.id
        this.rules = message.rules
        return
      case 'sync':
        this.receiveSync(message, nowMs)
        return
      case 'ticks':
        this.receiveTicks(message, nowMs)
        return
    }
  }

  /** Simulate up to the playout target; returns the ticks stepped. */
  advance(nowMs: number): number {
    if (this.state !== 'running' || !this.sim) return 0
    const target = this.playout.target(nowMs)
    let n = 0
    while (this.state === 'running' && this.sim.tick < target && n < this.maxSteps) {
      this.stepTick()
      n++
    }
    if (this.state === 'running' && this.playout.tooFarBehind(this.sim.tick)) {
      this.requestResync(`${this.playout.newest - this.sim.tick} ticks behind`)
    }
    return n
  }

  /**
   * This player's game view (the game's `view`; PROTOCOL.md, `view`), computed from the confirmed
   * simulation; undefined before the sync or for a game without a view.
   */
  view(): PlainData | undefined {
    return this.sim?.playerView(this.playerId)
  }

  /** Ask the server for a fresh sync and wait for it. */
  requestResync(why: string): void {
    this.lastProblem = why
    this.stats.resyncRequests++
    this.state = 'repairing'
    this.options.send({ t: 'resync' })
  }

  private receiveSync(message: SyncMessage, nowMs: number): void {
    const generation = ++this.generation
    this.entries = []
    this.head = 0
    this.hashes.clear()
    this.expected = message.tick + 1
    this.playout.reset(message.tick, nowMs)
    this.state = 'loading'
    this.stats.syncWireBytes = message.data.length
    const restore = (bytes: Uint8Array): void => {
      if (generation !== this.generation) return
      if (!this.rules) {
        this.requestResync('sync before welcome')
        return
      }
      this.stats.syncBytes = bytes.length
      const restored = restoreSyncPayload(bytes, {
        maxBodies: this.rules.maxBodies,
        // The stream holds only commands the room accepted: a room control in it is applied,
        // whatever this player's own rights (`rules.controls` says only whether its own are).
        controls: true,
        name: '',
        games: this.options.games,
        ...(this.options.listener ? { listener: this.options.listener } : {}),
      })
      if (!restored.ok || restored.sim.tick !== message.tick) {
        this.requestResync(restored.ok ? 'sync tick does not match its payload' : restored.reason)
        return
      }
      this.sim = restored.sim
      if (this.syncs++ > 0) this.stats.resyncs++
      this.state = 'running'
      this.restored(restored.sim)
    }
    if (!message.z) {
      restore(message.data)
      return
    }
    inflate(message.data).then(restore, (error: Error) => {
      if (generation === this.generation) this.requestResync(`sync does not inflate: ${error.message}`)
    })
  }

  /** A fresh simulation is in place (the predicting client also resets its own state). */
  protected restored(sim: RoomSimulation): void {
    this.options.onRestored?.(sim)
  }

  private receiveTicks(message: TicksMessage, nowMs: number): void {
    if (this.state === 'joining' || this.state === 'repairing') return
    if (message.tick !== this.expected || !(message.n >= 1)) {
      this.requestResync(`stream gap: expected tick ${this.expected}, got ${message.tick}`)
      return
    }
    const decoded = decodeEntries(message.c, message.tick, message.n)
    if (!decoded.ok) {
      this.requestResync(`bad stream entry: ${decoded.reason}`)
      return
    }
    for (const e of decoded.entries) this.entries.push(e)
    const last = message.tick + message.n - 1
    if (typeof message.hash === 'number') this.hashes.set(last, message.hash)
    this.expected = last + 1
    this.playout.arrive(last, nowMs)
    this.received(message.tick, last, decoded.entries)
  }

  /** Hook for the predicting client: ticks first..last arrived with these entries. */
  protected received(_first: number, _last: number, _entries: StreamEntry[]): void {}

  /** Apply one stream entry to a simulation; false when the simulation refused it. */
  protected applyEntry(sim: RoomSimulation, e: StreamEntry): boolean {
    const action = e.action
    if (action.k === 'join') sim.join(e.player, '', '')
    else if (action.k === 'leave') sim.leave(e.player)
    else return sim.applyAccepted(e.player, action) === null
    return true
  }

  /** Simulate the next tick from the queue and check its hash if the server sent one. */
  protected stepTick(): void {
    const sim = this.sim as RoomSimulation
    const tick = sim.tick + 1
    while (this.head < this.entries.length && this.entries[this.head].tick === tick) {
      if (!this.applyEntry(sim, this.entries[this.head])) this.stats.refused++
      this.head++
    }
    if (this.head > 1024 && this.head * 2 > this.entries.length) {
      this.entries = this.entries.slice(this.head)
      this.head = 0
    }
    sim.runTick()
    const expected = this.hashes.get(tick)
    if (expected === undefined) return
    this.hashes.delete(tick)
    this.checkHash(tick, sim.hash(), expected)
  }

  /** Compare a checkpoint; on a mismatch report the desync and wait for the server's sync. */
  protected checkHash(tick: number, mine: number, server: number): void {
    this.stats.hashesChecked++
    if (mine === server) {
      this.stats.verifiedTick = tick
      return
    }
    this.stats.desyncs++
    this.lastProblem = `desync at tick ${tick}: ${mine} here, ${server} on the server`
    this.state = 'repairing'
    this.options.send({ t: 'desync', tick, hash: mine, server })
  }
}
