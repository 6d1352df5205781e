/*
 * The deterministic part of a room: the game it runs (game.ts: SimGame, written with games/'s
 * defineGame), the world, its scene, pause and single-step state, the room tick, each player's
 * grab and cursor, the user joints (pins and ropes), grab counts, the time of the last scene load,
 * the game's state and its seeded PRNG. Everything that changes the world goes through here, in an
 * order the caller decides (the server's Room: joins, leaves and the tick's queued commands, then
 * tick()). What a command does is the game's: apply() finds it in the game's commands, checks its
 * arguments and runs it with a GameContext, whose primitives (spawn, grab, joints, scene loads,
 * pause) are the engine-level rules every game shares.
 *
 * Pure: no Node APIs, no clocks, no randomness; it runs in the server, in lockstep clients and in
 * the replay player. Two RoomSimulations built with the same options that see the same joins,
 * leaves, accepted commands and external world loads at the same ticks stay bit-identical
 * (hash(): the world's hash, mixed with the game's state and PRNG for a game that keeps state);
 * that is what recording and replay rely on.
 *
 * Two hooks report what happened:
 *   - the listener (the owner, one): world side effects to turn into wire events
 *   - observers (any number: a recorder, a lockstep stream): every state change in applied order,
 *     only commands that were accepted (a refused command changes nothing); `inspect` is not a
 *     simulation command and is refused here (the server's Room handles it itself)
 * A refused command returns a reason; nothing here throws to the caller. A game command that
 * throws may have changed the state before it threw, so it counts as applied (observers see it,
 * every replica throws the same way) and its sender gets "<kind> failed: <message>"; a game tick
 * that throws pauses the room and is reported to the listener (gameFailed).
 */
import {
  createWorld,
  type JointSettings,
  Prng,
  SCENES,
  type SceneBlueprint,
  type World,
} from '../../engine/index.ts'
import {
  buildSceneJoints,
  KILL_DISTANCE,
  KILL_PLANE_Y,
  type PinCommand,
  playerBodyColor,
  type RopeCommand,
  type SpawnCommand,
  TICK_RATE,
  type WireJoint,
  type WireJointDef,
  withJointSettings,
} from '../protocol/index.ts'
import {
  colorsHash,
  copyPlainData,
  type GameContext,
  NO_EVENTS,
  type PlainData,
  type SimCommand,
  type SimGame,
  type StepEvents,
  simulationHash,
  stepEvents,
} from './game.ts'
import { Histories, type SavedHistory } from './history.ts'
import {
  addUserJoint,
  createUserJoint,
  grabBody,
  grabRefusal,
  jointRefusal,
  moveGrab,
  removeJoint,
  setWorldGravity,
  spawnBody,
} from './world-commands.ts'

/** The PRNG seed of a room whose options give none. */
export const DEFAULT_SEED = 0x2f6b3a1d

/** A player's grab: its own mouse joint on a body. */
export interface Grab {
  joint: number
  body: number
}

/** A player's simulation state: grab and cursor (m). */
export interface SimPlayer {
  grab: Grab | null
  cursorX: number
  cursorY: number
}

/** Everything besides the world that a resumed simulation needs (a keyframe's state). */
export interface SimulationState {
  tick: number
  scene: string
  paused: boolean
  stepRequested: boolean
  /** The world steps on room ticks that are multiples of this (1, 2 or 4; slow motion); absent: 1. */
  slowMotion?: number
  /** The first player who joined the room (0 before anyone did), and whether it locked the controls. */
  creator?: number
  controlsLocked?: boolean
  /** Room tick of the last scene load or reset, or null for never. */
  lastLoadTick: number | null
  /** Players in join order, with their grabs and cursors. */
  players: Array<{ id: number; grab: Grab | null; cursorX: number; cursorY: number }>
  /** User joints in creation order. */
  userJoints: WireJoint[]
  /** The game's name, its state (null for a game without state) and its PRNG position. */
  game: string
  gameState: PlainData
  random: number
  /** Body colours, flat [body id, 0xRRGGBB, ...] in ascending ids (absent in states saved before colours). */
  colors?: number[]
  /** The players' undo and redo histories (history.ts; absent in states saved before them: none). */
  history?: SavedHistory[]
}

