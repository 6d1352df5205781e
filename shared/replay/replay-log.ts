/*
 * The replay log format (docs/replay-format.md is the byte-level specification): a 16-byte
 * preamble (magic, format, engine save-format and protocol versions, tick rate), then framed
 * records, each length-prefixed and CRC-32 checked:
 *
 *   u32 length L | u8 type | u32 tick | payload (L - 5 bytes) | u32 CRC-32 of the 4 + L bytes before it
 *
 * The first record is the header (room, scene, start time, rules, and a keyframe: the
 * simulation's state and saved world); then commands, joins, leaves, external world loads,
 * hashes, keyframes and a clean close, in applied order with non-decreasing ticks. Since version 2
 * the small records (commands, joins, leaves, hashes, close) of one writer flush are packed into
 * one block record: a zlib stream of `u8 type | varint tick delta | varint length | payload`
 * entries, so a flush costs one frame and deflate sees all its records at once; and a keyframe's
 * world may be a deflated byte delta against the previous keyframe's (z = 2, byte-delta.ts).
 *
 * Pure and browser-safe (Uint8Array/DataView only). The reader is streaming: push() chunks as
 * they arrive; it returns every complete, intact record and stops for good at the first torn or
 * corrupt one (bad length, bad checksum, undecodable payload, a tick going backwards or jumping
 * more than MAX_RECORD_GAP ahead), so a crash's torn tail is cut, never misread. A block is
 * accepted whole or not at all. Saved worlds may be deflated (zlib stream, RFC 1950): the writer
 * passes compressed bytes in, the reader hands them out untouched (see replay-runner.ts).
 */

import {
  decodeValue,
  encodeValue,
  InflateError,
  inflateZlibSync,
  TICK_RATE,
  validateClientMessage,
  WIRE_JOINT_KINDS,
  type WireJoint,
} from '../protocol/index.ts'
import {
  checkSavedHistory,
  copyPlainData,
  DEFAULT_SEED,
  type PlainData,
  type SavedHistory,
  type SimCommand,
  type SimulationState,
} from '../sim/index.ts'
import { crc32 } from './crc32.ts'

/** The 8 magic bytes opening every log: ASCII "CNCRDLOG". */
export const REPLAY_MAGIC = new Uint8Array([0x43, 0x4e, 0x43, 0x52, 0x44, 0x4c, 0x4f, 0x47])
/**
 * Version of this format. Version 3 has version 2's bytes; what changed is what a replay must
 * reproduce: keyframes carry the players' undo histories, and the room's hash covers them, so a
 * version 2 log (recorded before undo) is read but not replayed (replay-runner.ts incompatibility).
 */
export const REPLAY_FORMAT_VERSION = 3
/** Oldest format version this build still reads (version 1 has no blocks and no delta keyframes). */
export const OLDEST_READABLE_VERSION = 1
/** Preamble size in bytes. */
export const PREAMBLE_BYTES = 16
/** Largest record body (type + tick + payload) accepted: 64 MiB. */
export const MAX_RECORD_BYTES = 64 * 1024 * 1024
/** Bytes a record adds around its payload: length, type, tick, CRC. */
export const RECORD_OVERHEAD = 13
/**
 * Most ticks from one record to the next (and from a block's entry to the next): the writer puts a
 * hash record at every tick divisible by 60, so no two records of a log it wrote are further apart.
 * A reader refuses a record further ahead: replaying it would run ticks that no bytes pay for (one
 * 21-byte record 3,000,000 ticks ahead took a replay 17 s; one near tick 2^32 would take hours).
 */
export const MAX_RECORD_GAP = TICK_RATE
/** Most entries in one block record; the writer starts a new block at this many. */
export const MAX_BLOCK_ENTRIES = 65_536
/**
 * Most ticks from a block's first entry to its last; the writer starts a new block past it (a flush
 * a second writes blocks of about 60 ticks). With MAX_BLOCK_ENTRIES this bounds what a small
 * deflated block can ask a replay to do.
 */
export const MAX_BLOCK_TICKS = 600

