/*
 * Where rooms run, as the transport and the HTTP routes see it: on the main thread
 * (LocalRoomHost, --workers 0) or on a pool of worker threads (worker-pool.ts). A joined client
 * holds a RoomSeat: its validated messages go through it to the room, its leave too. A join may be
 * answered later (a worker answers after its next message batch); a refusal always arrives through
 * the request's `refused` callback, and messages delivered meanwhile are dropped if it is refused.
 */
import type { JoinMode } from '../../shared/index.ts'
import type { ClientSession } from '../net/index.ts'
import type { RoomSummary } from '../workers/index.ts'
import type { Room } from './room.ts'
import type { RoomManager } from './room-manager.ts'
import { handleRoomMessage, type RoomMessage, type Strike } from './room-messages.ts'
import type { RoomPlayer } from './room-player.ts'

/** A client's place in a room. */
export interface RoomSeat {
  readonly room: string
  /** The player id once known (0 until a worker has answered the join). */
  readonly playerId: number
  /** False once the room has closed under the client. */
  readonly open: boolean
  /** Hand the room a validated message of this client. */
  deliver(message: RoomMessage): void
  /** The client left (its socket closed). */
  leave(): void
}

/** A join as the transport asks for it. */
export interface JoinRequest {
  conn: ClientSession
  room: string
  name: string
  token: string | undefined
  mode: JoinMode
  /** Whether the connection's key allows room controls (http-access.ts); told in `welcome.rules`. */
  controls: boolean
  /** The game the join asks for (join.game), checked against the catalogue by the transport. */
  game: string | undefined
  /** A spectator's join (join.spectate): no player slot, every command refused. */
  spectate: boolean
  /** Strikes the room reports against this client. */
  strike: Strike
  /** The join was refused: `error` for the error message, `reason` for the close. */
  refused: (error: string, reason: string) => void
}

/** Rooms, wherever they run. */
export interface RoomHost {
  /** Whether a room of that name is open here (or being opened). */
  has(name: string): boolean
  /** Join a room (created on demand); null when refused at once (after `refused` was called). */
  join(request: JoinRequest): RoomSeat | null
  /** Open a room without a player (the default room). */
  open(name: string): void
  /** Close a room's players with a code and reason and dispose of it. */
  close(name: string, code: number, reason: string): void
  /** The open rooms for /rooms. */
  summaries(): RoomSummary[]
  /** Joined players. */
  readonly playerCount: number
}

/** A room as /rooms lists it. */
export function roomSummary(room: Room): RoomSummary {
  return {
    name: room.name,
    players: room.playerCount,
    spectators: room.players.size - room.playerCount,
    bodies: room.world.bodyCount,
    scene: room.scene,
    tick: room.tick,
    game: room.game.name,
  }
}

/** A seat in a room on the main thread. */
class LocalSeat implements RoomSeat {
  constructor(
    private readonly rooms: RoomManager,
    private readonly room_: Room,
    private readonly player: RoomPlayer,
    private readonly strike: Strike,
  ) {}

  get room(): string {
    return this.room_.name
  }

  get playerId(): number {
    return this.player.id
  }

  get open(): boolean {
    return this.player.joined && this.rooms.get(this.room_.name) === this.room_
  }

  deliver(message: RoomMessage): void {
    handleRoomMessage(this.room_, this.player, message, this.rooms.clock.fraction, this.strike)
  }

  leave(): void {
    this.room_.leave(this.player)
  }
}

/** Rooms on the main thread, in the process's own RoomManager (--workers 0). */
export class LocalRoomHost implements RoomHost {
  constructor(
    readonly rooms: RoomManager,
    private readonly maxRooms: number,
  ) {}

  has(name: string): boolean {
    return this.rooms.get(name) !== undefined
  }

  join(request: JoinRequest): RoomSeat | null {
    const room = this.rooms.getOrCreate(request.room, request.game)
    if (!room) {
      request.refused(`the server has reached its limit of ${this.maxRooms} rooms`, 'too many rooms')
      return null
    }
    const joined = room.join(
      request.conn,
      request.name,
      request.token,
      request.mode,
      request.controls,
      request.game,
      request.spectate,
    )
    if (typeof joined === 'string') {
      request.refused(joined, joined)
      return null
    }
    return new LocalSeat(this.rooms, room, joined, request.strike)
  }

  open(name: string): void {
    this.rooms.getOrCreate(name)
  }

  close(name: string, code: number, reason: string): void {
    this.rooms.close(name, code, reason)
  }

  summaries(): RoomSummary[] {
    return this.rooms.list().map(roomSummary)
  }

  get playerCount(): number {
    return this.rooms.playerCount
  }
}
