/*
 * The WebSocket transport: upgrades on /ws?room=NAME[&key=KEY], one ClientSession per socket, and
 * the message path decode -> validate -> room. Protections, in the order a message meets them:
 * at the upgrade the request target, the origin allowlist and the key (http-access.ts) and the
 * connection cap; ws's maxPayload (larger frames close the socket with 1009); the per-client
 * message rate (message-budget.ts: every frame counts, moves and acks included); text frames
 * refused; strict decoding and validation with strikes (too many -> closed with 1008 and a
 * reason); the join timeout; the per-tick input budget; heartbeats for dead peers.
 *
 * Strikes, the input budget, the message rate and dropping a client (after which nothing more it
 * sends is read) are peer-policy.ts. Every handler a client can reach is wrapped, so
 * no frame or request ends in an uncaught throw; every socket has an 'error' listener for the same
 * reason. Warnings about clients go through a LogLimiter. A `join` goes on to join-flow.ts (room
 * name, key, and the room directory).
 */
import type { IncomingMessage } from 'node:http'
import { performance } from 'node:perf_hooks'
import type { Duplex } from 'node:stream'
import type { Logger } from 'pino'
import { type RawData, type WebSocket, WebSocketServer } from 'ws'
import {
  CLOSE_CODES,
  type ClientMessage,
  decodeClientMessage,
  ROOM_CONTROL_COMMANDS,
  ROOM_NAME_PATTERN,
} from '../../shared/index.ts'
import { hardBufferLimit, type ServerConfig } from '../config/index.ts'
import { LogLimiter, type RoomDirectory, type ServerMetrics } from '../hosting/index.ts'
import {
  type Access,
  addressKey,
  checkAccess,
  clientAddress,
  MessageBudget,
  parseRequestTarget,
  rawHttpResponse,
} from '../http/index.ts'
import type { RoomHost } from '../rooms/index.ts'
import { ClientSession } from './client-session.ts'
import { JoinFlow } from './join-flow.ts'
import { type Peer, PeerPolicy } from './peer-policy.ts'

/** Accepts sockets and routes their messages to rooms. */
export class Transport {
  readonly wss: WebSocketServer
  readonly sessions = new Set<ClientSession>()
  private heartbeat: NodeJS.Timeout | null = null
  private readonly peers = new Map<ClientSession, Peer>()
  /** Rate-limited warnings about clients (at most 3 per address per 10 s, then a count). */
  readonly warnings: LogLimiter
  accepting = true
  /** Strikes, the message rate and dropping clients (peer-policy.ts). */
  readonly policy: PeerPolicy
  /** Joins: room names, keys, the room directory (join-flow.ts). */
  private readonly joins: JoinFlow

  constructor(
    private readonly config: ServerConfig,
    /** Where rooms run: this thread or the worker pool. */
    private readonly rooms: RoomHost,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.wss = new WebSocketServer({
      noServer: true,
      maxPayload: config.maxMessageBytes,
      perMessageDeflate: false,
    })
    this.warnings = new LogLimiter(log)
    this.policy = new PeerPolicy(config, metrics, this.warnings)
    this.joins = new JoinFlow(config, rooms, metrics, log, this.policy, this.warnings)
    this.heartbeat = setInterval(() => this.sweep(), config.heartbeatMs)
  }

  /** The shared room directory (--redis), or null for a server on its own. */
  get directory(): RoomDirectory | null {
    return this.joins.directory
  }

  set directory(directory: RoomDirectory | null) {
    this.joins.directory = directory
  }

  /** Handle an HTTP upgrade request; never throws (a bad request gets an HTTP error status). */
  handleUpgrade(request: IncomingMessage, socket: Duplex, head: Buffer): void {
    socket.on('error', () => socket.destroy())
    try {
      this.upgrade(request, socket, head)
    } catch (error) {
      this.log.error({ err: error }, 'upgrade failed')
      this.refuse(socket, 500, 'Internal Server Error')
    }
  }

  private refuse(socket: Duplex, status: number, text: string): void {
    if (socket.writable) socket.end(rawHttpResponse(status, text))
    else socket.destroy()
  }

  private upgrade(request: IncomingMessage, socket: Duplex, head: Buffer): void {
    const url = parseRequestTarget(request.url)
    if (!url) {
      this.refuse(socket, 400, 'Bad Request')
      return
    }
    if (url.pathname !== '/ws') {
      this.refuse(socket, 404, 'Not Found')
      return
    }
    if (!this.accepting) {
      this.refuse(socket, 503, 'Service Unavailable')
      return
    }
    const room = url.searchParams.get('room') ?? ''
    if (room !== '' && !ROOM_NAME_PATTERN.test(room)) {
      this.refuse(socket, 400, 'Bad Request')
      return
    }
    if (this.sessions.size >= this.config.maxConnections) {
      this.refuse(socket, 503, 'Service Unavailable')
      return
    }
    const decision = checkAccess(this.config, request, url, room)
    const address = clientAddress(request.socket)
    if (!decision.ok) {
      this.metrics.connectionsRefused.inc({ reason: decision.reason })
      this.warnings.warn(addressKey(address), { address, reason: decision.reason }, 'upgrade refused')
      this.refuse(socket, decision.status, decision.text)
      return
    }
    this.wss.handleUpgrade(request, socket, head, (ws) =>
      this.accept({
        ws,
        urlRoom: room,
        socket,
        address,
        access: decision.access,
      }),
    )
  }

