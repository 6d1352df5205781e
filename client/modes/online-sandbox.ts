/*
 * Online mode: a server room mirrored in the page. Server messages go into the shared
 * ClientMirror (the one decoder every client uses); each decoded snapshot's full frame is copied
 * into the SnapshotTimeline, which draws bodies a little in the past between two snapshots. Inputs
 * go out as protocol commands; cursor moves are coalesced to at most one per animation frame so a
 * 1000 Hz mouse never exceeds the room's per-tick input budget. Ping/pong once a second measures
 * the round trip. Byte counters give the HUD its kB/s. The lab asks the server to inspect the
 * selected body (re-asked after a reconnect or a new world, which clear it on the server) and
 * shows the contacts the server streams back.
 */
import type { Vec2 } from '../../engine/index.ts'
import {
  ClientMirror,
  type Command,
  type ContactsMessage,
  cssColor,
  type JoinMessage,
  type MirrorBody,
  type PlainData,
  PROTOCOL_VERSION,
  ROOM_NAME_PATTERN,
  type RoomRules,
  type ServerMessage,
  type SimCommand,
  TICK_RATE,
} from '../../shared/index.ts'
import { labFromServer, viewJoints } from '../draw/index.ts'
import { Connection, InputOutbox, MAX_SENDS, type Pose, ServerStats, SnapshotTimeline } from '../net/index.ts'
import { findClientGame, loadGameModule } from './game-modules.ts'
import { NoticeLog } from './notice-log.ts'
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

/** Where and how to join. */
export interface OnlineOptions {
  /** WebSocket URL without the query, e.g. ws://host:8080/ws. */
  url: string
  room: string
  name: string
  /** Access key for a server with join or admin tokens (the page's `?key=`), sent as `&key=`. */
  key?: string
  /** The game a room this join creates runs (the page's `&game=`). */
  game?: string
}

const TOKEN_KEY = 'concord.token.'
/** Largest shift of the own grabbed body by visual prediction (m). */
const MAX_PREDICTION = 2

/** Per-second rate counter. */
class Rate {
  private count = 0
  private windowStart = Number.NaN
  value = 0
  add(n: number, nowMs: number): void {
    this.tick(nowMs)
    this.count += n
  }
  tick(nowMs: number): void {
    if (Number.isNaN(this.windowStart)) this.windowStart = nowMs
    const elapsed = nowMs - this.windowStart
    if (elapsed >= 1000) {
      this.value = (this.count * 1000) / elapsed
      this.count = 0
      this.windowStart = nowMs
    }
  }
}

/** The sandbox mirroring a server room. */
export class OnlineSandbox implements Sandbox {
  readonly mode = 'online'
  readonly mirror = new ClientMirror()
  readonly timeline = new SnapshotTimeline()
  private readonly connection: Connection | null
  private readonly view: ViewBody[] = []
  private readonly viewById = new Map<number, ViewBody>()
  private viewDirty = true
  private pendingMove: Command | null = null
  /** Commands waiting for room in the input budget, in order (and spawns followed until seen). */
  private readonly outbox = new InputOutbox(
    (cmd) => this.transmit(cmd, this.outboxNow),
    (text) => this.tell(text),
  )
  private outboxNow = 0
  /** Inputs the server dropped over the budget since the last notice. */
  private droppedInputs = 0
  /** This page asked for a scene load or reset: the next new world is its own doing. */
  private ownLoad = false
  private seq = 0
  /** Scene ids answering this page's saveScene commands, by seq. */
  private readonly saved = new Map<number, string>()
  private pingId = 0
  private lastPing = 0
  private rttMs: number | null = null
  private readonly down = new Rate()
  private readonly up = new Rate()
  private readonly snaps = new Rate()
  private statusValue: SandboxStatus = { state: 'connecting' }
  private ownGrab = 0
  /** The latest grab target this page sent (m): where its own grabbed body is heading. */
  private localTarget: { x: number; y: number } | null = null
  /** Players whose cursor has left the origin (a new player's cursor starts there). */
  private readonly movedCursors = new Set<number>()
  private renderTick = Number.NaN
  private readonly pose: Pose = { x: 0, y: 0, angle: 0, awake: true }
  /** The body this player inspects (0 for none), and the lab data last built for it. */
  private inspected = 0
  private labCache: { message: ContactsMessage; data: LabData } | null = null
  private readonly notice = new NoticeLog()
  private readonly serverStats: ServerStats