/** World side effects, for the owner to turn into wire events. Called synchronously. */
export interface SimulationListener {
  bodyAdded(id: number): void
  bodyRemoved(id: number): void
  /** A command changed an existing body's shapes, material, colour, type or pose (ctx.bodyChanged). */
  bodyChanged?(id: number): void
  jointAdded(joint: WireJoint): void
  jointRemoved(id: number): void
  /** Pause, gravity or scene changed. */
  roomChanged(): void
  /** A player's cursor or grab changed. */
  cursorChanged(playerId: number): void
  /** The world was replaced (scene load, reset, external load); grabs and user joints are gone. */
  worldReplaced(): void
  /** The game emitted an event (ctx.emit) at room tick `tick`. */
  gameEvent?(tick: number, event: PlainData): void
  /** The game's tick threw: the room is now paused. */
  gameFailed?(tick: number, message: string): void
}

/** Every state change in applied order: what a recorder or a lockstep stream needs. */
export interface SimulationObserver {
  /** An accepted command, just applied at room tick `tick` (before that tick's step). */
  command(tick: number, playerId: number, cmd: SimCommand): void
  /** A tick ended: the world stepped (unless paused) and the room tick is now `tick`. */
  ticked?(tick: number): void
  join(tick: number, playerId: number, name: string, color: string): void
  leave(tick: number, playerId: number): void
  /** The world was replaced from outside a command (a benchmark blueprint, a restored keyframe). */
  worldLoaded(tick: number, scene: string): void
}

/** Room rules that change what commands may do. */
export interface SimulationOptions {
  /** The game the room runs (games/'s catalogue). */
  game: SimGame
  /** Seed of the game's PRNG (DEFAULT_SEED when absent). */
  seed?: number
  /** Body limit (also the user joint limit). */
  maxBodies: number
  /** Whether the game's room controls (the sandbox's scene, pause, step, reset, gravity) are allowed. */
  controls: boolean
  /** Initial scene name (a key of SCENES), for a game whose setup loads the room's scene. */
  scene: string
  /** Room name, for refusal reasons. */
  name: string
  listener?: SimulationListener
}

const NO_LISTENER: SimulationListener = {
  bodyAdded: () => {},
  bodyRemoved: () => {},
  jointAdded: () => {},
  jointRemoved: () => {},
  roomChanged: () => {},
  cursorChanged: () => {},
  worldReplaced: () => {},
}

/**
 * The movable bodies that have left the world: below the kill plane (KILL_PLANE_Y), beyond
 * KILL_DISTANCE, or with a non-finite position. Rooms remove them once a second (with a removal
 * event), the offline page's room too.
 */
export function strayBodies(world: World): number[] {
  const p = { x: 0, y: 0 }
  const out: number[] = []
  for (const id of world.bodyIds()) {
    if (world.getBodyType(id) === 'static') continue
    world.getPosition(id, p)
    if (!(Math.abs(p.x) <= KILL_DISTANCE) || !(Math.abs(p.y) <= KILL_DISTANCE) || !(p.y >= KILL_PLANE_Y))
      out.push(id)
  }
  return out
}

/** A world built from a scene blueprint, with the scene's joints as they travel. */
export function worldFromBlueprint(blueprint: SceneBlueprint): { world: World; joints: WireJoint[] } {
  const world = createWorld()
  const joints = buildSceneJoints(world, blueprint)
  return { world, joints }
}