  private accept(opened: {
    ws: WebSocket
    urlRoom: string
    socket: Duplex
    address: string
    access: Access
  }): void {
    const { ws } = opened
    const session = new ClientSession(ws, opened.urlRoom, this.metrics, hardBufferLimit(this.config))
    const peer: Peer = {
      session,
      socket: opened.socket,
      address: opened.address,
      access: opened.access,
      budget: new MessageBudget(this.config.maxMessagesPerSecond, () => performance.now()),
      dropped: false,
      joining: false,
    }
    this.sessions.add(session)
    this.peers.set(session, peer)
    this.metrics.connections.set(this.sessions.size)
    const joinTimer = setTimeout(() => {
      if (!session.seat) this.policy.drop(peer, CLOSE_CODES.joinTimeout, 'no join message in time')
    }, this.config.joinTimeoutMs)
    ws.on('error', (error) => {
      this.log.debug({ err: error.message, player: session.id }, 'socket error')
    })
    // Pongs draw on the message rate too: unsolicited ones were free (18.5 million were read from
    // one socket in 6 s). A ping flood is cut by ws itself, which terminates a socket with too
    // many of its answers unsent (maxPendingAutoPongs).
    ws.on('pong', () => this.pong(peer))
    ws.on('message', (data, isBinary) => this.receiveGuarded(peer, data, isBinary))
    ws.on('close', () => {
      clearTimeout(joinTimer)
      this.sessions.delete(session)
      this.peers.delete(session)
      this.metrics.connections.set(this.sessions.size)
      const seat = session.seat
      if (seat) {
        session.seat = null
        seat.leave()
        this.metrics.clients.set(this.rooms.playerCount)
      }
    })
  }

  /** receive() with a guard: a bug reached by a client's frame drops that client, never the process. */
  private receiveGuarded(peer: Peer, data: RawData, isBinary: boolean): void {
    if (peer.dropped) return
    try {
      this.receive(peer, data, isBinary)
    } catch (error) {
      this.failed(peer, error)
    }
  }

  /** A pong, guarded as frames are: it counts against the message rate and marks the peer alive. */
  private pong(peer: Peer): void {
    if (peer.dropped) return
    try {
      if (this.policy.withinRate(peer)) peer.session.alive = true
    } catch (error) {
      this.failed(peer, error)
    }
  }

  /** Handling a client's frame failed: log it (rate-limited) and drop that client. */
  private failed(peer: Peer, error: unknown): void {
    this.warnings.warn(
      addressKey(peer.address),
      { player: peer.session.id, err: error },
      'message handling failed',
    )
    try {
      this.policy.drop(peer, CLOSE_CODES.internal, 'server error handling your message')
    } catch {
      peer.session.ws.terminate()
    }
  }

  private receive(peer: Peer, data: RawData, isBinary: boolean): void {
    const session = peer.session
    this.metrics.messagesReceived.inc()
    this.metrics.bytesReceived.inc(
      Array.isArray(data) ? data.reduce((n, b) => n + b.length, 0) : data.byteLength,
    )
    if (!this.policy.withinRate(peer)) return
    if (!isBinary) {
      this.policy.reject(peer, 'text-frame', 'text frames are not accepted; send binary MessagePack')
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
        this.policy.drop(peer, CLOSE_CODES.version, result.reason)
        return
      }
      this.policy.reject(peer, result.code, result.reason, result.seq)
      return
    }
    this.dispatch(peer, result.value)
  }

  private dispatch(peer: Peer, message: ClientMessage): void {
    const session = peer.session
    if (message.t === 'join') {
      this.joins.join(peer, message)
      return
    }
    const seat = session.seat
    if (!seat) {
      this.policy.reject(
        peer,
        'not-joined',
        'send join first',
        message.t === 'input' || message.t === 'cmd' ? message.seq : undefined,
      )
      return
    }
    if (!seat.open) {
      this.policy.drop(peer, CLOSE_CODES.internal, 'room closed')
      return
    }
    if (message.t === 'input' && !peer.access.controls && ROOM_CONTROL_COMMANDS.includes(message.cmd.k)) {
      session.sendError('refused', `${message.cmd.k} is a room control: it needs the admin key`, message.seq)
      return
    }
    // The client has read everything up to the snapshot it acknowledges (the slow-reader rule).
    if (message.t === 'ack') session.unread.acknowledged(message.tick)
    seat.deliver(message)
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
      try {
        s.ws.ping()
      } catch {
        s.ws.terminate()
      }
    }
  }

  /**
   * Hand room `name` over to the server at `url` (the room directory found an older copy there):
   * every player of it gets `moved`, then the room closes here with 4006 (PROTOCOL.md: `moved`
   * always comes first).
   */
  moveRoom(name: string, url: string): void {
    for (const session of this.sessions) {
      if (session.seat?.room === name && session.open) session.send({ t: 'moved', room: name, url })
    }
    this.rooms.close(name, CLOSE_CODES.moved, `room ${name} moved to another server`)
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