  constructor(private readonly options: OnlineOptions) {
    const key = options.key ? `&key=${encodeURIComponent(options.key)}` : ''
    const url = `${options.url}?room=${encodeURIComponent(options.room)}${key}`
    this.serverStats = new ServerStats(options.url.replace(/^ws/, 'http').replace(/\/ws$/, ''))
    if (!ROOM_NAME_PATTERN.test(options.room)) {
      // No server accepts such a name: say so instead of retrying a connection that cannot work.
      const shown = options.room.length > 40 ? `${options.room.slice(0, 40)}…` : options.room
      this.statusValue = {
        state: 'error',
        message: `The room name "${shown}" in the address is not valid: a room name is 1-32 letters, digits, - or _. Open the Rooms list or fix the address.`,
        retrying: false,
      }
      this.connection = null
      return
    }
    this.connection = new Connection(url, () => this.joinMessage(), {
      message: (m, bytes) => this.receive(m, bytes),
      status: (text, retrying, fatal, retryAt) => {
        this.statusValue =
          text === null
            ? { state: 'connected' }
            : { state: 'error', message: text, retrying: retrying && !fatal, retryAt }
      },
    })
  }

  private joinMessage(): JoinMessage {
    let token: string | undefined
    try {
      token = sessionStorage.getItem(TOKEN_KEY + this.options.room) ?? undefined
    } catch {
      token = undefined
    }
    return {
      t: 'join',
      v: PROTOCOL_VERSION,
      room: this.options.room,
      name: this.options.name,
      mode: 'snapshot',
      ...(token ? { token } : {}),
      ...(this.options.game ? { game: this.options.game } : {}),
    }
  }

  private receive(message: ServerMessage, bytes: number): void {
    const now = performance.now()
    this.down.add(bytes, now)
    if (message.t === 'pong') {
      this.rttMs = now - message.time
      return
    }
    if (message.t === 'scene') this.saved.set(message.seq, message.id)
    if (message.t === 'error' && message.code === 'refused') this.tell(message.reason)
    if (message.t === 'error' && message.seq !== undefined) {
      if (message.code === 'input-budget') this.outbox.dropped(message.seq)
      else this.outbox.spawns.refused(message.seq)
    }
    if (message.t === 'events') for (const b of message.add) this.outbox.spawns.added(b, this.mirror.clientId)
    if (message.t === 'error' && message.code === 'input-budget') this.droppedInputs++
    if (message.t === 'events' && this.ownGrab && message.remove.includes(this.ownGrab)) {
      this.tell('The body you were holding was deleted by another player or left the world.')
      this.ownGrab = 0
    }
    if (message.t === 'state') {
      if (!this.ownLoad) this.tell(`Another player loaded the scene "${message.state.scene}".`)
      this.ownLoad = false
    }
    const ack = this.mirror.handle(message)
    switch (message.t) {
      case 'welcome':
        try {
          sessionStorage.setItem(TOKEN_KEY + this.options.room, message.token)
        } catch {}
        this.ownGrab = 0
        this.outbox.spawns.clear()
        this.resetTimeline(message.state.tick, now, message.rules)
        this.reinspect(now)
        if (message.notice) this.tell(message.notice)
        this.loadGame(message.rules.game)
        break
      case 'state':
        this.ownGrab = 0
        this.outbox.spawns.clear()
        this.resetTimeline(message.state.tick, now, this.mirror.rules)
        this.reinspect(now)
        break
      case 'events':
        this.viewDirty = true
        for (const b of message.change ?? []) this.timeline.forget(b.id)
        break
      case 'snap': {
        const applied = this.mirror.lastSnapshot
        if (ack && applied) {
          this.up.add(this.connection!.send(ack), now)
          this.timeline.push(applied.tick, applied.frame, now, applied.updated)
          const c = message.cursors
          for (let i = 0; i + 3 < c.length; i += 4) {
            // A player who has not moved yet sits at the origin: not a cursor worth drawing.
            if (c[i + 1] !== 0 || c[i + 2] !== 0 || c[i + 3] !== 0) this.movedCursors.add(c[i])
            this.timeline.pushCursor(c[i], applied.tick, c[i + 1] / 1000, c[i + 2] / 1000)
          }
          this.snaps.add(1, now)
        }
        break
      }
    }
  }

