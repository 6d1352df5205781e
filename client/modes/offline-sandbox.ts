/*
 * Offline mode: the room runs in the page. A RoomSimulation of the sandbox game (shared/sim, the
 * very simulation a server room runs) with one local player, joined as a room joins a player, so
 * body colours, undo histories, joint ownership and every game command (the joint tools, edit,
 * transform, duplicate, deleteMany, explode, slow, lock, undo and redo) behave as they do online.
 * There are no rules here: what a command does, and the text of a refusal, are the game's.
 *
 * Commands queue as a server room queues inputs and are applied through RoomSimulation.apply at
 * the next tick (a newer cursor move replaces a queued one), then RoomSimulation.runTick steps the
 * world unless paused, in slow motion on every slowMotion-th tick, and removes stray bodies once a
 * second. Frames are turned into whole 1/60 s ticks by the engine's FixedStepper (never a variable
 * step) and bodies are drawn between the last two world steps (alpha: the stepper's leftover
 * fraction, spread over the slowMotion ticks between two steps), so motion is smooth at any
 * display rate and speed. A refused command becomes a notice with the game's reason.
 *
 * Scene files: the world saves as a scene file in the page (downloaded), and a checked file opens
 * into the local room as the server's openScene would open it; share links need a server.
 */
import { type ContactInfo, DEFAULT_SCENE, FixedStepper, SCENES, type World } from '../../engine/index.ts'
import { type SceneFile, sandbox, saveRoomScene, sceneForRoom, sceneText } from '../../games/index.ts'
import {
  type Command,
  cssColor,
  type PlainData,
  playerBodyColor,
  type RoomRules,
  RoomSimulation,
  roomRules,
  type SimCommand,
  type SimulationListener,
  TICK_RATE,
} from '../../shared/index.ts'
import { WorldView } from '../draw/index.ts'
import { NoticeLog } from './notice-log.ts'
import type {
  LabData,
  RoomControl,
  Sandbox,
  SandboxStats,
  SandboxStatus,
  ViewBody,
  ViewCursor,
  ViewJoint,
} from './sandbox.ts'
import { simulationControl, simulationJoints, simulationLab } from './simulation-view.ts'

/** The page's player id: the first player to join a room, as a server's first player is. */
const PLAYER = 1
/** Bodies in the page's room (the server's default --max-bodies). */
const OFFLINE_MAX_BODIES = 1500

/** The sandbox with its room simulated in the page (see the file comment). */
export class OfflineSandbox implements Sandbox {
  readonly mode = 'offline'
  /** The room: the sandbox game's simulation with this page's one player. */
  readonly sim: RoomSimulation
  private readonly stepper = new FixedStepper()
  private lastNow = Number.NaN
  /** Commands for the next tick, in the order sent. */
  private queue: SimCommand[] = []
  private readonly view = new WorldView()
  /** Room ticks run since the world last stepped (slow motion spreads one step over several). */
  private ticksSinceStep = 0
  private readonly notice = new NoticeLog()
  private stepMs = 0
  /** The world's touching contacts, read once per world step at most. */
  private contactCache: { world: World; tick: number; contacts: ContactInfo[] } | null = null
  private readonly roomRules: RoomRules
  /** This player's colour, as a room gives its first player. */
  private readonly ownColor = cssColor(playerBodyColor(PLAYER)) as string

  constructor(scene = DEFAULT_SCENE) {
    const view = this.view
    const listener: SimulationListener = {
      bodyAdded: () => {},
      bodyRemoved: (id) => view.remove(id),
      bodyChanged: (id) => view.changed(id),
      jointAdded: () => {},
      jointRemoved: () => {},
      roomChanged: () => {},
      cursorChanged: () => {},
      worldReplaced: () => view.clear(),
      gameFailed: (_tick, message) => this.notice.add(message),
    }
    this.sim = new RoomSimulation({
      game: sandbox,
      name: 'offline',
      scene: Object.hasOwn(SCENES, scene) ? scene : DEFAULT_SCENE,
      maxBodies: OFFLINE_MAX_BODIES,
      controls: true,
      listener,
    })
    this.sim.join(PLAYER, 'you', this.color())
    view.colorOf = (id) => this.sim.bodyColors.get(id)
    // The page's room: one player, no spectators, no input budget, every control open.
    this.roomRules = roomRules(sandbox, {
      snapshotRate: TICK_RATE,
      maxBodies: OFFLINE_MAX_BODIES,
      maxClients: 1,
      inputsPerTick: Number.POSITIVE_INFINITY,
      controls: true,
      maxSpectators: 0,
    })
  }

