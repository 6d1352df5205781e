/*
 * The client SDK (docs/sdk.md): what someone else's page (or a Node program) uses to join a
 * Concord room. `connect()` opens one WebSocket (the browser's, or an injected constructor such
 * as the `ws` package's), joins in snapshot, lockstep or predict mode and resolves with a
 * `Session` at the welcome. The session is a thin wrapper over the classes the Concord page runs:
 * the snapshot mirror (ClientMirror), the lockstep and predicting runners (LockstepClient,
 * PredictClient, stepped from a 16 ms timer) and the games this build ships (games/'s findGame),
 * so an SDK client decodes and simulates exactly as the page does. A lockstep or predict session in
 * a room of a game the build does not ship (one the server loaded with --games) imports that game's
 * module from the server (GET /games/NAME.js, as the page does) before it applies anything after the
 * welcome; one that cannot be loaded is an `error` naming the game and the URL, and the session closes. `npm run build:sdk` bundles it
 * to dist/sdk/index.js with type declarations; the canvas renderer is apart, in sdk/render.ts.
 *
 * Reconnecting is opt-in (`reconnect`): after a drop the session waits, opens a new socket and
 * joins the same room in the same mode with the same name (and its reconnect token, so the server
 * gives its old player back within its reconnect window), doubling the wait after each failed
 * attempt. Each connection gets a fresh mirror and runner, filled by the new welcome; listeners
 * stay. A deliberate close() or a refusal that another try cannot change is final.
 *
 * A room held by another server (several servers sharing a room directory, `--redis`) is followed
 * as the page follows it: `moved`, then close 4006, and the session joins at the URL `moved` named,
 * at once, whether or not it reconnects after drops (at most MAX_MOVES times in a row).
 */
import { findGame, type Game, gameModuleUrl, gameOfModule } from '../games/index.ts'
import {
  CLOSE_CODES,
  type ClientMessage,
  ClientMirror,
  type Command,
  cssColor,
  decodeServerMessage,
  encodeMessage,
  LockstepClient,
  type PlainData,
  PROTOCOL_VERSION,
  PredictClient,
  ROOM_NAME_PATTERN,
  type RoomRules,
  type RoomSimulation,
  type ServerMessage,
  type SimulationListener,
  type WireJoint,
  type WireShape,
  wireShapesOf,
} from '../shared/index.ts'

export type { Command, RoomRules, ServerMessage, WireJoint, WireShape }

/** Games imported from servers (their --games modules), by name: shared by every session of the page. */
const loadedGames = new Map<string, Game>()
const findAnyGame = (name: string): Game | undefined => findGame(name) ?? loadedGames.get(name)

/**
 * Import game `name` from the server at `serverUrl` (ws, wss, http or https; GET /games/NAME.js, one self-contained ES module)
 * and keep it. A browser imports the URL; where that fails (Node imports no http: URLs) the text
 * is fetched and imported as a data: URL. Rejects naming the game and the URL.
 */
async function loadServerGame(serverUrl: string, name: string): Promise<void> {
  if (findAnyGame(name)) return
  const url = gameModuleUrl(serverUrl, name)
  let module: { default?: unknown }
  try {
    try {
      module = await import(/* @vite-ignore */ url)
    } catch {
      const response = await fetch(url)
      if (!response.ok) throw new Error(`GET answered ${response.status}`)
      module = await import(`data:text/javascript,${encodeURIComponent(await response.text())}`)
    }
  } catch (error) {
    throw new Error(`cannot load game ${name} from ${url}: ${(error as Error).message}`)
  }
  loadedGames.set(name, gameOfModule(module, name, url))
}

/** How a session follows the room (shared/protocol/PROTOCOL.md, `join.mode`). */
export type SessionMode = 'snapshot' | 'lockstep' | 'predict'

/** The part of the WebSocket API the SDK uses: the browser's, or the `ws` package's. */
export interface SocketLike {
  binaryType: string
  readyState: number
  onopen: ((event: unknown) => void) | null
  onmessage: ((event: { data: unknown }) => void) | null
  onclose: ((event: { code: number; reason: string }) => void) | null
  onerror: ((event: unknown) => void) | null
  send(data: Uint8Array): void
  close(code?: number, reason?: string): void
}

