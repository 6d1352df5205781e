/*
 * Exact schemas for decoded messages. A client message passes only if every field has the right
 * type and range, numbers are finite, strings and arrays are within their lengths, and there are
 * no unknown fields (so `__proto__`, `constructor` and `prototype` keys never pass). The result is
 * a fresh object built from the checked fields, never the decoded value itself.
 *
 * Ranges here are what the wire allows; the room then clamps to world bounds, force caps and its
 * body limit. Server messages are checked more loosely (type tag and required fields), enough for
 * a client not to trip over a different server version.
 */

import { MAX_OUTLINE_POINTS, MAX_POLYGON_VERTICES } from '../../engine/index.ts'
import type { DecodeResult } from './codec.ts'
import {
  MAX_BODY_SHAPES,
  MAX_GRAVITY,
  MAX_HOLD,
  MAX_NAME_LENGTH,
  MAX_SHAPE_EXTENT,
  MAX_TOKEN_LENGTH,
  MIN_SHAPE_EXTENT,
  PROTOCOL_VERSION,
  ROOM_NAME_PATTERN,
  SHAPE_SETTINGS,
  SPAWN_MATERIAL,
} from './constants.ts'
import type { ClientMessage, Command, ServerMessage, SpawnCommand, WireShape } from './messages.ts'

/** Largest id, sequence number or tick accepted (2^53 - 1). */
const MAX_INT = Number.MAX_SAFE_INTEGER
/** Largest coordinate accepted on the wire (m); rooms clamp to their world bounds. */
const MAX_COORD = 1e6

class SchemaError extends Error {}

type Fields = Record<string, unknown>

function fields(
  value: unknown,
  what: string,
  allowed: readonly string[],
  required: readonly string[],
): Fields {
  if (typeof value !== 'object' || value === null || Array.isArray(value)) {
    throw new SchemaError(`${what} must be a map`)
  }
  const proto = Object.getPrototypeOf(value)
  if (proto !== Object.prototype && proto !== null) throw new SchemaError(`${what} must be a plain map`)
  const keys = Object.keys(value)
  if (keys.length > allowed.length) throw new SchemaError(`${what} has too many fields`)
  for (const key of keys) {
    if (!allowed.includes(key)) throw new SchemaError(`${what} has unknown field "${key.slice(0, 32)}"`)
  }
  for (const key of required) {
    if (!Object.hasOwn(value, key)) throw new SchemaError(`${what} is missing field "${key}"`)
  }
  return value as Fields
}

/**
 * -0 as +0. The server writes every whole number as a MessagePack integer, so a -0 a client sent
 * reaches the replay log and the lockstep stream as 0; applied as -0 it would leave different
 * bits in the world than every replay of it (a spawn's vx, w or angle, a vertex, a grab point).
 */
function positiveZero(value: number): number {
  return value === 0 ? 0 : value
}

function int(value: unknown, what: string, min: number, max: number): number {
  if (typeof value !== 'number' || !Number.isInteger(value) || value < min || value > max) {
    throw new SchemaError(`${what} must be an integer in [${min}, ${max}]`)
  }
  return positiveZero(value)
}

function num(value: unknown, what: string, limit: number): number {
  if (typeof value !== 'number' || !Number.isFinite(value) || Math.abs(value) > limit) {
    throw new SchemaError(`${what} must be a finite number in [-${limit}, ${limit}]`)
  }
  return positiveZero(value)
}

function optNum(value: unknown, what: string, limit: number): number | undefined {
  return value === undefined || value === null ? undefined : num(value, what, limit)
}

function range(value: unknown, what: string, [min, max]: readonly [number, number]): number {
  if (typeof value !== 'number' || !Number.isFinite(value) || value < min || value > max) {
    throw new SchemaError(`${what} must be a finite number in [${min}, ${max}]`)
  }
  return positiveZero(value)
}

function optRange(value: unknown, what: string, limits: readonly [number, number]): number | undefined {
  return value === undefined || value === null ? undefined : range(value, what, limits)
}

function str(value: unknown, what: string, maxLength: number): string {
  if (typeof value !== 'string' || value.length > maxLength) {
    throw new SchemaError(`${what} must be a string of at most ${maxLength} characters`)
  }
  return value
}

