/*
 * The messages, as TypeScript types. Every WebSocket binary frame holds one MessagePack map with a
 * string field `t` naming its type. Field names are short but readable; PROTOCOL.md is the
 * reference for other languages. Client messages are validated by validate.ts before they reach a
 * room; server messages are trusted by the client but still shape-checked on decode.
 *
 * Quantized values: positions are integers of POSITION_QUANTUM (1 mm), angles integers in
 * [0, ANGLE_STEPS) (one turn = 65536). Body and joint ids are positive integers, never reused
 * within one world epoch (a scene load or reset starts a new epoch with a `state` message).
 */

/**
 * A shape's settings besides its geometry, present only when not the default: density (kg/m^2,
 * default 1), friction (0.6), restitution (0), rolling resistance (0), tangent speed (m/s, 0: a
 * conveyor surface), collision filter [categoryBits, maskBits, groupIndex] ([1, 0xffffffff, 0]) and
 * sensor (false). In a `spawn`, an absent one takes the spawn's own `density`, `friction` or
 * `restitution`, else the default.
 */
export interface WireShapeSettings {
  density?: number
  friction?: number
  restitution?: number
  rolling?: number
  tangent?: number
  filter?: [number, number, number]
  sensor?: boolean
}

/**
 * A shape as it travels, in its body's frame (m): a circle (radius, centre x, y when not the
 * origin), a box (half extents; in a `spawn` also an optional centre x, y and angle, rad; bodies
 * list an offset or turned box as a polygon), a polygon (vertices flat [x0, y0, ...], 3-8 of them,
 * counter-clockwise convex; `radius` > 0 rounds it), a capsule (centres [x1, y1, x2, y2] and
 * radius) or a segment (ends [x1, y1, x2, y2]); in a static `spawn` also a one-sided chain (its
 * points, the first and last ghosts; bodies list its segments as `segment`s); each with its
 * non-default settings.
 */
export type WireShape = WireShapeSettings &
  (
    | { type: 'circle'; radius: number; x?: number; y?: number }
    | { type: 'box'; hw: number; hh: number; x?: number; y?: number; angle?: number }
    | { type: 'polygon'; v: number[]; radius?: number }
    | { type: 'capsule'; v: number[]; radius: number }
    | { type: 'segment'; v: number[] }
    /** Spawns only: a one-sided open chain (engine chain()), its points flat; the first and last are ghosts. */
    | { type: 'chain'; v: number[] }
  )

/** Body type codes: 0 static, 1 kinematic, 2 dynamic. */
export type WireBodyType = 0 | 1 | 2

/** A body as it appears in full states and creation events (positions quantized). */
export interface WireBody {
  id: number
  kind: WireBodyType
  /** The body's shapes, in creation order (at least one). */
  shapes: WireShape[]
  /** The body's colour as 0xRRGGBB, when it has one (bodies players made); absent: drawn by kind. */
  color?: number
  /** Quantized x, y (mm) and angle (1/65536 turn). */
  x: number
  y: number
  a: number
  /** 1 when awake, 0 when asleep. */
  awake: 0 | 1
  /** In `events.add` only, for a body a `spawn` input created: the spawner's player id. */
  player?: number
  /** With `player`: the `seq` of the `spawn` input that created the body. */
  seq?: number
}

/**
 * What a joint is, as drawn: a pin (revolute joint, possibly with a motor, angle limits and a
 * spring), one of the distance joints: a rod (fixed length), a rope (pulls only, up to `max`), a
 * spring (`hz` > 0), or a weld (glued), a slider (prismatic joint along an axis), a wheel (a
 * wheel joint: suspension along an axis, free spin, motor) or a motor joint (drives b to a pose).
 */
export type WireJointKind = 'pin' | 'rod' | 'rope' | 'spring' | 'weld' | 'slider' | 'wheel' | 'motor'

/**
 * A joint as it travels (scene joints and players' joints alike); anchors in each body's local
 * frame (m). Every field is always present: those that do not apply to the kind are 0/false.
 */