/** Record type codes. */
export const RecordType = {
  header: 1,
  command: 2,
  join: 3,
  leave: 4,
  world: 5,
  hash: 6,
  keyframe: 7,
  close: 8,
  block: 9,
} as const

/** Record kinds that travel inside blocks (the small ones). */
export type BlockableRecord = Extract<ReplayRecord, { type: 'command' | 'join' | 'leave' | 'hash' | 'close' }>

/**
 * How a saved world is stored: 0 as is, 1 deflated (zlib stream), 2 (keyframes only) a deflated
 * byte delta against the saved world of the previous keyframe or header record.
 */
export type WorldEncoding = 0 | 1 | 2

/** A saved world as stored in a header, keyframe or world record. */
export interface StoredWorld {
  /** 0: `world` is World.save() bytes; 1: they are deflated (zlib, RFC 1950); 2: a deflated delta. */
  z: WorldEncoding
  world: Uint8Array
}

/** The versions in a log's preamble. */
export interface Preamble {
  format: number
  engine: number
  protocol: number
  tickRate: number
}

/** One decoded record. */
export type ReplayRecord =
  | ({
      type: 'header'
      tick: number
      room: string
      scene: string
      /** Wall-clock start, UTC ms since 1970. */
      start: number
      maxBodies: number
      controls: boolean
      state: SimulationState
      /** The writing process: host name and process id (recovery skips logs of live writers). */
      host: string
      pid: number
    } & StoredWorld)
  | { type: 'command'; tick: number; player: number; cmd: SimCommand }
  | { type: 'join'; tick: number; player: number; name: string; color: string }
  | { type: 'leave'; tick: number; player: number }
  | ({
      type: 'world'
      tick: number
      scene: string
      /** The body colours after the load, flat [id, 0xRRGGBB, ...] (absent in logs from before scene files kept them). */
      colors?: number[]
      /** The world's joints as they travel (a scene file's), for the replay's drawing and undo. */
      joints?: WireJoint[]
    } & StoredWorld)
  | { type: 'hash'; tick: number; hash: number; step: number }
  | ({ type: 'keyframe'; tick: number; state: SimulationState } & StoredWorld)
  | { type: 'close'; tick: number; reason: string; end: number }

/** Encode the 16-byte preamble. */
export function encodePreamble(p: Preamble): Uint8Array {
  const out = new Uint8Array(PREAMBLE_BYTES)
  out.set(REPLAY_MAGIC)
  const view = new DataView(out.buffer)
  view.setUint16(8, p.format, true)
  view.setUint16(10, p.engine, true)
  view.setUint16(12, p.protocol, true)
  view.setUint16(14, p.tickRate, true)
  return out
}

/** Frame one record: length, type, tick, payload, CRC-32. */
function frame(type: number, tick: number, payload: Uint8Array): Uint8Array {
  const body = 5 + payload.length
  const out = new Uint8Array(4 + body + 4)
  const view = new DataView(out.buffer)
  view.setUint32(0, body, true)
  out[4] = type
  view.setUint32(5, tick, true)
  out.set(payload, 9)
  view.setUint32(4 + body, crc32(out, 0, 4 + body), true)
  return out
}

const u32 = (n: number, rest?: Uint8Array): Uint8Array => {
  const out = new Uint8Array(4 + (rest?.length ?? 0))
  new DataView(out.buffer).setUint32(0, n, true)
  if (rest) out.set(rest, 4)
  return out
}

/** A record's payload (what follows type and tick). */
function encodePayload(r: ReplayRecord): Uint8Array {
  switch (r.type) {
    case 'header': {
      const { room, scene, start, maxBodies, controls, state, host, pid, z, world } = r
      return encodeValue({ room, scene, start, maxBodies, controls, state, host, pid, z, world })
    }
    case 'command':
      return u32(r.player, encodeValue(r.cmd))
    case 'join':
      return u32(r.player, encodeValue({ name: r.name, color: r.color }))
    case 'leave':
      return u32(r.player)
    case 'world':
      return encodeValue({ scene: r.scene, colors: r.colors, joints: r.joints, z: r.z, world: r.world })
    case 'hash': {
      const payload = new Uint8Array(8)
      const view = new DataView(payload.buffer)
      view.setUint32(0, r.hash, true)
      view.setUint32(4, r.step, true)
      return payload
    }
    case 'keyframe':
      return encodeValue({ state: r.state, z: r.z, world: r.world })
    case 'close':
      return encodeValue({ reason: r.reason, end: r.end })
  }
}