  /**
   * A room of a game this build does not ship (--games on the server): import its module for its
   * client module (game-modules.ts); the snapshots need no game code, so a failure is a notice.
   */
  private loadGame(game: string): void {
    if (!game || findClientGame(game)) return
    loadGameModule(this.options.url, game).catch((error: Error) =>
      this.tell(`The game ${game}'s page module did not load: ${error.message}`),
    )
  }

  /** A new session or a new world cleared the server's inspection: ask again if a body is still selected. */
  private reinspect(now: number): void {
    if (!this.inspected) return
    if (this.mirror.bodies.get(this.inspected)?.kind === 2)
      this.transmit({ k: 'inspect', body: this.inspected }, now)
    else this.inspected = 0
  }

  private resetTimeline(tick: number, now: number, rules: RoomRules | null): void {
    if (rules) this.timeline.nominalInterval = this.timeline.intervalTicks = TICK_RATE / rules.snapshotRate
    this.timeline.clear()
    const frame = this.mirror.history.get(tick)
    if (frame) this.timeline.push(tick, frame, now)
    this.viewDirty = true
  }

  update(nowMs: number): void {
    this.outbox.startFrame()
    if (this.connection?.isJoined) {
      this.reportDropped()
      this.drainOutbox(nowMs)
    }
    if (this.pendingMove && this.outbox.length === 0) {
      this.transmit(this.pendingMove, nowMs)
      this.pendingMove = null
    }
    if (nowMs - this.lastPing >= 1000 && this.connection?.isJoined) {
      this.lastPing = nowMs
      this.up.add(this.connection!.send({ t: 'ping', id: ++this.pingId, time: nowMs }), nowMs)
    }
    if (this.connection?.isJoined) this.serverStats.poll(nowMs)
    this.down.tick(nowMs)
    this.up.tick(nowMs)
    this.snaps.tick(nowMs)
    const tick = this.timeline.advance(nowMs)
    this.renderTick = tick
    this.refreshView(tick)
    this.predictOwnGrab(tick)
  }

  private refreshView(tick: number): void {
    if (this.viewDirty || this.view.length !== this.mirror.bodies.size) this.rebuildView()
    const grabbed = new Map<number, string>()
    for (const [id, c] of this.mirror.cursors) {
      if (c.body && id !== this.mirror.clientId)
        grabbed.set(c.body, this.mirror.players.get(id)?.color ?? '#fff')
    }
    if (this.ownGrab) grabbed.set(this.ownGrab, this.color())
    const pose = this.pose
    for (const v of this.view) {
      const m = this.mirror.bodies.get(v.id)
      if (!m) continue
      if (m.kind !== 0 && !Number.isNaN(tick) && this.timeline.sample(v.id, tick, pose)) {
        v.x = pose.x
        v.y = pose.y
        v.angle = pose.angle
        v.awake = pose.awake
      } else {
        v.x = m.x
        v.y = m.y
        v.angle = m.angle
        v.awake = m.awake
      }
      v.grabColor = grabbed.get(v.id) ?? null
    }
  }

  /**
   * Visual prediction of this player's own grab: the grabbed body is drawn shifted by how far the
   * local cursor has moved beyond the cursor the server had at the drawn tick, so it follows the
   * hand at once; as the server's poses catch up, the shift shrinks to zero by itself.
   */
  private predictOwnGrab(tick: number): void {
    if (!this.ownGrab || !this.localTarget || Number.isNaN(tick)) return
    const v = this.viewById.get(this.ownGrab)
    const server = this.pose
    if (!v || !this.timeline.sampleCursor(this.mirror.clientId, tick, server)) return
    let dx = this.localTarget.x - server.x
    let dy = this.localTarget.y - server.y
    const d = Math.sqrt(dx * dx + dy * dy)
    if (d > MAX_PREDICTION) {
      dx *= MAX_PREDICTION / d
      dy *= MAX_PREDICTION / d
    }
    v.x += dx
    v.y += dy
  }