function bool(value: unknown, what: string): boolean {
  if (typeof value !== 'boolean') throw new SchemaError(`${what} must be true or false`)
  return value
}

const SHAPE_FIELDS = [
  'type',
  'radius',
  'hw',
  'hh',
  'x',
  'y',
  'angle',
  'v',
  'density',
  'friction',
  'restitution',
  'rolling',
  'tangent',
  'filter',
  'sensor',
] as const
const SHAPE_SETTINGS_FIELDS = ['density', 'friction', 'restitution', 'rolling', 'tangent', 'filter', 'sensor']

/** A flat point list [x0, y0, ...] of `min` to `max` points, each coordinate within MAX_SHAPE_EXTENT. */
function pointList(
  value: unknown,
  what: string,
  min: number,
  max: number,
  limit = MAX_SHAPE_EXTENT,
): number[] {
  if (!Array.isArray(value) || value.length < 2 * min || value.length > 2 * max || value.length % 2 !== 0) {
    const count = min === max ? `${min}` : `${min} to ${max}`
    throw new SchemaError(`${what} must be a flat list of ${count} points [x0, y0, x1, y1, ...]`)
  }
  return value.map((c, i) => num(c, `${what}[${i}]`, limit))
}

/**
 * One shape of a spawn (PROTOCOL.md, Shape): its geometry within MAX_SHAPE_EXTENT of the body
 * origin, and its optional settings in their ranges; `what` names it in errors ("shape",
 * "shapes[2]").
 */
function validateShape(value: unknown, what: string): WireShape {
  const type = fields(value, what, SHAPE_FIELDS, ['type']).type
  // Errors name the field as "circle radius" (a spawn's shape) or "shapes[2] circle radius".
  const name = `${what === 'shape' ? '' : `${what} `}${String(type).slice(0, 16)}`
  const extent = (v: unknown, field: string): number =>
    range(v, `${name} ${field}`, [MIN_SHAPE_EXTENT, MAX_SHAPE_EXTENT])
  const at = (v: unknown, field: string): number | undefined =>
    optNum(v, `${name} ${field}`, MAX_SHAPE_EXTENT)
  const own = (allowed: string[], required: string[]): Fields =>
    fields(value, name, ['type', ...allowed, ...SHAPE_SETTINGS_FIELDS], required)
  let shape: WireShape
  if (type === 'circle') {
    const f = own(['radius', 'x', 'y'], ['radius'])
    shape = { type, radius: extent(f.radius, 'radius') }
    const x = at(f.x, 'x')
    const y = at(f.y, 'y')
    if (x !== undefined) shape.x = x
    if (y !== undefined) shape.y = y
  } else if (type === 'box') {
    const f = own(['hw', 'hh', 'x', 'y', 'angle'], ['hw', 'hh'])
    shape = { type, hw: extent(f.hw, 'hw'), hh: extent(f.hh, 'hh') }
    const x = at(f.x, 'x')
    const y = at(f.y, 'y')
    const angle = optNum(f.angle, `${name} angle`, 1e3)
    if (x !== undefined) shape.x = x
    if (y !== undefined) shape.y = y
    if (angle !== undefined) shape.angle = angle
  } else if (type === 'polygon') {
    const f = own(['v', 'radius'], ['v'])
    shape = { type, v: pointList(f.v, `${name} v`, 3, MAX_POLYGON_VERTICES) }
    if (f.radius !== undefined && f.radius !== null && f.radius !== 0)
      shape.radius = extent(f.radius, 'radius')
  } else if (type === 'capsule') {
    const f = own(['v', 'radius'], ['v', 'radius'])
    shape = { type, v: pointList(f.v, `${name} v`, 2, 2), radius: extent(f.radius, 'radius') }
  } else if (type === 'segment') {
    const f = own(['v'], ['v'])
    shape = { type, v: pointList(f.v, `${name} v`, 2, 2) }
  } else if (type === 'chain') {
    const f = own(['v'], ['v'])
    shape = { type, v: pointList(f.v, `${name} v`, 4, MAX_OUTLINE_POINTS) }
  } else {
    throw new SchemaError(`${what} type must be "circle", "box", "polygon", "capsule", "segment" or "chain"`)
  }
  const f = value as Fields
  for (const key of ['density', 'friction', 'restitution'] as const) {
    const v = optRange(f[key], `${what} ${key}`, SPAWN_MATERIAL[key])
    if (v !== undefined) shape[key] = v
  }
  for (const key of ['rolling', 'tangent'] as const) {
    const v = optRange(f[key], `${what} ${key}`, SHAPE_SETTINGS[key])
    if (v !== undefined) shape[key] = v
  }
  if (f.filter !== undefined && f.filter !== null) {
    if (!Array.isArray(f.filter) || f.filter.length !== 3)
      throw new SchemaError(`${what} filter must be [categoryBits, maskBits, groupIndex]`)
    shape.filter = [
      int(f.filter[0], `${what} filter categoryBits`, 0, 0xffffffff),
      int(f.filter[1], `${what} filter maskBits`, 0, 0xffffffff),
      int(f.filter[2], `${what} filter groupIndex`, -0x80000000, 0x7fffffff),
    ]
  }
  if (f.sensor !== undefined && f.sensor !== null && bool(f.sensor, `${what} sensor`)) shape.sensor = true
  return shape
}