  update(nowMs: number): void {
    const frame = Number.isNaN(this.lastNow) ? 0 : (nowMs - this.lastNow) / 1000
    this.lastNow = nowMs
    const ticks = this.stepper.advance(frame)
    const sim = this.sim
    if (ticks > 0) {
      const start = performance.now()
      for (let i = 0; i < ticks; i++) this.runTick()
      this.stepMs += ((performance.now() - start) / ticks - this.stepMs) * 0.1
    }
    const alpha = sim.paused ? 1 : Math.min(1, (this.ticksSinceStep + this.stepper.alpha) / sim.slowMotion)
    const grab = sim.players.get(PLAYER)?.grab?.body ?? 0
    this.view.refresh(sim.world, alpha, (id) => (id === grab ? this.ownColor : null))
  }

  /** One room tick: the queued commands (as a room applies a tick's inputs), then the simulation's tick. */
  private runTick(): void {
    const sim = this.sim
    if (this.queue.length > 0) {
      const queue = this.queue
      this.queue = []
      for (const cmd of queue) {
        const refused = sim.apply(PLAYER, cmd)
        if (refused !== null) this.notice.add(refused)
      }
    }
    const steps = sim.stepsNextTick()
    // The poses before the step, to draw between them and the poses after it.
    if (steps) this.view.capturePrevious(sim.world)
    sim.runTick()
    this.ticksSinceStep = steps ? 0 : this.ticksSinceStep + 1
  }

  bodies(): readonly ViewBody[] {
    return this.view.bodies()
  }

  joints(): readonly ViewJoint[] {
    return simulationJoints(this.sim, (id) => this.view.get(id))
  }

  /** Only this page's player is in its room: there are no other cursors. */
  cursors(): readonly ViewCursor[] {
    return []
  }

  contacts(): ContactInfo[] {
    const world = this.sim.world
    let cache = this.contactCache
    if (cache?.world !== world || cache.tick !== world.tick) {
      cache = { world, tick: world.tick, contacts: world.contacts() }
      this.contactCache = cache
    }
    return cache.contacts
  }

  /** Queue a command for the next tick (a newer cursor move replaces a queued one, as in a room). */
  send(cmd: Command): void {
    // Inspecting only chooses what a server sends a player: here the lab reads the world itself.
    if (cmd.k === 'inspect') return
    const last = this.queue.at(-1)
    if (cmd.k === 'move' && last?.k === 'move') this.queue[this.queue.length - 1] = cmd
    else this.queue.push(cmd)
  }

  /** Queue a game command (the sandbox's weld, hinge, edit, undo, ...) for the next tick. */
  sendGame(kind: string, args: { [key: string]: PlainData }): void {
    this.queue.push({ k: 'cmd', kind, a: args })
  }

  playerId(): number {
    return PLAYER
  }

  roomControl(): RoomControl {
    return simulationControl(this.sim, PLAYER)
  }

  /** The world as a scene file's text (docs/scene-format.md) named `name`. */
  sceneFile(name: string): string {
    return sceneText(saveRoomScene(this.sim, name))
  }

  /** Open a checked scene file into the page's room, as a server's openScene does; null, or why not. */
  openSceneFile(scene: SceneFile, name: string): string | null {
    const sim = this.sim
    if (scene.bodies.length > sim.maxBodies)
      return `${name} has ${scene.bodies.length} bodies; this page holds at most ${sim.maxBodies}`
    const built = sceneForRoom(scene)
    if (!built.ok) return `${name} does not open: ${built.error}`
    sim.loadWorld(`file:${name}`, built.world, built.joints, built.colors)
    this.ticksSinceStep = 0
    return null
  }

  color(): string {
    return this.ownColor
  }

  status(): SandboxStatus {
    return { state: 'offline' }
  }

  stats(): SandboxStats {
    const world = this.sim.world
    return {
      room: 'offline',
      players: 1,
      tick: world.tick,
      pingMs: null,
      delayMs: null,
      snapshotHz: null,
      downKBs: null,
      upKBs: null,
      awake: world.awakeBodyCount(),
      total: world.bodyCount,
      stepMs: this.stepMs,
    }
  }

  rules(): RoomRules {
    return this.roomRules
  }

  scene(): string {
    return this.sim.scene
  }

  paused(): boolean {
    return this.sim.paused
  }

  gravity(): { x: number; y: number } {
    return this.sim.world.getGravity()
  }

  inspect(_bodyId: number): void {}

  lab(bodyId: number): LabData | null {
    return simulationLab(this.sim, bodyId, this.contacts())
  }

  notices(): { count: number; latest: string | null; recent: readonly string[] } {
    return this.notice
  }

  retry(): void {}

  dispose(): void {}
}