/** The deterministic room (see the file comment). */
export class RoomSimulation {
  world: World
  scene: string
  paused = false
  stepRequested = false
  /** Slow motion: the world steps only on room ticks that are multiples of this (1, 2 or 4). */
  slowMotion = 1
  /** The first player who ever joined this room, 0 before anyone did; only it may lock the controls. */
  creator = 0
  /** Whether the creator locked the room controls to itself (released when it leaves). */
  controlsLocked = false
  /** The room tick: one more every tick, never reset (a server room starts at a tick below 60 that spreads its checkpoints; world.tick counts the current world's steps). */
  tick = 0
  /** Room tick of the last scene load or reset (they are rate limited). */
  lastLoadTick = Number.NEGATIVE_INFINITY
  /** Players by id, in join order. */
  readonly players = new Map<number, SimPlayer>()
  /** Joints on the wire by joint id: the scene's and players' pins and ropes (grabs are not here). */
  readonly userJoints = new Map<number, WireJoint>()
  /** Grabs per body id. */
  readonly grabCounts = new Map<number, number>()
  /**
   * Colours (0xRRGGBB) of the bodies players spawned, by body id: saved, synced and hashed with
   * the world. A static body with a colour was made by a player, and players may delete it.
   */
  readonly bodyColors = new Map<number, number>()
  /** Each player's undo and redo history (history.ts): saved, synced and hashed with the world. */
  readonly history = new Histories()
  /**
   * How many times a command changed a body in place (ctx.bodyChanged): not state (not saved or
   * hashed), a cue for views that cache bodies' shapes (the lockstep page) to read them again.
   */
  bodyEdits = 0
  readonly observers: SimulationObserver[] = []
  readonly maxBodies: number
  readonly controls: boolean
  readonly name: string
  /** The game this room runs. */
  readonly game: SimGame
  /** The game's state (plain data; undefined for a game without state). */
  gameState: PlainData | undefined
  /** The game's PRNG. */
  random: Prng
  /** The owner's listener (none while the game's setup builds the first world). */
  private listener: SimulationListener = NO_LISTENER
  /** What the game sees (one object per simulation; see context()). */
  private readonly ctx: GameContext
  private events: StepEvents = NO_EVENTS
  /** Ids of the players in join order, rebuilt on join and leave. */
  private playerIds: readonly number[] = []
  /** Whether the command being applied has been passed to the observers already. */
  private told = false

  constructor(options: SimulationOptions) {
    if (!Object.hasOwn(SCENES, options.scene)) throw new RangeError(`unknown scene "${options.scene}"`)
    this.game = options.game
    this.maxBodies = options.maxBodies
    this.controls = options.controls
    this.name = options.name
    this.scene = options.scene
    this.world = createWorld()
    this.random = new Prng(options.seed ?? DEFAULT_SEED)
    this.gameState = this.game.initialState()
    this.ctx = this.context()
    this.game.setup(this.ctx, { scene: options.scene })
    // Building the first world is not a scene load: the first `scene` command is not rate limited.
    this.lastLoadTick = Number.NEGATIVE_INFINITY
    this.listener = options.listener ?? NO_LISTENER
  }

  /** The simulation hash: world.hash() for a game without state, else mixed with its state and PRNG. */
  hash(): number {
    const worldHash = this.world.hash()
    const hash =
      this.gameState === undefined
        ? worldHash
        : simulationHash(worldHash, this.random.position(), this.gameState)
    const colored = this.bodyColors.size === 0 ? hash : colorsHash(hash, this.colorList())
    return this.history.empty ? colored : this.history.mixInto(colored)
  }

  /** Body colours as flat [body id, 0xRRGGBB, ...], ascending ids. */
  colorList(): number[] {
    const ids = [...this.bodyColors.keys()].sort((a, b) => a - b)
    const out: number[] = []
    for (const id of ids) out.push(id, this.bodyColors.get(id) as number)
    return out
  }