/**
 * A WebSocket constructor (globalThis.WebSocket in a browser; `import WebSocket from 'ws'` in Node):
 * its sockets must have the browser API that SocketLike lists.
 */
export type SocketConstructor = new (url: string) => object

/** What `connect` takes. */
export interface ConnectOptions {
  /** The server's address: `ws://host:port`, `wss://host` or `http(s)://...` (the SDK adds `/ws`). */
  url: string
  /** Room name: 1-32 of A-Z, a-z, 0-9, `_` and `-`, as the server accepts. */
  room: string
  /** Player name (at most 32 characters). */
  name: string
  /** 'snapshot' (default): the server streams the state; 'lockstep' / 'predict': this client simulates. */
  mode?: SessionMode
  /** The game a room this join creates runs (docs/games.md); refused if the open room runs another. */
  game?: string
  /** Watch without a player slot; every command is refused. */
  spectate?: boolean
  /** Access key of a server started with a join or admin token (sent as `key=`). */
  key?: string
  /** The WebSocket constructor; default globalThis.WebSocket. */
  WebSocket?: SocketConstructor
  /** Milliseconds to wait for the welcome before failing (default 10,000). */
  timeoutMs?: number
  /**
   * Listeners registered before the join, so they also hear what arrives with the welcome (a game
   * event in the same read): `{ event: fn, state: fn, ... }`, as `session.on(type, fn)`.
   */
  on?: { [K in keyof SessionEvents]?: (value: SessionEvents[K]) => void }
  /**
   * Reconnect after a drop (off by default): `true` for the defaults, or how often and how fast.
   * Only a session that joined reconnects; a first join that fails rejects as before.
   */
  reconnect?: boolean | ReconnectOptions
}

/** How a session reconnects after a drop (ConnectOptions.reconnect). */
export interface ReconnectOptions {
  /** Attempts after each drop before the session gives up and closes (default 10, at most 1000). */
  retries?: number
  /** The wait before the first attempt, ms (default 500); it doubles after each failed one. */
  delayMs?: number
  /** The longest wait between attempts, ms (default 10,000). */
  maxDelayMs?: number
}

/** What `reconnect: true` means. */
export const RECONNECT_DEFAULTS: Readonly<Required<ReconnectOptions>> = Object.freeze({
  retries: 10,
  delayMs: 500,
  maxDelayMs: 10_000,
})

/**
 * Close codes after which a session with `reconnect` tries again (PROTOCOL.md, Close codes): a
 * dropped connection (1006, 1005), a server shutting down or restarting (1001, 1012), a server
 * failure (1011), the room directory unavailable (1013), no join in time (4003), a lost room
 * (4008, "rejoin it"). Every other code is final: a deliberate close (1000), strikes (1008), a
 * frame too large (1009), replaced by another connection with the token (4000, also this
 * client's own failure code), full (4001), version (4004), forbidden key (4005), moved to another
 * server (4006; the `moved` before it is followed at once, reconnect or not), a room closed as
 * overloaded (4007).
 */
export const RECONNECT_CLOSE_CODES: readonly number[] = Object.freeze([
  1001, 1005, 1006, 1011, 1012, 1013, 4003, 4008,
])

/** A body as the session knows it: pose in metres and radians, y up. */
export interface SessionBody {
  id: number
  /** 0 static, 1 kinematic, 2 dynamic. */
  kind: 0 | 1 | 2
  /** Its shapes in the body frame. */
  shapes: WireShape[]
  /** CSS '#rrggbb' for bodies with a colour (players' bodies), else null. */
  color: string | null
  x: number
  y: number
  angle: number
  awake: boolean
}

/** A player of the room (spectators are not listed). */
export interface SessionPlayer {
  id: number
  name: string
  /** CSS '#rrggbb'. */
  color: string
}

/** A game event (`ctx.emit` in the game's rules) and the room tick it happened at. */
export interface GameEvent {
  tick: number
  event: unknown
}

/** A refusal or failure: the server's error code and reason, with the command's seq when it refused one. */
export interface SessionError {
  code: string
  reason: string
  seq?: number
}