/** A spawn's geometry: exactly one of `shape`, `shapes` (1 to MAX_BODY_SHAPES) or `outline` (3 to MAX_OUTLINE_POINTS points). */
function spawnGeometry(c: Fields): Pick<SpawnCommand, 'shape' | 'shapes' | 'outline'> {
  const given = (['shape', 'shapes', 'outline'] as const).filter(
    (key) => c[key] !== undefined && c[key] !== null,
  )
  if (given.length !== 1) throw new SchemaError('spawn needs exactly one of shape, shapes or outline')
  if (given[0] === 'shape') return { shape: validateShape(c.shape, 'shape') }
  if (given[0] === 'outline') return { outline: pointList(c.outline, 'outline', 3, MAX_OUTLINE_POINTS) }
  if (!Array.isArray(c.shapes) || c.shapes.length < 1 || c.shapes.length > MAX_BODY_SHAPES)
    throw new SchemaError(`shapes must be a list of 1 to ${MAX_BODY_SHAPES} shapes`)
  return { shapes: c.shapes.map((s, i) => validateShape(s, `shapes[${i}]`)) }
}

/** Every field a `spawn` may have besides `k`. */
const SPAWN_FIELDS = [
  'shape',
  'shapes',
  'outline',
  'x',
  'y',
  'angle',
  'vx',
  'vy',
  'w',
  'density',
  'friction',
  'restitution',
  'color',
  'static',
]

const id = (v: unknown, what: string): number => int(v, what, 1, MAX_INT)
const bodyOrWorld = (v: unknown, what: string): number => int(v, what, 0, MAX_INT)
const coord = (v: unknown, what: string): number => num(v, what, MAX_COORD)

