/*
 * The WebSocket transport: upgrades on /ws?room=NAME, one ClientSession per socket, and the
 * message path decode -> validate -> room. Protections, in the order a message meets them:
 * the connection cap at upgrade, ws's maxPayload (larger frames close the socket with 1009),
 * text frames refused, strict decoding and validation with strikes (too many -> closed with
 * 1008 and a reason), the join timeout, the per-tick input budget, heartbeats for dead peers.
 * Every socket has an 'error' listener: without one, a single bad frame would crash the process.
 */
import type { IncomingMessage } from 'node:http'
import type { Duplex } from 'node:stream'
import type { Logger } from 'pino'
import { type RawData, type WebSocket, WebSocketServer } from 'ws'
import { CLOSE_CODES, type ClientMessage, decodeClientMessage, ROOM_NAME_PATTERN } from '../shared/index.ts'
import { ClientSession } from './client-session.ts'
import type { ServerConfig } from './config.ts'
import type { ServerMetrics } from './metrics.ts'
import type { RoomManager } from './room-manager.ts'

/** Unsent bytes at which a client is dropped at once: 8 send-buffer budgets, at least 1 MiB. */
export function hardBufferLimit(config: ServerConfig): number {
  return Math.max(config.sendBufferBytes * 8, 1 << 20)
}

/** Accepts sockets and routes their messages to rooms. */
export class Transport {
  readonly wss: WebSocketServer
  readonly sessions = new Set<ClientSession>()
  private heartbeat: NodeJS.Timeout | null = null
  accepting = true

  constructor(
    private readonly config: ServerConfig,
    private readonly rooms: RoomManager,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.wss = new WebSocketServer({
      noServer: true,
      maxPayload: config.maxMessageBytes,
      perMessageDeflate: false,
    })
    this.heartbeat = setInterval(() => this.sweep(), config.heartbeatMs)
  }

  /** Handle an HTTP upgrade request. */
  handleUpgrade(request: IncomingMessage, socket: Duplex, head: Buffer): void {
    socket.on('error', () => socket.destroy())
    const url = new URL(request.url ?? '/', 'http://localhost')
    const refuse = (status: string): void => {
      socket.end(`HTTP/1.1 ${status}\r\nConnection: close\r\nContent-Length: 0\r\n\r\n`)
    }
    if (url.pathname !== '/ws') {
      refuse('404 Not Found')
      return
    }
    if (!this.accepting) {
      refuse('503 Service Unavailable')
      return
    }
    const room = url.searchParams.get('room') ?? ''
    if (room !== '' && !ROOM_NAME_PATTERN.test(room)) {
      refuse('400 Bad Request')
      return
    }
    if (this.sessions.size >= this.config.maxConnections) {
      refuse('503 Service Unavailable')
      return
    }
    this.wss.handleUpgrade(request, socket, head, (ws) => this.accept(ws, room))
  }

  private accept(ws: WebSocket, urlRoom: string): void {
    const session = new ClientSession(ws, urlRoom, this.metrics, hardBufferLimit(this.config))
    this.sessions.add(session)
    this.metrics.connections.set(this.sessions.size)
    const joinTimer = setTimeout(() => {
      if (!session.player) session.close(CLOSE_CODES.joinTimeout, 'no join message in time')
    }, this.config.joinTimeoutMs)
    ws.on('error', (error) => {
      this.log.debug({ err: error.message, player: session.id }, 'socket error')
    })
    ws.on('pong', () => {
      session.alive = true
    })
    ws.on('message', (data, isBinary) => this.receive(session, data, isBinary))
    ws.on('close', () => {
      clearTimeout(joinTimer)
      this.sessions.delete(session)
      this.metrics.connections.set(this.sessions.size)
      const player = session.player
      if (player) {
        session.player = null
        this.rooms.get(player.room)?.leave(player)
        this.metrics.clients.set(this.rooms.playerCount)
      }
    })
  }

  private reject(session: ClientSession, code: string, reason: string): void {
    this.metrics.rejected.inc({ reason: code })
    session.strikes++
    if (session.strikes > this.config.maxRejects) {
      this.log.warn(
        { player: session.id, reason },
        'disconnecting a client that keeps sending invalid messages',
      )
      session.close(CLOSE_CODES.policy, `too many invalid messages; last: ${reason}`)
      return
    }
    session.sendError(code, reason)
  }

