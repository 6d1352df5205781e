/*
 * A room on the server: the networking around one RoomSimulation (shared/sim/room-simulation.ts, the
 * deterministic part: world, grabs, user joints, pause, the room tick). Here: players and their
 * connections (behind PlayerConnection, never a socket), the input queue, events, snapshots and
 * hash checkpoints. The room manager drives every room from one TickClock at 60 Hz.
 *
 * One tick, in order:
 *   1. apply the inputs queued since the last tick, in arrival order, through the simulation
 *      (its observers, e.g. a recorder, see every accepted command there); `inspect` is handled
 *      here, it only chooses what a player is sent
 *   2. the simulation's tick: step unless paused, advance the room tick, once a second remove
 *      bodies that left the world
 *   3. send the tick's events (bodies and joints created or removed, room settings) to everyone,
 *      encoded once; new bodies carry their pose after this tick's step, and a spawned body the
 *      spawner's player id and input seq
 *   4. on snapshot ticks (every 60 / snapshotRate ticks, at an offset that spreads the rooms of a
 *      manager over the ticks of an interval; room-snapshots.ts): quantize the world once into a
 *      shared frame, then write each player's delta against its own acknowledged baseline within
 *      its byte budget (players whose baselines are equal, the usual case, share one encoded
 *      message), followed by the contacts of the body it inspects, if any; a player whose
 *      connection has too much buffered is skipped, and closed if it stays behind
 *   5. every second: a state hash checkpoint, forget departed players past the reconnect window
 *   6. the lockstep feed (lockstep-feed.ts): the tick's accepted commands, joins and leaves to the
 *      lockstep and predict players, the checkpoint hash, and saved worlds to those waiting for one
 *
 * Lockstep and predict players simulate the room themselves: steps 3-5 (events, room settings,
 * snapshots, contacts, hash messages) skip them.
 *
 * Room ticks grow by one per loop iteration and never reset (a new room starts at a tick below 60
 * that its manager picks to spread rooms' checkpoints over the clock, room-manager.ts); world.tick
 * counts steps of the current world (paused ticks do not step, a scene load starts a new world).
 */
import type { Logger } from 'pino'
import { DEFAULT_SCENE, SCENES, type SceneBlueprint, type World } from '../../engine/index.ts'
import { type Game, sandbox } from '../../games/index.ts'
import {
  encodeMessage,
  encodeValue,
  isMovable,
  type JoinMode,
  MAX_VIEW_BYTES,
  type PlainData,
  PROTOCOL_VERSION,
  QuantizedFrame,
  type RoomRules,
  RoomSimulation,
  roomRules,
  type ServerMessage,
  type SimCommand,
  type SimulationListener,
  TICK_RATE,
  type WireBody,
  type WireJoint,
  worldFromBlueprint,
} from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import { LockstepFeed } from './lockstep-feed.ts'
import type { PlayerConnection } from './player-connection.ts'
import { RENAME, renameArgs } from './player-names.ts'
import { RoomPlayer } from './room-player.ts'
import { assignIdentity, type DepartedPlayer, playerColor } from './room-players.ts'
import { isRoomCommand, RoomScenes, roomCommandArgs } from './room-scenes.ts'
import { RoomSnapshots } from './room-snapshots.ts'
import { fillFrame, fullState, refreshPose, wireBody } from './room-wire.ts'

/** How many ticks' worth of inputs over the budget may wait for later ticks before refusals. */
export const WAITING_TICKS = 4

/** A queued input: who sent it, its sequence number and the validated command. */
interface QueuedInput {
  player: RoomPlayer
  seq: number
  cmd: SimCommand
}

