/*
 * What a room simulation needs from a game, and what it gives the game. RoomSimulation runs one
 * SimGame: its setup builds the world, its commands are the only things players can do, its hooks
 * see joins, leaves and every stepped tick, and its state (plain data) is saved, synced and hashed
 * with the world. Game modules live in games/ and are written with games/'s defineGame, which
 * builds a SimGame (argument schemas compiled, names checked); shared/ never imports games/, so
 * the simulation takes the game as an object through this interface (the callers, server, client
 * and tests, choose it from games/'s catalogue by name).
 *
 * Built-in commands (spawn, grab, move, ... gravity: the input message's kinds, validated by
 * protocol/validate.ts) reach a game only if it lists them, flagged `builtin`; everything else is
 * a game command, `{ k: 'cmd', kind, a }`, whose arguments the game's `check` validates before its
 * `apply` sees them.
 *
 * The state is plain data (null, booleans, numbers, strings, arrays, objects with string keys):
 * copied with copyPlainData (which refuses anything else, naming where it is) and hashed with
 * hashPlainData, FNV-1a over a canonical walk (object keys sorted), so two replicas that hold equal
 * data hash equal whatever order their objects' keys were added in.
 */
import { type JointSettings, type Prng, SCENES, type World } from '../../engine/index.ts'
import {
  type Command,
  type PinCommand,
  type RoomRules,
  type RopeCommand,
  type SpawnCommand,
  TICK_RATE,
  type WireJoint,
  type WireJointDef,
  WORLD_HALF_EXTENT,
} from '../protocol/index.ts'
import type { GameHistory } from './history.ts'

/** Plain data: what game state, game command arguments and game events are made of. */
export type PlainData = null | boolean | number | string | PlainData[] | { [key: string]: PlainData }

/** A game command as the simulation applies it: its kind and its arguments (validated by the game). */
export interface GameCommand {
  k: 'cmd'
  kind: string
  a: PlainData
}

/** Anything a player can do to a room simulation: a built-in command or a game command. */
export type SimCommand = Command | GameCommand

/** The built-in command kinds a game may list (the input message's, less `inspect`). */
export const BUILTIN_KINDS = [
  'spawn',
  'grab',
  'move',
  'release',
  'delete',
  'pin',
  'rope',
  'unjoint',
  'scene',
  'pause',
  'step',
  'reset',
  'gravity',
] as const

/** A built-in command kind. */
export type BuiltinKind = (typeof BUILTIN_KINDS)[number]

/**
 * The last step's engine events, read from the world's event calls where the engine has them
 * (contactEvents, sensorEvents, jointEvents: the engine issues 27 and 28); null where it has not.
 */
export interface StepEvents {
  contacts: unknown | null
  sensors: unknown | null
  joints: unknown | null
}

/** The optional event calls of a World (present once the engine has them). */
interface EventSource {
  contactEvents?(): unknown
  sensorEvents?(): unknown
  jointEvents?(): unknown
}

/** No events: what ctx.events is outside a game's tick. */
export const NO_EVENTS: StepEvents = Object.freeze({ contacts: null, sensors: null, joints: null })

/** The events of a world's last step (see StepEvents). */
export function stepEvents(world: World): StepEvents {
  const source = world as unknown as EventSource
  return {
    contacts: typeof source.contactEvents === 'function' ? source.contactEvents() : null,
    sensors: typeof source.sensorEvents === 'function' ? source.sensorEvents() : null,
    joints: typeof source.jointEvents === 'function' ? source.jointEvents() : null,
  }
}

/**
 * What a game sees: the room's world and tick, its players, a seeded PRNG, its state, and the
 * room's primitives (bodies, grabs, user joints, scenes, pause) that keep clients and recordings
 * informed. A game changes the world through these primitives where one exists (a body made with
 * ctx.world.createBody is simulated everywhere, but snapshot clients only learn of it from the
 * next full state; ctx.createBody tells them at once).
 */
