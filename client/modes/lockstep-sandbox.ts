/*
 * Lockstep and predict modes in the page (?mode=lockstep or ?mode=predict): the sandbox simulates
 * the room itself. The connection joins with that mode; the server's `sync` and `ticks` go to a
 * LockstepClient (or a PredictClient), stepped every animation frame; the view is read straight
 * from the local simulation (the present one when predicting, with the correction offsets of
 * predict-smoothing.ts added), so there is no snapshot interpolation and the lab reads contacts
 * from the local world. Commands go to the server as inputs; a predicting sandbox also applies
 * them to its present at once. The HUD shows the mode, the last verified tick, desyncs, resyncs
 * and, when predicting, rollbacks per second, their depth and the re-simulation time.
 */

import {
  type Command,
  cssColor,
  type JoinMessage,
  LockstepClient,
  type PlainData,
  PROTOCOL_VERSION,
  PredictClient,
  type RoomRules,
  type RoomSimulation,
  type ServerMessage,
  TICK_RATE,
  type WirePlayer,
  type WireShape,
  wireShapesOf,
} from '../../shared/index.ts'
import { Connection } from '../net/index.ts'
import { findClientGame, loadGameModule } from './game-modules.ts'
import { NoticeLog } from './notice-log.ts'
import { CorrectionSmoother } from './predict-smoothing.ts'
import type {
  LabContact,
  LabData,
  PersonRow,
  RoomControl,
  Sandbox,
  SandboxStats,
  SandboxStatus,
  ViewBody,
  ViewCursor,
  ViewJoint,
} from './sandbox.ts'
import { simulationControl, simulationJoints, simulationLab } from './simulation-view.ts'

/** Where and how to join. */
export interface LockstepSandboxOptions {
  url: string
  room: string
  /** The game a room this join creates runs (the page's `&game=`). */
  game?: string
  name: string
  mode: 'lockstep' | 'predict'
  /** Access key for a server with join or admin tokens (the page's `?key=`), sent as `&key=`. */
  key?: string
}

const KIND = { static: 0, kinematic: 1, dynamic: 2 } as const

/** The sandbox simulating a server room locally (see the file comment). */
export class LockstepSandbox implements Sandbox {
  readonly mode = 'online'
  readonly runner: LockstepClient
  private readonly connection: Connection
  private readonly smoother = new CorrectionSmoother()
  private readonly view: ViewBody[] = []
  private readonly shapes = new Map<number, WireShape[]>()
  /** The drawn simulation's bodyEdits when the shapes were cached (an edit makes them stale). */
  private shapesEdits = 0
  private players: WirePlayer[] = []
  /** Scene ids the server answered this page's saveScene commands with, by seq. */
  private readonly saved = new Map<number, string>()
  private statusValue: SandboxStatus = { state: 'connecting' }
  private readonly notice = new NoticeLog()
  private lastFrame = Number.NaN
  private lastPing = 0
  private rttMs: number | null = null
  private seq = 0
  private downWindow = { start: Number.NaN, bytes: 0, value: 0 }
  private contactCache: { tick: number; contacts: LabContact[] } | null = null
  /** Messages held while the room's game module loads (see receive), else null. */
  private held: Array<[ServerMessage, number]> | null = null
  /** Players whose cursor has left the origin (a new player's cursor starts there). */
  private readonly movedCursors = new Set<number>()

  constructor(private readonly options: LockstepSandboxOptions) {
    const send = (m: Parameters<Connection['send']>[0]): void => {
      this.connection.send(m)
    }
    this.runner =
      options.mode === 'predict'
        ? new PredictClient({
            send,
            games: findClientGame,
            clock: () => performance.now(),
            onRollback: (before, after) => this.smoother.correct(before, after),
          })
        : new LockstepClient({ send, games: findClientGame })
    const key = options.key ? `&key=${encodeURIComponent(options.key)}` : ''
    this.connection = new Connection(
      `${options.url}?room=${encodeURIComponent(options.room)}${key}`,
      () => this.join(),
      {
        message: (m, bytes) => this.receive(m, bytes),
        status: (text, retrying, fatal) => {
          this.statusValue =
            text === null
              ? { state: 'connected' }
              : { state: 'error', message: text, retrying: retrying && !fatal }
        },
      },
    )
  }

  private join(): JoinMessage {
    return {
      t: 'join',
      v: PROTOCOL_VERSION,
      room: this.options.room,
      name: this.options.name,
      mode: this.options.mode,
      hold: this.runner.hold,
      ...(this.options.game ? { game: this.options.game } : {}),
    }
  }