export interface WireJoint {
  id: number
  kind: WireJointKind
  /** Body ids; 0 means the fixed world frame. */
  a: number
  b: number
  /** Local anchors (m): on body a (world point when a = 0) and on body b. */
  ax: number
  ay: number
  bx: number
  by: number
  /** Distance joints: rest length (m; a rope's is its longest), and the allowed range [min, max] (m); 0 for pins. */
  length: number
  min: number
  max: number
  /** Springs: stiffness (Hz) and damping ratio; 0 when rigid (a weld: its linear part). */
  hz: number
  damping: number
  /** Pins, welds, sliders, wheels: angle of b minus angle of a at creation (rad); limits and the drawn angle are relative to it. */
  ref: number
  /** Pins: the relative angle (rad); sliders and wheels: the translation (m); kept within [lower, upper] when `limit`. */
  limit: boolean
  lower: number
  upper: number
  /** Pins, wheels: a motor drives the relative angular speed to `speed` (rad/s) with at most `torque` (N m); sliders and distance joints: the translation or length at `speed` (m/s) with at most `force` (N). */
  motor: boolean
  speed: number
  torque: number
  /** Whether the two bodies collide with each other (Box2D's collideConnected). */
  collide: boolean
  /** Largest motor force (N): sliders, distance joints, motor joints. */
  force: number
  /** Sliders, wheels: the axis in body a's frame (unit; the world frame when a = 0). */
  ux: number
  uy: number
  /** Pins, sliders, wheels: whether the spring (`hz`, `damping`) acts. */
  spring: boolean
  /** The spring's target: a pin's angle (rad), a slider's translation (m); a motor joint's angular offset (rad). */
  target: number
  /** Welds: the angular spring (Hz, damping ratio); 0 when rigid. */
  ahz: number
  adamping: number
  /** Motor joints: the share of the pose error closed per sub-step (0-1). */
  correction: number
  /** The joint breaks above this reaction force (N) or torque (N m); 0 never. */
  breakForce: number
  breakTorque: number
  /** The player who made the joint (who may drive its motor); 0 for a scene's joint. */
  owner: number
}

/** A player in the room roster. */
export interface WirePlayer {
  id: number
  name: string
  /** CSS colour, '#rrggbb'. */
  color: string
}

/** The whole room state at one tick: sent in `welcome` and as `state` after a scene load or reset. */
export interface FullState {
  tick: number
  scene: string
  paused: boolean
  gravity: [number, number]
  /** Slow motion: the world steps on room ticks that are multiples of this (1, 2 or 4). */
  slow: number
  /** The room's creator (first player to join; 0 before) and whether it locked the room controls. */
  creator: number
  locked: boolean
  bodies: WireBody[]
  joints: WireJoint[]
}

/** Room rules announced in `welcome`. */
export interface RoomRules {
  tickRate: number
  snapshotRate: number
  maxBodies: number
  maxClients: number
  inputsPerTick: number
  controls: boolean
  scenes: string[]
  worldHalfExtent: number
  /** The game the room runs (docs/games.md), fixed when the room was created. */
  game: string
  /** The game's own command kinds (`cmd` messages), sorted; the built-in ones it accepts go by `input`. */
  commands: string[]
  /**
   * The built-in `input` kinds the game lists, sorted (the sandbox: all of them; a game with its own
   * commands often none). A page offers only the tools and controls whose commands are here or in
   * `commands`.
   */
  builtins: string[]
  /** Spectators the room admits besides its players (join.spectate). */
  maxSpectators: number
}

// ---------------------------------------------------------------- client -> server

/**
 * Spawn a body: exactly one of `shape` (one shape), `shapes` (a compound body, 1 to
 * MAX_BODY_SHAPES shapes) or `outline` (a simple polygon, flat [x0, y0, ...], 3 to 64 points in the
 * body frame, decomposed into convex pieces by the engine). Position (m), angle (rad), velocities
 * (m/s, rad/s); optional material for every shape that does not give its own: density (kg/m^2,
 * default 1), friction (default 0.6), restitution (default 0); `color` 0xRRGGBB (default: the
 * spawner's, by player id); `static` true makes a static body (no velocities).
 */
