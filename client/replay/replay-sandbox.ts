/*
 * Replay mode: a recorded log played in the page through the same RoomSimulation the server ran,
 * drawn by the same renderer as the live sandbox. The page's frame loop turns wall time into ticks
 * at the chosen speed (0.25x to 8x); bodies are drawn between the last two ticks. Players appear
 * as named cursors with their grab lines, and a body a player spawned flashes in that player's
 * colour for half a second. Replays are read only: tools that would change the world say so.
 */
import type { ContactInfo, World } from '../../engine/index.ts'
import type { Command, Inflate, RoomRules, SimulationListener } from '../../shared/index.ts'
import { WorldView } from '../draw/index.ts'
import {
  type LabData,
  type Sandbox,
  type SandboxStats,
  type SandboxStatus,
  simulationJoints,
  simulationLab,
  type ViewBody,
  type ViewCursor,
  type ViewJoint,
} from '../modes/index.ts'
import { type LoadedLog, ReplayPlayer } from './replay-player.ts'

/** Playback speeds offered, as multiples of real time. */
export const REPLAY_SPEEDS = [0.25, 0.5, 1, 2, 4, 8] as const
/** How long a spawned body flashes in its spawner's colour (ticks). */
const SPAWN_FLASH_TICKS = 30
/** Ticks of catch-up per frame at most (a background tab coming back does not freeze the page). */
const MAX_TICKS_PER_FRAME = 64

/** A recorded session played in the page (see the file comment). */
export class ReplaySandbox implements Sandbox {
  readonly mode = 'replay'
  playing = false
  speed = 1
  private readonly view = new WorldView()
  private readonly flashes = new Map<number, { color: string; until: number }>()
  private readonly cursorViews: ViewCursor[] = []
  private lastNow = Number.NaN
  private pending = 0
  /** The world's contacts, computed once per frame at most: cleared while and after a move. */
  private contactCache: ContactInfo[] | null = null
  private notice: string | null = null
  private noticeCount = 0

  private constructor(readonly player: ReplayPlayer) {
    this.view.colorOf = (id) => this.player.sim.bodyColors.get(id)
  }

  /** Open a loaded log at its first tick. */
  static async open(log: LoadedLog, inflate: Inflate): Promise<ReplaySandbox> {
    let sandbox: ReplaySandbox | null = null
    const listener: SimulationListener = {
      bodyAdded: (id) => sandbox?.bodyAdded(id),
      bodyRemoved: (id) => sandbox?.view.remove(id),
      bodyChanged: (id) => sandbox?.view.changed(id),
      jointAdded: () => {},
      jointRemoved: () => {},
      roomChanged: () => {},
      cursorChanged: () => {},
      worldReplaced: () => sandbox?.view.clear(),
    }
    const player = await ReplayPlayer.open(log, inflate, listener)
    sandbox = new ReplaySandbox(player)
    return sandbox
  }

  private get world(): World {
    return this.player.sim.world
  }

  private bodyAdded(id: number): void {
    const who = this.player.people.get(this.player.actingPlayer)
    if (who) this.flashes.set(id, { color: who.color, until: this.player.tick + SPAWN_FLASH_TICKS })
  }

  /**
   * Jump to a tick (through the nearest keyframe, in slices; see replay-player.ts); pauses
   * playback. Resolves true there, false when a newer seek took over.
   */
  async seek(tick: number): Promise<boolean> {
    this.playing = false
    const arrived = await this.tracked(this.player.seek(tick))
    if (arrived) this.redraw()
    return arrived
  }

  /** One tick forward from where the moves under way leave the world; pauses playback. */
  async stepOnce(): Promise<void> {
    this.playing = false
    if (await this.tracked(this.player.forwardBy(1))) this.redraw()
  }

  /** A move through the log; the world it ends in has new contacts. */
  private async tracked(move: Promise<boolean>): Promise<boolean> {
    try {
      return await move
    } finally {
      this.contactCache = null
    }
  }