/** One room: a simulation, its players, input queue, events and snapshots. */
export class Room {
  readonly sim: RoomSimulation
  /** Joined players by id, spectators included (RoomPlayer.spectator; playerCount counts the others). */
  readonly players = new Map<number, RoomPlayer>()
  /** Players in `players` that are not spectators. */
  playerCount = 0
  readonly departed = new Map<string, DepartedPlayer>()
  nextPlayerId = 1
  /** Room tick at which the last player left (for disposal), or -1 while occupied. */
  emptySince = 0
  /**
   * Whether a command was ever applied here (or the room was rebuilt from a log). An untouched
   * room is closed as soon as it is empty and its log removed: it holds nothing anyone made, and
   * a client that joins fresh names must not hold places under --max-rooms or push real
   * recordings out of --replay-keep (room-manager.ts disposeIdle, recordings.ts detach). A room
   * given a world from outside (a benchmark's blueprint) counts as touched.
   */
  touched = false
  /** Told to every player who joins (welcome.notice), e.g. that the room was restored after a restart; null: nothing. */
  notice: string | null = null
  /** Whether a player ever joined (an untouched room is closed early only once it had one). */
  visited = false
  readonly rules: RoomRules
  /** The tick stream, syncs and desync reports of lockstep and predict players. */
  readonly feed: LockstepFeed
  private queue: QueuedInput[] = []
  /** The other of the two queue arrays, swapped each tick (no new array per tick). */
  private spareQueue: QueuedInput[] = []
  /** The input being applied, so a body it spawns names its player and seq in `events`. */
  private applying: QueuedInput | null = null
  /** The room commands openScene and saveScene (room-scenes.ts). */
  private readonly sceneFiles: RoomScenes
  private events = {
    add: [] as WireBody[],
    remove: [] as number[],
    jadd: [] as WireJoint[],
    jremove: [] as number[],
  }
  /** Bodies a command changed this tick (ctx.bodyChanged), sent in events.change at its end. */
  private changed = new Set<number>()
  private roomChanged = false
  /** Events the game emitted this tick (ctx.emit), sent at its end to snapshot players. */
  private gameEvents: PlainData[] = []
  private readonly snapshotInterval: number
  /** Ticks with (tick + phase) % snapshotInterval === 0 send snapshots (see the constructor). */
  private readonly snapshotPhase: number
  /** Snapshots and the slow-reader rule (room-snapshots.ts). */
  private readonly snapshots: RoomSnapshots
  /** A game view that threw or was too big has been logged (once per room). */
  private viewWarned = false

  constructor(
    readonly name: string,
    readonly config: ServerConfig,
    readonly metrics: ServerMetrics,
    readonly log: Logger,
    /**
     * Where the room's periodic work falls on its manager's clock (room-manager.ts chooses it so
     * that rooms opened together do not pile their work onto the same ticks): the room's first
     * tick number, which fixes the clock ticks of its once-a-second checkpoints (room ticks that
     * are multiples of 60), and its snapshot phase (it sends on ticks where (tick + phase) is a
     * multiple of the snapshot interval).
     */
    spread: { startTick: number; snapshotPhase: number } = { startTick: 0, snapshotPhase: 0 },
    /** The game the room runs (fixed for the room's life). */
    readonly game: Game = sandbox,
  ) {
    this.snapshotInterval = TICK_RATE / config.snapshotRate
    this.snapshotPhase = spread.snapshotPhase % this.snapshotInterval
    this.sim = new RoomSimulation({
      game,
      name,
      scene: Object.hasOwn(SCENES, config.defaultScene) ? config.defaultScene : DEFAULT_SCENE,
      maxBodies: config.maxBodies,
      controls: config.roomControls,
      listener: this.listener(),
    })
    this.sim.tick = spread.startTick
    this.sceneFiles = new RoomScenes(
      config.sceneDir,
      config.maxSavedScenes,
      config.maxSavedSceneBytes,
      this.sim,
    )
    this.feed = new LockstepFeed(this.sim, name, metrics, log)
    this.snapshots = new RoomSnapshots(name, this.sim, this.players, config, metrics, log)
    this.rules = roomRules(game, {
      snapshotRate: config.snapshotRate,
      maxBodies: config.maxBodies,
      maxClients: config.maxClientsPerRoom,
      inputsPerTick: config.inputsPerTick,
      controls: config.roomControls,
      maxSpectators: config.maxSpectatorsPerRoom,
    })
  }

  /** Largest staleness (ticks) of a body write in the last snapshot round, for the benchmark. */
  get lastMaxStaleness(): number {
    return this.snapshots.lastMaxStaleness
  }

