/*
 * docs/replay-format.md is a contract: a reader written from the document alone (below: its own
 * bitwise CRC-32, @msgpack/msgpack instead of the code's msgpackr, Node's zlib) parses a real log
 * recorded by a server, every record as the document describes it (blocks inflated and split into
 * their entries, delta keyframes rebuilt against the previous keyframe), and agrees with the
 * code's reader record by record; it cuts a torn tail where the code does. The document's tables
 * (record kinds, preamble, limits) are compared with the code's constants.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { deflateSync, inflateSync } from 'node:zlib'
import { decode } from '@msgpack/msgpack'
import { beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { loadWorld, pyramidScene, SAVE_FORMAT_VERSION } from '../../../engine/index.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { PROTOCOL_VERSION, TICK_RATE } from '../../../shared/protocol/constants.ts'
import { crc32 } from '../../../shared/replay/crc32.ts'
import {
  encodeBlockEntries,
  encodeRecord,
  frameBlock,
  MAX_BLOCK_ENTRIES,
  MAX_BLOCK_TICKS,
  MAX_RECORD_BYTES,
  MAX_RECORD_GAP,
  PREAMBLE_BYTES,
  RECORD_OVERHEAD,
  REPLAY_FORMAT_VERSION,
  REPLAY_MAGIC,
  RecordType,
} from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

const DOC = 'docs/replay-format.md'
let doc: string
let log: Uint8Array

/** CRC-32 as the document defines it, bit by bit (no table). */
function docCrc(bytes: Uint8Array): number {
  let c = 0xffffffff
  for (const b of bytes) {
    c ^= b
    for (let k = 0; k < 8; k++) c = c & 1 ? (c >>> 1) ^ 0xedb88320 : c >>> 1
  }
  return (c ^ 0xffffffff) >>> 0
}

type DocRecord = {
  type: number
  tick: number
  end: number
  fields: Record<string, unknown>
  /** Whether it came out of a block. */
  inBlock: boolean
}
type DocRead = { preamble: number[]; records: DocRecord[]; ending: 'close' | 'boundary' | 'torn' | 'corrupt' }

const isMap = (v: unknown): v is Record<string, unknown> =>
  typeof v === 'object' && v !== null && !Array.isArray(v) && !(v instanceof Uint8Array)
const isInt = (v: unknown): boolean => Number.isInteger(v)
const STATE_KEYS = [
  'tick',
  'scene',
  'paused',
  'stepRequested',
  'slowMotion',
  'creator',
  'controlsLocked',
  'lastLoadTick',
  'players',
  'userJoints',
  'game',
  'gameState',
  'random',
  'colors',
  'history',
]

/** Throws unless `v` is a state map as the document's State table says. */
function checkState(v: unknown): void {
  if (!isMap(v)) throw new Error('state is not a map')
  expect(Object.keys(v).sort()).toEqual([...STATE_KEYS].sort())
  expect(isInt(v.tick) && typeof v.scene === 'string' && typeof v.paused === 'boolean').toBe(true)
  expect(v.lastLoadTick === null || isInt(v.lastLoadTick)).toBe(true)
  expect(typeof v.game === 'string' && isInt(v.random)).toBe(true)
  for (const p of v.players as unknown[]) {
    if (!isMap(p)) throw new Error('player is not a map')
    expect(isInt(p.id) && Number.isFinite(p.cursorX) && Number.isFinite(p.cursorY)).toBe(true)
    expect(p.grab === null || (isMap(p.grab) && isInt(p.grab.joint) && isInt(p.grab.body))).toBe(true)
  }
  for (const j of v.userJoints as unknown[]) {
    if (!isMap(j)) throw new Error('joint is not a map')
    expect(['pin', 'rod', 'rope', 'spring', 'weld', 'slider', 'wheel', 'motor']).toContain(j.kind)
    for (const k of ['limit', 'motor', 'collide']) expect(typeof j[k]).toBe('boolean')
    // Joints since issue 28 carry their owner and spring flag (older logs' joints lack them).
    if (j.owner !== undefined) expect(isInt(j.owner) && typeof j.spring === 'boolean').toBe(true)
  }
}

/** Unsigned LEB128 at `at[0]` (advanced past it), as the document defines varints. */
function docVarint(bytes: Uint8Array, at: number[]): number {
  let v = 0
  for (let shift = 0; ; shift += 7) {
    if (at[0] >= bytes.length) throw new Error('varint past the end')
    const b = bytes[at[0]++]
    v += (b & 0x7f) * 2 ** shift
    if (b < 0x80) return v
  }
}