  /**
   * Over the per-tick input budget: the input is dropped, but it counts as a strike only once per
   * tick, so a burst after a network hiccup costs little while a sustained flood is disconnected.
   */
  private overBudget(session: ClientSession, tick: number, reason: string): void {
    if (session.budgetStrikeTick === tick) {
      this.metrics.rejected.inc({ reason: 'input-budget' })
      return
    }
    session.budgetStrikeTick = tick
    this.reject(session, 'input-budget', reason)
  }

  private receive(session: ClientSession, data: RawData, isBinary: boolean): void {
    this.metrics.messagesReceived.inc()
    if (!isBinary) {
      this.reject(session, 'text-frame', 'text frames are not accepted; send binary MessagePack')
      return
    }
    const bytes = Array.isArray(data)
      ? Buffer.concat(data)
      : data instanceof ArrayBuffer
        ? new Uint8Array(data)
        : data
    const result = decodeClientMessage(bytes)
    if (!result.ok) {
      if (result.code === 'version') {
        this.metrics.rejected.inc({ reason: 'version' })
        session.sendError('version', result.reason)
        session.close(CLOSE_CODES.version, result.reason)
        return
      }
      this.reject(session, result.code, result.reason)
      return
    }
    this.dispatch(session, result.value)
  }

  private dispatch(session: ClientSession, message: ClientMessage): void {
    if (message.t === 'join') {
      this.join(session, message)
      return
    }
    const player = session.player
    if (!player) {
      this.reject(session, 'not-joined', 'send join first')
      return
    }
    const room = this.rooms.get(player.room)
    if (!room || !player.joined) {
      session.close(1011, 'room closed')
      return
    }
    switch (message.t) {
      case 'input': {
        const error = room.queueInput(player, message.seq, message.cmd)
        if (error) this.overBudget(session, room.tick, error)
        return
      }
      case 'ack':
        player.encoder.ack(message.tick)
        return
      case 'ping':
        // Pings share the input budget, so they cannot be used to amplify traffic.
        if (++player.inputsThisTick > this.config.inputsPerTick) {
          this.overBudget(session, room.tick, 'too many pings')
          return
        }
        session.send({
          t: 'pong',
          id: message.id,
          time: message.time,
          tick: room.tick + this.rooms.clock.fraction,
        })
        return
    }
  }

  private join(session: ClientSession, message: Extract<ClientMessage, { t: 'join' }>): void {
    if (session.player) {
      this.reject(session, 'already-joined', 'this socket has already joined a room')
      return
    }
    if (message.mode !== 'snapshot') {
      session.sendError('mode', `mode "${message.mode}" is not supported by this server; use "snapshot"`)
      session.close(CLOSE_CODES.policy, `unsupported mode ${message.mode}`)
      return
    }
    const name = message.room || session.urlRoom || this.config.defaultRoom
    if (message.room && session.urlRoom && message.room !== session.urlRoom) {
      this.reject(
        session,
        'room-mismatch',
        `join names room "${message.room}" but the URL names "${session.urlRoom}"`,
      )
      return
    }
    const room = this.rooms.getOrCreate(name)
    if (!room) {
      session.sendError('full', `the server has reached its limit of ${this.config.maxRooms} rooms`)
      session.close(CLOSE_CODES.full, 'too many rooms')
      return
    }
    const joined = room.join(session, message.name, message.token)
    if (typeof joined === 'string') {
      session.sendError('full', joined)
      session.close(CLOSE_CODES.full, joined)
      return
    }
    session.player = joined
    this.metrics.clients.set(this.rooms.playerCount)
  }

  /** Heartbeat: close peers that missed a pong, ping the rest, forgive old strikes. */
  private sweep(): void {
    for (const s of this.sessions) {
      if (!s.alive) {
        this.log.info({ player: s.id }, 'closing a peer that missed a heartbeat')
        s.ws.terminate()
        continue
      }
      s.alive = false
      s.strikes = 0
      s.errorsSent = 0
      try {
        s.ws.ping()
      } catch {
        s.ws.terminate()
      }
    }
  }

  /** Stop accepting; close every socket with a reason; resolves when all are closed (or forced). */
  async closeAll(code: number, reason: string, graceMs: number): Promise<void> {
    this.accepting = false
    if (this.heartbeat) clearInterval(this.heartbeat)
    this.heartbeat = null
    const closed = [...this.sessions].map(
      (s) =>
        new Promise<void>((resolve) => {
          if (s.ws.readyState === 3) return resolve()
          s.ws.once('close', () => resolve())
          s.close(code, reason)
        }),
    )
    const timeout = new Promise<void>((resolve) => setTimeout(resolve, graceMs).unref())
    await Promise.race([Promise.all(closed), timeout])
    for (const s of this.sessions) s.ws.terminate()
    this.wss.close()
  }
}
