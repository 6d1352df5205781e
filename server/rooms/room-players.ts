/*
 * Player identity within a room: ids handed out in join order, colours from a fixed palette, and
 * reconnect tokens. A client that rejoins with the token from its welcome within the reconnect
 * window gets its old id, name and colour back; if its old socket is still open (a dead peer not
 * yet detected), that socket is replaced.
 */
import { randomBytes } from 'node:crypto'
import { PLAYER_PALETTE } from '../../shared/index.ts'
import type { RoomPlayer } from './room-player.ts'

/** A player who left, remembered for the reconnect window. */
export interface DepartedPlayer {
  id: number
  name: string
  color: string
  leftTick: number
}

/** A player's colour from its id. */
export function playerColor(id: number): string {
  return PLAYER_PALETTE[(id - 1) % PLAYER_PALETTE.length]
}

/** What a join resolves to. */
export interface Identity {
  id: number
  token: string
  name?: string
  color?: string
  /** A joined player with the same token (a stale connection), to be closed. */
  replaced?: RoomPlayer
}

/** What identity assignment needs from a room. */
export interface RoomPlayers {
  players: Map<number, RoomPlayer>
  departed: Map<string, DepartedPlayer>
  nextPlayerId: number
  leave(player: RoomPlayer): void
}

/** Resolve a join's token to a returning identity or a fresh one. */
export function assignIdentity(room: RoomPlayers, token: string | undefined): Identity {
  if (token) {
    for (const s of room.players.values()) {
      if (s.token === token) {
        room.leave(s)
        const back = room.departed.get(token)!
        room.departed.delete(token)
        return { id: back.id, token, name: back.name, color: back.color, replaced: s }
      }
    }
    const back = room.departed.get(token)
    if (back) {
      room.departed.delete(token)
      return { id: back.id, token, name: back.name, color: back.color }
    }
  }
  return { id: room.nextPlayerId++, token: randomBytes(16).toString('hex') }
}
