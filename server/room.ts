/*
 * A room: one engine world, its players and their input queue, stepped at a fixed 60 Hz by the
 * server's clock (room-manager.ts drives every room from one TickClock).
 *
 * One tick, in order:
 *   1. apply the inputs queued since the last tick, in arrival order (applyCommand, the single
 *      entry point a recorder hooks into via onCommand)
 *   2. world.step() unless paused (a single-step request steps once while paused)
 *   3. advance the room tick; send the tick's events (bodies and joints created or removed, room
 *      settings) to everyone, encoded once
 *   4. on snapshot ticks: quantize the world once into a shared frame, then write each client's
 *      delta against its own acknowledged baseline within its byte budget, followed by the
 *      contacts of the body it inspects, if any; a client whose send buffer is full is skipped,
 *      and closed if it stays behind
 *   5. every second: a state hash checkpoint, housekeeping (out-of-bounds bodies, reconnect window)
 *
 * Room ticks count loop iterations and never reset; world.tick counts steps of the current world
 * (paused ticks do not step, a scene load starts a new world).
 */
import type { Logger } from 'pino'
import { buildScene, createWorld, SCENES, type SceneBlueprint, type World } from '../engine/index.ts'
import {
  ByteWriter,
  type Command,
  encodeMessage,
  KILL_DISTANCE,
  PROTOCOL_VERSION,
  QuantizedFrame,
  quantizePosition,
  type RoomRules,
  type ServerMessage,
  TICK_RATE,
  type WireBody,
  type WireJoint,
  WORLD_HALF_EXTENT,
} from '../shared/index.ts'
import type { ClientSession } from './client-session.ts'
import type { ServerConfig } from './config.ts'
import type { ServerMetrics } from './metrics.ts'
import { applyCommand } from './room-commands.ts'
import { assignIdentity, type DepartedPlayer, playerColor } from './room-players.ts'
import { encodeInspections, fillFrame, fullState } from './room-wire.ts'

/** A queued input: who sent it, its sequence number and the validated command. */
interface QueuedInput {
  session: ClientSession
  seq: number
  cmd: Command
}

/** Called for every command applied, in order: the hook for the replay recorder. */
export type CommandListener = (tick: number, clientId: number, cmd: Command) => void

/** One room: world, players, input queue, snapshots. */
export class Room {
  world: World
  scene: string
  paused = false
  stepRequested = false
  /** Ticks run since the room opened. */
  tick = 0
  /** Joined players by id. */
  readonly sessions = new Map<number, ClientSession>()
  /** User joints (pins, ropes) by joint id. */
  readonly userJoints = new Map<number, WireJoint>()
  /** Grabs per body id (bodies being pulled get priority in snapshots). */
  readonly grabCounts = new Map<number, number>()
  readonly departed = new Map<string, DepartedPlayer>()
  nextPlayerId = 1
  /** Room tick at which the last player left (for disposal), or -1 while occupied. */
  emptySince = 0
  /** Room tick of the last scene load or reset (they are rate limited). */
  lastLoadTick = Number.NEGATIVE_INFINITY
  /** Recorder hook. */
  onCommand: CommandListener | null = null
  /** Largest staleness (ticks) of a body write in the last snapshot round, for the benchmark. */
  lastMaxStaleness = 0
  readonly rules: RoomRules
  private queue: QueuedInput[] = []
  private events = {
    add: [] as WireBody[],
    remove: [] as number[],
    jadd: [] as WireJoint[],
    jremove: [] as number[],
  }
  private roomChanged = false
  private readonly frame = new QuantizedFrame(256)
  private readonly writer = new ByteWriter(4096)
  private readonly snapshotInterval: number
  private readonly budget: number
  private readonly weight = (id: number): number => (this.grabCounts.has(id) ? 8 : 0)

  constructor(
    readonly name: string,
    readonly config: ServerConfig,
    readonly metrics: ServerMetrics,
    readonly log: Logger,
  ) {
    this.snapshotInterval = TICK_RATE / config.snapshotRate
    this.budget = Math.floor(config.clientBandwidth / config.snapshotRate)
    this.scene = Object.hasOwn(SCENES, config.defaultScene) ? config.defaultScene : 'pyramid'
    this.world = this.makeWorld(this.scene)
    this.rules = {
      tickRate: TICK_RATE,
      snapshotRate: config.snapshotRate,
      maxBodies: config.maxBodies,
      maxClients: config.maxClientsPerRoom,
      inputsPerTick: config.inputsPerTick,
      controls: config.roomControls,
      scenes: Object.keys(SCENES),
      worldHalfExtent: WORLD_HALF_EXTENT,
    }
  }

  private makeWorld(scene: string): World {
    return this.worldFrom(SCENES[scene].make())
  }

  private worldFrom(blueprint: SceneBlueprint): World {
    const world = createWorld()
    buildScene(world, blueprint)
    return world
  }