/** What each event passes to its listeners. */
export interface SessionEvents {
  /** The world changed: a snapshot applied, a state loaded, or simulated ticks (the tick). */
  state: number
  /** A game event. */
  event: GameEvent
  /** The game state: lockstep and predict, after ticks ran; snapshot, at each game event (the event). */
  game: unknown
  /** An error from the server, or one this client hit (code `client`). */
  error: SessionError
  /** The session closed for good (code and reason): closed, refused, or out of reconnect attempts. */
  close: { code: number; reason: string }
  /** `reconnect`: the connection dropped (its code and reason); attempt `attempt` starts in `delayMs`. */
  reconnecting: { attempt: number; delayMs: number; code: number; reason: string }
  /** `reconnect`: attempt `attempts` joined again; `id` is this client's id now (the old one when the server kept it). */
  reconnected: { id: number; attempts: number }
}

/** The events `on` takes. */
const EVENT_TYPES: readonly string[] = [
  'state',
  'event',
  'game',
  'error',
  'close',
  'reconnecting',
  'reconnected',
]

/** Why a join attempt failed; `final` when another attempt cannot help (a refusal, a bad key). */
class JoinFailure extends Error {
  constructor(
    message: string,
    readonly code: number,
    readonly reason: string,
    readonly final: boolean,
  ) {
    super(message)
  }
}

/**
 * Moves a session follows in a row before it gives up (servers whose directory keeps disagreeing
 * would otherwise send it back and forth for ever); a welcome starts the count again.
 */
export const MAX_MOVES = 3

/** The client's own close code when it cannot follow the server (a protocol bug, a bad sync). */
const CLIENT_FAILURE = 4000
const STEP_MS = 16
const OPEN = 1

type Listener<K extends keyof SessionEvents> = (value: SessionEvents[K]) => void

const now = (): number => globalThis.performance.now()

/** The WebSocket URL of a room: `/ws?room=` on the server's address. */
export function roomUrl(url: string, room: string, key?: string): string {
  let parsed: URL
  try {
    parsed = new URL(url)
  } catch {
    throw new Error(`connect: url "${url}" is not an absolute address (ws://host:port or http://host:port)`)
  }
  if (parsed.protocol === 'http:') parsed.protocol = 'ws:'
  else if (parsed.protocol === 'https:') parsed.protocol = 'wss:'
  else if (parsed.protocol !== 'ws:' && parsed.protocol !== 'wss:')
    throw new Error(`connect: url "${url}" must start with ws://, wss://, http:// or https://`)
  const base = `${parsed.protocol}//${parsed.host}${parsed.pathname.replace(/\/(ws)?\/?$/, '')}`
  const keyParam = key === undefined ? '' : `&key=${encodeURIComponent(key)}`
  return `${base}/ws?room=${encodeURIComponent(room)}${keyParam}`
}

/** One joined room (see the file comment). */
export class Session {
  /** The mode this session joined in. */
  readonly mode: SessionMode
  /**
   * The snapshot mirror: players, rules, errors in every mode; bodies and joints in snapshot mode.
   * A reconnect replaces it with a fresh one that the new welcome fills.
   */
  mirror = new ClientMirror()
  /** The lockstep or predicting runner (null in snapshot mode); a reconnect replaces it too. */
  runner: LockstepClient | PredictClient | null = null
  /** The last game event received (snapshot mode). */
  private lastGameEvent: GameEvent | null = null
  private readonly listeners = new Map<keyof SessionEvents, Set<(value: never) => void>>()
  private seq = 0
  /** Predict mode: custom command seqs come from their own range (the runner numbers its inputs). */
  private customSeq = 1_000_000_000
  private timer: ReturnType<typeof setInterval> | null = null
  private closedWith: { code: number; reason: string } | null = null
  private readonly shapes = new Map<number, WireShape[]>()
  private shapesOf: RoomSimulation | null = null
  /** Frames received while the room's game module loads (null when none is loading). */
  private held: Uint8Array[] | null = null
  /** The socket of the current connection (null between a drop and the next attempt's socket). */
  private socket: SocketLike | null = null
  /** close() was called: nothing reconnects. */
  private closing = false
  /** This client closed its socket after failing to follow the server (final, like 4000). */
  private failed = false
  private retryTimer: ReturnType<typeof setTimeout> | null = null
  private retrying = false
  private readonly retry: Readonly<Required<ReconnectOptions>> | null
  /** The room's WebSocket URL: the one connect() was given, or the last `moved` followed. */
  private url: string
  /** Where the last `moved` of the current connection sends the session (a room URL), else null. */
  private movedTo: string | null = null

