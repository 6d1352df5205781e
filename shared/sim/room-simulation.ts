/*
 * The deterministic part of a room: the world, its scene, pause and single-step state, the room
 * tick, each player's grab and cursor, the user joints (pins and ropes), grab counts and the
 * scene-load rate limit. Everything that changes the world goes through here, in an order the
 * caller decides (the server's Room: joins, leaves and the tick's queued commands, then tick()).
 *
 * Pure: no Node APIs, no clocks, no randomness; it runs in the server, in lockstep clients and in
 * the replay player. Two RoomSimulations built with the same options that see the same joins,
 * leaves, accepted commands and external world loads at the same ticks stay bit-identical
 * (world.hash()); that is what recording and replay rely on.
 *
 * Two hooks report what happened:
 *   - the listener (the owner, one): world side effects to turn into wire events
 *   - observers (any number: a recorder, a lockstep stream): every state change in applied order,
 *     only commands that were accepted (a refused command changes nothing); `inspect` is not a
 *     simulation command and is refused here (the server's Room handles it itself)
 * A refused command returns a reason; nothing here throws to the caller.
 */
import { createWorld, SCENES, type SceneBlueprint, type World } from '../../engine/index.ts'
import {
  buildSceneJoints,
  type Command,
  KILL_DISTANCE,
  KILL_PLANE_Y,
  type SpawnCommand,
  TICK_RATE,
  type WireJoint,
} from '../protocol/index.ts'
import {
  addUserJoint,
  grabBody,
  grabRefusal,
  isMovable,
  jointRefusal,
  moveGrab,
  removeJoint,
  setWorldGravity,
  spawnBody,
} from './world-commands.ts'

/** Ticks between scene loads or resets in one room: building a scene is the costliest command. */
export const MIN_TICKS_BETWEEN_LOADS = 10

/** Commands that change room settings; refused when the room's controls are off. */
const CONTROLS = new Set(['scene', 'pause', 'step', 'reset', 'gravity'])

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
  /** Room tick of the last scene load or reset, or null for never. */
  lastLoadTick: number | null
  /** Players in join order, with their grabs and cursors. */
  players: Array<{ id: number; grab: Grab | null; cursorX: number; cursorY: number }>
  /** User joints in creation order. */
  userJoints: WireJoint[]
}

/** World side effects, for the owner to turn into wire events. Called synchronously. */
export interface SimulationListener {
  bodyAdded(id: number): void
  bodyRemoved(id: number): void
  jointAdded(joint: WireJoint): void
  jointRemoved(id: number): void
  /** Pause, gravity or scene changed. */
  roomChanged(): void
  /** A player's cursor or grab changed. */
  cursorChanged(playerId: number): void
  /** The world was replaced (scene load, reset, external load); grabs and user joints are gone. */
  worldReplaced(): void
}

/** Every state change in applied order: what a recorder or a lockstep stream needs. */
export interface SimulationObserver {
  /** An accepted command, just applied at room tick `tick` (before that tick's step). */
  command(tick: number, playerId: number, cmd: Command): void
  /** A tick ended: the world stepped (unless paused) and the room tick is now `tick`. */
  ticked?(tick: number): void
  join(tick: number, playerId: number, name: string, color: string): void
  leave(tick: number, playerId: number): void
  /** The world was replaced from outside a command (a benchmark blueprint, a restored keyframe). */
  worldLoaded(tick: number, scene: string): void
}