function validateCommand(value: unknown): Command {
  const k = fields(
    value,
    'cmd',
    ['k', ...SPAWN_FIELDS, 'body', 'lx', 'ly', 'a', 'b', 'ax', 'ay', 'bx', 'by', 'joint', 'name', 'paused'],
    ['k'],
  ).k
  const f = (allowed: string[]): Fields =>
    fields(
      value,
      `${String(k)} command`,
      ['k', ...allowed],
      allowed.filter((n) => !['angle', 'vx', 'vy', 'w', 'density', 'friction', 'restitution'].includes(n)),
    )
  switch (k) {
    case 'spawn': {
      const c = fields(value, 'spawn command', ['k', ...SPAWN_FIELDS], ['k', 'x', 'y'])
      const cmd: Command = { k, ...spawnGeometry(c), x: coord(c.x, 'x'), y: coord(c.y, 'y') }
      const angle = optNum(c.angle, 'angle', 1e3)
      const vx = optNum(c.vx, 'vx', MAX_COORD)
      const vy = optNum(c.vy, 'vy', MAX_COORD)
      const w = optNum(c.w, 'w', MAX_COORD)
      if (angle !== undefined) cmd.angle = angle
      if (vx !== undefined) cmd.vx = vx
      if (vy !== undefined) cmd.vy = vy
      if (w !== undefined) cmd.w = w
      for (const key of ['density', 'friction', 'restitution'] as const) {
        const v = optRange(c[key], key, SPAWN_MATERIAL[key])
        if (v !== undefined) cmd[key] = v
      }
      if (c.color !== undefined && c.color !== null) cmd.color = int(c.color, 'color', 0, 0xffffff)
      if (c.static !== undefined && c.static !== null && bool(c.static, 'static')) cmd.static = true
      return cmd
    }
    case 'grab': {
      const c = f(['body', 'lx', 'ly'])
      return { k, body: id(c.body, 'body'), lx: num(c.lx, 'lx', 1e3), ly: num(c.ly, 'ly', 1e3) }
    }
    case 'move': {
      const c = f(['x', 'y'])
      return { k, x: coord(c.x, 'x'), y: coord(c.y, 'y') }
    }
    case 'release':
    case 'step':
    case 'reset':
      f([])
      return { k }
    case 'delete':
      return { k, body: id(f(['body']).body, 'body') }
    case 'pin': {
      const c = f(['a', 'b', 'x', 'y'])
      return { k, a: bodyOrWorld(c.a, 'a'), b: id(c.b, 'b'), x: coord(c.x, 'x'), y: coord(c.y, 'y') }
    }
    case 'rope': {
      const c = f(['a', 'b', 'ax', 'ay', 'bx', 'by'])
      return {
        k,
        a: bodyOrWorld(c.a, 'a'),
        b: id(c.b, 'b'),
        ax: coord(c.ax, 'ax'),
        ay: coord(c.ay, 'ay'),
        bx: coord(c.bx, 'bx'),
        by: coord(c.by, 'by'),
      }
    }
    case 'unjoint':
      return { k, joint: id(f(['joint']).joint, 'joint') }
    case 'inspect':
      return { k, body: bodyOrWorld(f(['body']).body, 'body') }
    case 'scene':
      return { k, name: str(f(['name']).name, 'scene name', 32) }
    case 'pause':
      return { k, paused: bool(f(['paused']).paused, 'paused') }
    case 'gravity': {
      const c = f(['x', 'y'])
      return { k, x: num(c.x, 'gravity x', MAX_GRAVITY), y: num(c.y, 'gravity y', MAX_GRAVITY) }
    }
    default:
      throw new SchemaError(`unknown command "${String(k).slice(0, 32)}"`)
  }
}

/** A game's name: lowercase letters, digits and dashes, starting with a letter (as games/ defines them). */
const GAME_NAME_PATTERN = /^[a-z][a-z0-9-]{0,31}$/
/** A game command's kind: a letter, then up to 31 letters, digits or `_` (as games/ defines them). */
const GAME_KIND_PATTERN = /^[A-Za-z][A-Za-z0-9_]{0,31}$/
/** Limits of a game command's arguments: nesting depth, values in all, string and key lengths. */
export const GAME_ARGS_LIMITS = { depth: 8, values: 256, string: 1024, key: 32 } as const

/**
 * A game command's arguments as plain data: a map whose values are nil, booleans, finite numbers
 * (-0 as 0), strings, arrays and maps, within GAME_ARGS_LIMITS; throws naming the field. The game's
 * own schema is checked by the room, after this.
 */
function gameArgs(value: unknown): Fields {
  let count = 0
  const walk = (v: unknown, where: string, depth: number): unknown => {
    if (++count > GAME_ARGS_LIMITS.values)
      throw new SchemaError(`cmd a holds more than ${GAME_ARGS_LIMITS.values} values`)
    if (v === null || typeof v === 'boolean') return v
    if (typeof v === 'number') {
      if (!Number.isFinite(v)) throw new SchemaError(`${where} must be a finite number`)
      return positiveZero(v)
    }
    if (typeof v === 'string') return str(v, where, GAME_ARGS_LIMITS.string)
    if (depth >= GAME_ARGS_LIMITS.depth)
      throw new SchemaError(`${where} is nested deeper than ${GAME_ARGS_LIMITS.depth} levels`)
    if (Array.isArray(v)) return v.map((item, i) => walk(item, `${where}[${i}]`, depth + 1))
    if (typeof v === 'object' && Object.getPrototypeOf(v) === Object.prototype) {
      const out: Fields = {}
      for (const key of Object.keys(v)) {
        if (key.length > GAME_ARGS_LIMITS.key)
          throw new SchemaError(`${where} has a key longer than ${GAME_ARGS_LIMITS.key} characters`)
        out[key] = walk((v as Fields)[key], `${where}.${key}`, depth + 1)
      }
      return out
    }
    throw new SchemaError(`${where} must be nil, a boolean, a number, a string, a list or a map`)
  }
  if (typeof value !== 'object' || value === null || Array.isArray(value) || value instanceof Uint8Array)
    throw new SchemaError('cmd a must be a map')
  return walk(value, 'a', 0) as Fields
}

