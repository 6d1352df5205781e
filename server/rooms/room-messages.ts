/*
 * What a joined player's messages do in its room: inputs and game commands (checked against the
 * room's game first) are queued for the next tick, acks move
 * the player's snapshot baseline, pings are answered with the room tick, lockstep reports (and a
 * join's hold) go to the feed. The same code runs on the main thread (--workers 0) and inside a
 * room worker; the transport validates every message, checks access and counts it against the
 * message rate first, and turns the strikes reported here into its own strike rules.
 */
import type { ClientMessage, PlainData } from '../../shared/index.ts'
import type { Room } from './room.ts'
import type { RoomPlayer } from './room-player.ts'

/**
 * A lockstep or predict player's `join.hold`, handed to its room right after the join (the join
 * itself travels to a room worker without it): never a message a client sends.
 */
export interface HoldMessage {
  t: 'hold'
  hold: number
}

/** The messages a joined player sends to its room (everything but `join`), and its join's hold. */
export type RoomMessage = Exclude<ClientMessage, { t: 'join' }> | HoldMessage

/** A strike against the sender: over its per-tick input budget, or a message its room refused (`seq` of an input). */
export type Strike = (
  code: 'input-budget' | 'invalid',
  reason: string,
  tick: number,
  seq: number | undefined,
) => void

/** Handle one validated message of a joined player; `clockFraction` is the tick clock's fraction. */
export function handleRoomMessage(
  room: Room,
  player: RoomPlayer,
  message: RoomMessage,
  clockFraction: number,
  strike: Strike,
): void {
  if (player.spectator && (message.t === 'input' || message.t === 'cmd')) {
    player.conn.sendError('refused', 'spectators send no commands', message.seq)
    return
  }
  switch (message.t) {
    case 'input': {
      const error = room.queueInput(player, message.seq, message.cmd)
      if (error) strike('input-budget', error, room.tick, message.seq)
      return
    }
    case 'cmd': {
      const refused = room.queueGameCommand(player, message.seq, message.k, message.a as PlainData)
      if (refused) strike(refused.code, refused.reason, room.tick, message.seq)
      return
    }
    case 'ack':
      player.encoder.ack(message.tick)
      return
    case 'ping':
      // Pings share the input budget, so they cannot be used to amplify traffic.
      if (++player.inputsThisTick > room.config.inputsPerTick) {
        strike('input-budget', 'too many pings', room.tick, undefined)
        return
      }
      player.conn.send({ t: 'pong', id: message.id, time: message.time, tick: room.tick + clockFraction })
      return
    case 'hold':
      room.feed.setHold(player.id, message.hold)
      return
    case 'desync':
    case 'resync': {
      // Lockstep reports share the input budget too; the feed bounds the saved worlds they cause.
      if (++player.inputsThisTick > room.config.inputsPerTick) {
        strike('input-budget', `too many ${message.t} messages`, room.tick, undefined)
        return
      }
      const refused =
        message.t === 'desync'
          ? room.feed.reportDesync(player.id, message.tick, message.hash, message.server)
          : room.feed.requestSync(player.id)
      if (refused) strike('invalid', refused, room.tick, undefined)
      return
    }
  }
}