/** Room rules that change what commands may do. */
export interface SimulationOptions {
  /** Body limit (also the user joint limit). */
  maxBodies: number
  /** Whether scene, pause, step, reset and gravity are allowed. */
  controls: boolean
  /** Initial scene name (a key of SCENES). */
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
 * event); the offline sandbox does the same.
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
  readonly observers: SimulationObserver[] = []
  readonly maxBodies: number
  readonly controls: boolean
  readonly name: string
  private readonly listener: SimulationListener

  constructor(options: SimulationOptions) {
    if (!Object.hasOwn(SCENES, options.scene)) throw new RangeError(`unknown scene "${options.scene}"`)
    this.maxBodies = options.maxBodies
    this.controls = options.controls
    this.name = options.name
    this.listener = options.listener ?? NO_LISTENER
    this.scene = options.scene
    const built = worldFromBlueprint(SCENES[options.scene].make())
    this.world = built.world
    for (const j of built.joints) this.userJoints.set(j.id, j)
  }

  /** Add a player (or bring one back after a reconnect). */
  join(playerId: number, name: string, color: string): void {
    this.players.set(playerId, { grab: null, cursorX: 0, cursorY: 0 })
    for (const o of this.observers) o.join(this.tick, playerId, name, color)
  }

  /** Remove a player, releasing its grab. */
  leave(playerId: number): void {
    const player = this.players.get(playerId)
    if (!player) return
    this.release(playerId, player)
    this.players.delete(playerId)
    for (const o of this.observers) o.leave(this.tick, playerId)
  }

  /** Apply one command from a player at the current tick; returns a reason when refused. */
  apply(playerId: number, cmd: Command): string | null {
    const player = this.players.get(playerId)
    if (!player) return `player ${playerId} is not in this room`
    if (CONTROLS.has(cmd.k) && !this.controls) return `room controls are disabled in room ${this.name}`
    let error: string | null
    try {
      error = this.dispatch(playerId, player, cmd)
    } catch (e) {
      // Engine preconditions (a non-convex polygon, a degenerate joint) throw RangeError.
      error = `${cmd.k} refused: ${(e as Error).message}`
    }
    if (error === null) for (const o of this.observers) o.command(this.tick, playerId, cmd)
    return error
  }

  /** Run one tick: step unless paused (or a step was requested), advance the tick, housekeeping. */
  runTick(): void {
    if (!this.paused || this.stepRequested) this.world.step()
    this.stepRequested = false
    this.tick++
    if (this.tick % TICK_RATE === 0) this.sweep()
    for (const o of this.observers) o.ticked?.(this.tick)
  }

  /** Replace the world with a fresh copy of a named scene (SCENES). */
  loadScene(name: string): void {
    const built = worldFromBlueprint(SCENES[name].make())
    this.replaceWorld(name, built.world, built.joints)
  }

  /**
   * Replace the world from outside a command (a benchmark's blueprint, a restored world): observers
   * see it as a world load so a recording stays reproducible. `joints` are the world's joints as
   * they travel (worldFromBlueprint gives them), none for a world restored from bytes.
   */
  loadWorld(scene: string, world: World, joints: Iterable<WireJoint> = []): void {
    this.replaceWorld(scene, world, joints)
    for (const o of this.observers) o.worldLoaded(this.tick, scene)
  }

  /** This simulation's state besides the world (save the world with world.save()). */
  saveState(): SimulationState {
    return {
      tick: this.tick,
      scene: this.scene,
      paused: this.paused,
      stepRequested: this.stepRequested,
      lastLoadTick: Number.isFinite(this.lastLoadTick) ? this.lastLoadTick : null,
      players: [...this.players].map(([id, p]) => ({
        id,
        grab: p.grab ? { ...p.grab } : null,
        cursorX: p.cursorX,
        cursorY: p.cursorY,
      })),
      userJoints: [...this.userJoints.values()].map((j) => ({ ...j })),
    }
  }

  /**
   * Resume from a saved state and world (a keyframe): afterwards this simulation steps exactly as
   * the one that saved them. Observers are not told (the state came from them); the listener sees a
   * replaced world.
   */
  restoreState(state: SimulationState, world: World): void {
    this.tick = state.tick
    this.scene = state.scene
    this.paused = state.paused
    this.stepRequested = state.stepRequested
    this.lastLoadTick = state.lastLoadTick ?? Number.NEGATIVE_INFINITY
    this.world = world
    this.players.clear()
    this.grabCounts.clear()
    for (const p of state.players) {
      this.players.set(p.id, { grab: p.grab ? { ...p.grab } : null, cursorX: p.cursorX, cursorY: p.cursorY })
      if (p.grab) this.grabCounts.set(p.grab.body, (this.grabCounts.get(p.grab.body) ?? 0) + 1)
    }
    this.userJoints.clear()
    for (const j of state.userJoints) this.userJoints.set(j.id, { ...j })
    this.listener.worldReplaced()
    this.listener.roomChanged()
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
    this.world.destroyBody(id)
    this.listener.bodyRemoved(id)
  }

  private replaceWorld(scene: string, world: World, joints: Iterable<WireJoint>): void {
    this.lastLoadTick = this.tick
    for (const [pid, p] of this.players) {
      p.grab = null
      this.listener.cursorChanged(pid)
    }
    this.grabCounts.clear()
    this.userJoints.clear()
    for (const j of joints) this.userJoints.set(j.id, j)
    this.scene = scene
    this.world = world
    this.listener.worldReplaced()
    this.listener.roomChanged()
  }

  private dispatch(playerId: number, player: SimPlayer, cmd: Command): string | null {
    const world = this.world
    switch (cmd.k) {
      case 'spawn':
        return this.spawn(cmd)
      case 'grab':
        return this.grab(playerId, player, cmd.body, cmd.lx, cmd.ly)
      case 'move': {
        const p = moveGrab(world, player.grab?.joint ?? null, cmd.x, cmd.y)
        player.cursorX = p.x
        player.cursorY = p.y
        this.listener.cursorChanged(playerId)
        return null
      }
      case 'release':
        this.release(playerId, player)
        return null
      case 'delete':
        if (!isMovable(world, cmd.body)) return `body ${cmd.body} does not exist or is static`
        this.removeBody(cmd.body)
        return null
      case 'pin':
      case 'rope':
        return this.joint(cmd)
      case 'unjoint':
        if (!this.userJoints.has(cmd.joint)) return `joint ${cmd.joint} is not a joint in this room`
        removeJoint(world, cmd.joint)
        this.userJoints.delete(cmd.joint)
        this.listener.jointRemoved(cmd.joint)
        return null
      case 'scene':
        if (!Object.hasOwn(SCENES, cmd.name)) return `unknown scene "${cmd.name}"`
        if (this.tick - this.lastLoadTick < MIN_TICKS_BETWEEN_LOADS)
          return 'scene loads are limited to 6 per second'
        this.loadScene(cmd.name)
        return null
      case 'reset':
        if (this.tick - this.lastLoadTick < MIN_TICKS_BETWEEN_LOADS)
          return 'scene loads are limited to 6 per second'
        this.loadScene(this.scene)
        return null
      case 'pause':
        this.paused = cmd.paused
        this.listener.roomChanged()
        return null
      case 'step':
        this.stepRequested = true
        return null
      case 'gravity':
        setWorldGravity(world, cmd.x, cmd.y)
        this.listener.roomChanged()
        return null
      case 'inspect':
        return 'inspect is not a simulation command'
    }
  }

  private spawn(cmd: SpawnCommand): string | null {
    if (this.world.bodyCount >= this.maxBodies) return `body limit reached (${this.maxBodies})`
    const spawned = spawnBody(this.world, cmd)
    if (!spawned.ok) return spawned.reason
    this.listener.bodyAdded(spawned.value)
    return null
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

  private joint(cmd: Extract<Command, { k: 'pin' | 'rope' }>): string | null {
    const refusal = jointRefusal(this.world, cmd)
    if (refusal) return refusal
    if (this.userJoints.size >= this.maxBodies) return 'joint limit reached'
    const added = addUserJoint(this.world, cmd)
    if (!added.ok) return added.reason
    this.userJoints.set(added.value.id, added.value)
    this.listener.jointAdded(added.value)
    return null
  }

  /** Once a second: remove movable bodies that left the world or whose position is not finite. */
  private sweep(): void {
    for (const id of strayBodies(this.world)) this.removeBody(id)
  }
}
