/*
 * A room's lockstep feed: the tick stream for lockstep and predicting players, their syncs, and
 * their desync reports.
 *
 * The feed observes the room's RoomSimulation (the same observer interface the recorder uses, so
 * the stream and the log are one source): every accepted command, join and leave is an entry at
 * the tick it belongs to (observers see the completed-tick count; the entry is part of the next
 * tick). At the end of every room tick, after the simulation's tick:
 *
 *   1. a tick with entries or a hash checkpoint (every HASH_INTERVAL ticks) is flushed at once to
 *      every live follower: one `ticks` message covering that follower's unsent run up to this
 *      tick. Empty ticks are held back per follower, up to its `hold` (join.hold, DEFAULT_HOLD
 *      unless it said, at most MAX_HOLD): a run of empty ticks costs one short message per hold.
 *      Followers whose unsent runs start at the same tick share one encoding.
 *   2. followers waiting for a sync get one, if the rate limits allow: the saved simulation at
 *      this tick (sync-payload.ts), zlib-compressed when that is at least 10 % smaller, encoded
 *      once for everyone served at this tick. Their next `ticks` message starts at the next tick.
 *
 * A follower waits for a sync after joining, after a world load from outside a command (a
 * benchmark's blueprint), and after asking (a desync report or a resync request). While it waits
 * it gets no ticks. Saved worlds are bounded twice: each follower has a bucket of SYNC_BURST
 * syncs refilled one per CLIENT_SYNC_SECONDS, the room one of ROOM_SYNC_BURST refilled
 * ROOM_SYNCS_PER_SECOND per second; a request beyond them waits (one pending request per
 * follower, repeats are merged), so no flood can make the server send saved worlds without limit.
 *
 * A desync report names a tick and both hashes. It counts (concord_desyncs_total, a warning in the
 * log) only when the tick is one of the last CHECKPOINTS_KEPT checkpoints this room sent, the
 * server hash it quotes is the one sent, and the follower has not reported that tick or a later one
 * already; anything else is refused as invalid (the transport counts it against the sender).
 */
import { deflateSync } from 'node:zlib'
import type { Logger } from 'pino'
import {
  type Command,
  DEFAULT_HOLD,
  encodeEntry,
  encodeMessage,
  encodeSyncPayload,
  MAX_HOLD,
  type RoomSimulation,
  type SimulationObserver,
  type StreamEntry,
  TICK_RATE,
} from '../../shared/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import type { PlayerConnection } from './player-connection.ts'

/** Ticks between hash checkpoints in the stream (one a second). */
export const HASH_INTERVAL = TICK_RATE
/** Checkpoints remembered for desync reports: a minute's worth. */
export const CHECKPOINTS_KEPT = 60
/** Syncs a follower may get back to back. */
export const SYNC_BURST = 2
/** Seconds per extra sync a follower earns. */
export const CLIENT_SYNC_SECONDS = 5
/** Syncs a room may send back to back. */
export const ROOM_SYNC_BURST = 8
/** Syncs per second a room earns. */
export const ROOM_SYNCS_PER_SECOND = 2

/** A lockstep or predicting player of the feed. */
export interface Follower {
  readonly id: number
  readonly conn: PlayerConnection
  /** Waiting for a sync (gets no ticks until it has one). */
  waiting: boolean
  /** Syncs it may still get now (refills over time). */
  tokens: number
  /** Room tick of its last refill. */
  refilledAt: number
  /** Newest checkpoint tick it reported a desync for. */
  reportedTick: number
  /** Syncs sent to it. */
  syncs: number
  /** Longest run of empty ticks held back for it (ticks, 1..MAX_HOLD). */
  hold: number
  /** First tick not yet sent to it. */
  runStart: number
}

/** The lockstep feed of one room (see the file comment). */
export class LockstepFeed implements SimulationObserver {
  readonly followers = new Map<number, Follower>()
  /** Entries of the current tick, not yet sent. */
  private pending: StreamEntry[] = []
  private roomTokens = ROOM_SYNC_BURST
  private roomRefilledAt: number
  private readonly checkpoints = new Map<number, number>()
  /** Size of the last sync on the wire and before compression (bytes), for benchmarks. */
  lastSyncBytes = 0
  lastSyncRawBytes = 0

  constructor(
    private readonly sim: RoomSimulation,
    private readonly room: string,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.roomRefilledAt = sim.tick
    sim.observers.push(this)
  }

  /** Start following: the player waits for its first sync (sent at the end of this tick). */
  add(id: number, conn: PlayerConnection): void {
    this.followers.set(id, {
      id,
      conn,
      waiting: true,
      tokens: SYNC_BURST,
      refilledAt: this.sim.tick,
      reportedTick: -1,
      syncs: 0,
      hold: DEFAULT_HOLD,
      runStart: this.sim.tick + 1,
    })
  }

  /**
   * Set how many empty ticks may be held back for a follower (join.hold, validated to
   * 1..MAX_HOLD by the transport); ignored for players that are not followers.
   */
  setHold(id: number, hold: number): void {
    const f = this.followers.get(id)
    if (f) f.hold = Math.min(MAX_HOLD, Math.max(1, Math.floor(hold)))
  }

  /** Stop following (the player left). */
  remove(id: number): void {
    this.followers.delete(id)
  }

  command(tick: number, player: number, cmd: Command): void {
    this.pending.push({ tick: tick + 1, player, action: cmd })
  }