  private rebuildView(): void {
    this.view.length = 0
    const alive = new Set<number>()
    for (const m of this.mirror.bodies.values()) {
      let v = this.viewById.get(m.id)
      if (!v || v.shapes !== m.shapes) v = this.makeView(m)
      this.view.push(v)
      alive.add(m.id)
    }
    for (const id of this.viewById.keys()) if (!alive.has(id)) this.viewById.delete(id)
    this.view.sort((a, b) => a.kind - b.kind || a.id - b.id)
    this.viewDirty = false
  }

  private makeView(m: MirrorBody): ViewBody {
    const v: ViewBody = { ...m, color: cssColor(m.color), grabColor: null }
    this.viewById.set(m.id, v)
    return v
  }

  bodies(): readonly ViewBody[] {
    return this.view
  }

  joints(): readonly ViewJoint[] {
    const forces = this.jointForces()
    return viewJoints(
      this.mirror.joints.values(),
      (id) => this.viewById.get(id),
      (id) => forces.get(id) ?? null,
    )
  }

  /** Reaction forces on each joint's body b (N) for the joints acting on the inspected body (the only ones the server sends). */
  private jointForces(): Map<number, Vec2> {
    const out = new Map<number, Vec2>()
    const message = this.mirror.inspected
    if (!message || message.body !== this.inspected) return out
    for (const f of message.joints) {
      const j = this.mirror.joints.get(f.id)
      if (!j) continue
      const sign = j.b === message.body ? 1 : -1
      out.set(f.id, { x: sign * f.fx, y: sign * f.fy })
    }
    return out
  }

  cursors(): readonly ViewCursor[] {
    const out: ViewCursor[] = []
    const at = this.pose
    for (const [id, c] of this.mirror.cursors) {
      const p = this.mirror.players.get(id)
      if (id === this.mirror.clientId || !p || !this.movedCursors.has(id)) continue
      // Drawn on the bodies' delayed timeline, so a held body and its cursor move together.
      const smooth = !Number.isNaN(this.renderTick) && this.timeline.sampleCursor(id, this.renderTick, at)
      out.push({
        id,
        name: p.name,
        color: p.color,
        x: smooth ? at.x : c.x,
        y: smooth ? at.y : c.y,
        body: c.body,
      })
    }
    return out
  }

  contacts(): readonly LabContact[] | null {
    return this.inspected ? (this.lab(this.inspected)?.contacts ?? null) : null
  }

  send(cmd: Command): void {
    const now = performance.now()
    if (cmd.k === 'move') {
      if (this.ownGrab) this.localTarget = { x: cmd.x, y: cmd.y }
      this.pendingMove = cmd
      return
    }
    // Keep the order of what the player did: a cursor move made before this command goes first.
    if (this.pendingMove) {
      this.outbox.push(this.pendingMove)
      this.pendingMove = null
    }
    if (cmd.k === 'grab') {
      this.ownGrab = cmd.body
      this.localTarget = null
    }
    if (cmd.k === 'release') this.ownGrab = 0
    if (cmd.k === 'delete' && cmd.body === this.ownGrab) this.ownGrab = 0
    if (cmd.k === 'scene' || cmd.k === 'reset') this.ownLoad = true
    this.outbox.push(cmd)
    this.drainOutbox(now)
  }

  roomCommand(kind: string, args: { [key: string]: PlainData }): number | null {
    if (!this.connection?.isJoined) return null
    const seq = ++this.seq
    if (kind === 'openScene') this.ownLoad = true
    this.up.add(this.connection.send({ t: 'cmd', seq, k: kind, a: args }), performance.now())
    return seq
  }

  savedScenes(): ReadonlyMap<number, string> {
    return this.saved
  }

  sendGame(kind: string, args: { [key: string]: PlainData }): void {
    // In order with the built-in commands: a cursor move made before it goes first.
    if (this.pendingMove) {
      this.outbox.push(this.pendingMove)
      this.pendingMove = null
    }
    this.outbox.push({ k: 'cmd', kind, a: args })
    this.drainOutbox(performance.now())
  }

  playerId(): number {
    return this.mirror.clientId
  }

  gameState(): unknown {
    return this.mirror.view
  }