  private receive(message: ServerMessage, bytes: number): void {
    // A room of a game this build does not ship (--games on the server): hold the room's messages
    // until the page has imported the game's module (game-modules.ts), then take them in order.
    if (this.held) {
      this.held.push([message, bytes])
      return
    }
    if (message.t === 'welcome' && message.rules.game && !findClientGame(message.rules.game)) {
      this.held = [[message, bytes]]
      loadGameModule(this.options.url, message.rules.game).then(
        () => {
          const held = this.held ?? []
          this.held = null
          for (const [m, b] of held) this.receive(m, b)
        },
        (error: Error) => {
          this.held = null
          this.statusValue = { state: 'error', message: error.message, retrying: false }
        },
      )
      return
    }
    const now = performance.now()
    this.downWindow.bytes += bytes
    if (message.t === 'pong') this.rttMs = now - message.time
    if (message.t === 'players') this.players = message.players
    if (message.t === 'scene') this.saved.set(message.seq, message.id)
    if (message.t === 'welcome') {
      this.players = message.players
      if (message.notice) this.noted(message.notice)
    }
    if (message.t === 'error' && message.code === 'refused') this.noted(message.reason)
    this.runner.handle(message, now)
  }

  /** The simulation drawn: the present when predicting, else the confirmed one. */
  private drawn(): RoomSimulation | null {
    return this.runner instanceof PredictClient ? (this.runner.present ?? this.runner.sim) : this.runner.sim
  }

  update(nowMs: number): void {
    this.runner.advance(nowMs)
    if (!Number.isNaN(this.lastFrame)) this.smoother.decay(nowMs - this.lastFrame)
    this.lastFrame = nowMs
    if (nowMs - this.lastPing >= 1000 && this.connection.isJoined) {
      this.lastPing = nowMs
      this.connection.send({ t: 'ping', id: Math.floor(nowMs), time: nowMs })
    }
    const w = this.downWindow
    if (Number.isNaN(w.start)) w.start = nowMs
    if (nowMs - w.start >= 1000) {
      w.value = (w.bytes * 1000) / (nowMs - w.start)
      w.bytes = 0
      w.start = nowMs
    }
    this.refreshView()
  }

  private refreshView(): void {
    this.view.length = 0
    const sim = this.drawn()
    if (!sim) return
    const world = sim.world
    // A command changed bodies in place (the Edit tool): their shapes and materials are read again.
    if (sim.bodyEdits !== this.shapesEdits) {
      this.shapes.clear()
      this.shapesEdits = sim.bodyEdits
    }
    const grabbed = new Map<number, string>()
    for (const [id, p] of sim.players) if (p.grab) grabbed.set(p.grab.body, this.playerColor(id))
    const p = { x: 0, y: 0 }
    for (const id of world.bodyIds()) {
      let shapes = this.shapes.get(id)
      if (!shapes) {
        shapes = wireShapesOf(world, id)
        this.shapes.set(id, shapes)
      }
      world.getPosition(id, p)
      const o = this.smoother.offset(id)
      this.view.push({
        id,
        kind: KIND[world.getBodyType(id)],
        shapes,
        color: cssColor(sim.bodyColors.get(id)),
        x: p.x + (o?.x ?? 0),
        y: p.y + (o?.y ?? 0),
        angle: world.getAngle(id) + (o?.a ?? 0),
        awake: world.isAwake(id),
        grabColor: grabbed.get(id) ?? null,
      })
    }
    this.view.sort((a, b) => a.kind - b.kind || a.id - b.id)
    if (this.shapes.size > this.view.length * 2 + 64) {
      const alive = new Set(this.view.map((v) => v.id))
      for (const id of this.shapes.keys()) if (!alive.has(id)) this.shapes.delete(id)
    }
  }

  private playerColor(id: number): string {
    return this.players.find((p) => p.id === id)?.color ?? '#fff'
  }

  bodies(): readonly ViewBody[] {
    return this.view
  }

  joints(): readonly ViewJoint[] {
    const sim = this.drawn()
    if (!sim) return []
    const byId = new Map(this.view.map((v) => [v.id, v]))
    return simulationJoints(sim, (id) => byId.get(id))
  }

  cursors(): readonly ViewCursor[] {
    const sim = this.drawn()
    if (!sim) return []
    const out: ViewCursor[] = []
    for (const pl of this.players) {
      const s = sim.players.get(pl.id)
      if (pl.id === this.runner.playerId || !s) continue
      // A player who has not moved yet sits at the origin: not a cursor worth drawing.
      if (s.cursorX !== 0 || s.cursorY !== 0 || s.grab) this.movedCursors.add(pl.id)
      if (!this.movedCursors.has(pl.id)) continue
      out.push({
        id: pl.id,
        name: pl.name,
        color: pl.color,
        x: s.cursorX,
        y: s.cursorY,
        body: s.grab?.body ?? 0,
      })
    }
    return out
  }