export interface GameContext<S = PlainData | undefined> {
  /** The engine world (replaced by a scene load: read it from ctx each time). */
  readonly world: World
  /** The room tick: ticks run since the room opened (the current tick while commands apply). */
  readonly tick: number
  /** Player ids in join order. */
  readonly players: readonly number[]
  /** The room's seeded PRNG (its position is saved and synced; the only randomness a game may use). */
  readonly random: Prng
  /** The last step's engine events; NO_EVENTS outside tick(). */
  readonly events: StepEvents
  /** The game's own state (plain data), saved, synced and hashed with the world. */
  state: S
  /** Whether the room is paused (the world does not step and tick() is not called). */
  paused: boolean
  /** Room tick of the last scene load or world replacement, or -Infinity for never. */
  readonly lastLoadTick: number
  /** The room's current scene name (the last one loaded). */
  readonly scene: string
  /** The room's body limit (also its user joint limit). */
  readonly maxBodies: number
  /** Send an event (plain data) to the room's clients; lockstep clients compute it themselves. */
  emit(event: PlainData): void
  /** Step once at the end of this tick even while paused. */
  requestStep(): void
  /** Slow motion: the world steps only on room ticks that are multiples of this (1, 2 or 4; a RangeError otherwise). */
  slowMotion: number
  /** The first player who joined the room (0 before anyone did). */
  readonly creator: number
  /** While true, room controls (commands marked control) are refused for everyone but the creator. */
  controlsLocked: boolean
  /**
   * Each player's undo and redo history (history.ts): a command that should be undoable records
   * what it changed with `ctx.history.record(player, { kind, before, after })`.
   */
  readonly history: GameHistory
  /**
   * Create a body and tell clients, coloured `color` (0xRRGGBB) when given; refused at the body
   * limit or by an engine precondition.
   */
  createBody(def: Parameters<World['createBody']>[0], color?: number): number | string
  /**
   * A body from a spawn command (clamped as PROTOCOL.md says), coloured `cmd.color`, else the
   * player's colour (playerBodyColor) when `player` is given; the id, or a refusal.
   */
  spawn(cmd: SpawnCommand, player?: number): number | string
  /** A body's colour (0xRRGGBB) when a spawn gave it one, else null (scene and game bodies). */
  bodyColor(id: number): number | null
  /** Destroy a body and what is attached to it (grabs, user joints), telling clients. */
  destroyBody(id: number): void
  /** Set a body's colour (0xRRGGBB), or remove it (null); clients learn it from bodyChanged. */
  setBodyColor(id: number, color: number | null): void
  /**
   * Tell clients that a body's shapes, material, filter, colour, type or pose changed from a
   * command (events.change: its whole wire body); a body made static leaves their snapshots.
   */
  bodyChanged(id: number): void
  /** A player's grab of a dynamic body at a local point (releases its earlier grab); null or a refusal. */
  grab(player: number, body: number, lx: number, ly: number): string | null
  /** Move a player's cursor (and its grab's target) to a point clamped to the world. */
  moveCursor(player: number, x: number, y: number): void
  /** Release a player's grab, if any. */
  release(player: number): void
  /** A player's grabbed body, or 0. */
  grabbedBody(player: number): number
  /** A player's cursor (m). */
  cursor(player: number): { x: number; y: number }
  /** Add a pin or rope (user joint, listed on the wire); null or a refusal. */
  addJoint(cmd: PinCommand | RopeCommand): string | null
  /**
   * Add a joint of any kind that travels (weld, pin, distance, slider, wheel, motor), made by player
   * `owner` (who alone may drive its motor: setJointMotor), with the same body, anchor and limit
   * rules as a pin; `what` names the command in refusals. The joint id, or a refusal.
   */
  createJoint(owner: number, def: WireJointDef, what: string): number | string
  /** A joint of the room as it travels (scene and players' joints; not grabs), or undefined. */
  userJoint(id: number): Readonly<WireJoint> | undefined
  /** Set the motor speed of a joint with a motor (rad/s for pins and wheels, m/s for sliders and distance joints); null or a refusal. */
  setJointMotor(id: number, speed: number): string | null
  /**
   * Change a room joint's settings (World.setJointSettings: the engine's names, checked as the
   * engine checks them); its wire form is rebuilt from the joint as it now stands and travels in
   * events.jadd (same id: clients replace it). Null, or a refusal naming the field.
   */
  setJointSettings(id: number, settings: JointSettings): string | null
  /** Remove a user joint; null or a refusal naming the id. */
  removeJoint(id: number): string | null
  /** Replace the world with a fresh copy of a named scene (grabs and user joints go); null or a refusal. */
  loadScene(name: string): string | null
  /** Set gravity (m/s^2) and wake every dynamic body. */
  setGravity(x: number, y: number): void
}