export interface SpawnCommand {
  k: 'spawn'
  shape?: WireShape
  shapes?: WireShape[]
  outline?: number[]
  x: number
  y: number
  angle?: number
  vx?: number
  vy?: number
  w?: number
  density?: number
  friction?: number
  restitution?: number
  color?: number
  static?: boolean
}
/** Grab a body at a local point (m); the grab target starts at that point's world position. */
export interface GrabCommand {
  k: 'grab'
  body: number
  lx: number
  ly: number
}
/** Move the cursor (m); while grabbing, it is the grab target. */
export interface MoveCommand {
  k: 'move'
  x: number
  y: number
}
/** Release this player's grab. */
export interface ReleaseCommand {
  k: 'release'
}
/** Delete a dynamic body. */
export interface DeleteCommand {
  k: 'delete'
  body: number
}
/** Pin body b (to body a, or to the world when a = 0) at a world point (m). */
export interface PinCommand {
  k: 'pin'
  a: number
  b: number
  x: number
  y: number
}
/** Tie a rope between world points on body a (0 = world) and body b (m); length = their distance. */
export interface RopeCommand {
  k: 'rope'
  a: number
  b: number
  ax: number
  ay: number
  bx: number
  by: number
}
/** Remove a pin or rope. */
export interface UnjointCommand {
  k: 'unjoint'
  joint: number
}
/** Room control: load a scene by name (SCENES). */
export interface SceneCommand {
  k: 'scene'
  name: string
}
/** Room control: pause or resume. */
export interface PauseCommand {
  k: 'pause'
  paused: boolean
}
/** Room control: advance one step while paused. */
export interface StepCommand {
  k: 'step'
}
/** Room control: reload the current scene. */
export interface ResetCommand {
  k: 'reset'
}
/** Room control: set gravity (m/s^2). */
export interface GravityCommand {
  k: 'gravity'
  x: number
  y: number
}

/**
 * Choose the body whose contacts the server streams to this player (the lab's free-body
 * diagram); 0 clears the choice. It changes nothing in the world and is not recorded.
 */
export interface InspectCommand {
  k: 'inspect'
  body: number
}

/** Every input command a client may send. */
export type Command =
  | SpawnCommand
  | GrabCommand
  | MoveCommand
  | ReleaseCommand
  | DeleteCommand
  | PinCommand
  | RopeCommand
  | UnjointCommand
  | SceneCommand
  | PauseCommand
  | StepCommand
  | ResetCommand
  | GravityCommand
  | InspectCommand

/** How a client follows its room: see PROTOCOL.md (join). */
export type JoinMode = 'snapshot' | 'lockstep' | 'predict'

/** First message on a socket: join a room (the URL's ?room= when `room` is empty). */
export interface JoinMessage {
  t: 'join'
  v: number
  room: string
  name: string
  /**
   * 'snapshot' (streamed state), 'lockstep' (a saved world, then the tick stream: the client
   * simulates) or 'predict' (lockstep, and the client applies its own inputs ahead of the server).
   */
  mode: JoinMode
  /** Reconnect token from an earlier welcome, to keep the same player id. */
  token?: string
  /**
   * Lockstep and predict: the most empty ticks (1-60) the server may hold back and send as one
   * `ticks` message (DEFAULT_HOLD when absent); ignored in snapshot mode.
   */
  hold?: number
  /**
   * Join as a spectator: no player slot (not counted against maxClients or the game's players,
   * limited by rules.maxSpectators), no cursor, not in the roster; every input and cmd refused.
   */
  spectate?: boolean
  /**
   * The game the room should run (docs/games.md) when this join creates it; a join that names
   * another game than an open room runs is refused. Absent: whatever the room runs (a new room
   * runs the sandbox).
   */
  game?: string
}
/** One input command with the client's sequence number. */
export interface InputMessage {
  t: 'input'
  seq: number
  cmd: Command
}
/**
 * A game command (docs/games.md): kind `k` with arguments `a` (a map of plain data), checked
 * against the game's JSON Schema before the game sees it.
 */