function validateJoin(value: unknown): ClientMessage {
  const m = fields(
    value,
    'join',
    ['t', 'v', 'room', 'name', 'mode', 'token', 'hold', 'game', 'spectate'],
    ['t', 'v', 'room', 'name', 'mode'],
  )
  const room = str(m.room, 'room', 32)
  if (room !== '' && !ROOM_NAME_PATTERN.test(room)) {
    throw new SchemaError('room must be 1-32 letters, digits, "-" or "_"')
  }
  // biome-ignore lint/suspicious/noControlCharactersInRegex: control characters are what we reject
  const name = str(m.name, 'name', MAX_NAME_LENGTH).replace(/[\u0000-\u001f\u007f]/g, '')
  if (m.mode !== 'snapshot' && m.mode !== 'lockstep' && m.mode !== 'predict')
    throw new SchemaError('mode must be "snapshot", "lockstep" or "predict"')
  const join: ClientMessage = { t: 'join', v: PROTOCOL_VERSION, room, name, mode: m.mode }
  if (m.token !== undefined && m.token !== null) join.token = str(m.token, 'token', MAX_TOKEN_LENGTH)
  if (m.hold !== undefined && m.hold !== null) join.hold = int(m.hold, 'hold', 1, MAX_HOLD)
  if (m.game !== undefined && m.game !== null) {
    const game = str(m.game, 'game', 32)
    if (!GAME_NAME_PATTERN.test(game))
      throw new SchemaError('game must be 1-32 lowercase letters, digits or "-", starting with a letter')
    join.game = game
  }
  if (m.spectate !== undefined && m.spectate !== null) {
    if (bool(m.spectate, 'spectate')) join.spectate = true
  }
  return join
}

function validateClient(value: unknown): ClientMessage {
  const t = fields(
    value,
    'message',
    [
      't',
      'v',
      'room',
      'name',
      'mode',
      'token',
      'hold',
      'game',
      'spectate',
      'seq',
      'cmd',
      'k',
      'a',
      'tick',
      'id',
      'time',
      'hash',
      'server',
    ],
    ['t'],
  ).t
  switch (t) {
    case 'join':
      return validateJoin(value)
    case 'input': {
      const m = fields(value, 'input', ['t', 'seq', 'cmd'], ['t', 'seq', 'cmd'])
      return { t, seq: int(m.seq, 'seq', 0, MAX_INT), cmd: validateCommand(m.cmd) }
    }
    case 'cmd': {
      const m = fields(value, 'cmd', ['t', 'seq', 'k', 'a'], ['t', 'seq', 'k', 'a'])
      const seq = int(m.seq, 'seq', 0, MAX_INT)
      const k = str(m.k, 'cmd k', 32)
      if (!GAME_KIND_PATTERN.test(k))
        throw new SchemaError('cmd k must be a letter followed by up to 31 letters, digits or "_"')
      return { t, seq, k, a: gameArgs(m.a) }
    }
    case 'ack':
      return { t, tick: int(fields(value, 'ack', ['t', 'tick'], ['t', 'tick']).tick, 'tick', 0, MAX_INT) }
    case 'ping': {
      const m = fields(value, 'ping', ['t', 'id', 'time'], ['t', 'id', 'time'])
      return { t, id: int(m.id, 'id', 0, MAX_INT), time: num(m.time, 'time', Number.MAX_VALUE) }
    }
    case 'desync': {
      const m = fields(value, 'desync', ['t', 'tick', 'hash', 'server'], ['t', 'tick', 'hash', 'server'])
      const hash = (v: unknown, what: string): number => int(v, what, 0, 0xffffffff)
      return {
        t,
        tick: int(m.tick, 'tick', 0, MAX_INT),
        hash: hash(m.hash, 'hash'),
        server: hash(m.server, 'server'),
      }
    }
    case 'resync':
      fields(value, 'resync', ['t'], ['t'])
      return { t }
    default:
      throw new SchemaError(`unknown message type "${String(t).slice(0, 32)}"`)
  }
}