  private redraw(): void {
    this.view.capturePrevious(this.world)
    this.refresh(1)
  }

  update(nowMs: number): void {
    const dt = Number.isNaN(this.lastNow) ? 0 : Math.min((nowMs - this.lastNow) / 1000, 0.25)
    this.lastNow = nowMs
    if (this.playing && this.player.atEnd && !this.player.busy) this.playing = false
    if (this.player.busy) this.contactCache = null
    if (this.playing && !this.player.busy) {
      this.pending += dt * 60 * this.speed
      const ticks = Math.min(Math.floor(this.pending), MAX_TICKS_PER_FRAME)
      if (ticks > 0) {
        this.pending -= ticks
        this.view.capturePrevious(this.world)
        void this.tracked(this.player.forwardBy(ticks))
      }
    }
    this.refresh(this.playing ? Math.min(this.pending, 1) : 1)
  }

  private refresh(alpha: number): void {
    const tick = this.player.tick
    const held = new Map<number, string>()
    for (const [id, p] of this.player.sim.players) {
      if (p.grab) held.set(p.grab.body, this.player.people.get(id)?.color ?? '#888888')
    }
    for (const [id, f] of this.flashes) if (f.until <= tick) this.flashes.delete(id)
    this.view.refresh(this.world, alpha, (id) => held.get(id) ?? this.flashes.get(id)?.color ?? null)
  }

  bodies(): readonly ViewBody[] {
    return this.view.bodies()
  }

  joints(): readonly ViewJoint[] {
    return simulationJoints(this.player.sim, (id) => this.view.get(id))
  }

  cursors(): readonly ViewCursor[] {
    this.cursorViews.length = 0
    for (const [id, p] of this.player.sim.players) {
      // A player who has not moved yet sits at the origin: not a cursor worth drawing.
      if (p.cursorX === 0 && p.cursorY === 0 && !p.grab) continue
      const who = this.player.people.get(id)
      this.cursorViews.push({
        id,
        name: who?.name ?? `player ${id}`,
        color: who?.color ?? '#888888',
        x: p.cursorX,
        y: p.cursorY,
        body: p.grab ? p.grab.body : 0,
      })
    }
    return this.cursorViews
  }

  contacts(): ContactInfo[] {
    this.contactCache ??= this.world.contacts()
    return this.contactCache
  }

  /** Replays are read only: every tool command is answered with a notice. */
  send(cmd: Command): void {
    if (cmd.k === 'pause') {
      this.playing = !cmd.paused
      return
    }
    if (cmd.k === 'step') {
      void this.stepOnce()
      return
    }
    if (cmd.k === 'move') return
    this.noticeCount++
    this.notice = `a replay is read only: ${cmd.k} is not applied`
  }

  sendGame(kind: string): void {
    this.noticeCount++
    this.notice = `a replay is read only: ${kind} is not applied`
  }

  playerId(): number {
    return 0
  }

  color(): string {
    return '#ff9f1c'
  }

  status(): SandboxStatus {
    return { state: 'offline' }
  }

  stats(): SandboxStats {
    return {
      room: this.player.log.header.room,
      players: this.player.sim.players.size,
      tick: this.player.tick,
      pingMs: null,
      delayMs: null,
      snapshotHz: null,
      downKBs: null,
      upKBs: null,
      awake: this.world.awakeBodyCount(),
      total: this.world.bodyCount,
      stepMs: null,
    }
  }

  rules(): RoomRules | null {
    return null
  }

  scene(): string {
    return this.player.sim.scene
  }

  paused(): boolean {
    return !this.playing
  }

  gravity(): { x: number; y: number } {
    return this.world.getGravity()
  }

  inspect(_bodyId: number): void {}

  lab(bodyId: number): LabData | null {
    return simulationLab(this.player.sim, bodyId, this.contacts())
  }

  notices(): { count: number; latest: string | null } {
    return { count: this.noticeCount, latest: this.notice }
  }

  retry(): void {}

  dispose(): void {
    this.playing = false
    this.player.cancel()
  }
}
