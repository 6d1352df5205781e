/*
 * Protocol constants shared by the server, the browser client and the bots. Changing anything
 * that alters the bytes on the wire means bumping PROTOCOL_VERSION.
 */

/** Wire protocol version; a join with another version is refused with an error naming both. */
export const PROTOCOL_VERSION = 3

/** Simulation rate (Hz): the server steps every room 60 times per second. */
export const TICK_RATE = 60

/** Position quantum (m): positions travel as integers of 1 mm. */
export const POSITION_QUANTUM = 0.001

/** Angle resolution (steps per turn): 16 bits per turn, about 0.0055 degrees. */
export const ANGLE_STEPS = 65536

/** Velocity quantum (m/s or rad/s) for the few places velocities travel (events). */
export const VELOCITY_QUANTUM = 0.001

/** Half size of the square world inputs are clamped to (m): x and y in [-WORLD_HALF_EXTENT, +]. */
export const WORLD_HALF_EXTENT = 500

/** Bodies further than this from the origin (m) are removed by the room, so numbers stay small. */
export const KILL_DISTANCE = 1000

/**
 * The kill plane (m): a body below it has left the world (flung off the ground, which every scene
 * puts at y = 0) and is removed, so it neither falls forever awake nor stretches the camera's fit.
 */
export const KILL_PLANE_Y = -50

/** Longest player name (UTF-16 code units). */
export const MAX_NAME_LENGTH = 32

/** Longest room name; room names match ROOM_NAME_PATTERN. */
export const MAX_ROOM_NAME_LENGTH = 32

/** Allowed room names: letters, digits, dash and underscore. */
export const ROOM_NAME_PATTERN = /^[A-Za-z0-9_-]{1,32}$/

/** Players' colours by id ('#rrggbb'): player id i has PLAYER_PALETTE[(i - 1) % 12], its cursor and its bodies' default. */
export const PLAYER_PALETTE: readonly string[] = [
  '#e6194b',
  '#3cb44b',
  '#4363d8',
  '#f58231',
  '#911eb4',
  '#42d4f4',
  '#f032e6',
  '#bfef45',
  '#fabed4',
  '#469990',
  '#dcbeff',
  '#9a6324',
]

/** The default colour (0xRRGGBB) of the bodies a player spawns: its roster colour. */
export function playerBodyColor(playerId: number): number {
  const n = PLAYER_PALETTE.length
  return Number.parseInt(PLAYER_PALETTE[(((playerId - 1) % n) + n) % n].slice(1), 16)
}

/** A 0xRRGGBB colour as CSS '#rrggbb'; null for none. */
export function cssColor(rgb: number | undefined | null): string | null {
  return typeof rgb === 'number' ? `#${(rgb & 0xffffff).toString(16).padStart(6, '0')}` : null
}

/** Most shapes a `spawn` may list in `shapes` (an `outline` may decompose into more pieces). */
export const MAX_BODY_SHAPES = 16

/** Ranges of a shape's rolling resistance (dimensionless) and tangent speed (m/s) on the wire, [min, max]. */
export const SHAPE_SETTINGS = {
  rolling: [0, 10],
  tangent: [-100, 100],
} as const

/**
 * Largest spawned shape extent (m): a circle's, capsule's or rounded polygon's radius, a box's half
 * size, and every coordinate of a vertex, end or centre in the body frame (|x|, |y|).
 */
export const MAX_SHAPE_EXTENT = 10

/** Smallest spawned shape extent (m). */
export const MIN_SHAPE_EXTENT = 0.05

/** Largest spawn speed (m/s) and angular speed (rad/s). */
export const MAX_SPAWN_SPEED = 100

/** Largest gravity component a room control may set (m/s^2). */
export const MAX_GRAVITY = 100

/** Largest rope length (m). */
export const MAX_ROPE_LENGTH = 100

/** Most contacts one `contacts` message carries (each has at most 2 points): about 2 kB. */
export const MAX_INSPECT_CONTACTS = 16

/**
 * Largest `join.hold` (ticks): the most empty ticks the server may hold back before it sends them
 * to a lockstep or predict client as one `ticks` message (a hash checkpoint, every 60 ticks, is
 * sent at once anyway).
 */
export const MAX_HOLD = 60

/** Hold (ticks) for a lockstep or predict client whose join does not say: 2, the stream at 30 Hz at least. */
export const DEFAULT_HOLD = 2

/** Largest reconnect token length (characters). */
export const MAX_TOKEN_LENGTH = 64

/** WebSocket close codes used by the server (RFC 6455 plus the 4000-4999 private range). */
export const CLOSE_CODES = {
  /** Server shutting down (RFC 6455 "going away"). */
  goingAway: 1001,
  /** Protocol violation: garbage, wrong version, text frames. */
  policy: 1008,
  /** Frame larger than the server's max payload (sent by ws itself). */
  tooBig: 1009,
  /** The room is full, or the server has too many rooms or connections. */
  full: 4001,
  /** The client fell too far behind reading its socket. */
  tooSlow: 4002,
  /** No join within the join timeout. */
  joinTimeout: 4003,
  /** Protocol version mismatch. */
  version: 4004,
  /** The join names a room this connection's key does not admit it to. */
  forbidden: 4005,
  /** The server failed handling this client's message (a server bug; the process carries on). */
  internal: 1011,
  /** The room is held by another server; the `moved` message before the close says where. */
  moved: 4006,
  /** The room was closed for going over its tick budget again and again (error `overloaded` first). */
  overloaded: 4007,
  /** The thread running the room failed (error `room-lost` first); rejoin: it is rebuilt from its log when recorded. */
  roomLost: 4008,
  /** The room directory (Redis) could not be asked; try again later (RFC 6455 1013). */
  tryAgain: 1013,
} as const

/** Commands that change the whole room; admin-only when the server has an admin token. */
export const ROOM_CONTROL_COMMANDS: readonly string[] = ['scene', 'pause', 'step', 'reset', 'gravity']

/** How far beyond a body's outline a pin or rope anchor may lie (m): a lever arm stays short. */
export const ANCHOR_MARGIN = 0.5

/** Spawn material ranges: density (kg/m^2), friction and restitution (dimensionless), [min, max]. */
export const SPAWN_MATERIAL = {
  density: [0.05, 100],
  friction: [0, 2],
  restitution: [0, 1],
} as const

/** Largest game view (a game's `view` for one player) the server sends: bytes of its MessagePack encoding. */
export const MAX_VIEW_BYTES = 1024
