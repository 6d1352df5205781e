/*
 * A socket's join, from the `join` message to a seat in a room (transport.ts hands every `join`
 * here): the room it names (the message's, else the URL's, else the default room; when both name
 * one they must agree), whether the connection's key admits it there (http-access.ts), and where
 * the room runs. A room this server has open is joined here; with the shared room directory
 * (--redis) a room it does not have is claimed first, and the client of a room another server
 * holds gets `moved` with that server's URL and a 4006 close. A join refused for a full server
 * gives its claim back, so a room name is never left claimed by a server that does not hold it.
 * A join that would open a room draws on its address's room-opening rate (room-creation-rate.ts):
 * over it, the join gets `full` naming the limit, counted and logged (rate-limited) as refused.
 */
import type { Logger } from 'pino'
import { CLOSE_CODES, type ClientMessage } from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import { findServerGame, serverGameNames } from '../games/index.ts'
import type { LogLimiter, RoomDirectory, ServerMetrics } from '../hosting/index.ts'
import { addressKey } from '../http/index.ts'
import type { RoomHost } from '../rooms/index.ts'
import type { Peer, PeerPolicy } from './peer-policy.ts'
import { RoomCreationRate } from './room-creation-rate.ts'

export type JoinMessage = Extract<ClientMessage, { t: 'join' }>

/** What a join may do to its connection: the transport's own strike and close rules (peer-policy.ts). */
export type JoinActions = Pick<PeerPolicy, 'reject' | 'drop' | 'roomStrike'>

/** Joins for one transport (see the file comment). */
export class JoinFlow {
  /** The shared room directory (--redis), or null for a server on its own. */
  directory: RoomDirectory | null = null
  /** Directory claims not yet answered, by room (a claim no room came of is given back). */
  private readonly claiming = new Map<string, number>()
  /** Rooms each address may still open this minute (--max-new-rooms-per-ip). */
  private readonly openings: RoomCreationRate

  constructor(
    private readonly config: ServerConfig,
    /** Where rooms run: this thread or the worker pool. */
    private readonly rooms: RoomHost,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
    private readonly actions: JoinActions,
    /** Rate-limited warnings about clients (the transport's). */
    private readonly warnings: LogLimiter,
  ) {
    this.openings = new RoomCreationRate(config.maxNewRoomsPerIp)
  }

  /** A `join` message from `peer`. */
  join(peer: Peer, message: JoinMessage): void {
    const session = peer.session
    if (session.seat || peer.joining) {
      this.actions.reject(peer, 'already-joined', 'this socket has already joined a room')
      return
    }
    const name = message.room || session.urlRoom || this.config.defaultRoom
    if (message.room && session.urlRoom && message.room !== session.urlRoom) {
      this.actions.reject(
        peer,
        'room-mismatch',
        `join names room "${message.room}" but the URL names "${session.urlRoom}"`,
      )
      return
    }
    if (message.game !== undefined && !findServerGame(message.game)) {
      this.actions.reject(
        peer,
        'invalid',
        `unknown game "${message.game}"; this server has ${serverGameNames().join(', ')}`,
      )
      return
    }
    if (peer.access.room !== null && name !== peer.access.room) {
      const reason = `room "${name}" needs a key; without one this connection may join only "${peer.access.room}"`
      this.metrics.rejected.inc({ reason: 'forbidden' })
      session.sendError('forbidden', reason)
      this.actions.drop(peer, CLOSE_CODES.forbidden, reason)
      return
    }
    // Without a directory a room not open here is opened here. With one, the claim may find it
    // on another server (`moved`, which opens nothing): here() takes the opening once claimed.
    if (!this.directory && !this.rooms.has(name) && !this.openings.allows(addressKey(peer.address))) {
      this.refuseOpening(peer, name)
      return
    }
    if (this.directory && !this.rooms.has(name)) {
      this.throughDirectory(this.directory, peer, message, name)
      return
    }
    this.here(peer, message, name)
  }