/** The document's delta worlds: literal and copy runs against `base`. */
function docDelta(base: Uint8Array, delta: Uint8Array): Uint8Array {
  const at = [0]
  const n = docVarint(delta, at)
  const out: number[] = []
  let shift = 0
  while (out.length < n) {
    const r = docVarint(delta, at)
    const len = r % 2 === 0 ? r / 2 : (r - 1) / 2
    if (len < 1 || out.length + len > n) throw new Error('bad run')
    if (r % 2 === 0) {
      out.push(...delta.subarray(at[0], at[0] + len))
      at[0] += len
    } else {
      const z = docVarint(delta, at)
      const p = out.length + shift + (z % 2 === 0 ? z / 2 : -(z + 1) / 2)
      if (p < 0 || p + len > base.length) throw new Error('copy outside the base')
      shift = p - out.length
      out.push(...base.subarray(p, p + len))
    }
  }
  expect(at[0]).toBe(delta.length)
  return Uint8Array.from(out)
}

/**
 * Throws unless `z`/`world` are a saved world as the document says; returns the World.save()
 * bytes (`base`: the previous keyframe's or header's, for z = 2 in keyframes).
 */
function savedWorld(m: Record<string, unknown>, base?: Uint8Array): Uint8Array {
  expect(base ? [0, 1, 2] : [0, 1]).toContain(m.z)
  expect(m.world).toBeInstanceOf(Uint8Array)
  if (m.z === 0) return m.world as Uint8Array
  const inflated = new Uint8Array(inflateSync(m.world as Uint8Array))
  return m.z === 1 ? inflated : docDelta(base as Uint8Array, inflated)
}

/** A block's payload as the document says: a zlib stream of (type, tick delta, length, payload). */
function docBlock(
  payload: Uint8Array,
  tick: number,
): Array<{ type: number; tick: number; payload: Uint8Array }> {
  const bytes = new Uint8Array(inflateSync(payload))
  const out = []
  const at = [0]
  while (at[0] < bytes.length) {
    const type = bytes[at[0]++]
    if (![2, 3, 4, 6, 8].includes(type)) throw new Error(`type ${type} in a block`)
    tick += docVarint(bytes, at)
    const length = docVarint(bytes, at)
    if (at[0] + length > bytes.length) throw new Error('entry past the block')
    if (out.length === 65536) throw new Error('more than 65536 entries')
    if (out.length > 0 && tick - out[0].tick > 600) throw new Error('entries over more than 600 ticks')
    out.push({ type, tick, payload: bytes.subarray(at[0], at[0] + length) })
    at[0] += length
  }
  if (out.length === 0) throw new Error('empty block')
  return out
}

/** A record's fields from its payload, as the kinds table says. */
function docFields(type: number, payload: Uint8Array): Record<string, unknown> {
  const pv = new DataView(payload.buffer, payload.byteOffset, payload.byteLength)
  switch (type) {
    case 2:
    case 3:
      return { player: pv.getUint32(0, true), ...(decode(payload.subarray(4)) as Record<string, unknown>) }
    case 4:
      expect(payload.length).toBe(4)
      return { player: pv.getUint32(0, true) }
    case 6:
      expect(payload.length).toBe(8)
      return { hash: pv.getUint32(0, true), step: pv.getUint32(4, true) }
    case 1:
    case 5:
    case 7:
    case 8:
      return decode(payload) as Record<string, unknown>
    default:
      throw new Error(`unknown type ${type}`)
  }
}