  /** The current world. */
  get world(): World {
    return this.sim.world
  }

  /** The current scene name. */
  get scene(): string {
    return this.sim.scene
  }

  /** The room tick. */
  get tick(): number {
    return this.sim.tick
  }

  /** Grabs per body id. */
  get grabCounts(): ReadonlyMap<number, number> {
    return this.sim.grabCounts
  }

  /**
   * Add a player and send its welcome; returns the player, or a reason when refused. `controls`
   * is false when the player's key does not allow room controls (an admin token it lacks): its
   * welcome then says `rules.controls` false, as the room will answer its controls.
   */
  join(
    conn: PlayerConnection,
    name: string,
    token: string | undefined,
    mode: JoinMode = 'snapshot',
    controls = true,
    game?: string,
    spectate = false,
  ): RoomPlayer | string {
    if (game !== undefined && game !== this.game.name)
      return `room ${this.name} runs the game ${this.game.name}, not ${game}`
    if (spectate) return this.joinSpectator(conn, name, mode, controls)
    if (this.playerCount >= this.config.maxClientsPerRoom) return `room ${this.name} is full`
    if (this.playerCount >= this.game.maxPlayers)
      return `room ${this.name} is full (${this.game.name} admits ${this.game.maxPlayers} players)`
    const identity = assignIdentity(this, token)
    if (identity.replaced) identity.replaced.conn.close(4000, 'replaced by a reconnect with the same token')
    const player = new RoomPlayer(
      identity.id,
      identity.name ?? (name.trim() || `player ${identity.id}`),
      identity.color ?? playerColor(identity.id),
      identity.token,
      this.name,
      conn,
    )
    player.lockstep = mode !== 'snapshot'
    this.players.set(player.id, player)
    this.playerCount++
    this.sim.join(player.id, player.name, player.color)
    this.welcome(player, controls)
    this.broadcast({ t: 'players', players: this.roster() })
    // The newcomer learns every cursor from the next snapshot.
    for (const p of this.players.values()) p.cursorDirty = true
    this.log.info({ room: this.name, player: player.id, name: player.name }, 'player joined')
    return player
  }

  /**
   * A spectator's join: an id of its own (from the players' sequence, so ids stay unique in the
   * room; never a player's, never reused by a reconnect), no simulation player, no roster entry,
   * no cursor; within --max-spectators. It is sent what a player in its mode is sent.
   */
  private joinSpectator(
    conn: PlayerConnection,
    name: string,
    mode: JoinMode,
    controls: boolean,
  ): RoomPlayer | string {
    const watching = this.players.size - this.playerCount
    if (watching >= this.config.maxSpectatorsPerRoom)
      return `room ${this.name} has its ${this.config.maxSpectatorsPerRoom} spectators (--max-spectators)`
    const id = this.nextPlayerId++
    const spectator = new RoomPlayer(id, name.trim() || `spectator ${id}`, '#808080', '', this.name, conn)
    spectator.spectator = true
    spectator.lockstep = mode !== 'snapshot'
    this.players.set(id, spectator)
    this.welcome(spectator, controls)
    this.log.info({ room: this.name, spectator: id, name: spectator.name }, 'spectator joined')
    return spectator
  }

  /** Send a newcomer its welcome (a lockstep one's sync follows at the end of this tick). */
  private welcome(player: RoomPlayer, controls: boolean): void {
    const conn = player.conn
    if (player.lockstep) this.feed.add(player.id, conn)
    this.emptySince = -1
    this.visited = true
    const frame = new QuantizedFrame()
    fillFrame(this.world, frame)
    player.encoder.reset(frame, this.tick)
    conn.send({
      t: 'welcome',
      v: PROTOCOL_VERSION,
      id: player.id,
      token: player.token,
      room: this.name,
      rules: controls || !this.rules.controls ? this.rules : { ...this.rules, controls: false },
      players: this.roster(),
      state: fullState(
        this.world,
        this.tick,
        this.scene,
        this.sim.paused,
        this.sim.userJoints.values(),
        this.sim.bodyColors,
        { slow: this.sim.slowMotion, creator: this.sim.creator, locked: this.sim.controlsLocked },
      ),
      ...(this.notice === null ? {} : { notice: this.notice }),
    })
  }

