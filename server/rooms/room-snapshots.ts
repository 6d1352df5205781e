/*
 * A room's snapshots (step 4 of a room tick, room.ts): on a snapshot tick, the world is quantized
 * once into a shared frame, then each snapshot-mode player gets its delta against its own
 * acknowledged baseline within its byte budget (players whose baselines are equal, the usual case,
 * share one encoded message), followed by the contacts of the body it inspects, if any. The
 * slow-reader rule runs here for every player, lockstep and predict players too: one with more
 * unread data than the send-buffer budget is skipped, and closed if it stays behind.
 */

import type { Logger } from 'pino'
import {
  ByteWriter,
  type EncodeStats,
  encodeMessage,
  QuantizedFrame,
  quantizePosition,
  type RoomSimulation,
  type SnapshotEncoder,
  TICK_RATE,
} from '../../shared/index.ts'
import { hardBufferLimit, type ServerConfig } from '../config/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import { DROP_CONNECTION } from './player-connection.ts'
import type { RoomPlayer } from './room-player.ts'
import { encodeInspections, fillFrame } from './room-wire.ts'

/** A snapshot encoded this tick, for players with the same baseline (SnapshotEncoder.follow). */
interface SharedSnapshot {
  encoder: SnapshotEncoder
  bytes: Uint8Array
}

/** The snapshot side of one room. */
export class RoomSnapshots {
  /** Largest staleness (ticks) of a body write in the last snapshot round, for the benchmark. */
  lastMaxStaleness = 0
  /** The encodes of this snapshot tick that later clients may take over (emptied after each). */
  private readonly shared: SharedSnapshot[] = []
  private readonly frame = new QuantizedFrame(256)
  private readonly writer = new ByteWriter(4096)
  /** Bytes of snapshot per player per snapshot tick. */
  private readonly budget: number
  private readonly weight = (id: number): number => (this.sim.grabCounts.has(id) ? 8 : 0)

  constructor(
    private readonly roomName: string,
    private readonly sim: RoomSimulation,
    private readonly players: ReadonlyMap<number, RoomPlayer>,
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.budget = Math.floor(config.clientBandwidth / config.snapshotRate)
  }

  /** Send this tick's snapshots (called on snapshot ticks). */
  send(): void {
    if (this.players.size === 0) return
    fillFrame(this.sim.world, this.frame)
    const cursors: number[] = []
    for (const p of this.players.values()) {
      if (!p.cursorDirty) continue
      const s = this.sim.players.get(p.id)
      if (!s) continue
      cursors.push(p.id, quantizePosition(s.cursorX), quantizePosition(s.cursorY), s.grab ? s.grab.body : 0)
      p.cursorDirty = false
    }
    let inspected: Set<number> | null = null
    for (const p of this.players.values()) if (p.inspect !== 0) (inspected ??= new Set()).add(p.inspect)
    const contacts = inspected
      ? encodeInspections(this.sim.world, this.sim.tick, inspected, this.sim.userJoints)
      : null
    let staleness = 0
    const shared = this.shared
    shared.length = 0
    for (const p of this.players.values()) {
      // A lockstep player's tick stream cannot be skipped, but the slow-reader rule closes it too.
      if (p.lockstep) {
        if (!p.dropped) this.overBudget(p)
        continue
      }
      staleness = Math.max(staleness, this.sendSnapshot(p, cursors, contacts?.get(p.inspect), shared))
    }
    shared.length = 0
    this.lastMaxStaleness = staleness
  }

  /**
   * The slow-reader rule, on snapshot ticks: whether `player` has more unread data than the
   * send-buffer budget. One that has been over it for --slow-client-seconds, or is over the hard
   * limit (8 budgets, at least 1 MiB), is closed without a close frame.
   */
  overBudget(player: RoomPlayer): boolean {
    const buffered = player.conn.buffered()
    if (buffered <= this.config.sendBufferBytes) {
      player.behindSince = -1
      return false
    }
    if (player.behindSince < 0) player.behindSince = this.sim.tick
    const tooLong = this.sim.tick - player.behindSince > this.config.slowClientSeconds * TICK_RATE
    if (tooLong || buffered > hardBufferLimit(this.config)) {
      this.log.warn(
        {
          room: this.roomName,
          player: player.id,
          buffered,
          rule: tooLong ? 'slow-client-seconds' : 'hard-limit',
        },
        'closing a client that stopped reading',
      )
      this.metrics.slowClientsClosed.inc()
      player.dropped = true
      player.conn.close(DROP_CONNECTION, 'stopped reading')
    }
    return true
  }

  /**
   * Send one player its snapshot and, when it inspects a body, that body's contacts; or skip both
   * when its connection has too much buffered. Returns the snapshot's staleness. A player whose
   * baseline equals that of a player already encoded this tick gets the same message bytes
   * (SnapshotEncoder.follow); otherwise its encode joins `shared` for the players after it.
   */
  private sendSnapshot(
    player: RoomPlayer,
    cursors: number[],
    contacts: Uint8Array | undefined,
    shared: SharedSnapshot[],
  ): number {
    if (player.dropped) return 0
    if (this.overBudget(player)) {
      this.metrics.snapshotsSkipped.inc()
      return 0
    }
    let bytes: Uint8Array | null = null
    let stats: EncodeStats | null = null
    for (let i = 0; i < shared.length; i++) {
      stats = player.encoder.follow(shared[i].encoder, this.frame, this.sim.tick, this.budget)
      if (stats) {
        bytes = shared[i].bytes
        break
      }
    }
    if (!bytes || !stats) {
      this.writer.reset()
      const base = player.encoder.referenceTick
      stats = player.encoder.encode(this.writer, this.frame, this.sim.tick, this.budget, this.weight)
      const data = this.writer.bytes.subarray(0, this.writer.length)
      bytes = encodeMessage({ t: 'snap', tick: this.sim.tick, base, data, cursors })
      shared.push({ encoder: player.encoder, bytes })
    }
    // Marked as the snapshot of this tick: its ack tells how far the client has read.
    player.conn.sendBytes(bytes, this.sim.tick)
    if (contacts) player.conn.sendBytes(contacts)
    return stats.maxStaleness
  }
}