/** Encode one record as framed bytes ready to append. */
export function encodeRecord(r: ReplayRecord): Uint8Array {
  if (r.type === 'keyframe' || r.type === 'header' || r.type === 'world') {
    if (r.z === 2 && r.type !== 'keyframe')
      throw new RangeError(`a ${r.type} record cannot hold a delta world`)
  }
  return frame(RecordType[r.type], r.tick, encodePayload(r))
}

function pushVarint(out: number[], v: number): void {
  while (v >= 0x80) {
    out.push((v % 0x80) | 0x80)
    v = Math.floor(v / 0x80)
  }
  out.push(v)
}

/**
 * The bytes a block's zlib stream inflates to: each record as u8 type, varint tick delta (from
 * the previous record, the first from the block's tick: its first record's), varint payload
 * length, payload. Throws a RangeError for an empty list.
 */
export function encodeBlockEntries(records: readonly BlockableRecord[]): Uint8Array {
  if (records.length === 0) throw new RangeError('a block needs at least one record')
  const parts: Uint8Array[] = []
  let size = 0
  let tick = records[0].tick
  for (const r of records) {
    const payload = encodePayload(r)
    const head: number[] = [RecordType[r.type]]
    pushVarint(head, r.tick - tick)
    pushVarint(head, payload.length)
    tick = r.tick
    parts.push(Uint8Array.from(head), payload)
    size += head.length + payload.length
  }
  const out = new Uint8Array(size)
  let at = 0
  for (const p of parts) {
    out.set(p, at)
    at += p.length
  }
  return out
}

/** Frame a block record: `tick` is its first record's, `zlib` the deflated encodeBlockEntries bytes. */
export function frameBlock(tick: number, zlib: Uint8Array): Uint8Array {
  return frame(RecordType.block, tick, zlib)
}

/** Why a record or preamble was refused. */
export class ReplayFormatError extends Error {}

type Fields = Record<string, unknown>

function map(v: unknown, what: string): Fields {
  if (typeof v !== 'object' || v === null || Array.isArray(v) || v instanceof Uint8Array)
    throw new ReplayFormatError(`${what} is not a map`)
  return v as Fields
}
function int(v: unknown, what: string, min = 0, max = Number.MAX_SAFE_INTEGER): number {
  if (typeof v !== 'number' || !Number.isInteger(v) || v < min || v > max)
    throw new ReplayFormatError(`${what} is not an integer in [${min}, ${max}]: ${String(v).slice(0, 40)}`)
  return v
}
function finite(v: unknown, what: string): number {
  if (typeof v !== 'number' || !Number.isFinite(v))
    throw new ReplayFormatError(`${what} is not a finite number`)
  return v
}
function str(v: unknown, what: string): string {
  if (typeof v !== 'string' || v.length > 256) throw new ReplayFormatError(`${what} is not a short string`)
  return v
}
function bool(v: unknown, what: string): boolean {
  if (typeof v !== 'boolean') throw new ReplayFormatError(`${what} is not a boolean`)
  return v
}
function storedWorld(m: Fields, delta = false): StoredWorld {
  const z = int(m.z, 'world encoding', 0, delta ? 2 : 1) as WorldEncoding
  if (!(m.world instanceof Uint8Array)) throw new ReplayFormatError('world is not a byte array')
  return { z, world: m.world }
}
const JOINT_KINDS: readonly string[] = WIRE_JOINT_KINDS
const JOINT_NUMBERS = [
  'ax',
  'ay',
  'bx',
  'by',
  'length',
  'min',
  'max',
  'hz',
  'damping',
  'ref',
  'lower',
  'upper',
  'speed',
  'torque',
] as const
const JOINT_FLAGS = ['limit', 'motor', 'collide'] as const
/** Fields added with the joints of issue 28: logs written before them lack them (0 or false then). */
const JOINT_NUMBERS_SINCE_28 = [
  'force',
  'ux',
  'uy',
  'target',
  'ahz',
  'adamping',
  'correction',
  'breakForce',
  'breakTorque',
] as const

