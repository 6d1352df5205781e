/*
 * A joined player as the room's networking sees it: identity, connection, the snapshot delta
 * state, the per-tick input budget, what it inspects and backpressure state. What the player
 * does to the world (grab, cursor) lives in the room's RoomSimulation.
 */
import { type SimCommand, SnapshotEncoder } from '../../shared/index.ts'
import type { PlayerConnection } from './player-connection.ts'

/** A player in a room. */
export class RoomPlayer {
  /** Whether it is still in the room. */
  joined = true
  /**
   * A spectator (join.spectate): it gets what players get (snapshots or the tick stream, events,
   * hashes) but holds no player slot, is not in the simulation or the roster, and every input
   * and game command it sends is refused.
   */
  spectator = false
  /** A lockstep or predict player: it gets the tick stream (lockstep-feed.ts), not snapshots. */
  lockstep = false
  /** Cursor or grab changed since the last snapshot. */
  cursorDirty = false
  /** Body whose contacts follow each snapshot (the lab), or 0. */
  inspect = 0
  readonly encoder = new SnapshotEncoder()
  /** Inputs (and pings) counted against the current tick's budget. */
  inputsThisTick = 0
  /** Index in the room queue of this player's move for the current tick, or -1. */
  queuedMove = -1
  /** Inputs over a tick's budget, in arrival order, waiting for the next ticks (room.ts). */
  readonly waiting: Array<{ seq: number; cmd: SimCommand }> = []
  /** Room tick since which the send buffer has been over budget, or -1. */
  behindSince = -1
  /** Dropped for not reading: nothing more is sent while its connection closes. */
  dropped = false
  /** MessagePack bytes of the last game view sent to it (room.ts sendViews), or null. */
  lastView: Uint8Array | null = null

  constructor(
    readonly id: number,
    /** Display name (the join's, or the latest `rename`). */
    public name: string,
    readonly color: string,
    readonly token: string,
    readonly room: string,
    readonly conn: PlayerConnection,
  ) {}
}