  /** Replace the body colours from a flat [body id, 0xRRGGBB, ...] list. */
  setColors(colors: readonly number[]): void {
    this.bodyColors.clear()
    for (let i = 0; i + 1 < colors.length; i += 2) this.bodyColors.set(colors[i], colors[i + 1])
  }

  /** Why a player cannot join (the game is full), or null. */
  joinRefusal(playerId: number): string | null {
    if (this.players.has(playerId) || this.players.size < this.game.maxPlayers) return null
    return `game ${this.game.name} is full (${this.game.maxPlayers} players)`
  }

  /** Add a player (or bring one back after a reconnect); returns a reason when the game is full. */
  join(playerId: number, name: string, color: string): string | null {
    const refusal = this.joinRefusal(playerId)
    if (refusal) return refusal
    const rejoin = this.players.has(playerId)
    if (this.creator === 0) this.creator = playerId
    this.players.set(playerId, { grab: null, cursorX: 0, cursorY: 0 })
    this.playerIds = Object.freeze([...this.players.keys()])
    for (const o of this.observers) o.join(this.tick, playerId, name, color)
    if (!rejoin) this.game.onJoin?.(this.ctx, playerId)
    return null
  }

  /**
   * Put a player back from a saved room (a sync payload, a clone) without telling anyone; players
   * must be restored in join order, which is the order ctx.players gives the game.
   */
  restorePlayer(playerId: number, player: SimPlayer): void {
    this.players.set(playerId, player)
    this.playerIds = Object.freeze([...this.players.keys()])
  }

  /** Remove a player, releasing its grab. */
  leave(playerId: number): void {
    const player = this.players.get(playerId)
    if (!player) return
    this.release(playerId, player)
    if (playerId === this.creator && this.controlsLocked) {
      this.controlsLocked = false
      this.listener.roomChanged()
    }
    this.game.onLeave?.(this.ctx, playerId)
    this.history.forget(playerId)
    this.players.delete(playerId)
    this.playerIds = Object.freeze([...this.players.keys()])
    for (const o of this.observers) o.leave(this.tick, playerId)
  }

  /**
   * Apply one command from a player at the current tick; returns a reason when refused, or when a
   * game command threw (it counts as applied then: see the file comment and applyAccepted).
   */
  apply(playerId: number, cmd: SimCommand): string | null {
    this.told = false
    const player = this.players.get(playerId)
    if (!player) return `player ${playerId} is not in this room`
    if (cmd.k === 'inspect') return 'inspect is not a simulation command'
    const custom = cmd.k === 'cmd'
    const kind = custom ? cmd.kind : cmd.k
    const def = Object.hasOwn(this.game.commands, kind) ? this.game.commands[kind] : undefined
    if (!def || def.builtin === custom) return `game ${this.game.name} has no ${kind} command`
    if (def.control && !this.controls) return `room controls are disabled in room ${this.name}`
    if (def.control && this.controlsLocked && playerId !== this.creator)
      return `room controls are locked by the room's creator (player ${this.creator})`
    const args = custom ? cmd.a : cmd
    const invalid = def.check(args)
    if (invalid !== null) return `${kind} refused: ${invalid}`
    let error: string | null
    try {
      const result = def.apply(this.ctx, playerId, args)
      error = typeof result === 'string' ? result : null
    } catch (e) {
      // Game code may have changed the state before it threw: everyone applies it and throws alike.
      this.tell(playerId, cmd)
      return `${kind} failed: ${(e as Error).message}`
    }
    if (error === null) this.tell(playerId, cmd)
    return error
  }

  /**
   * Apply a command that the room applied (a replayed or streamed one): null when it applied as
   * it did there (also when game code threw, as it did there), else why it was refused here.
   */
  applyAccepted(playerId: number, cmd: SimCommand): string | null {
    const error = this.apply(playerId, cmd)
    return this.told ? null : error
  }

