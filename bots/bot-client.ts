/*
 * A Node client of the protocol: one WebSocket, the shared ClientMirror, acks for every decoded
 * snapshot, pings for clock sync, and helpers to send commands. The bots (bots.ts) and the
 * integration tests both use it, so tests exercise the same client code a real player runs.
 * waitFor() resolves on a condition checked after every message (no sleeps).
 */
import { performance } from 'node:perf_hooks'
import WebSocket from 'ws'
import {
  type ClientMessage,
  ClientMirror,
  type Command,
  decodeServerMessage,
  encodeMessage,
  type JoinMode,
  PROTOCOL_VERSION,
  type ServerMessage,
} from '../shared/index.ts'

/** Options for a bot connection. */
export interface BotOptions {
  url: string
  room: string
  name: string
  token?: string
  /** Answer snapshots with acks (default true). */
  ack?: boolean
  /** Access key for servers with a join or admin token (sent as `key=` in the WebSocket URL). */
  key?: string
  /** The local address to connect from (tests use other loopback addresses as other clients). */
  localAddress?: string
  /** Origin header to send (browsers always send one; Node clients only when asked). */
  origin?: string
  /** How to follow the room (default 'snapshot'); lockstep-bot.ts runs the lockstep modes. */
  mode?: JoinMode
  /** join.hold for the lockstep modes (the server's default when absent). */
  hold?: number
  /** join.game: the game a room this join creates runs (docs/games.md). */
  game?: string
  /** join.spectate: watch without a player slot (every command refused). */
  spectate?: boolean
}

/** A connected protocol client. */
export class BotClient {
  readonly mirror = new ClientMirror()
  readonly ws: WebSocket
  /** Every decoded server message, in order (tests inspect these). */
  readonly received: ServerMessage[] = []
  /** Raw frames received, for independent decoding in tests. */
  readonly frames: Uint8Array[] = []
  bytesReceived = 0
  /** Smoothed round-trip time (ms) from ping/pong, or NaN before the first pong. */
  rtt = Number.NaN
  /** Server tick minus the local estimate at the last pong (ticks). */
  tickOffset = 0
  closeCode = 0
  closeReason = ''
  keepFrames = false
  /** The first message this client could not decode or apply (a protocol bug), if any. */
  failure: Error | null = null
  /** Drop the next n snapshots unread (to simulate loss in tests). */
  dropSnapshots = 0
  /** The URL of a `moved` message received instead of a welcome, else null. */
  movedTo: string | null = null
  /** Called after each message has been applied to the mirror. */
  onServerMessage: ((message: ServerMessage) => void) | null = null
  private seq = 0
  private pingId = 0
  private waiters: Array<() => void> = []
  readonly closed: Promise<void>
  readonly opened: Promise<void>

  constructor(readonly options: BotOptions) {
    const key = options.key === undefined ? '' : `&key=${encodeURIComponent(options.key)}`
    const url = `${options.url.replace(/\/$/, '')}/ws?room=${encodeURIComponent(options.room)}${key}`
    this.ws = new WebSocket(url, {
      perMessageDeflate: false,
      origin: options.origin,
      localAddress: options.localAddress,
    })
    this.ws.binaryType = 'nodebuffer'
    this.opened = new Promise((resolve, reject) => {
      this.ws.once('open', () => resolve())
      this.ws.once('error', reject)
    })
    this.ws.on('error', () => {})
    this.closed = new Promise((resolve) => {
      this.ws.once('close', (code, reason) => {
        this.closeCode = code
        this.closeReason = reason.toString()
        this.notify()
        resolve()
      })
    })
    this.ws.on('message', (data: Buffer, isBinary) => this.onMessage(data, isBinary))
  }

  /**
   * Connect and join; resolves at the welcome. A `moved` answer (the room is held by another
   * server, shared/protocol/PROTOCOL.md) is followed to the URL it names, at most `maxMoves` times.
   */
  static async connect(options: BotOptions, maxMoves = 3): Promise<BotClient> {
    const bot = new BotClient(options)
    await bot.opened
    bot.join()
    await bot.waitFor(() => bot.mirror.clientId !== 0 || bot.movedTo !== null, 'welcome')
    if (bot.movedTo === null) return bot
    await bot.closed
    if (maxMoves <= 0) throw new Error(`room ${options.room} moved too many times (last to ${bot.movedTo})`)
    return BotClient.connect({ ...options, url: bot.movedTo }, maxMoves - 1)
  }

