/*
 * PROTOCOL.md's promises about refusals, the input budget, `events` and number encoding, checked
 * against a real server with a client built from the document alone (doc-client.ts: `ws` and
 * @msgpack/msgpack, no shared/ code). Expected values come from the document's rules worked by
 * hand, not from the server's code.
 */
import type { Socket } from 'node:net'
import { encode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { type Decoded, DocClient, parseSnapshotData } from './doc-client.ts'

const BOX = { type: 'box', hw: 0.25, hh: 0.25 }
/** --max-rejects (default 20) and rules.inputsPerTick (default 8) as documented. */
const MAX_REJECTS = 20
const INPUTS_PER_TICK = 8

let server: RunningServer

beforeAll(async () => {
  // A long heartbeat: strikes are forgiven at each one, and these tests count them.
  server = await startTestServer({ defaultScene: 'empty', heartbeatMs: 60_000 })
})
afterAll(async () => {
  await server.close()
})

const errors = (c: DocClient): Array<{ code: unknown; seq: unknown }> =>
  c.all('error').map((e) => ({ code: e.code, seq: e.seq }))

/** Every body of every `events.add` received. */
const added = (c: DocClient): Array<Record<string, unknown>> =>
  c
    .all('events')
    .flatMap((e) => (e.add as Array<Record<string, unknown>>).map((b) => ({ ...b, tick: e.tick })))

/** Send frames in one TCP write, so the server reads them together within one tick. */
function sendTogether(c: DocClient, frames: Uint8Array[]): void {
  const socket = (c.ws as unknown as { _socket: Socket })._socket
  socket.cork()
  for (const f of frames) c.sendBytes(f)
  socket.uncork()
}

const input = (seq: unknown, cmd: Record<string, unknown>): Uint8Array => encode({ t: 'input', seq, cmd })

describe('PROTOCOL.md refusals', { timeout: 30_000 }, () => {
  it('answers each refused input with an error carrying its seq (schema-invalid ones too), and none for unreadable seqs', async () => {
    const c = await DocClient.joined(server.url, 'seqs', 'seqs')
    const frames = [
      input(101, { k: 'move', x: 'left', y: 0 }),
      input(102, { k: 'fly' }),
      input(103, { k: 'spawn', shape: BOX, x: 1_000_001, y: 0 }),
      encode({ t: 'input', seq: 104, cmd: { k: 'release' }, extra: 1 }),
      input(105, { k: 'delete', body: 999_999 }),
      input(106, { k: 'move', x: Number.NaN, y: 0 }),
      input(107, { k: 'move', x: new Date(0), y: 0 }), // a timestamp extension: malformed, unread
      input(-1, { k: 'fly' }),
      input(1.5, { k: 'fly' }),
      new Uint8Array([0xc1]),
      new Uint8Array([...encode({ t: 'ping', id: 1, time: 0 }), 0]),
    ]
    for (const f of frames) c.sendBytes(f)
    await c.waitFor(() => c.all('error').length >= frames.length, 'an error per refused frame')
    const key = (e: { code: unknown; seq: unknown }): string => `${String(e.code)}:${String(e.seq)}`
    expect(errors(c).map(key).sort()).toEqual(
      [
        'invalid:101',
        'invalid:102',
        'invalid:103',
        'invalid:104',
        'refused:105',
        'invalid:106',
        'malformed:undefined',
        'invalid:undefined',
        'invalid:undefined',
        'malformed:undefined',
        'malformed:undefined',
      ].sort(),
    )
    // An input before the join: not-joined, with its seq.
    const early = await DocClient.open(server.url, 'seqs')
    early.send({ t: 'input', seq: 7, cmd: { k: 'release' } })
    const notJoined = await early.waitFor((m) => m.t === 'error', 'not-joined')
    expect([notJoined.code, notJoined.seq]).toEqual(['not-joined', 7])
    expect(c.close).toBeNull()
    c.end()
    early.end()
  })

  it('answers every refused message until strike 21, which closes with 1008 naming that refusal', async () => {
    const c = await DocClient.joined(server.url, 'strikes', 'striker')
    // Room refusals are not strikes: 32 of them, 8 per tick, all answered, the socket stays open.
    for (let round = 0; round < 4; round++) {
      for (let i = 0; i < INPUTS_PER_TICK; i++)
        c.send({ t: 'input', seq: round * 8 + i, cmd: { k: 'delete', body: 1e9 } })
      await c.waitFor(() => c.all('error').length === (round + 1) * 8, `refusals of round ${round}`)
    }
    expect(new Set(c.all('error').map((e) => e.code))).toEqual(new Set(['refused']))
    expect(c.all('error').map((e) => e.seq)).toEqual([...Array(32).keys()])
    expect(c.close).toBeNull()
    // Invalid ones are strikes: 25 sent, 20 answered (more than version 1's 10), the 21st closes.
    for (let i = 1; i <= 25; i++) c.send({ t: 'input', seq: 100 + i, cmd: { k: `fly${i}` } })
    const close = await c.closed()
    expect(close.code).toBe(1008)
    expect(close.reason).toContain('unknown command "fly21"')
    const invalid = c.all('error').filter((e) => e.code === 'invalid')
    expect(invalid.map((e) => e.seq)).toEqual(Array.from({ length: MAX_REJECTS }, (_, i) => 101 + i))
  })

  it("keeps inputs over the per-tick budget waiting (4 ticks' worth), refuses the rest with input-budget and its seq; every spawn is accounted for once", async () => {
    const c = await DocClient.joined(server.url, 'budget', 'spawner')
    // 8 for the coming tick and 32 waiting are always kept; of the other 20, those arriving
    // before a tick drains the waiting room are kept too, the rest refused.
    const count = 60
    const frames = Array.from({ length: count }, (_, i) =>
      input(i + 1, { k: 'spawn', shape: BOX, x: -20 + i, y: 5 + (i % 4) }),
    )
    sendTogether(c, frames)
    const answered = (seq: number): number =>
      added(c).filter((b) => b.seq === seq).length + c.all('error').filter((e) => e.seq === seq).length
    await c.waitFor(() => frames.every((_, i) => answered(i + 1) > 0), 'every spawn answered')
    for (let seq = 1; seq <= count; seq++) expect(answered(seq), `spawn ${seq} answered once`).toBe(1)
    const bodies = added(c)
    expect(bodies.every((b) => b.player === c.id)).toBe(true)
    const perTick = new Map<unknown, number>()
    for (const b of bodies) perTick.set(b.tick, (perTick.get(b.tick) ?? 0) + 1)
    for (const n of perTick.values()) expect(n).toBeLessThanOrEqual(INPUTS_PER_TICK)
    expect(bodies.length).toBeGreaterThanOrEqual(INPUTS_PER_TICK * 5)
    // Applied in the order sent: the kept spawns' seqs rise with their ticks.
    const keptSeqs = bodies.map((b) => b.seq as number)
    expect(keptSeqs).toEqual([...keptSeqs].sort((x, y) => x - y))
    const refused = c.all('error')
    expect(refused.length).toBeGreaterThan(0)
    expect(new Set(refused.map((e) => e.code))).toEqual(new Set(['input-budget']))
    expect(bodies.length + refused.length).toBe(count)
    expect(c.close).toBeNull()
    c.end()
  })
})

describe('PROTOCOL.md accepted values', { timeout: 30_000 }, () => {
  it('accepts each documented range up to its edge and refuses just beyond it as invalid, then clamps', async () => {
    const c = await DocClient.joined(server.url, 'ranges', 'ranger')
    const spawn = (extra: Record<string, unknown>, i: number): Record<string, unknown> => ({
      k: 'spawn',
      shape: BOX,
      x: -40 + 3 * i,
      y: 30 + 5 * i, // apart: the 10 m shapes touch nothing
      ...extra,
    })
    // [command, the answer the document promises]: 'add' (applied), 'refused' (valid, not applied), 'invalid'.
    const cases: Array<[Record<string, unknown>, string]> = [
      [spawn({ angle: 1000 }, 0), 'add'],
      [spawn({ angle: 1000.01 }, 1), 'invalid'],
      [spawn({ vx: 1e6 }, 2), 'add'],
      [spawn({ vx: 1e6 + 1 }, 3), 'invalid'],
      [spawn({ w: 1e6 }, 4), 'add'],
      [spawn({ shape: { type: 'circle', radius: 0.05 } }, 5), 'add'],
      [spawn({ shape: { type: 'circle', radius: 0.049 } }, 6), 'invalid'],
      [spawn({ shape: { type: 'box', hw: 10, hh: 0.05 } }, 7), 'add'],
      [spawn({ shape: { type: 'box', hw: 10.001, hh: 1 } }, 8), 'invalid'],
      [spawn({ shape: { type: 'polygon', v: [0, 0, 10, 0, 0, 10] } }, 9), 'add'],
      [spawn({ shape: { type: 'polygon', v: [0, 0, 10.5, 0, 0, 10] } }, 10), 'invalid'],
      [{ k: 'grab', body: 999_999, lx: 1000, ly: -1000 }, 'refused'],
      [{ k: 'grab', body: 999_999, lx: 1000.5, ly: 0 }, 'invalid'],
      [{ k: 'delete', body: 2 ** 53 - 1 }, 'refused'],
      [{ k: 'delete', body: 0 }, 'invalid'],
      [{ k: 'delete', body: 2 ** 53 }, 'invalid'],
      [{ k: 'pin', a: 0, b: 999_999, x: -1e6, y: 1e6 }, 'refused'],
      [{ k: 'pin', a: 0, b: 999_999, x: -1e6 - 1, y: 0 }, 'invalid'],
      [{ k: 'scene', name: 'x'.repeat(32) }, 'refused'],
      [{ k: 'scene', name: 'x'.repeat(33) }, 'invalid'],
      [{ k: 'unjoint', joint: 999_999 }, 'refused'],
      [spawn({ w: 100 }, 21), 'add'],
    ]
    cases.forEach(([cmd], seq) => {
      c.send({ t: 'input', seq, cmd })
    })
    const answer = (seq: number): string | undefined =>
      added(c).some((b) => b.seq === seq)
        ? 'add'
        : (c.all('error').find((e) => e.seq === seq)?.code as string | undefined)
    await c.waitFor(() => cases.every((_, seq) => answer(seq) !== undefined), 'every case answered')
    expect(cases.map((_, seq) => answer(seq))).toEqual(cases.map(([, expected]) => expected))
    // The clamps, after the one step the add event's pose includes: vx 1e6 -> 100 m/s moves x by
    // 100/60 m; w 1e6 turns the box exactly as w 100 does (and it turned).
    const pose = (seq: number): Record<string, unknown> => added(c).find((b) => b.seq === seq)!
    expect(pose(2).x).toBe(Math.round((-40 + 3 * 2 + 100 / 60) * 1000))
    expect(pose(4).a).toBe(pose(21).a)
    expect(pose(4).a).toBeGreaterThan(0)
    // The largest seq comes back whole; one beyond it cannot be echoed.
    c.send({ t: 'input', seq: 2 ** 53 - 1, cmd: { k: 'unjoint', joint: 1 } })
    c.send({ t: 'input', seq: 2 ** 53, cmd: { k: 'unjoint', joint: 1 } })
    await c.waitFor(
      () => c.all('error').length === 2 + cases.filter(([, e]) => e !== 'add').length,
      'two more',
    )
    // (the invalid one is answered at once, the refused one when the room applies its tick)
    const lastTwo = c
      .all('error')
      .slice(-2)
      .map((e) => [e.code, e.seq])
    expect(lastTwo).toContainEqual(['refused', 2 ** 53 - 1])
    expect(lastTwo).toContainEqual(['invalid', undefined])
    c.end()
  })
})

describe('PROTOCOL.md input budget', { timeout: 30_000 }, () => {
  it('lets a move replace the waiting move without counting, while pings count', async () => {
    const c = await DocClient.joined(server.url, 'coalesce', 'mover')
    const spawns = Array.from({ length: INPUTS_PER_TICK - 1 }, (_, i) =>
      input(i + 1, { k: 'spawn', shape: BOX, x: -10 + 2 * i, y: 5 }),
    )
    const moves = Array.from({ length: 20 }, (_, i) => input(100 + i, { k: 'move', x: i + 1, y: 2 }))
    // 7 spawns and one move fill the budget of 8; the 19 later moves replace the waiting one.
    sendTogether(c, [...spawns, ...moves, encode({ t: 'ping', id: 9, time: 0 })])
    await c.waitFor(() => added(c).length === spawns.length, 'every spawn applied')
    const refused = await c.waitFor((m) => m.t === 'error', 'the ping refused')
    expect([refused.code, refused.seq]).toEqual(['input-budget', undefined])
    const me = c.id
    const cursor = (): number[] | undefined => {
      for (const snap of c.all('snap').reverse()) {
        const flat = snap.cursors as number[]
        for (let i = 0; i + 3 < flat.length; i += 4) if (flat[i] === me) return flat.slice(i, i + 4)
      }
      return undefined
    }
    await c.waitFor(() => (cursor()?.[1] ?? 0) !== 0, 'my moved cursor in a snapshot')
    expect(cursor()).toEqual([me, 20_000, 2_000, 0])
    expect(c.all('error')).toHaveLength(1)
    expect(c.all('pong')).toEqual([])
    c.end()
  })
})

describe('PROTOCOL.md events and numbers', { timeout: 30_000 }, () => {
  it('lists a new body with its pose after the step of the tick the message names, and its spawner', async () => {
    const a = await DocClient.joined(server.url, 'events', 'a')
    const b = await DocClient.joined(server.url, 'events', 'b')
    a.send({ t: 'input', seq: 41, cmd: { k: 'spawn', shape: BOX, x: 2, y: 20, vx: 6 } })
    const seen = async (c: DocClient): Promise<Record<string, unknown>> => {
      await c.waitFor(() => added(c).some((x) => x.seq === 41), 'the add event')
      return added(c).find((x) => x.seq === 41)!
    }
    const [forA, forB] = await Promise.all([seen(a), seen(b)])
    expect(forB).toEqual(forA)
    expect(forA.player).toBe(a.id)
    // One 1/60 s step at 6 m/s: 2 m + 0.1 m, quantized to mm; the unstepped pose would be 2000.
    expect(forA.x).toBe(2100)
    expect(forA.y as number).toBeLessThan(20_000)
    // A body added at a snapshot tick (every other tick at 30 snapshots per second) is in that
    // snapshot as an absolute entry with the very pose of the add event.
    let seq = 41
    let match: { add: Record<string, unknown>; snap: Decoded } | undefined
    while (!match) {
      const s = ++seq
      a.send({ t: 'input', seq: s, cmd: { k: 'spawn', shape: BOX, x: -30 + s, y: 10, vx: 3, w: 1 } })
      await a.waitFor(() => added(a).some((x) => x.seq === s), 'the add event')
      const add = added(a).find((x) => x.seq === s)!
      const snap = await a.waitFor(
        (m) => m.t === 'snap' && (m.tick as number) >= (add.tick as number),
        'a snap',
      )
      if (snap.tick === add.tick) match = { add, snap }
      expect(seq, 'an add at a snapshot tick within 20 spawns').toBeLessThan(62)
    }
    const entry = parseSnapshotData(match.snap.data as Uint8Array).find((e) => e.id === match!.add.id)
    expect(entry).toEqual({ id: match.add.id, flags: 1 | 2, x: match.add.x, y: match.add.y, a: match.add.a })
    // Scene bodies (the welcome's state) name no spawner.
    const state = a.first('welcome').state as { bodies: Array<Record<string, unknown>> }
    for (const body of state.bodies) expect(Object.keys(body)).not.toContain('seq')
    a.end()
    b.end()
  })

  it('keeps a clockwise polygon counter-clockwise and refuses collinear, too-close or concave points', async () => {
    const c = await DocClient.joined(server.url, 'polygons', 'shaper')
    const spawn = (seq: number, v: number[]): void =>
      c.send({ t: 'input', seq, cmd: { k: 'spawn', shape: { type: 'polygon', v }, x: 4 * seq, y: 5 } })
    spawn(1, [0, 0, 0, 1, 1, 0]) // clockwise
    spawn(2, [0, 0, 1, 0, 2, 0, 1, 1]) // three points in a line
    spawn(3, [0, 0, 0.0005, 0, 0.5, 0.5]) // two points 0.5 mm apart
    spawn(4, [0, 0, 1, 0, 0.2, 0.2, 0, 1]) // concave
    await c.waitFor(() => added(c).length + c.all('error').length === 4, 'four answers')
    expect(added(c).map((b) => [b.seq, b.shapes])).toEqual([
      [1, [{ type: 'polygon', v: [1, 0, 0, 1, 0, 0] }]],
    ])
    expect(c.all('error').map((e) => [e.code, e.seq])).toEqual([
      ['refused', 2],
      ['refused', 3],
      ['refused', 4],
    ])
    c.end()
  })

  it('rounds halves toward +infinity when quantizing positions', async () => {
    const c = await DocClient.joined(server.url, 'round', 'rounder')
    // x * 1000 is exactly a half for each; the expected integers follow the documented rule by hand.
    const cases: Array<[number, number]> = [
      [0.0025, 3],
      [-0.0025, -2],
      [0.0005, 1],
      [-0.0005, 0],
      [1.0025, 1003],
      [-1.0025, -1002],
    ]
    for (const [i, [x]] of cases.entries()) {
      c.send({ t: 'input', seq: i, cmd: { k: 'spawn', shape: BOX, x, y: 10 + 3 * i } })
    }
    await c.waitFor(() => added(c).length === cases.length, 'the spawned bodies')
    for (const [i, [, q]] of cases.entries()) expect(added(c).find((b) => b.seq === i)!.x).toBe(q)
    c.end()
  })

  it('sends whole numbers as integers and accepts whole floats for integer fields and the full coordinate range', async () => {
    const c = await DocClient.joined(server.url, 'numbers', 'numbers')
    // The welcome's gravity [0, -10]: the key "gravity", then a 2-array of fixints 0 and -10.
    const gravity = Buffer.from([0xa7, ...Buffer.from('gravity'), 0x92, 0x00, 0xf6])
    expect(Buffer.from(c.frames[0]).includes(gravity)).toBe(true)
    // Every number written as a float64, seq and ids included.
    c.send(
      { t: 'input', seq: 77, cmd: { k: 'spawn', shape: BOX, x: 1_000_000, y: 3 } },
      { forceIntegerToFloat: true },
    )
    c.send({ t: 'ping', id: 5, time: 12 }, { forceIntegerToFloat: true })
    await c.waitFor(() => added(c).some((b) => b.seq === 77), 'the float-encoded spawn')
    const pong = await c.waitFor((m) => m.t === 'pong', 'pong')
    expect([pong.id, pong.time]).toEqual([5, 12])
    // x = 1,000,000 m is on the wire range's edge: accepted, clamped to the 500 m world bound.
    expect(added(c).find((b) => b.seq === 77)!.x).toBe(500_000)
    expect(c.all('error')).toEqual([])
    c.end()
  })
})