  /**
   * Run one tick: step unless paused (or a step was requested) or slowed (in slow motion the world
   * steps only on room ticks that are multiples of slowMotion, counted before this tick's
   * increment), then the game's tick, housekeeping.
   */
  runTick(): void {
    const step = this.stepsNextTick()
    if (step) {
      this.world.step()
      this.removeBrokenJoints()
    }
    this.stepRequested = false
    this.tick++
    if (step && this.game.tick) this.runGameTick(this.game.tick)
    if (this.tick % TICK_RATE === 0) this.sweep()
    for (const o of this.observers) o.ticked?.(this.tick)
  }

  /**
   * Whether the next runTick steps the world: not paused (or a single step was requested) and, in
   * slow motion, a room tick that is a multiple of slowMotion. A page that draws between the last
   * two steps keeps the poses before a tick that will step.
   */
  stepsNextTick(): boolean {
    return (!this.paused && this.tick % this.slowMotion === 0) || this.stepRequested
  }

  /** Replace the world with a fresh copy of a named scene (SCENES). */
  loadScene(name: string): void {
    const built = worldFromBlueprint(SCENES[name].make())
    this.replaceWorld(name, built.world, built.joints)
  }

  /**
   * Replace the world from outside a command (a benchmark's blueprint, a restored world): observers
   * see it as a world load so a recording stays reproducible. `joints` are the world's joints as
   * they travel (worldFromBlueprint gives them), none for a world restored from bytes; `colors` its
   * bodies' colours, flat [body id, 0xRRGGBB, ...] (a scene file's).
   */
  loadWorld(
    scene: string,
    world: World,
    joints: Iterable<WireJoint> = [],
    colors: readonly number[] = [],
  ): void {
    this.replaceWorld(scene, world, joints, colors)
    for (const o of this.observers) o.worldLoaded(this.tick, scene)
  }

  /** This simulation's state besides the world (save the world with world.save()). */
  saveState(): SimulationState {
    return {
      tick: this.tick,
      scene: this.scene,
      paused: this.paused,
      stepRequested: this.stepRequested,
      slowMotion: this.slowMotion,
      creator: this.creator,
      controlsLocked: this.controlsLocked,
      lastLoadTick: Number.isFinite(this.lastLoadTick) ? this.lastLoadTick : null,
      players: [...this.players].map(([id, p]) => ({
        id,
        grab: p.grab ? { ...p.grab } : null,
        cursorX: p.cursorX,
        cursorY: p.cursorY,
      })),
      userJoints: [...this.userJoints.values()].map((j) => ({ ...j })),
      game: this.game.name,
      gameState: this.gameState === undefined ? null : copyPlainData(this.gameState),
      random: this.random.position(),
      colors: this.colorList(),
      history: this.history.save(),
    }
  }

  /**
   * Resume from a saved state and world (a keyframe): afterwards this simulation steps exactly as
   * the one that saved them. Observers are not told (the state came from them); the listener sees a
   * replaced world. Throws a RangeError for another game's state.
   */
  restoreState(state: SimulationState, world: World): void {
    if (state.game !== this.game.name)
      throw new RangeError(`a state of game ${state.game} cannot resume a ${this.game.name} room`)
    this.tick = state.tick
    this.scene = state.scene
    this.paused = state.paused
    this.stepRequested = state.stepRequested
    this.slowMotion = state.slowMotion ?? 1
    this.creator = state.creator ?? 0
    this.controlsLocked = state.controlsLocked ?? false
    this.lastLoadTick = state.lastLoadTick ?? Number.NEGATIVE_INFINITY
    this.world = world
    this.players.clear()
    this.grabCounts.clear()
    for (const p of state.players) {
      this.players.set(p.id, { grab: p.grab ? { ...p.grab } : null, cursorX: p.cursorX, cursorY: p.cursorY })
      if (p.grab) this.grabCounts.set(p.grab.body, (this.grabCounts.get(p.grab.body) ?? 0) + 1)
    }
    this.playerIds = Object.freeze([...this.players.keys()])
    this.userJoints.clear()
    for (const j of state.userJoints) this.userJoints.set(j.id, { ...j })
    this.restoreGame(state.gameState, state.random)
    this.setColors(state.colors ?? [])
    this.history.restore(state.history ?? [])
    this.listener.worldReplaced()
    this.listener.roomChanged()
  }