  /** @internal Sessions come from `connect()`. */
  constructor(
    readonly options: Readonly<ConnectOptions>,
    url: string,
    private readonly Socket: SocketConstructor,
  ) {
    this.url = url
    this.mode = options.mode ?? 'snapshot'
    this.retry = reconnectSettings(options.reconnect)
    this.reset()
  }

  /** A fresh mirror and runner for a new connection. */
  private reset(): void {
    this.stopStepping()
    this.mirror = new ClientMirror()
    const send = (message: ClientMessage): void => this.write(message)
    const listener = this.gameListener()
    if (this.mode === 'predict')
      this.runner = new PredictClient({ send, games: findAnyGame, clock: now, listener })
    else if (this.mode === 'lockstep')
      this.runner = new LockstepClient({ send, games: findAnyGame, listener })
    else this.runner = null
    this.shapes.clear()
    this.shapesOf = null
    this.held = null
  }

  /** This client's id in the room (0 before the welcome). */
  get id(): number {
    return this.mirror.clientId
  }

  /** The room's name. */
  get room(): string {
    return this.mirror.room
  }

  /** The room's rules from the welcome (game, its command kinds, limits). */
  get rules(): RoomRules | null {
    return this.mirror.rules
  }

  /** The room tick this session shows: the newest snapshot's, or the simulated (predict: present) tick. */
  get tick(): number {
    const sim = this.simulation()
    return sim ? sim.tick : this.mirror.tick
  }

  /** Whether the session is joined now (false while reconnecting and once closed). */
  get open(): boolean {
    return this.closedWith === null && !this.retrying
  }

  /** Whether the session is between a drop and a successful reconnect attempt. */
  get reconnecting(): boolean {
    return this.retrying
  }

  /** The simulation drawn in lockstep and predict modes (predict: the present), else null. */
  simulation(): RoomSimulation | null {
    if (!this.runner) return null
    if (this.runner instanceof PredictClient && this.runner.present) return this.runner.present
    return this.runner.sim
  }

  /** Send a built-in command (`input`: spawn, grab, move, release, ...); returns its seq. */
  send(cmd: Command): number {
    if (this.runner instanceof PredictClient) return this.runner.input(cmd, now())
    const seq = ++this.seq
    this.write({ t: 'input', seq, cmd })
    return seq
  }

  /** Send a custom game command (`cmd`); returns its seq. Refusals arrive as `error` with that seq. */
  command(kind: string, args: Record<string, unknown> = {}): number {
    if (typeof kind !== 'string' || kind === '')
      throw new TypeError('command: kind must be a non-empty string')
    if (args === null || typeof args !== 'object' || Array.isArray(args))
      throw new TypeError(`command ${kind}: args must be an object`)
    const seq = this.runner instanceof PredictClient ? ++this.customSeq : ++this.seq
    this.write({ t: 'cmd', seq, k: kind, a: args })
    return seq
  }

  /** Listen to an event; returns the function that stops listening. */
  on<K extends keyof SessionEvents>(type: K, fn: Listener<K>): () => void {
    if (!EVENT_TYPES.includes(type))
      throw new Error(`on: unknown event "${String(type)}" (${EVENT_TYPES.join(', ')})`)
    let set = this.listeners.get(type)
    if (!set) {
      set = new Set()
      this.listeners.set(type, set)
    }
    const entry = fn as (value: never) => void
    set.add(entry)
    return () => {
      set.delete(entry)
    }
  }

  /** The room's bodies now (a fresh array; poses as last received or simulated). */
  bodies(): SessionBody[] {
    const sim = this.simulation()
    if (!sim) {
      const out: SessionBody[] = []
      for (const b of this.mirror.bodies.values())
        out.push({
          id: b.id,
          kind: b.kind,
          shapes: b.shapes,
          color: cssColor(b.color),
          x: b.x,
          y: b.y,
          angle: b.angle,
          awake: b.awake,
        })
      return out
    }
    if (this.shapesOf !== sim) {
      this.shapes.clear()
      this.shapesOf = sim
    }
    const world = sim.world
    const kinds = { static: 0, kinematic: 1, dynamic: 2 } as const
    const p = { x: 0, y: 0 }
    return world.bodyIds().map((id) => {
      let shapes = this.shapes.get(id)
      if (!shapes) {
        shapes = wireShapesOf(world, id)
        this.shapes.set(id, shapes)
      }
      world.getPosition(id, p)
      return {
        id,
        kind: kinds[world.getBodyType(id)],
        shapes,
        color: cssColor(sim.bodyColors.get(id)),
        x: p.x,
        y: p.y,
        angle: world.getAngle(id),
        awake: world.isAwake(id),
      }
    })
  }