  /** Remove a player: release its grab, keep its identity for the reconnect window. */
  leave(player: RoomPlayer): void {
    if (this.players.get(player.id) !== player) return
    if (player.spectator) {
      this.feed.remove(player.id)
      player.joined = false
      this.players.delete(player.id)
      if (this.players.size === 0) this.emptySince = this.tick
      this.log.info({ room: this.name, spectator: player.id }, 'spectator left')
      return
    }
    this.playerCount--
    this.sim.leave(player.id)
    this.feed.remove(player.id)
    player.joined = false
    player.inspect = 0
    this.players.delete(player.id)
    this.departed.set(player.token, {
      id: player.id,
      name: player.name,
      color: player.color,
      leftTick: this.tick,
    })
    if (this.players.size === 0) this.emptySince = this.tick
    this.broadcast({ t: 'players', players: this.roster() })
    this.log.info({ room: this.name, player: player.id }, 'player left')
  }

  /** The roster for welcome and players messages. */
  roster(): Array<{ id: number; name: string; color: string }> {
    const roster: Array<{ id: number; name: string; color: string }> = []
    for (const p of this.players.values())
      if (!p.spectator) roster.push({ id: p.id, name: p.name, color: p.color })
    return roster
  }

  /**
   * Queue an input for the next tick; returns an error reason when the budget is spent. A move
   * replaces the same player's move already queued (only the latest cursor position matters), so
   * fast mice never use up the budget. Inputs over a tick's budget wait, in order, for the next
   * ticks (up to WAITING_TICKS ticks' worth), so a burst after a network or server hiccup loses
   * nothing; only beyond that is an input refused.
   */
  queueInput(player: RoomPlayer, seq: number, cmd: SimCommand): string | null {
    const budget = this.config.inputsPerTick
    const waiting = player.waiting
    if (cmd.k === 'move') {
      const last = waiting[waiting.length - 1]
      if (last?.cmd.k === 'move') {
        last.seq = seq
        last.cmd = cmd
        return null
      }
      if (waiting.length === 0 && player.queuedMove >= 0) {
        const queued = this.queue[player.queuedMove]
        queued.seq = seq
        queued.cmd = cmd
        return null
      }
    }
    if (waiting.length === 0 && player.inputsThisTick < budget) {
      this.enqueue(player, seq, cmd)
      return null
    }
    if (waiting.length >= budget * WAITING_TICKS) {
      return `input budget exceeded: at most ${budget} inputs per tick, ${budget * WAITING_TICKS} more waiting`
    }
    waiting.push({ seq, cmd })
    return null
  }

  /**
   * Check a game command (`cmd` message) against the room's game, then queue it like an input:
   * an unknown kind or arguments that do not fit the game's schema are refused here, naming the
   * field, before the game sees them; the input budget applies as to every input.
   */
  queueGameCommand(
    player: RoomPlayer,
    seq: number,
    kind: string,
    args: PlainData,
  ): { code: 'invalid' | 'input-budget'; reason: string } | null {
    if (kind === RENAME) {
      const checked = renameArgs(args)
      if ('error' in checked) return { code: 'invalid', reason: `rename refused: ${checked.error}` }
      const error = this.queueInput(player, seq, { k: 'cmd', kind, a: checked })
      return error === null ? null : { code: 'input-budget', reason: error }
    }
    if (isRoomCommand(kind)) {
      const invalid = roomCommandArgs(kind, args)
      if (invalid !== null) return { code: 'invalid', reason: `${kind} refused: ${invalid}` }
      const error = this.queueInput(player, seq, { k: 'cmd', kind, a: args })
      return error === null ? null : { code: 'input-budget', reason: error }
    }
    const def = Object.hasOwn(this.game.commands, kind) ? this.game.commands[kind] : undefined
    if (!def || def.builtin)
      return { code: 'invalid', reason: `game ${this.game.name} has no ${kind} command` }
    const invalid = def.check(args)
    if (invalid !== null) return { code: 'invalid', reason: `${kind} refused: ${invalid}` }
    const error = this.queueInput(player, seq, { k: 'cmd', kind, a: args })
    return error === null ? null : { code: 'input-budget', reason: error }
  }