/** A reader written from the document: framing, CRC, kinds and fields, order, torn tails. */
function docRead(bytes: Uint8Array): DocRead {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
  const magic = new TextDecoder().decode(bytes.subarray(0, 8))
  if (magic !== 'CNCRDLOG' || view.getUint16(8, true) !== 3) throw new Error('not a version 3 log')
  const preamble = [8, 10, 12, 14].map((o) => view.getUint16(o, true))
  const records: DocRecord[] = []
  let at = 16
  let ending: DocRead['ending'] = 'boundary'
  while (at < bytes.length) {
    if (bytes.length - at < 4) {
      ending = 'torn'
      break
    }
    const L = view.getUint32(at, true)
    if (L < 5 || L > 67108864) {
      ending = 'corrupt'
      break
    }
    if (at + 4 + L + 4 > bytes.length) {
      ending = 'torn'
      break
    }
    if (docCrc(bytes.subarray(at, at + 4 + L)) !== view.getUint32(at + 4 + L, true)) {
      ending = 'corrupt'
      break
    }
    const type = bytes[at + 4]
    const tick = view.getUint32(at + 5, true)
    const payload = bytes.subarray(at + 9, at + 4 + L)
    const end = at + 4 + L + 4
    let entries: Array<{ type: number; tick: number; payload: Uint8Array }>
    try {
      entries = type === 9 ? docBlock(payload, tick) : [{ type, tick, payload }]
    } catch {
      ending = 'corrupt'
      break
    }
    const fresh: DocRecord[] = []
    let prev = records.at(-1)
    for (const e of entries) {
      const first = records.length + fresh.length === 0
      const misordered = prev && (prev.type === 8 || e.tick < prev.tick || e.tick > prev.tick + 60)
      if (first !== (e.type === 1) || misordered) break
      prev = { type: e.type, tick: e.tick, end, fields: docFields(e.type, e.payload), inBlock: type === 9 }
      fresh.push(prev)
    }
    if (fresh.length < entries.length) {
      ending = 'corrupt'
      break
    }
    records.push(...fresh)
    at = end
  }
  if (ending === 'boundary' && records.at(-1)?.type === 8) ending = 'close'
  return { preamble, records, ending }
}

beforeAll(async () => {
  doc = await readFile(DOC, 'utf8')
  const dir = await mkdtemp(join(tmpdir(), 'concord-format-'))
  // Rooms on the main thread: this file reads the live room's world and tick.
  const server = await startTestServer({
    ...inProcessRooms,
    record: true,
    replayDir: dir,
    keyframeTicks: 60,
    keyframeBudget: 0,
    defaultScene: 'tower',
  })
  const a = await BotClient.connect({ url: server.url, room: 'doc', name: 'ada' })
  const b = await BotClient.connect({ url: server.url, room: 'doc', name: 'bob' })
  const room = server.rooms.get('doc')!
  const dynamic = (): number[] => [...a.mirror.bodies.values()].filter((x) => x.kind === 2).map((x) => x.id)
  await a.waitFor(() => dynamic().length > 3, 'bodies')
  const [first, second] = dynamic()
  a.command({ k: 'grab', body: first, lx: 0, ly: 0 })
  const body = a.mirror.bodies.get(second)!
  b.command({ k: 'pin', a: 0, b: second, x: body.x, y: body.y })
  // At least 130 ticks after the load, so two keyframes follow it (the reader compares those).
  let end = 200
  for (let i = 0; room.tick < end; i++) {
    a.command({ k: 'move', x: Math.sin(i / 4) * 2, y: 4 })
    if (i === 5) {
      room.loadBlueprint('small pyramid', pyramidScene(4))
      end = Math.max(200, room.tick + 130)
    }
    await a.waitFor(() => a.mirror.tick >= Math.min(room.tick, end) - 1)
    await new Promise((r) => setTimeout(r, 15))
  }
  await b.close()
  await a.waitFor(() => room.players.size === 1, 'bob leaves')
  await a.close()
  await server.close()
  const name = (await listLogNames(dir)).find((n) => n.startsWith('doc-'))!
  log = new Uint8Array(await readFile(join(dir, name)))
}, 60_000)