  /** The user joints (pins, ropes, the sandbox's joint commands). */
  joints(): WireJoint[] {
    const sim = this.simulation()
    return [...(sim ? sim.userJoints.values() : this.mirror.joints.values())]
  }

  /** The room's players (spectators are not listed). */
  players(): SessionPlayer[] {
    return [...this.mirror.players.values()].map((p) => ({ id: p.id, name: p.name, color: p.color }))
  }

  /**
   * The game's state: in lockstep and predict modes the simulation's own (a copy-free view: do not
   * change it), null before the first sync or for a game without state; in snapshot mode the last
   * game event received (the server sends events, not the state), or null.
   */
  gameState(): unknown {
    if (!this.runner) return this.lastGameEvent?.event ?? null
    return this.simulation()?.gameState ?? null
  }

  /**
   * This player's view of the game (the game's `view(ctx, player)`, e.g. the goal game's score,
   * phase and clock; docs/games.md "Views"): in snapshot mode the last `view` message, in lockstep
   * and predict modes computed by the session's own simulation; for a game without `view`, its
   * whole state (the default view); null for a game without state or before the first.
   */
  view(): unknown {
    if (!this.runner) return this.mirror.view
    return this.runner.view() ?? null
  }

  /** Close the session (and stop reconnecting); resolves when it has closed. */
  close(): Promise<void> {
    this.closing = true
    this.stopStepping()
    if (this.retryTimer) clearTimeout(this.retryTimer)
    this.retryTimer = null
    if (this.closedWith) return Promise.resolve()
    const socket = this.socket
    if (!socket || socket.readyState > OPEN) {
      this.retrying = false
      this.closed(1000, 'bye')
      return Promise.resolve()
    }
    return new Promise((resolve) => {
      this.on('close', () => resolve())
      socket.close(1000, 'bye')
    })
  }

  private gameListener(): SimulationListener {
    const nothing = (): void => {}
    return {
      bodyAdded: nothing,
      bodyRemoved: nothing,
      jointAdded: nothing,
      jointRemoved: nothing,
      roomChanged: nothing,
      cursorChanged: nothing,
      worldReplaced: nothing,
      gameEvent: (tick, event: PlainData) => this.emit('event', { tick, event }),
    }
  }

  private emit<K extends keyof SessionEvents>(type: K, value: SessionEvents[K]): void {
    const set = this.listeners.get(type)
    if (!set) return
    for (const fn of [...set]) (fn as Listener<K>)(value)
  }

  private write(message: ClientMessage): void {
    if (this.socket?.readyState === OPEN) this.socket.send(encodeMessage(message))
  }

  /** @internal One frame from the socket. */
  receive(data: unknown): void {
    let bytes: Uint8Array
    if (data instanceof ArrayBuffer) bytes = new Uint8Array(data)
    else if (data instanceof Uint8Array) bytes = data
    else return
    // Frames after the welcome wait while the room's game module loads (see the file comment).
    if (this.held) {
      this.held.push(bytes)
      return
    }
    const decoded = decodeServerMessage(bytes)
    if (!decoded.ok) {
      this.fail(`could not decode a server message: ${decoded.reason}`)
      return
    }
    const message = decoded.value
    if (message.t === 'moved') {
      try {
        this.movedTo = roomUrl(message.url, this.options.room, this.options.key)
      } catch {
        // Not a ws/http address: nothing to follow; the 4006 close that comes next is final.
        this.emit('error', { code: 'client', reason: `cannot follow moved to "${message.url}"` })
      }
    }
    let ack: ReturnType<ClientMirror['handle']>
    try {
      ack = this.mirror.handle(message)
    } catch (error) {
      this.fail(`could not apply ${message.t}: ${(error as Error).message}`)
      return
    }
    if (ack) this.write(ack)
    if (this.runner) this.runner.handle(message, now())
    if (message.t === 'welcome' && this.runner) {
      if (!findAnyGame(message.rules.game)) this.loadGame(message.rules.game)
      this.startStepping()
    }
    if (message.t === 'error') {
      const error: SessionError = { code: message.code, reason: message.reason }
      if (typeof message.seq === 'number') error.seq = message.seq
      this.emit('error', error)
    }
    if (message.t === 'game' && !this.runner) {
      for (const event of message.events) {
        this.lastGameEvent = { tick: message.tick, event }
        this.emit('event', this.lastGameEvent)
        this.emit('game', event)
      }
    }
    if (!this.runner && (message.t === 'snap' || message.t === 'state' || message.t === 'events'))
      this.emit('state', this.mirror.tick)
  }