  /**
   * The game's view for `player` (SimGame.view): a copy of the plain data it returns; for a game
   * without a view, a copy of the whole game state (the default view, the same for every player);
   * undefined for a game with neither, or a player not in the room. Throws what the view throws,
   * or a RangeError naming what in it is not plain data.
   */
  playerView(player: number): PlainData | undefined {
    if (!this.players.has(player)) return undefined
    const view = this.game.view
    if (!view) return this.gameState === undefined ? undefined : copyPlainData(this.gameState)
    return copyPlainData(view(this.ctx, player), 'view')
  }

  /** Set the game's state and PRNG position from saved values (null state: a game without state). */
  restoreGame(gameState: PlainData, random: number): void {
    this.gameState = this.game.initialState() === undefined ? undefined : copyPlainData(gameState)
    this.random = new Prng(random)
  }

  /** Destroy a body and everything attached to it (grabs, user joints). */
  removeBody(id: number): void {
    for (const [jid, j] of this.userJoints) {
      if (j.a === id || j.b === id) {
        this.userJoints.delete(jid)
        this.listener.jointRemoved(jid)
      }
    }
    for (const [pid, p] of this.players) {
      if (p.grab?.body === id) {
        p.grab = null
        this.listener.cursorChanged(pid)
      }
    }
    this.grabCounts.delete(id)
    this.bodyColors.delete(id)
    this.world.destroyBody(id)
    this.listener.bodyRemoved(id)
  }

  /** The step's broken joints (world.jointEvents(), ascending ids) leave the user joints, as a removal. */
  private removeBrokenJoints(): void {
    const broken = this.world.jointEvents().broken
    for (let i = 0; i < broken.length; i++) {
      if (!this.userJoints.delete(broken[i])) continue
      this.listener.jointRemoved(broken[i])
    }
  }

  private tell(playerId: number, cmd: SimCommand): void {
    this.told = true
    for (const o of this.observers) o.command(this.tick, playerId, cmd)
  }

  private runGameTick(tick: (ctx: GameContext) => void): void {
    this.events = stepEvents(this.world)
    try {
      tick(this.ctx)
    } catch (e) {
      this.paused = true
      this.listener.roomChanged()
      this.listener.gameFailed?.(this.tick, `${this.game.name} tick failed: ${(e as Error).message}`)
    } finally {
      this.events = NO_EVENTS
    }
  }

  private replaceWorld(
    scene: string,
    world: World,
    joints: Iterable<WireJoint>,
    colors: readonly number[] = [],
  ): void {
    this.lastLoadTick = this.tick
    for (const [pid, p] of this.players) {
      p.grab = null
      this.listener.cursorChanged(pid)
    }
    this.grabCounts.clear()
    this.setColors(colors)
    this.history.clear()
    this.userJoints.clear()
    for (const j of joints) this.userJoints.set(j.id, j)
    this.scene = scene
    this.world = world
    this.listener.worldReplaced()
    this.listener.roomChanged()
  }