  join(tick: number, player: number): void {
    this.pending.push({ tick: tick + 1, player, action: { k: 'join' } })
  }

  leave(tick: number, player: number): void {
    this.pending.push({ tick: tick + 1, player, action: { k: 'leave' } })
  }

  /** A world replaced from outside a command: the stream cannot express it, so everyone resyncs. */
  worldLoaded(): void {
    for (const f of this.followers.values()) f.waiting = true
  }

  /**
   * A follower asks for a fresh sync (it fell behind or could not restore one); repeats merge
   * into one pending request. Returns a reason when the player is not a follower.
   */
  requestSync(id: number): string | null {
    const f = this.followers.get(id)
    if (!f) return 'resync requests are for lockstep and predict players'
    f.waiting = true
    return null
  }

  /**
   * A follower reports a desync; returns a reason when the report is refused (unknown tick, a
   * server hash that was never sent, a repeat), or null when it was counted and a sync queued.
   */
  reportDesync(id: number, tick: number, clientHash: number, serverHash: number): string | null {
    const f = this.followers.get(id)
    if (!f) return 'desync reports are for lockstep and predict players'
    const sent = this.checkpoints.get(tick)
    if (sent === undefined) return `tick ${tick} is not a recent hash checkpoint of room ${this.room}`
    if (sent !== serverHash) return `the server's hash at tick ${tick} was ${sent}, not ${serverHash}`
    if (tick <= f.reportedTick) return `desync at tick ${tick} already reported`
    if (clientHash === serverHash) return 'the two hashes are equal: not a desync'
    f.reportedTick = tick
    f.waiting = true
    this.metrics.desyncs.inc()
    this.log.warn({ room: this.room, player: id, tick, clientHash, serverHash }, 'lockstep desync reported')
    return null
  }

  /**
   * End of a room tick (after the simulation's tick): stream, checkpoint, serve waiting followers.
   * `checkpoint` is sim.hash() when the caller computed it at this tick already.
   */
  endTick(checkpoint?: number): void {
    const tick = this.sim.tick
    let hash: number | undefined
    if (tick % HASH_INTERVAL === 0 && this.followers.size > 0) {
      hash = checkpoint ?? this.sim.hash()
      this.checkpoints.set(tick, hash)
      this.checkpoints.delete(tick - HASH_INTERVAL * CHECKPOINTS_KEPT)
    }
    const hasEntries = this.pending.length > 0
    const anyWaiting = this.serveableWaiting()
    this.flush(tick, hasEntries || hash !== undefined, hash)
    this.pending = []
    if (anyWaiting) this.serveSyncs()
  }

  /** Send every live follower its unsent run up to `last` when it is due (or `now`). */
  private flush(last: number, now: boolean, hash: number | undefined): void {
    let encoded: Map<number, Uint8Array> | null = null
    for (const f of this.followers.values()) {
      if (f.waiting || last < f.runStart) continue
      if (!now && last - f.runStart + 1 < f.hold) continue
      encoded ??= new Map()
      let bytes = encoded.get(f.runStart)
      if (!bytes) {
        const start = f.runStart
        bytes = encodeMessage({
          t: 'ticks' as const,
          tick: start,
          n: last - start + 1,
          c: this.pending.map((e) => encodeEntry(e, start)),
          ...(hash === undefined ? {} : { hash }),
        })
        encoded.set(start, bytes)
      }
      f.conn.sendBytes(bytes)
      f.runStart = last + 1
    }
  }

  /** Refill the buckets; whether some waiting follower can be served now. */
  private serveableWaiting(): boolean {
    const tick = this.sim.tick
    const roomEarned = Math.floor(((tick - this.roomRefilledAt) * ROOM_SYNCS_PER_SECOND) / TICK_RATE)
    if (roomEarned > 0) {
      this.roomTokens = Math.min(ROOM_SYNC_BURST, this.roomTokens + roomEarned)
      this.roomRefilledAt += (roomEarned * TICK_RATE) / ROOM_SYNCS_PER_SECOND
    }
    if (this.roomTokens < 1) return false
    const per = CLIENT_SYNC_SECONDS * TICK_RATE
    let any = false
    for (const f of this.followers.values()) {
      const earned = Math.floor((tick - f.refilledAt) / per)
      if (earned > 0) {
        f.tokens = Math.min(SYNC_BURST, f.tokens + earned)
        f.refilledAt += earned * per
      }
      if (f.tokens >= SYNC_BURST) f.refilledAt = tick
      if (f.waiting && f.tokens >= 1) any = true
    }
    return any
  }

  /** Send the saved simulation to every waiting follower the buckets allow. */
  private serveSyncs(): void {
    let bytes: Uint8Array | null = null
    for (const f of this.followers.values()) {
      if (!f.waiting || f.tokens < 1 || this.roomTokens < 1) continue
      bytes ??= this.encodeSync()
      f.tokens--
      this.roomTokens--
      f.waiting = false
      f.runStart = this.sim.tick + 1
      f.syncs++
      f.conn.sendBytes(bytes)
    }
  }

  private encodeSync(): Uint8Array {
    const raw = encodeSyncPayload(this.sim)
    const packed = deflateSync(raw, { level: 1 })
    const z = packed.length < raw.length * 0.9
    const data = z ? new Uint8Array(packed.buffer, packed.byteOffset, packed.length) : raw
    this.lastSyncRawBytes = raw.length
    this.lastSyncBytes = data.length
    return encodeMessage({ t: 'sync', tick: this.sim.tick, z, data })
  }
}