/** One command of a game, as the simulation runs it. */
export interface SimCommandDef {
  /** A built-in kind (its arguments were validated by the protocol), or a game command. */
  readonly builtin: boolean
  /** A room control: refused when the room's controls are off. */
  readonly control: boolean
  /** Why the arguments are refused (naming the field), or null; built-in commands return null. */
  check(args: unknown): string | null
  /** Apply the command; a string returned refuses it (before changing anything), anything else accepts. */
  apply(ctx: GameContext, player: number, args: unknown): unknown
}

/** A game as RoomSimulation runs it (games/'s defineGame builds one). */
export interface SimGame {
  readonly name: string
  readonly minPlayers: number
  readonly maxPlayers: number
  /** The commands by kind. */
  readonly commands: Readonly<Record<string, SimCommandDef>>
  /** A fresh copy of the initial state, or undefined for a game without state. */
  initialState(): PlainData | undefined
  /** Build the room's first world (the simulation starts with an empty one) and state. */
  setup(ctx: GameContext, options: { scene: string }): void
  onJoin?(ctx: GameContext, player: number): void
  onLeave?(ctx: GameContext, player: number): void
  /** After every world step (not while paused). */
  tick?(ctx: GameContext): void
  /** What `player` sees of the game (plain data, sent to that player only); changes nothing. */
  view?(ctx: GameContext, player: number): PlainData
}

/** Finds a game by name (games/'s catalogue); undefined for an unknown name. */
export type GameCatalog = (name: string) => SimGame | undefined

/** What a room's host decides of its rules (a server's settings, or the offline page's). */
export type RoomLimits = Pick<
  RoomRules,
  'snapshotRate' | 'maxBodies' | 'maxClients' | 'inputsPerTick' | 'controls' | 'maxSpectators'
>

/**
 * The rules a room running `game` announces (welcome.rules, PROTOCOL.md): the tick rate, scenes and
 * world size every room shares, the game's name and its own command kinds (sorted), and `limits`.
 */
export function roomRules(game: SimGame, limits: RoomLimits): RoomRules {
  return {
    tickRate: TICK_RATE,
    snapshotRate: limits.snapshotRate,
    maxBodies: limits.maxBodies,
    maxClients: limits.maxClients,
    inputsPerTick: limits.inputsPerTick,
    controls: limits.controls,
    // Only a game that lists the scene command loads scenes: the others' list is empty.
    scenes: Object.hasOwn(game.commands, 'scene') ? Object.keys(SCENES) : [],
    worldHalfExtent: WORLD_HALF_EXTENT,
    game: game.name,
    commands: Object.keys(game.commands)
      .filter((k) => !game.commands[k].builtin)
      .sort(),
    builtins: Object.keys(game.commands)
      .filter((k) => game.commands[k].builtin)
      .sort(),
    maxSpectators: limits.maxSpectators,
  }
}

/** A deep copy of plain data; throws a RangeError naming the first thing that is not plain data. */
export function copyPlainData(value: unknown, where = 'state'): PlainData {
  return copy(value, where, 0)
}