  /** The game's view of this simulation (GameContext): accessors over its fields, and its primitives. */
  private context(): GameContext {
    const sim = this
    const player = (id: number): SimPlayer => {
      const p = sim.players.get(id)
      if (!p) throw new RangeError(`player ${id} is not in this room`)
      return p
    }
    return {
      get world() {
        return sim.world
      },
      get tick() {
        return sim.tick
      },
      get players() {
        return sim.playerIds
      },
      get random() {
        return sim.random
      },
      get events() {
        return sim.events
      },
      get state() {
        return sim.gameState
      },
      set state(value) {
        sim.gameState = value
      },
      get paused() {
        return sim.paused
      },
      set paused(value) {
        sim.paused = value
        sim.listener.roomChanged()
      },
      get lastLoadTick() {
        return sim.lastLoadTick
      },
      get scene() {
        return sim.scene
      },
      get maxBodies() {
        return sim.maxBodies
      },
      emit: (event) => sim.listener.gameEvent?.(sim.tick, copyPlainData(event, 'event')),
      requestStep: () => {
        sim.stepRequested = true
      },
      get slowMotion() {
        return sim.slowMotion
      },
      set slowMotion(value) {
        if (value !== 1 && value !== 2 && value !== 4)
          throw new RangeError(`slowMotion must be 1, 2 or 4, got ${value}`)
        sim.slowMotion = value
        sim.listener.roomChanged()
      },
      get creator() {
        return sim.creator
      },
      get controlsLocked() {
        return sim.controlsLocked
      },
      set controlsLocked(value) {
        sim.controlsLocked = value
        sim.listener.roomChanged()
      },
      get history() {
        return sim.history
      },
      createBody: (def, color) => sim.createBody(def, color),
      spawn: (cmd, player) => sim.spawn(cmd, player),
      bodyColor: (id) => sim.bodyColors.get(id) ?? null,
      destroyBody: (id) => {
        if (sim.world.hasBody(id)) sim.removeBody(id)
      },
      setBodyColor: (id, color) => {
        if (color === null) sim.bodyColors.delete(id)
        else if (sim.world.hasBody(id)) sim.bodyColors.set(id, color)
      },
      bodyChanged: (id) => {
        if (!sim.world.hasBody(id)) return
        sim.bodyEdits++
        sim.listener.bodyChanged?.(id)
      },
      grab: (id, body, lx, ly) => sim.grab(id, player(id), body, lx, ly),
      moveCursor: (id, x, y) => {
        const p = player(id)
        const at = moveGrab(sim.world, p.grab?.joint ?? null, x, y)
        p.cursorX = at.x
        p.cursorY = at.y
        sim.listener.cursorChanged(id)
      },
      release: (id) => sim.release(id, player(id)),
      grabbedBody: (id) => player(id).grab?.body ?? 0,
      cursor: (id) => {
        const p = player(id)
        return { x: p.cursorX, y: p.cursorY }
      },
      addJoint: (cmd) => sim.joint(cmd),
      createJoint: (owner, def, what) => sim.createJoint(owner, def, what),
      userJoint: (id) => sim.userJoints.get(id),
      setJointMotor: (id, speed) => sim.setJointMotor(id, speed),
      setJointSettings: (id, settings) => sim.setJointSettings(id, settings),
      removeJoint: (id) => {
        if (!sim.userJoints.has(id)) return `joint ${id} is not a joint in this room`
        removeJoint(sim.world, id)
        sim.userJoints.delete(id)
        sim.listener.jointRemoved(id)
        return null
      },
      loadScene: (name) => {
        if (!Object.hasOwn(SCENES, name)) return `unknown scene "${name}"`
        sim.loadScene(name)
        return null
      },
      setGravity: (x, y) => {
        setWorldGravity(sim.world, x, y)
        sim.listener.roomChanged()
      },
    }
  }

  private createBody(def: Parameters<World['createBody']>[0], color?: number): number | string {
    if (this.world.bodyCount >= this.maxBodies) return `body limit reached (${this.maxBodies})`
    let id: number
    try {
      id = this.world.createBody(def)
    } catch (e) {
      return `body refused: ${(e as Error).message}`
    }
    if (color !== undefined) this.bodyColors.set(id, color)
    this.listener.bodyAdded(id)
    return id
  }

