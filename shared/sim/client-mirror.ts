/*
 * A client's copy of a room, built only from server messages: bodies with their shapes and latest
 * poses, user joints, players and cursors, room settings, and the snapshot history that decodes
 * deltas. The browser client, the bots and the tests all use it, so they decode exactly alike.
 *
 * `handle()` applies one server message and returns the ack to send back, if any: every snapshot
 * that decoded is acknowledged, which lets the server advance that client's baseline.
 */
import {
  type AckMessage,
  type AppliedSnapshot,
  type ContactsMessage,
  dequantizeAngle,
  dequantizePosition,
  FRAME_AWAKE,
  type FullState,
  QuantizedFrame,
  type RoomRules,
  type ServerMessage,
  SnapshotHistory,
  type WireBody,
  type WireJoint,
  type WirePlayer,
  type WireShape,
} from '../protocol/index.ts'

/** A body as the client knows it (poses in metres and radians, dequantized). */
export interface MirrorBody {
  id: number
  kind: 0 | 1 | 2
  /** Its shapes in the body frame (at least one). */
  shapes: WireShape[]
  /** 0xRRGGBB when the body has a colour. */
  color?: number
  x: number
  y: number
  angle: number
  awake: boolean
  /** Server tick of the last update of this body. */
  tick: number
  /** For a body a `spawn` input created: the spawner's player id and that input's `seq`. */
  player?: number
  seq?: number
}

/** A player's cursor (m) and grabbed body id (0 when none). */
export interface MirrorCursor {
  x: number
  y: number
  body: number
}

/** The client-side mirror of one room. */
export class ClientMirror {
  /** This client's player id (0 before welcome). */
  clientId = 0
  /** Reconnect token from the welcome. */
  token = ''
  room = ''
  rules: RoomRules | null = null
  scene = ''
  paused = false
  /** Slow motion (1, 2 or 4), the room's creator and whether it locked the controls (FullState, room). */
  slow = 1
  creator = 0
  locked = false
  gravity: [number, number] = [0, -10]
  readonly bodies = new Map<number, MirrorBody>()
  readonly joints = new Map<number, WireJoint>()
  readonly players = new Map<number, WirePlayer>()
  readonly cursors = new Map<number, MirrorCursor>()
  readonly history = new SnapshotHistory()
  /** Newest server tick seen in a welcome, state or snapshot. */
  tick = 0
  /** Last state hash checkpoint from the server. */
  lastHash: { tick: number; step: number; hash: number } | null = null
  /** The last snapshot applied (its frame is reused by the history; copy to keep). */
  lastSnapshot: AppliedSnapshot | null = null
  /** The latest contacts of the body this client inspects (null when none, or after a new world). */
  inspected: ContactsMessage | null = null
  /** The room's game's view for this player (the last `view` message; null before one) and its tick. */
  view: unknown = null
  viewTick = -1
  /** Error messages received (`seq` when the error refused an input that carried one). */
  readonly errors: Array<{ code: string; reason: string; seq?: number }> = []

  /** Apply one server message; returns an ack to send when it was a snapshot that decoded. */
  handle(message: ServerMessage): AckMessage | null {
    switch (message.t) {
      case 'welcome':
        this.clientId = message.id
        this.token = message.token
        this.room = message.room
        this.rules = message.rules
        this.players.clear()
        for (const p of message.players) this.players.set(p.id, p)
        this.loadState(message.state)
        return null
      case 'state':
        this.loadState(message.state)
        return null
      case 'events':
        for (const b of message.add) this.addBody(b)
        for (const id of message.remove) this.removeBody(id)
        for (const j of message.jadd) this.joints.set(j.id, j)
        for (const id of message.jremove) this.joints.delete(id)
        for (const b of message.change ?? []) this.changeBody(b)
        return null
      case 'room':
        this.paused = message.paused
        this.slow = message.slow
        this.creator = message.creator
        this.locked = message.locked
        this.gravity = message.gravity
        this.scene = message.scene
        return null
      case 'players':
        this.players.clear()
        for (const p of message.players) this.players.set(p.id, p)
        for (const id of this.cursors.keys()) if (!this.players.has(id)) this.cursors.delete(id)
        return null
      case 'snap':
        return this.applySnapshot(message.tick, message.base, message.data, message.cursors)
      case 'hash':
        this.lastHash = { tick: message.tick, step: message.step, hash: message.hash }
        return null
      case 'error':
        this.errors.push(
          message.seq === undefined || message.seq === null
            ? { code: message.code, reason: message.reason }
            : { code: message.code, reason: message.reason, seq: message.seq },
        )
        return null
      case 'contacts':
        this.inspected = message
        return null
      case 'view':
        this.view = message.view
        this.viewTick = message.tick
        return null
      default:
        return null
    }
  }