function joint(v: unknown): WireJoint {
  const m = map(v, 'user joint')
  if (typeof m.kind !== 'string' || !JOINT_KINDS.includes(m.kind))
    throw new ReplayFormatError(`user joint kind is not one of ${JOINT_KINDS.join(', ')}`)
  const out: Record<string, unknown> = {
    id: int(m.id, 'joint id'),
    kind: m.kind,
    a: int(m.a, 'joint body a'),
    b: int(m.b, 'joint body b'),
  }
  for (const k of JOINT_NUMBERS) out[k] = finite(m[k], `joint ${k}`)
  for (const k of JOINT_FLAGS) out[k] = bool(m[k], `joint ${k}`)
  for (const k of JOINT_NUMBERS_SINCE_28) out[k] = m[k] === undefined ? 0 : finite(m[k], `joint ${k}`)
  out.spring = m.spring === undefined ? false : bool(m.spring, 'joint spring')
  out.owner = m.owner === undefined ? 0 : int(m.owner, 'joint owner')
  return out as unknown as WireJoint
}

function simState(v: unknown): SimulationState {
  const m = map(v, 'state')
  if (!Array.isArray(m.players) || !Array.isArray(m.userJoints))
    throw new ReplayFormatError('state lists missing')
  return {
    tick: int(m.tick, 'state tick'),
    scene: str(m.scene, 'state scene'),
    paused: bool(m.paused, 'paused'),
    stepRequested: bool(m.stepRequested, 'stepRequested'),
    // Logs from before slow motion and the control lock step every tick, unlocked.
    slowMotion: m.slowMotion === undefined ? 1 : slowFactor(m.slowMotion),
    creator: m.creator === undefined ? 0 : int(m.creator, 'state creator'),
    controlsLocked: m.controlsLocked === undefined ? false : bool(m.controlsLocked, 'state controlsLocked'),
    lastLoadTick: m.lastLoadTick === null ? null : int(m.lastLoadTick, 'lastLoadTick'),
    players: m.players.map((p) => {
      const f = map(p, 'player')
      const g = f.grab === null ? null : map(f.grab, 'grab')
      return {
        id: int(f.id, 'player id'),
        grab: g === null ? null : { joint: int(g.joint, 'grab joint'), body: int(g.body, 'grab body') },
        cursorX: finite(f.cursorX, 'cursorX'),
        cursorY: finite(f.cursorY, 'cursorY'),
      }
    }),
    userJoints: m.userJoints.map(joint),
    // Logs from before games were the sandbox's, which keeps no state.
    game: m.game === undefined ? 'sandbox' : str(m.game, 'state game'),
    gameState: m.gameState === undefined ? null : plain(m.gameState, 'state gameState'),
    random: m.random === undefined ? DEFAULT_SEED : int(m.random, 'state random'),
    // Logs from before body colours have none.
    colors: m.colors === undefined ? [] : colorList(m.colors),
    // Logs from before undo histories have none.
    history: m.history === undefined ? [] : savedHistory(m.history),
  }
}

function savedHistory(v: unknown): SavedHistory[] {
  const problem = checkSavedHistory(v)
  if (problem !== null) throw new ReplayFormatError(`state ${problem}`)
  return plain(v, 'state history') as unknown as SavedHistory[]
}

function slowFactor(v: unknown): number {
  const every = int(v, 'state slowMotion')
  if (every !== 1 && every !== 2 && every !== 4)
    throw new ReplayFormatError('state slowMotion must be 1, 2 or 4')
  return every
}

function colorList(v: unknown): number[] {
  if (!Array.isArray(v) || v.length % 2 !== 0)
    throw new ReplayFormatError('state colors must be a flat pair list')
  return v.map((c, i) => int(c, `state colors[${i}]`))
}