  /** @internal The session closed for good. */
  closed(code: number, reason: string): void {
    this.stopStepping()
    this.retrying = false
    if (this.closedWith) return
    this.closedWith = { code, reason }
    this.emit('close', this.closedWith)
  }

  /**
   * @internal Open a socket and join; resolves at the welcome. A first join (`first`) reports its
   * close as the session's; a reconnect attempt sends the token of the connection before. A
   * `moved` answer is followed (`moves` counts the ones followed so far).
   */
  attach(first: boolean, token = '', moves = 0): Promise<void> {
    const url = this.url
    const options = this.options
    this.movedTo = null
    return new Promise((resolve, reject) => {
      let socket: SocketLike
      try {
        socket = new this.Socket(url) as SocketLike
      } catch (error) {
        reject(new JoinFailure(`connect: cannot open ${url}: ${(error as Error).message}`, 1006, '', true))
        return
      }
      socket.binaryType = 'arraybuffer'
      this.socket = socket
      let joined = false
      let settled = false
      let refusal: SessionError | null = null
      const settle = (error: JoinFailure | null): void => {
        if (settled) return
        settled = true
        clearTimeout(timeout)
        if (error) reject(error)
        else resolve()
      }
      const timeoutMs = options.timeoutMs ?? 10_000
      const timeout = setTimeout(() => {
        settle(
          new JoinFailure(
            `connect: no welcome from ${url} within ${timeoutMs} ms`,
            4003,
            'no welcome',
            false,
          ),
        )
        socket.close(1000, 'no welcome')
      }, timeoutMs)
      socket.onopen = () => {
        const join: ClientMessage = {
          t: 'join',
          v: PROTOCOL_VERSION,
          room: options.room,
          name: options.name,
          mode: this.mode,
        }
        if (options.game !== undefined) join.game = options.game
        if (options.spectate) join.spectate = true
        if (token !== '') join.token = token
        if (this.runner) join.hold = this.runner.hold
        socket.send(encodeMessage(join))
      }
      socket.onmessage = (event) => {
        if (this.socket !== socket) return
        this.receive(event.data)
        if (this.id !== 0) {
          joined = true
          settle(null)
        } else {
          const last = this.mirror.errors.at(-1)
          if (last) refusal = last
        }
      }
      socket.onerror = () => {}
      socket.onclose = (event) => {
        if (this.socket === socket) this.socket = null
        if (joined) {
          this.dropped(event.code, event.reason)
          return
        }
        const to = this.movedTo
        if (to !== null && event.code === CLOSE_CODES.moved && !this.closing && !settled) {
          // The room is held by another server (PROTOCOL.md, `moved`): join there instead.
          clearTimeout(timeout)
          if (moves >= MAX_MOVES) {
            settle(
              new JoinFailure(
                `connect: room ${options.room} moved ${moves + 1} times in a row (last to ${to}); the servers' room directory disagrees`,
                event.code,
                event.reason,
                true,
              ),
            )
            if (first) this.closed(event.code, event.reason)
            return
          }
          this.url = to
          this.attach(first, token, moves + 1).then(
            () => settle(null),
            (failure: JoinFailure) => settle(failure),
          )
          return
        }
        // A first join's close is the session's; so is an attempt's that close() cut short.
        if (first || this.closing) this.closed(event.code, event.reason)
        if (refusal) {
          const why = `${refusal.code}: ${refusal.reason}`
          settle(
            new JoinFailure(
              `connect: ${url} refused the join: ${why} (close ${event.code})`,
              event.code,
              why,
              true,
            ),
          )
        } else if (event.code === 1006)
          // A refused upgrade looks like an unreachable server: a plain GET of the URL says why.
          void refusedUpgrade(url).then((why) =>
            settle(
              why
                ? new JoinFailure(`connect: ${url} refused the join: ${why}`, event.code, why, true)
                : new JoinFailure(
                    `connect: ${url} closed before the welcome (close 1006); is the server running and the address right?`,
                    event.code,
                    event.reason,
                    false,
                  ),
            ),
          )
        else
          settle(
            new JoinFailure(
              `connect: ${url} closed before the welcome (close ${event.code}${event.reason ? ` ${event.reason}` : ''})`,
              event.code,
              event.reason,
              !RECONNECT_CLOSE_CODES.includes(event.code),
            ),
          )
      }
    })
  }

