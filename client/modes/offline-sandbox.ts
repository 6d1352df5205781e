/*
 * Offline mode: the engine runs in the page. Frames are turned into whole 1/60 s steps by the
 * engine's FixedStepper (never a variable step) and drawn between the last two steps by the
 * stepper's leftover fraction (alpha), so motion is smooth at any display rate; the same protocol
 * commands the server would
 * receive are applied to the local world here, so every tool behaves as it does online. The lab
 * reads world.contacts() directly: the impulses of the step that was just taken.
 */
import {
  type ContactInfo,
  createWorld,
  DEFAULT_SCENE,
  FixedStepper,
  type JointId,
  SCENES,
  type Vec2,
  type World,
} from '../../engine/index.ts'
import {
  addUserJoint,
  buildSceneJoints,
  type Command,
  deleteBody,
  grabBody,
  grabRefusal,
  moveGrab,
  type PlainData,
  playerBodyColor,
  type RoomRules,
  removeJoint,
  setWorldGravity,
  spawnBody,
  strayBodies,
  TICK_RATE,
  type WireJoint,
} from '../../shared/index.ts'
import { labFromWorld, viewJoints, WorldView } from '../draw/index.ts'
import type {
  LabData,
  Sandbox,
  SandboxStats,
  SandboxStatus,
  ViewBody,
  ViewCursor,
  ViewJoint,
} from './sandbox.ts'

const OWN_COLOR = '#ff9f1c'

/** The sandbox with the engine in the page. */
export class OfflineSandbox implements Sandbox {
  readonly mode = 'offline'
  world: World
  private sceneName: string
  private isPaused = false
  private stepOnce = false
  /** Slow motion: the world steps on every slow-th fixed step only (1, 2 or 4), as a room does. */
  private slow = 1
  private fixedSteps = 0
  private readonly stepper = new FixedStepper()
  private lastNow = Number.NaN
  private readonly view = new WorldView()
  /** Colours of the bodies spawned here (the offline player is player 1), as a room keeps them. */
  private readonly colors = new Map<number, number>()
  private readonly joints_ = new Map<JointId, WireJoint>()
  private grab: { joint: JointId; body: number } | null = null
  private noticeCount = 0
  private latestNotice: string | null = null
  private stepMs = 0
  private contactCache: ContactInfo[] | null = null

  constructor(scene = DEFAULT_SCENE) {
    this.view.colorOf = (id) => this.colors.get(id)
    this.sceneName = Object.hasOwn(SCENES, scene) ? scene : DEFAULT_SCENE
    this.world = this.build(this.sceneName)
  }

  private build(scene: string): World {
    const world = createWorld()
    const joints = buildSceneJoints(world, SCENES[scene].make())
    this.view.clear()
    this.colors?.clear()
    this.joints_.clear()
    for (const j of joints) this.joints_.set(j.id, j)
    this.grab = null
    return world
  }

  update(nowMs: number): void {
    const frame = Number.isNaN(this.lastNow) ? 0 : (nowMs - this.lastNow) / 1000
    this.lastNow = nowMs
    let steps = this.stepper.advance(frame)
    if (this.slow > 1) {
      const before = this.fixedSteps
      this.fixedSteps += steps
      steps =
        Math.floor((this.fixedSteps + this.slow - 1) / this.slow) -
        Math.floor((before + this.slow - 1) / this.slow)
    }
    if (this.isPaused) steps = this.stepOnce ? 1 : 0
    this.stepOnce = false
    if (steps > 0) {
      const start = performance.now()
      for (let i = 0; i < steps - 1; i++) this.stepWorld()
      this.view.capturePrevious(this.world)
      this.stepWorld()
      // Once a second, as a room does: bodies that left the world (below the kill plane) go.
      if (Math.floor(this.world.tick / TICK_RATE) !== Math.floor((this.world.tick - steps) / TICK_RATE)) {
        for (const id of strayBodies(this.world)) this.apply({ k: 'delete', body: id })
      }
      this.stepMs += ((performance.now() - start) / steps - this.stepMs) * 0.1
      this.contactCache = null
    }
    const held = this.grab?.body ?? 0
    this.view.refresh(this.world, this.isPaused ? 1 : this.stepper.alpha, (id) =>
      id === held ? OWN_COLOR : null,
    )
  }

  bodies(): readonly ViewBody[] {
    return this.view.bodies()
  }

  joints(): readonly ViewJoint[] {
    const forces = new Map<number, Vec2>()
    for (const info of this.world.joints()) forces.set(info.id, info.force)
    return viewJoints(
      this.joints_.values(),
      (id) => this.view.get(id),
      (id) => forces.get(id) ?? null,
    )
  }

  cursors(): readonly ViewCursor[] {
    return []
  }

  contacts(): ContactInfo[] {
    this.contactCache ??= this.world.contacts()
    return this.contactCache
  }