function plain(v: unknown, what: string): PlainData {
  try {
    return copyPlainData(v, what)
  } catch (error) {
    throw new ReplayFormatError((error as Error).message)
  }
}

/** A game command record's map: { k: 'cmd', kind, a }. */
function gameCommand(m: Record<string, unknown>): SimCommand {
  return { k: 'cmd', kind: str(m.kind, 'command kind'), a: plain(m.a, 'command arguments') }
}

function msgpack(bytes: Uint8Array, what: string): unknown {
  const decoded = decodeValue(bytes)
  if (!decoded.ok) throw new ReplayFormatError(`${what}: ${decoded.reason}`)
  return decoded.value
}

/**
 * Decode a record body (type, tick, payload) already checked by its CRC: one record, or a block's
 * records in order. `format` is the log's version (version 1 has no blocks and no delta worlds).
 * Throws ReplayFormatError.
 */
export function decodeRecordBody(body: Uint8Array, format = REPLAY_FORMAT_VERSION): ReplayRecord[] {
  const type = body[0]
  const tick = new DataView(body.buffer, body.byteOffset, body.byteLength).getUint32(1, true)
  const payload = body.subarray(5)
  if (type !== RecordType.block) return [decodePayload(type, tick, payload, format)]
  if (format < 2) throw new ReplayFormatError(`a block record in a version ${format} log`)
  let entries: Uint8Array
  try {
    entries = inflateZlibSync(payload, MAX_RECORD_BYTES)
  } catch (error) {
    if (error instanceof InflateError) throw new ReplayFormatError(`block: ${error.message}`)
    throw error
  }
  return decodeBlockEntries(tick, entries)
}

/** The records of an inflated block (see encodeBlockEntries). */
function decodeBlockEntries(tick: number, entries: Uint8Array): ReplayRecord[] {
  const out: ReplayRecord[] = []
  let at = 0
  const varint = (what: string): number => {
    let v = 0
    for (let scale = 1; scale <= 2 ** 28; scale *= 0x80) {
      if (at >= entries.length)
        throw new ReplayFormatError(`block entry ${out.length + 1}: ends inside its ${what}`)
      const b = entries[at++]
      v += (b & 0x7f) * scale
      if (b < 0x80) return v
    }
    throw new ReplayFormatError(`block entry ${out.length + 1}: ${what} varint too long`)
  }
  while (at < entries.length) {
    const type = entries[at++]
    if (!BLOCK_TYPES.has(type))
      throw new ReplayFormatError(`block entry ${out.length + 1}: type ${type} cannot be inside a block`)
    if (out.length === MAX_BLOCK_ENTRIES)
      throw new ReplayFormatError(`a block of more than ${MAX_BLOCK_ENTRIES} entries`)
    tick += varint('tick delta')
    if (tick > 0xffffffff)
      throw new ReplayFormatError(`block entry ${out.length + 1}: tick ${tick} overflows`)
    if (out.length > 0 && tick - out[0].tick > MAX_BLOCK_TICKS)
      throw new ReplayFormatError(
        `block entry ${out.length + 1}: tick ${tick} is ${tick - out[0].tick} ticks after the block's first (at most ${MAX_BLOCK_TICKS})`,
      )
    const length = varint('length')
    if (at + length > entries.length)
      throw new ReplayFormatError(`block entry ${out.length + 1}: ${length}-byte payload runs past the block`)
    out.push(decodePayload(type, tick, entries.subarray(at, at + length), REPLAY_FORMAT_VERSION))
    at += length
  }
  if (out.length === 0) throw new ReplayFormatError('an empty block')
  return out
}

const BLOCK_TYPES = new Set<number>([
  RecordType.command,
  RecordType.join,
  RecordType.leave,
  RecordType.hash,
  RecordType.close,
])