  /**
   * The joined connection closed: follow a `moved` at once, reconnect when the session may and the
   * code allows, else close.
   */
  private dropped(code: number, reason: string): void {
    this.stopStepping()
    const moved = this.movedTo !== null && code === CLOSE_CODES.moved
    if (this.closing || this.failed || (!moved && (!this.retry || !RECONNECT_CLOSE_CODES.includes(code)))) {
      this.closed(code, reason)
      return
    }
    this.retrying = true
    if (moved) {
      this.url = this.movedTo as string
      this.scheduleAttempt(1, this.mirror.token, code, reason, true)
    } else this.scheduleAttempt(1, this.mirror.token, code, reason)
  }

  /**
   * Wait (delayMs doubled per failed attempt, at most maxDelayMs; no wait `now`, for a moved room),
   * then try to join again. A session without `reconnect` makes only the attempt that follows a
   * `moved`; with it, that attempt failing starts the retries (from 1) at the new address.
   */
  private scheduleAttempt(attempt: number, token: string, code: number, reason: string, now = false): void {
    if (this.closing) return
    const retry = this.retry
    let delayMs = 0
    if (!now) {
      if (!retry || attempt > retry.retries) {
        const last = `close ${code}${reason ? ` ${reason}` : ''}`
        this.emit('error', {
          code: 'client',
          reason: retry
            ? `gave up reconnecting after ${retry.retries} attempts (last: ${last})`
            : `could not join the room at ${this.url} after it moved (${last})`,
        })
        this.closed(code, reason)
        return
      }
      delayMs = Math.min(retry.maxDelayMs, retry.delayMs * 2 ** (attempt - 1))
    }
    this.emit('reconnecting', { attempt, delayMs, code, reason })
    this.retryTimer = setTimeout(() => {
      this.retryTimer = null
      if (this.closing) return
      this.reset()
      this.attach(false, token).then(
        () => {
          this.retrying = false
          this.emit('reconnected', { id: this.id, attempts: attempt })
        },
        (failure: JoinFailure) => {
          if (this.closing) return
          if (failure.final) {
            this.emit('error', { code: 'client', reason: failure.message })
            this.closed(failure.code, failure.reason)
            return
          }
          // A failed move's attempt is a drop at the new address: its retries start at 1.
          this.scheduleAttempt(now ? 1 : attempt + 1, token, failure.code, failure.reason)
        },
      )
    }, delayMs)
  }

  /** The code and reason the socket closed with, or null while open. */
  get closeInfo(): { code: number; reason: string } | null {
    return this.closedWith
  }

  /** Hold every later frame until game `name`'s module is loaded, then apply them in order. */
  private loadGame(name: string): void {
    const held: Uint8Array[] = []
    this.held = held
    loadServerGame(this.url, name).then(
      () => {
        // A reconnect meanwhile dropped these frames with their connection (reset).
        if (this.held !== held) return
        this.held = null
        for (const bytes of held) this.receive(bytes)
      },
      (error: Error) => {
        if (this.held === held) this.fail(error.message)
      },
    )
  }

  private fail(reason: string): void {
    this.failed = true
    this.emit('error', { code: 'client', reason })
    this.socket?.close(CLIENT_FAILURE, reason.slice(0, 120))
  }