  private spawn(cmd: SpawnCommand, player?: number): number | string {
    if (this.world.bodyCount >= this.maxBodies) return `body limit reached (${this.maxBodies})`
    const spawned = spawnBody(this.world, cmd)
    if (!spawned.ok) return spawned.reason
    const color = cmd.color ?? (player === undefined ? undefined : playerBodyColor(player))
    if (color !== undefined) this.bodyColors.set(spawned.value, color)
    this.listener.bodyAdded(spawned.value)
    return spawned.value
  }

  private grab(playerId: number, player: SimPlayer, body: number, lx: number, ly: number): string | null {
    const refusal = grabRefusal(this.world, body)
    if (refusal) return refusal
    this.release(playerId, player)
    const grabbed = grabBody(this.world, body, lx, ly)
    if (!grabbed.ok) {
      // The earlier grab is gone: record that much so a replay releases it too.
      for (const o of this.observers) o.command(this.tick, playerId, { k: 'release' })
      return grabbed.reason
    }
    const { joint, target } = grabbed.value
    player.grab = { joint, body }
    player.cursorX = target.x
    player.cursorY = target.y
    this.listener.cursorChanged(playerId)
    this.grabCounts.set(body, (this.grabCounts.get(body) ?? 0) + 1)
    return null
  }

  private release(playerId: number, player: SimPlayer): void {
    const g = player.grab
    if (!g) return
    removeJoint(this.world, g.joint)
    const n = (this.grabCounts.get(g.body) ?? 1) - 1
    if (n > 0) this.grabCounts.set(g.body, n)
    else this.grabCounts.delete(g.body)
    player.grab = null
    this.listener.cursorChanged(playerId)
  }

  private joint(cmd: PinCommand | RopeCommand): string | null {
    const refusal = jointRefusal(this.world, cmd)
    if (refusal) return refusal
    if (this.userJoints.size >= this.maxBodies) return 'joint limit reached'
    const added = addUserJoint(this.world, cmd)
    if (!added.ok) return added.reason
    this.userJoints.set(added.value.id, added.value)
    this.listener.jointAdded(added.value)
    return null
  }

  private createJoint(owner: number, def: WireJointDef, what: string): number | string {
    if (this.userJoints.size >= this.maxBodies) return 'joint limit reached'
    const added = createUserJoint(this.world, def, owner, what)
    if (!added.ok) return added.reason
    this.userJoints.set(added.value.id, added.value)
    this.listener.jointAdded(added.value)
    return added.value.id
  }

  private setJointMotor(id: number, speed: number): string | null {
    const j = this.userJoints.get(id)
    if (!j) return `joint ${id} is not a joint in this room`
    if (!j.motor || j.kind === 'weld' || j.kind === 'motor') return `joint ${id} has no motor`
    if (!Number.isFinite(speed)) return `motor speed ${speed} is not a finite number`
    this.world.setJointMotorSpeed(id, speed)
    // A new object: a predicting client's copies share joint objects with the confirmed simulation.
    const next = { ...j, speed }
    this.userJoints.set(id, next)
    // Snapshot players see the new speed (events.jadd replaces the joint by its id).
    this.listener.jointAdded(next)
    return null
  }

  private setJointSettings(id: number, settings: JointSettings): string | null {
    const j = this.userJoints.get(id)
    if (!j || !this.world.hasJoint(id)) return `joint ${id} is not a joint in this room`
    try {
      this.world.setJointSettings(id, settings)
    } catch (e) {
      if (e instanceof RangeError) return e.message
      throw e
    }
    // A new object (predicting clients share joint objects with the confirmed simulation).
    const next = withJointSettings(j, this.world.getJointDef(id))
    this.userJoints.set(id, next)
    this.listener.jointAdded(next)
    return null
  }

  /** Once a second: remove movable bodies that left the world or whose position is not finite. */
  private sweep(): void {
    for (const id of strayBodies(this.world)) this.removeBody(id)
  }
}