export interface GameCommandMessage {
  t: 'cmd'
  seq: number
  k: string
  a: Record<string, unknown>
}
/** Acknowledge a snapshot: the server may use its tick as the next baseline. */
export interface AckMessage {
  t: 'ack'
  tick: number
}
/** Clock sync request; `time` is the client's clock (ms), echoed back. */
export interface PingMessage {
  t: 'ping'
  id: number
  time: number
}

/**
 * Lockstep: the client's hash after `tick` differs from the server's; the server counts and logs
 * it and answers with a fresh `sync` (rate limited).
 */
export interface DesyncMessage {
  t: 'desync'
  tick: number
  /** The client's hash at `tick`. */
  hash: number
  /** The server's hash at `tick`, as the client received it. */
  server: number
}
/** Lockstep: the client fell behind or lost its state and asks for a fresh `sync` (rate limited). */
export interface ResyncMessage {
  t: 'resync'
}

/** Every message a client sends. */
export type ClientMessage =
  | JoinMessage
  | InputMessage
  | GameCommandMessage
  | AckMessage
  | PingMessage
  | DesyncMessage
  | ResyncMessage

// ---------------------------------------------------------------- server -> client

/** The events a room's game emitted (ctx.emit) during tick `tick`, in order (snapshot players only). */
export interface GameEventsMessage {
  t: 'game'
  tick: number
  events: unknown[]
}

/**
 * The room's game's view for this player (the game's `view`, plain data of at most MAX_VIEW_BYTES
 * as MessagePack; a game without `view` sends its whole state), sent to a snapshot player when it
 * changed, at most once per snapshot interval.
 */
export interface ViewMessage {
  t: 'view'
  tick: number
  view: unknown
}

/** Reply to join: identity, rules and the full state. */
export interface WelcomeMessage {
  t: 'welcome'
  v: number
  id: number
  token: string
  room: string
  rules: RoomRules
  players: WirePlayer[]
  state: FullState
  /** Something to tell the player in plain words (e.g. the room was restored after a server restart). */
  notice?: string
}
/** A new world epoch (scene load or reset): forget every body and baseline. */
export interface StateMessage {
  t: 'state'
  state: FullState
}
/** Bodies and joints created or removed during one tick (sent before any snapshot using them). */
export interface EventsMessage {
  t: 'events'
  tick: number
  add: WireBody[]
  remove: number[]
  jadd: WireJoint[]
  jremove: number[]
  /**
   * Bodies a command changed (shapes, material, filter, colour, type or pose: the sandbox's edit
   * and transform), as they are at `tick`; absent when none. Replace your copy, keep its joints; a
   * body now static leaves your snapshot baselines.
   */
  change?: WireBody[]
}
/** Room settings changed: pause state, gravity, scene name. */
export interface RoomMessage {
  t: 'room'
  tick: number
  paused: boolean
  gravity: [number, number]
  scene: string
  /** Slow motion (1, 2 or 4), the creator and the control lock, as in FullState. */
  slow: number
  creator: number
  locked: boolean
}
/** The roster changed. */
export interface PlayersMessage {
  t: 'players'
  players: WirePlayer[]
}
/**
 * A snapshot at `tick`, relative to the client's copy at tick `base` (see snapshot-codec.ts for
 * the `data` layout). `cursors` is flat [playerId, x mm, y mm, grabbedBodyId or 0, ...].
 */