describe('docs/replay-format.md', () => {
  it("lists exactly the code's record kinds, preamble values and limits", () => {
    const kinds = [...doc.matchAll(/^\| (\d+) \| ([a-z]+) \|/gm)].map((m) => [m[2], Number(m[1])])
    expect(Object.fromEntries(kinds)).toEqual(RecordType)
    expect(doc).toContain(`ASCII \`CNCRDLOG\``)
    expect(new TextDecoder().decode(REPLAY_MAGIC)).toBe('CNCRDLOG')
    expect(doc).toContain(`# Concord replay log format, version ${REPLAY_FORMAT_VERSION}`)
    expect(doc).toContain(`\`${REPLAY_FORMAT_VERSION}\` (this document)`)
    expect(doc).toContain(`\`SAVE_FORMAT_VERSION\`, now \`${SAVE_FORMAT_VERSION}\``)
    expect(doc).toContain(`now \`${PROTOCOL_VERSION}\``)
    expect(doc).toContain(`\`${TICK_RATE}\` |`)
    expect(doc).toContain(`L <= ${MAX_RECORD_BYTES}`)
    expect(doc).toContain(`(${RECORD_OVERHEAD} bytes of framing around the payload)`)
    expect(doc).toContain(`more than ${MAX_RECORD_GAP} ticks after the previous`)
    expect(doc).toContain(`more than ${MAX_BLOCK_ENTRIES} entries or whose last`)
    expect(doc).toContain(`entry is more than ${MAX_BLOCK_TICKS} ticks after its first`)
    expect(doc).toContain('preamble (16 bytes)')
    expect(PREAMBLE_BYTES).toBe(16)
    const check = new TextEncoder().encode('123456789')
    expect(docCrc(check)).toBe(0xcbf43926)
    expect(crc32(check)).toBe(0xcbf43926)
    expect(doc).toContain('`0xCBF43926`')
  })

  it("a reader written from the document parses a real log as the code's reader does", () => {
    const ours = docRead(log)
    expect(ours.ending).toBe('close')
    expect(ours.preamble).toEqual([REPLAY_FORMAT_VERSION, SAVE_FORMAT_VERSION, PROTOCOL_VERSION, TICK_RATE])
    const code = new ReplayLogReader().push(log)
    expect(ours.records.length).toBe(code.length)
    const seen = new Set<number>()
    const hashAt = new Map<number, number>()
    /** Saved world of the last header or keyframe (a delta's base), and the z values met. */
    let base: Uint8Array | undefined
    const zs = new Set<unknown>()
    // Keyframes after the blueprint load compared with the room's hash: before it, bob's pin is in
    // his undo history and the room's hash mixes that in (the hash record's rule), so the world's
    // own hash is the room's only once the load has cleared it (and no player spawned or coloured).
    let loaded = false
    let compared = 0
    for (const [i, r] of ours.records.entries()) {
      const c = code[i]
      seen.add(r.type)
      expect(RecordType[c.type], `record ${i}`).toBe(r.type)
      expect(r.tick).toBe(c.tick)
      const f = r.fields
      switch (c.type) {
        case 'header':
          expect(Object.keys(f).sort()).toEqual([
            'controls',
            'host',
            'maxBodies',
            'pid',
            'room',
            'scene',
            'start',
            'state',
            'world',
            'z',
          ])
          expect(f.room).toBe('doc')
          checkState(f.state)
          base = savedWorld(f)
          expect(loadWorld(base).hash()).toBe(loadWorld(c.z === 1 ? inflateSync(c.world) : c.world).hash())
          break
        case 'command':
          expect({ ...f }).toEqual({ player: c.player, ...c.cmd })
          break
        case 'join':
          expect(f).toEqual({ player: c.player, name: c.name, color: c.color })
          break
        case 'leave':
          expect(f).toEqual({ player: c.player })
          break
        case 'hash':
          expect(f).toEqual({ hash: c.hash, step: c.step })
          hashAt.set(r.tick, c.hash)
          break
        case 'world':
          expect(Object.keys(f).sort()).toEqual(['colors', 'joints', 'scene', 'world', 'z'])
          expect(f.scene).toBe('small pyramid')
          loaded = true
          // A blueprint's world: no colours; its joints as they travel (the small pyramid has none).
          expect([f.colors, f.joints]).toEqual([[], []])
          savedWorld(f)
          break
        case 'keyframe': {
          checkState(f.state)
          expect((f.state as { tick: number }).tick).toBe(r.tick)
          // A keyframe holds the state at the end of its tick: its world hashes to that tick's hash.
          zs.add(f.z)
          base = savedWorld(f, base)
          const hash = loadWorld(base).hash()
          if (loaded && hashAt.has(r.tick)) {
            expect(hash, `keyframe at ${r.tick}`).toBe(hashAt.get(r.tick))
            compared++
          }
          break
        }
        case 'close':
          expect(typeof f.reason).toBe('string')
          expect(isInt(f.end)).toBe(true)
          break
      }
    }
    expect([...seen].sort()).toEqual([1, 2, 3, 4, 5, 6, 7, 8])
    expect(compared).toBeGreaterThanOrEqual(2)
    // Small records travel in blocks, big ones never; keyframes are whole and deltas.
    for (const r of ours.records) expect(r.inBlock, `type ${r.type}`).toBe([2, 3, 4, 6, 8].includes(r.type))
    expect([...zs].sort()).toEqual([1, 2])
    expect(ours.records.filter((r) => r.type === 7).every((r) => r.tick % 60 === 0)).toBe(true)
    expect(ours.records.filter((r) => r.type === 6 && r.tick % 60 === 0).length).toBeGreaterThanOrEqual(3)
  })

  it('refuses a record too far ahead and a block past its limits where the code does', () => {
    // The real log up to its close, then crafted records: framed correctly, only their ticks and
    // sizes break the rules. Each case is tried at the limit (kept) and one past it (cut).
    const records = docRead(log).records
    // The last record of the frame before the close's (a block may hold the close and more).
    const last = records.filter((r) => r.end < records.at(-1)!.end).at(-1)!
    const prefix = log.subarray(0, last.end)
    const t = last.tick
    const hash = (tick: number) => ({ type: 'hash' as const, tick, hash: 1, step: 1 })
    const block = (entries: ReturnType<typeof hash>[]) =>
      frameBlock(entries[0].tick, deflateSync(encodeBlockEntries(entries)))
    // Entries every 60 ticks (the gap rule holds), the last `span` ticks after the first.
    const spread = (from: number, span: number) =>
      [...Array.from({ length: Math.ceil(span / 60) }, (_, i) => i * 60), span].map((d) => hash(from + d))
    const cases: Array<[string, Uint8Array, boolean]> = [
      ['a hash record 60 ticks on', encodeRecord(hash(t + MAX_RECORD_GAP)), true],
      ['a hash record 61 ticks on', encodeRecord(hash(t + MAX_RECORD_GAP + 1)), false],
      ['3,000,000 ticks on', encodeRecord(hash(t + 3_000_000)), false],
      ['a block 61 ticks on', block([hash(t + 61)]), false],
      ['a block over 600 ticks', block(spread(t + 1, MAX_BLOCK_TICKS)), true],
      ['a block over 601 ticks', block(spread(t + 1, MAX_BLOCK_TICKS + 1)), false],
      ['65536 entries', block(Array.from({ length: MAX_BLOCK_ENTRIES }, () => hash(t))), true],
      ['65537 entries', block(Array.from({ length: MAX_BLOCK_ENTRIES + 1 }, () => hash(t))), false],
    ]
    for (const [what, crafted, kept] of cases) {
      const bytes = new Uint8Array(prefix.length + crafted.length)
      bytes.set(prefix)
      bytes.set(crafted, prefix.length)
      const ours = docRead(bytes)
      const reader = new ReplayLogReader()
      reader.push(bytes)
      const code = reader.finish()
      const intact = kept ? bytes.length : prefix.length
      expect({ what, doc: ours.records.at(-1)!.end, code: code.intactBytes }).toEqual({
        what,
        doc: intact,
        code: intact,
      })
      expect({ what, doc: ours.ending, code: code.state }).toEqual({
        what,
        doc: kept ? 'boundary' : 'corrupt',
        code: kept ? 'end' : 'corrupt',
      })
    }
  })

  it('cuts torn tails and corrupt records where the code does, keeping the same intact prefix', () => {
    const ends = docRead(log).records.map((r) => r.end)
    for (let k = 0; k < 40; k++) {
      const cut = 17 + Math.floor((((k * 7919) % 1000) / 1000) * (log.length - 17))
      const ours = docRead(log.subarray(0, cut))
      const reader = new ReplayLogReader()
      reader.push(log.subarray(0, cut))
      const code = reader.finish()
      const intact = ends.filter((e) => e <= cut).at(-1) ?? 16
      expect(ours.records.at(-1)?.end ?? 16).toBe(intact)
      expect(code.intactBytes).toBe(intact)
      // The code calls a log cut inside its header invalid (no header to start from).
      if (ours.records.length === 0) expect(code.state).toBe('invalid')
      else expect(ours.ending === 'torn').toBe(code.state === 'torn')
      // A flipped bit inside the last intact record makes it, and nothing after, unusable.
      if (ours.records.length > 1) {
        const flipped = log.slice(0, cut)
        flipped[intact - 6] ^= 0x10
        const bad = docRead(flipped)
        const before = ends.filter((e) => e < intact).at(-1) ?? 16
        expect(bad.ending).toBe('corrupt')
        expect(bad.records.at(-1)?.end ?? 16).toBe(before)
        const r2 = new ReplayLogReader()
        r2.push(flipped)
        expect(r2.finish()).toMatchObject({ state: 'corrupt', intactBytes: before })
      }
    }
  })
})