  people(): readonly PersonRow[] {
    const m = this.mirror
    const out: PersonRow[] = []
    for (const p of m.players.values()) {
      const self = p.id === m.clientId
      const holds = self ? this.ownGrab : (m.cursors.get(p.id)?.body ?? 0)
      out.push({ id: p.id, name: p.name, color: p.color, self, creator: p.id === m.creator, holds })
    }
    return out.sort((a, b) => a.id - b.id)
  }

  roomControl(): RoomControl {
    const m = this.mirror
    return { slow: m.slow, creator: m.creator, locked: m.locked, self: m.clientId }
  }

  /** One notice for the inputs the server dropped since the last frame, and the spawns sent again. */
  private reportDropped(): void {
    const resent = this.outbox.takeResent()
    const givenUp = this.outbox.takeGivenUp()
    if (this.droppedInputs === 0 && resent === 0 && givenUp === 0) return
    const again = resent > 0 ? `; the ${resent} new shapes among them are sent again` : ''
    const lost = givenUp > 0 ? `; ${givenUp} new shapes were lost after ${MAX_SENDS} tries` : ''
    this.tell(`The room was too busy for ${this.droppedInputs} of your actions at once${again}${lost}.`)
    this.droppedInputs = 0
  }

  /** Show the player a notice. */
  private tell(text: string): void {
    this.notice.add(text)
  }

  /** Send one command now; spawns are followed until the world shows them. */
  private transmit(cmd: SimCommand, now: number): void {
    if (!this.connection) return
    if (cmd.k === 'cmd') {
      this.up.add(
        this.connection.send({ t: 'cmd', seq: ++this.seq, k: cmd.kind, a: cmd.a as Record<string, unknown> }),
        now,
      )
      return
    }
    this.up.add(this.connection.send({ t: 'input', seq: ++this.seq, cmd }), now)
    if (cmd.k === 'spawn') this.outbox.spawns.sent(this.seq, cmd)
  }

  /** Send what the input budget allows of the queued commands. */
  private drainOutbox(now: number): void {
    this.outboxNow = now
    this.outbox.drain(this.mirror.rules?.inputsPerTick ?? 8)
  }

  color(): string {
    return this.mirror.players.get(this.mirror.clientId)?.color ?? '#ff9f1c'
  }

  status(): SandboxStatus {
    return this.statusValue
  }

  stats(): SandboxStats {
    let awake = 0
    for (const v of this.view) if (v.kind !== 0 && v.awake) awake++
    return {
      room: this.mirror.room || this.options.room,
      players: this.mirror.players.size,
      tick: Math.floor(this.mirror.tick),
      pingMs: this.rttMs,
      delayMs: (this.timeline.delayTicks * 1000) / TICK_RATE,
      snapshotHz: this.snaps.value,
      downKBs: this.down.value / 1000,
      upKBs: this.up.value / 1000,
      awake,
      total: this.mirror.bodies.size,
      stepMs: this.serverStats.tickMs,
    }
  }

  rules(): RoomRules | null {
    const rules = this.mirror.rules
    // The room's controls, unless this page's key does not open them (the server has an admin key).
    if (!rules?.controls || this.connection?.controlsAllowed !== false) return rules
    return { ...rules, controls: false }
  }

  scene(): string {
    return this.mirror.scene
  }

  paused(): boolean {
    return this.mirror.paused
  }

  gravity(): { x: number; y: number } {
    return { x: this.mirror.gravity[0], y: this.mirror.gravity[1] }
  }

  inspect(bodyId: number): void {
    const body = this.mirror.bodies.get(bodyId)
    const id = body?.kind === 2 ? bodyId : 0
    if (id === this.inspected) return
    this.inspected = id
    if (this.connection?.isJoined) this.transmit({ k: 'inspect', body: id }, performance.now())
  }

  lab(bodyId: number): LabData | null {
    const message = this.mirror.inspected
    if (!message || message.body !== bodyId || bodyId !== this.inspected) return null
    if (this.labCache?.message !== message) {
      this.labCache = { message, data: labFromServer(message, this.gravity()) }
    }
    return this.labCache.data
  }

  notices(): { count: number; latest: string | null; recent: readonly string[] } {
    return this.notice
  }

  retry(): void {
    this.connection?.retryNow()
  }

  dispose(): void {
    this.connection?.close()
  }
}