/**
 * Check a decoded value against the client message schemas. A join with another protocol version
 * fails with code 'version' and a reason naming both versions, before any other field is checked.
 */
export function validateClientMessage(value: unknown): DecodeResult<ClientMessage> {
  if (typeof value === 'object' && value !== null && (value as Fields).t === 'join') {
    const v = (value as Fields).v
    if (v !== PROTOCOL_VERSION) {
      const theirs = typeof v === 'number' ? String(v) : 'none'
      return {
        ok: false,
        code: 'version',
        reason: `protocol version mismatch: client ${theirs}, server ${PROTOCOL_VERSION}`,
      }
    }
  }
  try {
    return { ok: true, value: validateClient(value) }
  } catch (error) {
    const reason = error instanceof SchemaError ? error.message : 'message rejected'
    const seq = refusedSeq(value)
    return seq === undefined
      ? { ok: false, code: 'invalid', reason }
      : { ok: false, code: 'invalid', reason, seq }
  }
}

/**
 * The `seq` of a refused `input`, when the message is a map with `t: "input"` and a `seq` that
 * is itself valid (an integer in [0, 2^53 - 1]); otherwise undefined (nothing trustworthy to echo).
 */
function refusedSeq(value: unknown): number | undefined {
  if (typeof value !== 'object' || value === null || Array.isArray(value)) return undefined
  const m = value as Fields
  if ((m.t !== 'input' && m.t !== 'cmd') || !Object.hasOwn(m, 'seq')) return undefined
  const seq = m.seq
  return typeof seq === 'number' && Number.isInteger(seq) && seq >= 0 && seq <= MAX_INT ? seq : undefined
}

const SERVER_FIELDS: Record<ServerMessage['t'], readonly string[]> = {
  game: ['tick', 'events'],
  view: ['tick', 'view'],
  sync: ['tick', 'z', 'data'],
  ticks: ['tick', 'n', 'c'],
  welcome: ['v', 'id', 'token', 'room', 'rules', 'players', 'state'],
  state: ['state'],
  events: ['tick', 'add', 'remove', 'jadd', 'jremove'],
  room: ['tick', 'paused', 'gravity', 'scene', 'slow', 'creator', 'locked'],
  players: ['players'],
  snap: ['tick', 'base', 'data', 'cursors'],
  pong: ['id', 'time', 'tick'],
  hash: ['tick', 'step', 'hash'],
  error: ['code', 'reason'],
  moved: ['room', 'url'],
  contacts: ['tick', 'body', 'mass', 'total', 'contacts'],
  scene: ['seq', 'id'],
}

/** Check a decoded server message's type tag and required fields. */
export function validateServerMessage(value: unknown): DecodeResult<ServerMessage> {
  if (typeof value !== 'object' || value === null) return { ok: false, code: 'invalid', reason: 'not a map' }
  const t = (value as Fields).t
  const required =
    typeof t === 'string' && Object.hasOwn(SERVER_FIELDS, t) ? SERVER_FIELDS[t as ServerMessage['t']] : null
  if (!required) return { ok: false, code: 'invalid', reason: `unknown server message type "${String(t)}"` }
  for (const key of required) {
    if (!Object.hasOwn(value, key)) return { ok: false, code: 'invalid', reason: `${t} is missing "${key}"` }
  }
  if (t === 'snap' && !((value as Fields).data instanceof Uint8Array)) {
    return { ok: false, code: 'invalid', reason: 'snap data must be binary' }
  }
  if (t === 'sync' && !((value as Fields).data instanceof Uint8Array)) {
    return { ok: false, code: 'invalid', reason: 'sync data must be binary' }
  }
  if (t === 'ticks' && !Array.isArray((value as Fields).c)) {
    return { ok: false, code: 'invalid', reason: 'ticks c must be a list' }
  }
  if (t === 'contacts' && !Array.isArray((value as Fields).contacts)) {
    return { ok: false, code: 'invalid', reason: 'contacts must be a list' }
  }
  return { ok: true, value: value as unknown as ServerMessage }
}
