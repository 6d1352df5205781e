/*
 * The seam between the page and where the physics runs. An online sandbox mirrors a server room
 * (snapshots, interpolation); an offline sandbox runs the room's simulation in the page. Both
 * speak the wire protocol's Command type, so every tool produces the same commands whichever side
 * applies them, and both hand the renderer the same view: bodies with poses for this frame,
 * joints, cursors.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { SceneFile } from '../../games/index.ts'
import type {
  Command,
  PlainData,
  RoomRules,
  WireJoint,
  WireJointForceKind,
  WireJointKind,
  WireShape,
} from '../../shared/index.ts'

/** A body as drawn this frame. */
export interface ViewBody {
  id: number
  /** 0 static, 1 kinematic, 2 dynamic. */
  kind: 0 | 1 | 2
  /** Its shapes in the body frame (at least one). */
  shapes: WireShape[]
  /** Its colour as CSS '#rrggbb' (bodies players made), or null: drawn in its kind's colour. */
  color: string | null
  x: number
  y: number
  angle: number
  awake: boolean
  /** Colour of the player grabbing it, or null. */
  grabColor: string | null
}

/** A joint as drawn this frame: its wire description placed on this frame's body poses. */
export interface ViewJoint {
  id: number
  kind: WireJointKind
  /** The joint's kind and parameters as they travel. */
  spec: WireJoint
  /** World anchors (m) on body a (or the world) and on body b. */
  ax: number
  ay: number
  bx: number
  by: number
  /** Angle of body a (rad), 0 for the world. */
  angleA: number
  /** Pins, welds, sliders, wheels: the relative angle (angle b - angle a - ref) in (-pi, pi] (rad). */
  angle: number
  /** Sliders and wheels: the axis in the world now (unit), and the translation along it (m, 0 when made). */
  axisX: number
  axisY: number
  translation: number
  /** Reaction force on body b at its anchor in the last step (N); body a feels the opposite. Null when unknown. */
  force: Vec2 | null
}

/** Another player's cursor (m) with its grab. */
export interface ViewCursor {
  id: number
  name: string
  color: string
  x: number
  y: number
  /** Grabbed body id, 0 when none. */
  body: number
}

/** A player in the room's list (the page's player list). */
export interface PersonRow {
  id: number
  name: string
  /** CSS '#rrggbb'. */
  color: string
  /** This page's player. */
  self: boolean
  /** The room's creator (who may lock the room controls). */
  creator: boolean
  /** The body this player holds, 0 when none. */
  holds: number
}

/** Numbers for the HUD; null where a mode has no such number. */
export interface SandboxStats {
  room: string
  players: number
  tick: number
  pingMs: number | null
  delayMs: number | null
  snapshotHz: number | null
  downKBs: number | null
  upKBs: number | null
  awake: number
  total: number
  stepMs: number | null
  /** Lockstep and predict modes only (lockstep-sandbox.ts). */
  lockstep?: LockstepStats
}

/** What the HUD shows in lockstep and predict modes; null where lockstep has no such number. */
export interface LockstepStats {
  mode: 'lockstep' | 'predict'
  /** 'loading', 'running' or 'repairing' (waiting for a sync). */
  state: string
  /** Last tick whose state hash matched the server's. */
  verifiedTick: number
  desyncs: number
  resyncs: number
  rollbacksPerSecond: number | null
  /** Depth of the last rollback (ticks). */
  rollbackDepth: number | null
  /** Re-simulation time per frame (ms, smoothed). */
  resimMs: number | null
}

/**
 * A touching contact as the lab and the debug layer need it: the engine's ContactInfo without the
 * separations. Normal from A to B; impulses of the last step (N s), tangent (normal.y, -normal.x).
 */
export interface LabContact {
  bodyA: number
  bodyB: number
  normal: Vec2
  points: ReadonlyArray<{ point: Vec2; normalImpulse: number; tangentImpulse: number }>
}

/** A joint's or grab's force on the lab's body (N) at a world point (m). */
export interface LabJointForce {
  id: number
  kind: WireJointForceKind
  point: Vec2
  force: Vec2
}