  private enqueue(player: RoomPlayer, seq: number, cmd: SimCommand): void {
    player.inputsThisTick++
    if (cmd.k === 'move') player.queuedMove = this.queue.length
    this.queue.push({ player, seq, cmd })
  }

  /** Run one tick (see the file comment). */
  runTick(): void {
    const queue = this.queue
    this.queue = this.spareQueue
    for (let i = 0; i < queue.length; i++) {
      const input = queue[i]
      if (this.players.get(input.player.id) !== input.player) continue
      this.applying = input
      const error = this.apply(input.player, input.cmd)
      this.applying = null
      if (error) input.player.conn.sendError('refused', error, input.seq)
    }
    queue.length = 0
    this.spareQueue = queue
    for (const p of this.players.values()) {
      p.inputsThisTick = 0
      p.queuedMove = -1
      // Waiting inputs go first into the next tick's budget, ahead of anything sent later.
      const take = Math.min(p.waiting.length, this.config.inputsPerTick)
      if (take === 0) continue
      for (let i = 0; i < take; i++) this.enqueue(p, p.waiting[i].seq, p.waiting[i].cmd)
      p.waiting.splice(0, take)
    }
    this.sim.runTick()
    this.flushEvents()
    if ((this.tick + this.snapshotPhase) % this.snapshotInterval === 0) {
      this.snapshots.send()
      this.sendViews()
    }
    const hash = this.tick % TICK_RATE === 0 ? this.sim.hash() : undefined
    if (hash !== undefined) this.everySecond(hash)
    this.feed.endTick(hash)
  }

  /** Replace the world with a scene blueprint (benchmarks use sizes SCENES does not list). */
  loadBlueprint(name: string, blueprint: SceneBlueprint): void {
    const built = worldFromBlueprint(blueprint)
    this.sim.loadWorld(name, built.world, built.joints)
    this.touched = true
  }

  /** Encode once, send to every player. */
  broadcast(message: ServerMessage): void {
    if (this.players.size === 0) return
    const bytes = encodeMessage(message)
    for (const p of this.players.values()) p.conn.sendBytes(bytes)
  }

  /** Encode once, send to every snapshot-mode player (lockstep players simulate these themselves). */
  private broadcastSnapshotMode(message: ServerMessage): void {
    let bytes: Uint8Array | null = null
    for (const p of this.players.values()) {
      if (p.lockstep) continue
      bytes ??= encodeMessage(message)
      p.conn.sendBytes(bytes)
    }
  }

  /** Close every player with a reason. */
  closeAll(code: number, reason: string): void {
    for (const p of this.players.values()) p.conn.close(code, reason)
  }

  private apply(player: RoomPlayer, cmd: SimCommand): string | null {
    if (cmd.k === 'cmd' && cmd.kind === RENAME) return this.rename(player, (cmd.a as { name: string }).name)
    if (cmd.k === 'cmd' && isRoomCommand(cmd.kind)) return this.applyRoomCommand(player, cmd.kind, cmd.a)
    if (cmd.k !== 'inspect') {
      const refused = this.sim.apply(player.id, cmd)
      if (refused === null) this.touched = true
      return refused
    }
    // Inspecting only chooses what this player is sent: the world does not change, nothing is recorded.
    if (cmd.body !== 0 && !isMovable(this.world, cmd.body))
      return `body ${cmd.body} does not exist or is static`
    player.inspect = cmd.body
    return null
  }

  /** The room command `rename` (player-names.ts): a new name, and every player the new roster. */
  private rename(player: RoomPlayer, name: string): null {
    if (player.name === name) return null
    this.log.info({ room: this.name, player: player.id, from: player.name, name }, 'player renamed')
    player.name = name
    this.broadcast({ t: 'players', players: this.roster() })
    return null
  }