  /** Refuse a join that would open room `name`: its address opened its rooms for this minute. */
  private refuseOpening(peer: Peer, name: string): void {
    const key = addressKey(peer.address)
    const limit = this.config.maxNewRoomsPerIp
    const reason = `this address opened ${limit} new rooms within a minute (--max-new-rooms-per-ip); join an open room, or open "${name}" in ${this.openings.waitSeconds(key)} s`
    this.metrics.roomsRefused.inc({ reason: 'rate' })
    this.warnings.warn(
      key,
      { address: peer.address, room: name, limit },
      'room opening refused: over the per-address rate',
    )
    peer.session.sendError('full', reason)
    this.actions.drop(peer, CLOSE_CODES.full, 'too many new rooms from this address')
  }

  /**
   * A room this server does not have open: claim it in the directory first. If another server
   * holds it, the client gets `moved` with that server's URL and a 4006 close; if the directory
   * cannot answer, the join is refused (1013) rather than risk a second copy of the room.
   */
  private throughDirectory(directory: RoomDirectory, peer: Peer, message: JoinMessage, name: string): void {
    const session = peer.session
    peer.joining = true
    this.claiming.set(name, (this.claiming.get(name) ?? 0) + 1)
    const answered = (): void => {
      peer.joining = false
      const left = (this.claiming.get(name) ?? 1) - 1
      if (left > 0) this.claiming.set(name, left)
      else this.claiming.delete(name)
    }
    directory.claim(name).then(
      (where) => {
        answered()
        if (peer.dropped || !session.open || session.seat) {
          // Nobody joins: give the claim back unless the room opened here or another claim waits.
          if (where.holder === 'self' && !this.rooms.has(name) && !this.claiming.has(name))
            directory.release(name).catch(() => {})
          return
        }
        if (where.holder === 'self') {
          try {
            // At the room limit nothing is opened: give the claim back.
            this.here(peer, message, name, () => {
              if (!this.rooms.has(name)) directory.release(name).catch(() => {})
            })
          } catch (error) {
            this.log.error({ err: error, room: name }, 'join after the directory claim failed')
            this.actions.drop(peer, CLOSE_CODES.internal, 'join failed')
          }
          return
        }
        session.send({ t: 'moved', room: name, url: where.url })
        this.actions.drop(peer, CLOSE_CODES.moved, `room ${name} is on another server`)
      },
      (error: Error) => {
        answered()
        // The library's words (host, port, command) stay in the log: the client learns what to do.
        this.log.warn({ room: name, err: error.message }, 'room directory unavailable; join refused')
        if (peer.dropped || !session.open) return
        session.sendError('unavailable', 'the room directory is unavailable; try again in a few seconds')
        this.actions.drop(peer, CLOSE_CODES.tryAgain, 'room directory unavailable')
      },
    )
  }

  private here(peer: Peer, message: JoinMessage, name: string, afterRefusal?: () => void): void {
    const session = peer.session
    // Opening a room takes one of the address's openings (checked in join(); a claim may have
    // taken a moment, so the room may be open by now, and then nothing is taken).
    if (!this.rooms.has(name) && !this.openings.take(addressKey(peer.address))) {
      this.refuseOpening(peer, name)
      afterRefusal?.()
      return
    }
    const seat = this.rooms.join({
      conn: session,
      room: name,
      name: message.name,
      token: message.token,
      mode: message.mode,
      controls: peer.access.controls,
      game: message.game,
      spectate: message.spectate === true,
      strike: (code, reason, tick, seq) => this.actions.roomStrike(peer, code, reason, tick, seq),
      refused: (error, reason) => {
        session.seat = null
        session.sendError('full', error)
        this.actions.drop(peer, CLOSE_CODES.full, reason)
        afterRefusal?.()
      },
    })
    if (!seat) return
    session.seat = seat
    // The feed holds empty ticks for lockstep players; the join reaches a room worker without it.
    if (message.hold !== undefined && message.mode !== 'snapshot')
      seat.deliver({ t: 'hold', hold: message.hold })
    this.metrics.clients.set(this.rooms.playerCount)
  }
}