/** Everything the lab needs about one body, with where it came from. */
export interface LabData {
  contacts: readonly LabContact[]
  joints: readonly LabJointForce[]
  mass: number
  /** Moment of inertia (kg m^2). */
  inertia: number
  /** Velocity (m/s) and angular velocity (rad/s). */
  velocity: Vec2
  angularVelocity: number
  gravity: { x: number; y: number }
  /** 'world' when read from the world stepping in the page, 'server' when the room's server sent it. */
  source: 'world' | 'server'
}

/** What the page shows of slow motion and the control lock (PROTOCOL.md `room`). */
export interface RoomControl {
  slow: number
  creator: number
  locked: boolean
  self: number
}

/** Connection status shown to the user. */
export type SandboxStatus =
  | { state: 'connecting' }
  | { state: 'connected' }
  | { state: 'offline' }
  | { state: 'error'; message: string; retrying: boolean; retryAt?: number }

/** A running sandbox, online or offline. */
export interface Sandbox {
  /** Where the physics runs: a server room, this page, or a recorded log played in this page. */
  readonly mode: 'online' | 'offline' | 'replay'
  /** Advance to this animation frame (ms, performance.now()); cheap when nothing changed. */
  update(nowMs: number): void
  /** Bodies to draw this frame (the array and objects are reused between frames). */
  bodies(): readonly ViewBody[]
  joints(): readonly ViewJoint[]
  /** Other players' cursors (not this player's own). */
  cursors(): readonly ViewCursor[]
  /** Touching contacts for the debug layer, when this mode has them. */
  contacts(): readonly LabContact[] | null
  /** Apply or send one command. */
  send(cmd: Command): void
  /** Apply or send one game command (the sandbox's joint commands: weld, hinge, ...). */
  sendGame(kind: string, args: { [key: string]: PlainData }): void
  /** This player's id in the room (offline 1: the page's room has one player; 0 in replays). */
  playerId(): number
  /** Slow motion (1, 2 or 4), the room's creator and control lock, and this player's id. */
  roomControl?(): RoomControl
  /** Everyone in the room, by id: names, colours, the creator, who holds what. Absent offline. */
  people?(): readonly PersonRow[]
  /**
   * The game state this page has for the room's game's client module (docs/games.md, "Client
   * modules"): the player's game view when the game has one (received or computed), else the
   * simulation's game state where the page simulates, else null. Absent offline and in replays.
   */
  gameState?(): unknown
  /** This player's colour. */
  color(): string
  status(): SandboxStatus
  stats(): SandboxStats
  rules(): RoomRules | null
  scene(): string
  paused(): boolean
  gravity(): { x: number; y: number }
  /** Choose the body the lab shows (0 for none); online, the server then streams its contacts. */
  inspect(bodyId: number): void
  /** Free-body data for one body, or null when it does not exist or its data has not arrived. */
  lab(bodyId: number): LabData | null
  /**
   * Problems the server reported about this player's inputs: how many so far, the newest, and
   * (where a mode keeps them) the last few, oldest first, so two in quick succession both show.
   */
  notices(): { count: number; latest: string | null; recent?: readonly string[] }
  /**
   * Send a room or game command (`cmd`: e.g. the room commands openScene and saveScene); its seq,
   * or null where there is no server (offline, replay). Absent in modes without a server.
   */
  roomCommand?(kind: string, args: { [key: string]: PlainData }): number | null
  /** The scene ids the server answered this page's saveScene commands with, by the command's seq. */
  savedScenes?(): ReadonlyMap<number, string>
  /**
   * The world as a scene file's text (docs/scene-format.md) named `name`, made in the page: where
   * the room runs in the page (offline); online, the server saves (roomCommand saveScene).
   */
  sceneFile?(name: string): string
  /** Open a checked scene file (`name`: its file name) into the room in the page; null, or why not. */
  openSceneFile?(scene: SceneFile, name: string): string | null
  /** Reconnect now instead of waiting for the backoff (no-op offline). */
  retry(): void
  /** Close sockets and timers. */
  dispose(): void
}