  /** A room command (room-scenes.ts): open a saved scene, or save the world and tell the sender its id. */
  private applyRoomCommand(player: RoomPlayer, kind: string, args: PlainData): string | null {
    if (kind === 'openScene') {
      const id = (args as { id: string }).id
      const refused = this.sceneFiles.open(
        id,
        this.config.roomControls,
        Object.hasOwn(this.game.commands, 'scene'),
      )
      if (refused === null) this.touched = true
      return refused
    }
    const saved = this.sceneFiles.save(this.name)
    if ('error' in saved) return saved.error
    player.conn.send({ t: 'scene', seq: this.applying?.seq ?? 0, id: saved.id })
    return null
  }

  /** The simulation's side effects, as this tick's events. */
  private listener(): SimulationListener {
    return {
      bodyAdded: (id) => {
        const body = wireBody(this.sim.world, id, this.sim.bodyColors)
        const input = this.applying
        if (input?.cmd.k === 'spawn') {
          body.player = input.player.id
          body.seq = input.seq
        }
        this.events.add.push(body)
      },
      bodyRemoved: (id) => {
        for (const p of this.players.values()) {
          if (p.inspect === id) p.inspect = 0
          p.encoder.removeBody(id)
        }
        this.events.remove.push(id)
      },
      bodyChanged: (id) => {
        this.changed.add(id)
        // A body made static leaves snapshots, as a removed one does (a moving one comes back absolute).
        if (this.sim.world.getBodyType(id) === 'static')
          for (const p of this.players.values()) p.encoder.removeBody(id)
      },
      jointAdded: (joint) => this.events.jadd.push(joint),
      jointRemoved: (id) => this.events.jremove.push(id),
      roomChanged: () => {
        this.roomChanged = true
      },
      cursorChanged: (id) => {
        const p = this.players.get(id)
        if (p) p.cursorDirty = true
      },
      worldReplaced: () => this.sendNewWorld(),
      gameEvent: (_tick, event) => this.gameEvents.push(event),
      gameFailed: (tick, message) =>
        this.log.warn({ room: this.name, game: this.game.name, tick }, `${message}; the room is paused`),
    }
  }

  /** After a scene load: drop the old world's events, send everyone the new full state. */
  private sendNewWorld(): void {
    this.events = { add: [], remove: [], jadd: [], jremove: [] }
    this.changed.clear()
    const frame = new QuantizedFrame()
    fillFrame(this.world, frame)
    const bytes = encodeMessage({
      t: 'state',
      state: fullState(
        this.world,
        this.tick,
        this.scene,
        this.sim.paused,
        this.sim.userJoints.values(),
        this.sim.bodyColors,
        { slow: this.sim.slowMotion, creator: this.sim.creator, locked: this.sim.controlsLocked },
      ),
    })
    for (const p of this.players.values()) {
      p.inspect = 0
      p.encoder.reset(frame, this.tick)
      if (!p.lockstep) p.conn.sendBytes(bytes)
    }
    this.log.info({ room: this.name, scene: this.scene }, 'scene loaded')
  }

  /**
   * This tick's changed bodies as they travel, ascending ids: a body also added this tick has its
   * `add` entry rebuilt instead (spawner kept), and a body removed since is left out.
   */
  private changedBodies(): WireBody[] {
    if (this.changed.size === 0) return []
    const out: WireBody[] = []
    const ids = [...this.changed].sort((a, b) => a - b)
    this.changed.clear()
    for (const id of ids) {
      if (!this.world.hasBody(id)) continue
      const fresh = wireBody(this.world, id, this.sim.bodyColors)
      const added = this.events.add.findIndex((b) => b.id === id)
      if (added < 0) {
        out.push(fresh)
        continue
      }
      const old = this.events.add[added]
      if (old.player !== undefined) {
        fresh.player = old.player
        fresh.seq = old.seq
      }
      this.events.add[added] = fresh
    }
    return out
  }