  private loadState(state: FullState): void {
    this.inspected = null
    this.bodies.clear()
    this.joints.clear()
    this.scene = state.scene
    this.paused = state.paused
    this.slow = state.slow ?? 1
    this.creator = state.creator ?? 0
    this.locked = state.locked ?? false
    this.gravity = state.gravity
    this.tick = state.tick
    const frame = new QuantizedFrame()
    for (const b of state.bodies) {
      this.addBody(b)
      if (b.kind !== 0) frame.put(b.id, b.x, b.y, b.a, b.awake === 1)
    }
    for (const j of state.joints) this.joints.set(j.id, j)
    this.history.reset(frame, state.tick)
  }

  private addBody(b: WireBody): void {
    const body: MirrorBody = {
      id: b.id,
      kind: b.kind,
      shapes: b.shapes,
      x: dequantizePosition(b.x),
      y: dequantizePosition(b.y),
      angle: dequantizeAngle(b.a),
      awake: b.awake === 1,
      tick: this.tick,
    }
    if (typeof b.color === 'number') body.color = b.color
    if (typeof b.player === 'number' && typeof b.seq === 'number') {
      body.player = b.player
      body.seq = b.seq
    }
    this.bodies.set(b.id, body)
  }

  /** A body a command changed: the new copy replaces the old (joints kept); a static body leaves the baselines. */
  private changeBody(b: WireBody): void {
    const old = this.bodies.get(b.id)
    if (!old) return
    this.addBody(b)
    const body = this.bodies.get(b.id) as MirrorBody
    if (old.player !== undefined && body.player === undefined) {
      body.player = old.player
      body.seq = old.seq
    }
    if (b.kind === 0) this.history.removeBody(b.id)
  }

  private removeBody(id: number): void {
    if (this.inspected?.body === id) this.inspected = null
    this.bodies.delete(id)
    this.history.removeBody(id)
    for (const [jid, j] of this.joints) if (j.a === id || j.b === id) this.joints.delete(jid)
  }

  private applySnapshot(tick: number, base: number, data: Uint8Array, cursors: number[]): AckMessage | null {
    const applied = this.history.apply(tick, base, data)
    if (!applied) return null
    // Refresh every body from the full state at this tick, not only the listed ones: a body can
    // return to its baseline pose (and so be left out) after an unacknowledged snapshot moved it.
    const frame = applied.frame
    for (let i = 0; i < frame.count; i++) {
      const id = frame.ids[i]
      const body = this.bodies.get(id)
      if (!body) continue
      const x = dequantizePosition(frame.x[id])
      const y = dequantizePosition(frame.y[id])
      const angle = dequantizeAngle(frame.a[id])
      const awake = (frame.flags[id] & FRAME_AWAKE) !== 0
      if (x === body.x && y === body.y && angle === body.angle && awake === body.awake) continue
      body.x = x
      body.y = y
      body.angle = angle
      body.awake = awake
      body.tick = tick
    }
    for (let i = 0; i + 3 < cursors.length; i += 4) {
      this.cursors.set(cursors[i], {
        x: dequantizePosition(cursors[i + 1]),
        y: dequantizePosition(cursors[i + 2]),
        body: cursors[i + 3],
      })
    }
    this.tick = tick
    this.lastSnapshot = applied
    return { t: 'ack', tick }
  }
}