export interface SnapshotMessage {
  t: 'snap'
  tick: number
  base: number
  data: Uint8Array
  cursors: number[]
}
/** Clock sync reply: the ping's id and time, and the server's tick (fractional) when answering. */
export interface PongMessage {
  t: 'pong'
  id: number
  time: number
  tick: number
}
/** State hash checkpoint: world.hash() after `step` world steps, at room tick `tick`. */
export interface HashMessage {
  t: 'hash'
  tick: number
  step: number
  hash: number
}
/** The room is held by another server: reconnect to `url` + `/ws?room=` + room and join there. */
export interface MovedMessage {
  t: 'moved'
  room: string
  /** The holding server's WebSocket base URL (ws:// or wss://, no path). */
  url: string
}
/** Something was refused; `code` is machine-readable, `reason` for people. */
export interface ErrorMessage {
  t: 'error'
  code: string
  reason: string
  /** The input's seq when an input was refused. */
  seq?: number
}

/** One contact point: world position (m) and the impulses of the last step (N s). */
export interface WireContactPoint {
  x: number
  y: number
  /** Normal impulse, along +normal on body b and -normal on body a. */
  n: number
  /** Friction impulse along the tangent (ny, -nx), with the same sign rule. */
  t: number
}

/** A touching contact between bodies a and b (a < b as the engine orders them), normal from a to b. */
export interface WireContact {
  a: number
  b: number
  nx: number
  ny: number
  points: WireContactPoint[]
}

/** Kinds of joint force on an inspected body: a joint's kind, or a player's grab. */
export type WireJointForceKind = WireJointKind | 'grab'

/** A joint's (or a grab's) force on the inspected body in the last step. */
export interface WireJointForce {
  /** The joint id (a grab's joint id is not in any joint list). */
  id: number
  kind: WireJointForceKind
  /** World point where it acts on the inspected body (m). */
  x: number
  y: number
  /** Force on the inspected body (N) and pure torque on it besides the force's moment (N m). */
  fx: number
  fy: number
  torque: number
}

/**
 * The contacts touching the body this player inspects, sent right after each of its snapshots
 * while it inspects one (at most MAX_INSPECT_CONTACTS of them, the largest normal impulses).
 */
export interface ContactsMessage {
  t: 'contacts'
  tick: number
  body: number
  /** The body's mass (kg). */
  mass: number
  /** Touching contacts of the body in all, sent or not. */
  total: number
  contacts: WireContact[]
  /** The body's moment of inertia about its centre of mass (kg m^2). */
  inertia: number
  /** The body's velocity (m/s) and angular velocity (rad/s) after the last step. */
  vx: number
  vy: number
  w: number
  /** Every joint and grab acting on the body (at most MAX_INSPECT_CONTACTS, the largest forces). */
  joints: WireJointForce[]
}

/**
 * Lockstep: the room's simulation after tick `tick` (the world's saved bytes and the room state
 * around it, see sync-payload.ts), deflated when `z`. The `ticks` that follow continue from it.
 */
export interface SyncMessage {
  t: 'sync'
  tick: number
  /** True when `data` is zlib-compressed (RFC 1950). */
  z: boolean
  data: Uint8Array
}
/**
 * Lockstep: ticks `tick` .. `tick + n - 1` in order; `c` lists their entries
 * [tick offset, player, kind code, ...arguments] (tick-stream.ts); `hash`, when present, is the
 * state hash after the last of them.
 */
export interface TicksMessage {
  t: 'ticks'
  tick: number
  n: number
  c: unknown[][]
  hash?: number
}

/** The room saved its world as scene file `id` (GET /scenes/ID) for the `saveScene` command `seq`. */
export interface SceneSavedMessage {
  t: 'scene'
  seq: number
  id: string
}

/** Every message the server sends. */
export type ServerMessage =
  | SceneSavedMessage
  | GameEventsMessage
  | ViewMessage
  | SyncMessage
  | TicksMessage
  | WelcomeMessage
  | StateMessage
  | EventsMessage
  | RoomMessage
  | PlayersMessage
  | SnapshotMessage
  | PongMessage
  | HashMessage
  | ErrorMessage
  | MovedMessage
  | ContactsMessage