const MAX_DEPTH = 64

function copy(value: unknown, where: string, depth: number): PlainData {
  if (depth > MAX_DEPTH) throw new RangeError(`${where} is nested deeper than ${MAX_DEPTH} levels`)
  if (value === null || typeof value === 'boolean' || typeof value === 'number' || typeof value === 'string')
    return value
  if (Array.isArray(value)) return value.map((v, i) => copy(v, `${where}[${i}]`, depth + 1))
  if (typeof value === 'object' && Object.getPrototypeOf(value) === Object.prototype) {
    const out: { [key: string]: PlainData } = {}
    for (const key of Object.keys(value)) {
      out[key] = copy((value as Record<string, unknown>)[key], `${where}.${key}`, depth + 1)
    }
    return out
  }
  const what =
    value === undefined ? 'undefined' : typeof value === 'object' ? 'a class instance' : typeof value
  throw new RangeError(`${where} is ${what}; game state and events must be plain data`)
}

const FNV_OFFSET = 0x811c9dc5
const FNV_PRIME = 0x01000193
const scratch = new DataView(new ArrayBuffer(8))

/** FNV-1a of one byte into a running hash. */
const mix = (h: number, byte: number): number => Math.imul(h ^ byte, FNV_PRIME) >>> 0

function mixUint32(h: number, v: number): number {
  h = mix(h, v & 0xff)
  h = mix(h, (v >>> 8) & 0xff)
  h = mix(h, (v >>> 16) & 0xff)
  return mix(h, v >>> 24)
}

function mixString(h: number, s: string): number {
  h = mixUint32(h, s.length)
  for (let i = 0; i < s.length; i++) {
    const c = s.charCodeAt(i)
    h = mix(mix(h, c & 0xff), c >>> 8)
  }
  return h
}

function mixValue(h: number, v: PlainData): number {
  if (v === null) return mix(h, 0)
  if (typeof v === 'boolean') return mix(h, v ? 2 : 1)
  if (typeof v === 'number') {
    // -0 travels as 0 through MessagePack: hash them alike.
    scratch.setFloat64(0, v === 0 ? 0 : v, true)
    return mixUint32(mixUint32(mix(h, 3), scratch.getUint32(0, true)), scratch.getUint32(4, true))
  }
  if (typeof v === 'string') return mixString(mix(h, 4), v)
  if (Array.isArray(v)) {
    h = mixUint32(mix(h, 5), v.length)
    for (const item of v) h = mixValue(h, item)
    return h
  }
  const keys = Object.keys(v).sort()
  h = mixUint32(mix(h, 6), keys.length)
  for (const key of keys) h = mixValue(mixString(h, key), v[key])
  return h
}

/** A 32-bit FNV-1a hash of plain data, object keys sorted, continuing from `seed`. */
export function hashPlainData(value: PlainData, seed = FNV_OFFSET): number {
  return mixValue(seed >>> 0, value)
}

/** The simulation hash of a game with state: FNV-1a of the world hash, the PRNG position and the state. */
export function simulationHash(worldHash: number, random: number, state: PlainData): number {
  return hashPlainData(state, mixUint32(mixUint32(FNV_OFFSET, worldHash), random))
}

/**
 * A simulation hash with the room's body colours mixed in: FNV-1a of `hash` then of `colors`
 * (flat [body id, 0xRRGGBB, ...], ascending ids) as plain data. Rooms without coloured bodies keep
 * their hash unchanged (the caller skips this for an empty list).
 */
export function colorsHash(hash: number, colors: number[]): number {
  return continueHash(hash, colors)
}

/** A hash continued over plain data: FNV-1a of `hash` (u32), then of `value` as plain data. */
export function continueHash(hash: number, value: PlainData): number {
  return hashPlainData(value, mixUint32(FNV_OFFSET, hash))
}
