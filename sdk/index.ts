/*
 * The client SDK (docs/sdk.md): what someone else's page (or a Node program) uses to join a
 * Concord room. `connect()` opens one WebSocket (the browser's, or an injected constructor such
 * as the `ws` package's), joins in snapshot, lockstep or predict mode and resolves with a
 * `Session` at the welcome. The session is a thin wrapper over the classes the Concord page runs:
 * the snapshot mirror (ClientMirror), the lockstep and predicting runners (LockstepClient,
 * PredictClient, stepped from a 16 ms timer) and the games this build ships (games/'s findGame),
 * so an SDK client decodes and simulates exactly as the page does. `npm run build:sdk` bundles it
 * to dist/sdk/index.js with type declarations; the canvas renderer is apart, in sdk/render.ts.
 */
import { findGame } from '../games/index.ts'
import {
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
}

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
  /** The socket closed (code and reason). */
  close: { code: number; reason: string }
}

/** The events `on` takes. */
const EVENT_TYPES: readonly string[] = ['state', 'event', 'game', 'error', 'close']

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
  /** The snapshot mirror: players, rules, errors in every mode; bodies and joints in snapshot mode. */
  readonly mirror = new ClientMirror()
  /** The lockstep or predicting runner (null in snapshot mode). */
  readonly runner: LockstepClient | PredictClient | null
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

  /** @internal Sessions come from `connect()`. */
  constructor(
    private readonly socket: SocketLike,
    readonly options: Readonly<ConnectOptions>,
  ) {
    this.mode = options.mode ?? 'snapshot'
    const send = (message: ClientMessage): void => this.write(message)
    const listener = this.gameListener()
    if (this.mode === 'predict')
      this.runner = new PredictClient({ send, games: findGame, clock: now, listener })
    else if (this.mode === 'lockstep') this.runner = new LockstepClient({ send, games: findGame, listener })
    else this.runner = null
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

  /** Whether the socket is still open. */
  get open(): boolean {
    return this.closedWith === null
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

  /** Close the socket; resolves when it has closed. */
  close(): Promise<void> {
    this.stopStepping()
    if (this.closedWith) return Promise.resolve()
    return new Promise((resolve) => {
      this.on('close', () => resolve())
      this.socket.close(1000, 'bye')
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
    if (this.socket.readyState === OPEN) this.socket.send(encodeMessage(message))
  }

  /** @internal One frame from the socket. */
  receive(data: unknown): void {
    let bytes: Uint8Array
    if (data instanceof ArrayBuffer) bytes = new Uint8Array(data)
    else if (data instanceof Uint8Array) bytes = data
    else return
    const decoded = decodeServerMessage(bytes)
    if (!decoded.ok) {
      this.fail(`could not decode a server message: ${decoded.reason}`)
      return
    }
    const message = decoded.value
    let ack: ReturnType<ClientMirror['handle']>
    try {
      ack = this.mirror.handle(message)
    } catch (error) {
      this.fail(`could not apply ${message.t}: ${(error as Error).message}`)
      return
    }
    if (ack) this.write(ack)
    if (this.runner) this.runner.handle(message, now())
    if (message.t === 'welcome' && this.runner) this.startStepping()
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

  /** @internal The socket closed. */
  closed(code: number, reason: string): void {
    this.stopStepping()
    if (this.closedWith) return
    this.closedWith = { code, reason }
    this.emit('close', this.closedWith)
  }

  /** The code and reason the socket closed with, or null while open. */
  get closeInfo(): { code: number; reason: string } | null {
    return this.closedWith
  }

  private fail(reason: string): void {
    this.emit('error', { code: 'client', reason })
    this.socket.close(CLIENT_FAILURE, reason.slice(0, 120))
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
  let url: string
  try {
    url = roomUrl(options.url, options.room, options.key)
  } catch (error) {
    return Promise.reject(error)
  }
  return new Promise((resolve, reject) => {
    let socket: SocketLike
    try {
      socket = new Socket(url) as SocketLike
    } catch (error) {
      reject(new Error(`connect: cannot open ${url}: ${(error as Error).message}`))
      return
    }
    socket.binaryType = 'arraybuffer'
    const session = new Session(socket, { ...options, mode })
    for (const [type, fn] of Object.entries(options.on ?? {}))
      if (fn) session.on(type as keyof SessionEvents, fn as (value: unknown) => void)
    let settled = false
    let refusal: SessionError | null = null
    const settle = (error: Error | null): void => {
      if (settled) return
      settled = true
      clearTimeout(timeout)
      if (error) reject(error)
      else resolve(session)
    }
    const timeout = setTimeout(() => {
      settle(new Error(`connect: no welcome from ${url} within ${options.timeoutMs ?? 10_000} ms`))
      socket.close(1000, 'no welcome')
    }, options.timeoutMs ?? 10_000)
    socket.onopen = () => {
      const join: ClientMessage = {
        t: 'join',
        v: PROTOCOL_VERSION,
        room: options.room,
        name: options.name,
        mode,
      }
      if (options.game !== undefined) join.game = options.game
      if (options.spectate) join.spectate = true
      if (session.runner) join.hold = session.runner.hold
      socket.send(encodeMessage(join))
    }
    socket.onmessage = (event) => {
      session.receive(event.data)
      if (session.id !== 0) settle(null)
      else {
        const last = session.mirror.errors.at(-1)
        if (last) refusal = last
      }
    }
    socket.onerror = () => {}
    socket.onclose = (event) => {
      session.closed(event.code, event.reason)
      if (refusal)
        settle(
          new Error(
            `connect: ${url} refused the join: ${refusal.code}: ${refusal.reason} (close ${event.code})`,
          ),
        )
      else if (event.code === 1006)
        // A refused upgrade looks like an unreachable server: a plain GET of the URL says why.
        void refusedUpgrade(url).then((why) =>
          settle(
            new Error(
              why
                ? `connect: ${url} refused the join: ${why}`
                : `connect: ${url} closed before the welcome (close 1006); is the server running and the address right?`,
            ),
          ),
        )
      else
        settle(
          new Error(
            `connect: ${url} closed before the welcome (close ${event.code}${event.reason ? ` ${event.reason}` : ''})`,
          ),
        )
    }
  })
}