  /** One step; the joints it broke leave the drawn joints, as they leave a room's. */
  private stepWorld(): void {
    this.world.step()
    for (const id of this.world.jointEvents().broken) this.joints_.delete(id)
  }

  /**
   * Apply a command to the local world through shared/sim/world-commands.ts, as a room would, with the
   * same clamps and caps; refused commands are ignored (they never throw).
   */
  send(cmd: Command): void {
    this.apply(cmd)
  }

  /** The sandbox's explode and slow commands on the local world (the game's rules; lock and the joint tools need a room). */
  sendGame(kind: string, args: { [key: string]: PlainData }): void {
    if (kind === 'explode') {
      const { x, y, radius, impulse } = args as { x: number; y: number; radius: number; impulse: number }
      this.world.explode({ position: { x, y }, radius, falloff: radius, impulsePerLength: impulse })
    } else if (kind === 'slow' && (args.every === 1 || args.every === 2 || args.every === 4)) {
      this.slow = args.every
      this.fixedSteps = 0
    } else if (kind !== 'explode' && kind !== 'slow') {
      // The joint tools are the room's game commands: this page's own world does not run the game.
      this.noticeCount++
      this.latestNotice = `The ${kind} tool needs a room: open the sandbox online to build machines.`
    }
  }

  roomControl(): { slow: number; creator: number; locked: boolean; self: number } {
    return { slow: this.slow, creator: 0, locked: false, self: 0 }
  }

  private apply(cmd: Command): void {
    const w = this.world
    switch (cmd.k) {
      case 'spawn': {
        const spawned = spawnBody(w, cmd)
        if (spawned.ok) this.colors.set(spawned.value, cmd.color ?? playerBodyColor(1))
        return
      }
      case 'grab': {
        if (grabRefusal(w, cmd.body)) return
        this.release()
        const grabbed = grabBody(w, cmd.body, cmd.lx, cmd.ly)
        if (grabbed.ok) this.grab = { joint: grabbed.value.joint, body: cmd.body }
        return
      }
      case 'move':
        moveGrab(w, this.grab?.joint ?? null, cmd.x, cmd.y)
        return
      case 'release':
        this.release()
        return
      case 'delete':
        // As in a room: static bodies drawn here (they have a colour) may be deleted too.
        if (this.colors.has(cmd.body) && w.hasBody(cmd.body)) w.destroyBody(cmd.body)
        else if (deleteBody(w, cmd.body)) return
        this.colors.delete(cmd.body)
        if (this.grab?.body === cmd.body) this.grab = null
        for (const [id, j] of this.joints_) if (j.a === cmd.body || j.b === cmd.body) this.joints_.delete(id)
        this.view.remove(cmd.body)
        return
      case 'pin':
      case 'rope': {
        const added = addUserJoint(w, cmd)
        if (added.ok) this.joints_.set(added.value.id, added.value)
        return
      }
      case 'unjoint':
        if (this.joints_.has(cmd.joint)) removeJoint(w, cmd.joint)
        this.joints_.delete(cmd.joint)
        return
      case 'scene':
        if (!Object.hasOwn(SCENES, cmd.name)) return
        this.sceneName = cmd.name
        this.world = this.build(cmd.name)
        return
      case 'reset':
        this.world = this.build(this.sceneName)
        return
      case 'pause':
        this.isPaused = cmd.paused
        return
      case 'step':
        this.stepOnce = true
        return
      case 'gravity':
        setWorldGravity(w, cmd.x, cmd.y)
        return
    }
  }

  private release(): void {
    if (this.grab) removeJoint(this.world, this.grab.joint)
    this.grab = null
  }

  color(): string {
    return OWN_COLOR
  }

  status(): SandboxStatus {
    return { state: 'offline' }
  }

  stats(): SandboxStats {
    return {
      room: 'offline',
      players: 1,
      tick: this.world.tick,
      pingMs: null,
      delayMs: null,
      snapshotHz: null,
      downKBs: null,
      upKBs: null,
      awake: this.world.awakeBodyCount(),
      total: this.world.bodyCount,
      stepMs: this.stepMs,
    }
  }

  rules(): RoomRules | null {
    return null
  }

  scene(): string {
    return this.sceneName
  }

  paused(): boolean {
    return this.isPaused
  }

  gravity(): { x: number; y: number } {
    return this.world.getGravity()
  }

  inspect(_bodyId: number): void {}

  lab(bodyId: number): LabData | null {
    const w = this.world
    if (!w.hasBody(bodyId) || w.getBodyType(bodyId) !== 'dynamic') return null
    return labFromWorld(w, bodyId, this.contacts(), (id) => this.joints_.get(id)?.kind)
  }

  playerId(): number {
    return 0
  }

  notices(): { count: number; latest: string | null } {
    return { count: this.noticeCount, latest: this.latestNotice }
  }

  retry(): void {}

  dispose(): void {}
}