  contacts(): readonly LabContact[] | null {
    const sim = this.drawn()
    if (!sim) return null
    if (this.contactCache?.tick !== sim.tick)
      this.contactCache = { tick: sim.tick, contacts: sim.world.contacts() }
    return this.contactCache.contacts
  }

  send(cmd: Command): void {
    if (this.runner instanceof PredictClient) this.runner.input(cmd, performance.now())
    else this.connection.send({ t: 'input', seq: ++this.seq, cmd })
  }

  /** Send a game command (`cmd`: kind and arguments, docs/games.md); returns its seq. */
  sendGame(kind: string, args: Record<string, unknown>): number {
    // A predicting page applies its own game command at once (PredictClient.gameCommand).
    if (this.runner instanceof PredictClient)
      return this.runner.gameCommand(kind, args as { [key: string]: PlainData }, performance.now())
    this.connection.send({ t: 'cmd', seq: ++this.seq, k: kind, a: args })
    return this.seq
  }

  /** Send a room command (openScene, saveScene, rename: PROTOCOL.md "Room commands"); its seq, or null before the join. */
  roomCommand(kind: string, args: { [key: string]: PlainData }): number | null {
    if (!this.connection.isJoined) return null
    return this.sendGame(kind, args)
  }

  /** The scene ids the server answered this page's saveScene commands with, by seq. */
  savedScenes(): ReadonlyMap<number, string> {
    return this.saved
  }

  playerId(): number {
    return this.runner.playerId
  }

  /**
   * This player's game view as the drawn simulation has it (PredictClient: the present), else the
   * drawn simulation's game state (null before the sync or for a game without state).
   */
  gameState(): unknown {
    return this.runner.view() ?? this.drawn()?.gameState ?? null
  }

  people(): readonly PersonRow[] {
    const sim = this.drawn()
    const creator = sim?.creator ?? 0
    return this.players
      .map((p) => ({
        id: p.id,
        name: p.name,
        color: p.color,
        self: p.id === this.runner.playerId,
        creator: p.id === creator,
        holds: sim?.players.get(p.id)?.grab?.body ?? 0,
      }))
      .sort((a, b) => a.id - b.id)
  }

  roomControl(): RoomControl {
    return simulationControl(this.drawn(), this.runner.playerId)
  }

  color(): string {
    return this.playerColor(this.runner.playerId)
  }

  status(): SandboxStatus {
    return this.statusValue
  }

  stats(): SandboxStats {
    const sim = this.drawn()
    const r = this.runner
    let awake = 0
    for (const v of this.view) if (v.kind !== 0 && v.awake) awake++
    const predict = r instanceof PredictClient ? r.predict : null
    return {
      room: this.options.room,
      players: this.players.length,
      tick: sim?.tick ?? 0,
      pingMs: this.rttMs,
      delayMs: (r.playout.delay * 1000) / TICK_RATE,
      snapshotHz: null,
      downKBs: this.downWindow.value / 1000,
      upKBs: null,
      awake,
      total: this.view.length,
      stepMs: null,
      lockstep: {
        mode: this.options.mode,
        state: r.state,
        verifiedTick: r.stats.verifiedTick,
        desyncs: r.stats.desyncs,
        resyncs: r.stats.resyncs,
        rollbacksPerSecond: predict?.rollbacksPerSecond ?? null,
        rollbackDepth: predict?.lastDepth ?? null,
        resimMs: predict?.resimMsSmoothed ?? null,
      },
    }
  }

  rules(): RoomRules | null {
    const rules = this.runner.rules
    // The room's controls, unless this page's key does not open them (the server has an admin key).
    if (!rules?.controls || this.connection?.controlsAllowed !== false) return rules
    return { ...rules, controls: false }
  }

  scene(): string {
    return this.drawn()?.scene ?? ''
  }

  paused(): boolean {
    return this.drawn()?.paused ?? false
  }

  gravity(): { x: number; y: number } {
    return this.drawn()?.world.getGravity() ?? { x: 0, y: -10 }
  }

  inspect(): void {}

  lab(bodyId: number): LabData | null {
    const sim = this.drawn()
    return sim ? simulationLab(sim, bodyId, sim.world.contacts()) : null
  }

  notices(): { count: number; latest: string | null; recent: readonly string[] } {
    return this.notice
  }

  /** Count a notice the server sent, keeping the last three. */
  private noted(text: string): void {
    this.notice.add(text)
  }

  retry(): void {
    this.connection.retryNow()
  }

  dispose(): void {
    this.connection.close()
  }
}