  private startStepping(): void {
    if (this.timer || !this.runner) return
    const runner = this.runner
    this.timer = setInterval(() => {
      const stepped = runner.advance(now())
      if (runner.lastProblem && runner.state === 'repairing') return
      if (stepped > 0 || runner instanceof PredictClient) {
        this.emit('state', this.tick)
        if (stepped > 0) this.emit('game', this.gameState())
      }
    }, STEP_MS)
  }

  private stopStepping(): void {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
  }
}

/** Why the server refuses a WebSocket URL's upgrade ("400 room name ..."), or null when it cannot be asked. */
async function refusedUpgrade(url: string): Promise<string | null> {
  const probe = new URL(url)
  probe.protocol = probe.protocol === 'wss:' ? 'https:' : 'http:'
  try {
    const answer = await fetch(probe, { cache: 'no-store' })
    if (answer.status < 400) return null
    return `${answer.status} ${(await answer.text()).trim()}`
  } catch {
    return null
  }
}

/**
 * Open a socket to `options.url`, join `options.room` and resolve with the session at the
 * welcome (lockstep and predict: the simulation follows within a moment, `simulation()`). Rejects
 * with an error naming the problem: a bad option, an unreachable server, a refused join (the
 * server's error code and reason), or no welcome within `timeoutMs`.
 */
export function connect(options: ConnectOptions): Promise<Session> {
  if (options === null || typeof options !== 'object')
    return Promise.reject(new TypeError('connect: options must be an object'))
  const mode = options.mode ?? 'snapshot'
  if (mode !== 'snapshot' && mode !== 'lockstep' && mode !== 'predict')
    return Promise.reject(
      new Error(`connect: mode must be 'snapshot', 'lockstep' or 'predict', not '${String(mode)}'`),
    )
  if (typeof options.room !== 'string' || !ROOM_NAME_PATTERN.test(options.room))
    return Promise.reject(
      new Error(`connect: room "${String(options.room)}" is not a room name (1-32 of A-Z a-z 0-9 _ -)`),
    )
  if (typeof options.name !== 'string') return Promise.reject(new Error('connect: name must be a string'))
  const Socket = options.WebSocket ?? (globalThis as { WebSocket?: SocketConstructor }).WebSocket
  if (!Socket)
    return Promise.reject(
      new Error('connect: no WebSocket here; pass one, e.g. { WebSocket } from the ws package'),
    )
  for (const type of Object.keys(options.on ?? {}))
    if (!EVENT_TYPES.includes(type))
      return Promise.reject(
        new Error(`connect: options.on: unknown event "${type}" (${EVENT_TYPES.join(', ')})`),
      )
  try {
    reconnectSettings(options.reconnect)
  } catch (error) {
    return Promise.reject(error)
  }
  let url: string
  try {
    url = roomUrl(options.url, options.room, options.key)
  } catch (error) {
    return Promise.reject(error)
  }
  const session = new Session({ ...options, mode }, url, Socket)
  for (const [type, fn] of Object.entries(options.on ?? {}))
    if (fn) session.on(type as keyof SessionEvents, fn as (value: unknown) => void)
  return session.attach(true).then(
    () => session,
    (failure: Error) => Promise.reject(new Error(failure.message)),
  )
}

/** The reconnect settings `reconnect` asks for (null: off); throws naming a bad field. */
function reconnectSettings(
  reconnect: ConnectOptions['reconnect'],
): Readonly<Required<ReconnectOptions>> | null {
  if (reconnect === undefined || reconnect === false) return null
  if (reconnect === true) return RECONNECT_DEFAULTS
  if (reconnect === null || typeof reconnect !== 'object')
    throw new Error('connect: reconnect must be true, false or { retries?, delayMs?, maxDelayMs? }')
  const out = { ...RECONNECT_DEFAULTS, ...reconnect }
  const check = (field: keyof ReconnectOptions, min: number, max: number): void => {
    const v = out[field]
    if (typeof v !== 'number' || !Number.isInteger(v) || v < min || v > max)
      throw new Error(
        `connect: reconnect.${field} must be an integer from ${min} to ${max}, not ${String(v)}`,
      )
  }
  check('retries', 1, 1000)
  check('delayMs', 1, 600_000)
  check('maxDelayMs', out.delayMs, 600_000)
  return Object.freeze(out)
}