  /** Add a joined player and send its welcome; returns an error reason when refused. */
  join(session: ClientSession, name: string, token: string | undefined): string | null {
    if (this.sessions.size >= this.config.maxClientsPerRoom) return `room ${this.name} is full`
    const identity = assignIdentity(this, token)
    if (identity.replaced) identity.replaced.close(4000, 'replaced by a reconnect with the same token')
    session.id = identity.id
    session.token = identity.token
    session.name = identity.name ?? (name.trim() || `player ${identity.id}`)
    session.color = identity.color ?? playerColor(identity.id)
    session.room = this.name
    session.joined = true
    this.sessions.set(session.id, session)
    this.emptySince = -1
    const frame = new QuantizedFrame()
    fillFrame(this.world, frame)
    session.encoder.reset(frame, this.tick)
    session.send({
      t: 'welcome',
      v: PROTOCOL_VERSION,
      id: session.id,
      token: session.token,
      room: this.name,
      rules: this.rules,
      players: this.roster(),
      state: fullState(this.world, this.tick, this.scene, this.paused, this.userJoints.values()),
    })
    this.broadcast({ t: 'players', players: this.roster() })
    // The newcomer learns every cursor from the next snapshot.
    for (const s of this.sessions.values()) s.cursorDirty = true
    this.log.info({ room: this.name, player: session.id, name: session.name }, 'player joined')
    return null
  }

  /** Remove a player: release its grab, keep its identity for the reconnect window. */
  leave(session: ClientSession): void {
    if (this.sessions.get(session.id) !== session) return
    applyCommand(this, session, { k: 'release' })
    session.inspect = 0
    this.sessions.delete(session.id)
    this.departed.set(session.token, {
      id: session.id,
      name: session.name,
      color: session.color,
      leftTick: this.tick,
    })
    if (this.sessions.size === 0) this.emptySince = this.tick
    this.broadcast({ t: 'players', players: this.roster() })
    this.log.info({ room: this.name, player: session.id }, 'player left')
  }

  /** The roster for welcome and players messages. */
  roster(): Array<{ id: number; name: string; color: string }> {
    return [...this.sessions.values()].map((s) => ({ id: s.id, name: s.name, color: s.color }))
  }

  /**
   * Queue an input for the next tick; returns an error reason when over the per-tick budget. A
   * move replaces the same player's move already queued for this tick (only the latest cursor
   * position matters), so fast mice never use up the budget.
   */
  queueInput(session: ClientSession, seq: number, cmd: Command): string | null {
    if (cmd.k === 'move' && session.queuedMove >= 0) {
      const queued = this.queue[session.queuedMove]
      queued.seq = seq
      queued.cmd = cmd
      return null
    }
    if (session.inputsThisTick >= this.config.inputsPerTick) {
      return `input budget exceeded: at most ${this.config.inputsPerTick} inputs per tick`
    }
    session.inputsThisTick++
    if (cmd.k === 'move') session.queuedMove = this.queue.length
    this.queue.push({ session, seq, cmd })
    return null
  }

  /** Run one tick (see the file comment). */
  runTick(): void {
    const queue = this.queue
    this.queue = []
    for (const input of queue) {
      if (!input.session.joined || this.sessions.get(input.session.id) !== input.session) continue
      const error = applyCommand(this, input.session, input.cmd)
      if (error) input.session.sendError('refused', error, input.seq)
    }
    for (const s of this.sessions.values()) {
      s.inputsThisTick = 0
      s.queuedMove = -1
    }
    if (!this.paused || this.stepRequested) this.world.step()
    this.stepRequested = false
    this.tick++
    this.flushEvents()
    if (this.tick % this.snapshotInterval === 0) this.sendSnapshots()
    if (this.tick % TICK_RATE === 0) this.everySecond()
  }

  /** Record a body creation event. */
  bodyAdded(body: WireBody): void {
    this.events.add.push(body)
  }

  /** Destroy a body and everything attached to it, with events. */
  removeBody(id: number): void {
    for (const [jid, j] of this.userJoints) {
      if (j.a === id || j.b === id) {
        this.userJoints.delete(jid)
        this.events.jremove.push(jid)
      }
    }
    for (const s of this.sessions.values()) {
      if (s.grab?.body === id) {
        s.grab = null
        s.cursorDirty = true
      }
      if (s.inspect === id) s.inspect = 0
      s.encoder.removeBody(id)
    }
    this.grabCounts.delete(id)
    this.world.destroyBody(id)
    this.events.remove.push(id)
  }

  /** Record a user joint creation or removal. */
  jointAdded(joint: WireJoint): void {
    this.userJoints.set(joint.id, joint)
    this.events.jadd.push(joint)
  }

  /** Remove a user joint. */
  jointRemoved(id: number): void {
    this.userJoints.delete(id)
    this.events.jremove.push(id)
  }

  /** Pause, gravity or scene changed: tell everyone at the end of the tick. */
  markRoomChanged(): void {
    this.roomChanged = true
  }