  /** Send the join message (`hold` for the lockstep modes: join.hold, the server's default when absent). */
  join(version = PROTOCOL_VERSION, hold = this.options.hold): void {
    const join: ClientMessage = {
      t: 'join',
      v: version,
      room: this.options.room,
      name: this.options.name,
      mode: this.options.mode ?? 'snapshot',
    }
    if (this.options.token) join.token = this.options.token
    if (hold !== undefined && join.mode !== 'snapshot') join.hold = hold
    if (this.options.game !== undefined) join.game = this.options.game
    if (this.options.spectate) join.spectate = true
    this.send(join)
  }

  private onMessage(data: Buffer, isBinary: boolean): void {
    this.bytesReceived += data.length
    if (!isBinary) return
    if (this.keepFrames) this.frames.push(new Uint8Array(data))
    const decoded = decodeServerMessage(data)
    if (!decoded.ok) {
      this.failure = new Error(`could not decode a server message: ${decoded.reason}`)
      this.ws.close(1002, 'undecodable server message')
      return
    }
    const message = decoded.value
    if (message.t === 'snap' && this.dropSnapshots > 0) {
      this.dropSnapshots--
      return
    }
    this.received.push(message)
    if (this.received.length > 10000) this.received.splice(0, 5000)
    if (message.t === 'pong') this.onPong(message.time, message.tick)
    if (message.t === 'moved') this.movedTo = message.url
    let ack: ReturnType<ClientMirror['handle']>
    try {
      ack = this.mirror.handle(message)
    } catch (error) {
      // A snapshot that does not decode against our baselines: a protocol bug. Fail loudly.
      this.failure = error as Error
      this.ws.close(1002, `client could not apply ${message.t}: ${(error as Error).message}`.slice(0, 120))
      return
    }
    if (ack && this.options.ack !== false) this.send(ack)
    this.onServerMessage?.(message)
    this.notify()
  }

  private onPong(sentAt: number, serverTick: number): void {
    const rtt = performance.now() - sentAt
    this.rtt = Number.isNaN(this.rtt) ? rtt : this.rtt * 0.8 + rtt * 0.2
    this.tickOffset = serverTick + (rtt / 2000) * 60 - this.mirror.tick
  }

  private notify(): void {
    const waiters = this.waiters
    this.waiters = []
    for (const w of waiters) w()
  }

  /** Resolve when `condition` holds (checked after every message); rejects if the socket closes first. */
  waitFor(condition: () => boolean, what = 'condition'): Promise<void> {
    return new Promise((resolve, reject) => {
      const check = (): void => {
        if (condition()) {
          resolve()
        } else if (this.ws.readyState === WebSocket.CLOSED) {
          reject(
            new Error(
              `socket closed (${this.closeCode} ${this.closeReason}) while waiting for ${what}${this.failure ? `: ${this.failure.message}` : ''}`,
            ),
          )
        } else {
          this.waiters.push(check)
        }
      }
      check()
    })
  }

  /** Resolve at the next message satisfying `match`. */
  nextMessage<T extends ServerMessage>(match: (m: ServerMessage) => m is T): Promise<T> {
    const start = this.received.length
    let found: T | undefined
    return this.waitFor(() => {
      for (let i = start; i < this.received.length && !found; i++)
        if (match(this.received[i])) found = this.received[i] as T
      return found !== undefined
    }).then(() => found as T)
  }

  /** Send any client message. */
  send(message: ClientMessage): void {
    if (this.ws.readyState === WebSocket.OPEN) this.ws.send(encodeMessage(message))
  }

  /** Send an input command; returns its sequence number. */
  command(cmd: Command): number {
    const seq = ++this.seq
    this.send({ t: 'input', seq, cmd })
    return seq
  }

  /** Send a game command (`cmd`: docs/games.md); returns its sequence number. */
  gameCommand(kind: string, args: Record<string, unknown>): number {
    const seq = ++this.seq
    this.send({ t: 'cmd', seq, k: kind, a: args })
    return seq
  }

  /** Send a clock-sync ping. */
  ping(): void {
    this.send({ t: 'ping', id: ++this.pingId, time: performance.now() })
  }

  /** Close the socket and wait for it. */
  async close(): Promise<void> {
    if (this.ws.readyState !== WebSocket.CLOSED) this.ws.close(1000, 'bye')
    await this.closed
  }
}