  private flushEvents(): void {
    const e = this.events
    const change = this.changedBodies()
    if (e.add.length + e.remove.length + e.jadd.length + e.jremove.length + change.length > 0) {
      // New bodies are shown as they are at this tick, after its step (as a snapshot of it would).
      for (const body of e.add) refreshPose(this.world, body)
      this.broadcastSnapshotMode(
        change.length > 0
          ? { t: 'events', tick: this.tick, ...e, change }
          : { t: 'events', tick: this.tick, ...e },
      )
      this.events = { add: [], remove: [], jadd: [], jremove: [] }
    }
    if (this.gameEvents.length > 0) {
      this.broadcastSnapshotMode({ t: 'game', tick: this.tick, events: this.gameEvents })
      this.gameEvents = []
    }
    if (this.roomChanged) {
      const g = this.world.getGravity()
      this.broadcastSnapshotMode({
        t: 'room',
        tick: this.tick,
        paused: this.sim.paused,
        gravity: [g.x, g.y],
        scene: this.scene,
        slow: this.sim.slowMotion,
        creator: this.sim.creator,
        locked: this.sim.controlsLocked,
      })
      this.roomChanged = false
    }
  }

  /**
   * Each snapshot player's game view (the game's `view`), sent to that player alone when its
   * MessagePack bytes changed since the last one it got (PROTOCOL.md, `view`). A view that throws
   * or passes MAX_VIEW_BYTES is not sent, and logged once per room. A game without `view` sends
   * its whole state instead (sendStateViews).
   */
  private sendViews(): void {
    if (!this.game.view) {
      this.sendStateViews()
      return
    }
    for (const p of this.players.values()) {
      if (p.lockstep || p.spectator || p.dropped) continue
      let view: PlainData | undefined
      try {
        view = this.sim.playerView(p.id)
      } catch (error) {
        this.viewProblem(p.id, `its view threw: ${(error as Error).message}`)
        continue
      }
      if (view === undefined) continue
      const bytes = encodeValue(view)
      if (bytes.length > MAX_VIEW_BYTES) {
        this.viewProblem(p.id, `its view is ${bytes.length} bytes, over the ${MAX_VIEW_BYTES}-byte limit`)
        continue
      }
      if (p.lastView !== null && sameBytes(p.lastView, bytes)) continue
      p.lastView = bytes
      p.conn.sendBytes(encodeMessage({ t: 'view', tick: this.tick, view }))
    }
  }

  /**
   * The default view of a game without `view`: its whole state, the same for every snapshot
   * player, encoded once per snapshot tick and sent to each player whose last view differs. A
   * state over MAX_VIEW_BYTES is not sent, and logged once per room naming the fix (a `view`).
   */
  private sendStateViews(): void {
    const state = this.sim.gameState
    if (state === undefined) return
    const bytes = encodeValue(state)
    if (bytes.length > MAX_VIEW_BYTES) {
      this.viewProblem(
        undefined,
        `it has no view, so its view is its whole state, and the state is ${bytes.length} bytes, over the ${MAX_VIEW_BYTES}-byte limit (give the game a view(ctx, player) that returns less)`,
      )
      return
    }
    let frame: Uint8Array | null = null
    for (const p of this.players.values()) {
      if (p.lockstep || p.spectator || p.dropped) continue
      if (p.lastView !== null && sameBytes(p.lastView, bytes)) continue
      p.lastView = bytes
      frame ??= encodeMessage({ t: 'view', tick: this.tick, view: state })
      p.conn.sendBytes(frame)
    }
  }

  private viewProblem(player: number | undefined, problem: string): void {
    if (this.viewWarned) return
    this.viewWarned = true
    this.log.warn(
      { room: this.name, game: this.game.name, player, tick: this.tick },
      `game ${this.game.name}: ${problem}; the view is not sent (logged once per room)`,
    )
  }

  private everySecond(hash: number): void {
    this.broadcastSnapshotMode({ t: 'hash', tick: this.tick, step: this.world.tick, hash })
    const window = this.config.reconnectSeconds * TICK_RATE
    for (const [token, d] of this.departed) if (this.tick - d.leftTick > window) this.departed.delete(token)
  }
}

function sameBytes(a: Uint8Array, b: Uint8Array): boolean {
  if (a.length !== b.length) return false
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false
  return true
}