  /** Replace the world with a fresh copy of a named scene (SCENES) and send everyone the new full state. */
  loadScene(name: string): void {
    this.loadBlueprint(name, SCENES[name].make())
  }

  /** Replace the world with a scene blueprint (benchmarks use sizes SCENES does not list). */
  loadBlueprint(name: string, blueprint: SceneBlueprint): void {
    this.lastLoadTick = this.tick
    for (const s of this.sessions.values()) {
      s.grab = null
      s.inspect = 0
      s.cursorDirty = true
    }
    this.grabCounts.clear()
    this.userJoints.clear()
    this.events = { add: [], remove: [], jadd: [], jremove: [] }
    this.scene = name
    this.world = this.worldFrom(blueprint)
    const frame = new QuantizedFrame()
    fillFrame(this.world, frame)
    const bytes = encodeMessage({
      t: 'state',
      state: fullState(this.world, this.tick, name, this.paused, []),
    })
    for (const s of this.sessions.values()) {
      s.encoder.reset(frame, this.tick)
      s.sendBytes(bytes)
    }
    this.markRoomChanged()
    this.log.info({ room: this.name, scene: name }, 'scene loaded')
  }

  /** Encode once, send to every player. */
  broadcast(message: ServerMessage): void {
    if (this.sessions.size === 0) return
    const bytes = encodeMessage(message)
    for (const s of this.sessions.values()) s.sendBytes(bytes)
  }

  private flushEvents(): void {
    const e = this.events
    if (e.add.length + e.remove.length + e.jadd.length + e.jremove.length > 0) {
      this.broadcast({ t: 'events', tick: this.tick, ...e })
      this.events = { add: [], remove: [], jadd: [], jremove: [] }
    }
    if (this.roomChanged) {
      const g = this.world.getGravity()
      this.broadcast({
        t: 'room',
        tick: this.tick,
        paused: this.paused,
        gravity: [g.x, g.y],
        scene: this.scene,
      })
      this.roomChanged = false
    }
  }

  private sendSnapshots(): void {
    if (this.sessions.size === 0) return
    fillFrame(this.world, this.frame)
    const cursors: number[] = []
    for (const s of this.sessions.values()) {
      if (!s.cursorDirty) continue
      cursors.push(s.id, quantizePosition(s.cursorX), quantizePosition(s.cursorY), s.grab ? s.grab.body : 0)
      s.cursorDirty = false
    }
    const inspected = new Set<number>()
    for (const s of this.sessions.values()) if (s.inspect !== 0) inspected.add(s.inspect)
    const contacts = encodeInspections(this.world, this.tick, inspected)
    let staleness = 0
    for (const s of this.sessions.values()) {
      staleness = Math.max(staleness, this.sendSnapshot(s, cursors, contacts.get(s.inspect)))
    }
    this.lastMaxStaleness = staleness
  }

  /**
   * Send one client its snapshot and, when it inspects a body, that body's contacts; or skip both
   * when its send buffer is full. Returns the snapshot's staleness.
   */
  private sendSnapshot(session: ClientSession, cursors: number[], contacts: Uint8Array | undefined): number {
    const buffered = session.ws.bufferedAmount
    if (buffered > this.config.sendBufferBytes) {
      this.metrics.snapshotsSkipped.inc()
      if (session.behindSince < 0) session.behindSince = this.tick
      const hardLimit = Math.max(this.config.sendBufferBytes * 8, 1 << 20)
      if (
        this.tick - session.behindSince > this.config.slowClientSeconds * TICK_RATE ||
        buffered > hardLimit
      ) {
        this.log.warn(
          { room: this.name, player: session.id, buffered },
          'closing a client that stopped reading',
        )
        this.metrics.slowClientsClosed.inc()
        session.ws.terminate()
      }
      return 0
    }
    session.behindSince = -1
    this.writer.reset()
    const base = session.encoder.referenceTick
    const stats = session.encoder.encode(this.writer, this.frame, this.tick, this.budget, this.weight)
    const data = this.writer.bytes.subarray(0, this.writer.length)
    session.sendBytes(encodeMessage({ t: 'snap', tick: this.tick, base, data, cursors }))
    if (contacts) session.sendBytes(contacts)
    return stats.maxStaleness
  }

  private everySecond(): void {
    this.broadcast({ t: 'hash', tick: this.tick, step: this.world.tick, hash: this.world.hash() })
    const p = { x: 0, y: 0 }
    for (const id of this.world.bodyIds()) {
      if (this.world.getBodyType(id) === 'static') continue
      this.world.getPosition(id, p)
      if (Math.abs(p.x) > KILL_DISTANCE || Math.abs(p.y) > KILL_DISTANCE) this.removeBody(id)
    }
    const window = this.config.reconnectSeconds * TICK_RATE
    for (const [token, d] of this.departed) if (this.tick - d.leftTick > window) this.departed.delete(token)
  }

  /** Close every player with a reason. */
  closeAll(code: number, reason: string): void {
    for (const s of this.sessions.values()) s.close(code, reason)
  }
}