function decodePayload(type: number, tick: number, payload: Uint8Array, format: number): ReplayRecord {
  const view = new DataView(payload.buffer, payload.byteOffset, payload.byteLength)
  const player = (): number => {
    if (payload.length < 4) throw new ReplayFormatError('record too short for a player id')
    return view.getUint32(0, true)
  }
  switch (type) {
    case 1: {
      const m = map(msgpack(payload, 'header'), 'header')
      return {
        type: 'header',
        tick,
        room: str(m.room, 'room'),
        scene: str(m.scene, 'scene'),
        start: int(m.start, 'start time'),
        maxBodies: int(m.maxBodies, 'maxBodies'),
        controls: bool(m.controls, 'controls'),
        state: simState(m.state),
        host: str(m.host, 'host'),
        pid: int(m.pid, 'pid'),
        ...storedWorld(m),
      }
    }
    case 2: {
      const id = player()
      const cmd = msgpack(payload.subarray(4), 'command')
      if ((cmd as { k?: unknown } | null)?.k === 'cmd')
        return { type: 'command', tick, player: id, cmd: gameCommand(map(cmd, 'command')) }
      const checked = validateClientMessage({ t: 'input', seq: 0, cmd })
      if (!checked.ok) throw new ReplayFormatError(`command: ${checked.reason}`)
      if (checked.value.t !== 'input') throw new ReplayFormatError('command is not an input')
      return { type: 'command', tick, player: id, cmd: checked.value.cmd }
    }
    case 3: {
      const id = player()
      const m = map(msgpack(payload.subarray(4), 'join'), 'join')
      return { type: 'join', tick, player: id, name: str(m.name, 'name'), color: str(m.color, 'color') }
    }
    case 4:
      if (payload.length !== 4) throw new ReplayFormatError('leave record has the wrong size')
      return { type: 'leave', tick, player: player() }
    case 5: {
      const m = map(msgpack(payload, 'world'), 'world')
      if (m.joints != null && !Array.isArray(m.joints))
        throw new ReplayFormatError('world joints is not a list')
      return {
        type: 'world',
        tick,
        scene: str(m.scene, 'scene'),
        // Logs from before scene files kept colours and joints in world records have neither.
        colors: m.colors == null ? undefined : colorList(m.colors),
        joints: m.joints == null ? undefined : (m.joints as unknown[]).map(joint),
        ...storedWorld(m),
      }
    }
    case 6:
      if (payload.length !== 8) throw new ReplayFormatError('hash record has the wrong size')
      return { type: 'hash', tick, hash: view.getUint32(0, true), step: view.getUint32(4, true) }
    case 7: {
      const m = map(msgpack(payload, 'keyframe'), 'keyframe')
      return { type: 'keyframe', tick, state: simState(m.state), ...storedWorld(m, format >= 2) }
    }
    case 8: {
      const m = map(msgpack(payload, 'close'), 'close')
      return { type: 'close', tick, reason: str(m.reason, 'close reason'), end: int(m.end, 'end time') }
    }
    default:
      throw new ReplayFormatError(`unknown record type ${type}`)
  }
}

/** Read and check a preamble; throws ReplayFormatError naming what is wrong. */
export function decodePreamble(bytes: Uint8Array): Preamble {
  if (bytes.length < PREAMBLE_BYTES)
    throw new ReplayFormatError(`too short for a replay log (${bytes.length} bytes)`)
  for (let i = 0; i < REPLAY_MAGIC.length; i++)
    if (bytes[i] !== REPLAY_MAGIC[i])
      throw new ReplayFormatError('not a Concord replay log (bad magic bytes)')
  const view = new DataView(bytes.buffer, bytes.byteOffset, PREAMBLE_BYTES)
  const p = {
    format: view.getUint16(8, true),
    engine: view.getUint16(10, true),
    protocol: view.getUint16(12, true),
    tickRate: view.getUint16(14, true),
  }
  if (p.format < OLDEST_READABLE_VERSION || p.format > REPLAY_FORMAT_VERSION)
    throw new ReplayFormatError(
      `unsupported replay format version ${p.format} (this build reads versions ${OLDEST_READABLE_VERSION} to ${REPLAY_FORMAT_VERSION})`,
    )
  return p
}
