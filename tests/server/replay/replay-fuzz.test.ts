/*
 * Replay logs from untrusted hands (a file a user opens in the replay tool or the browser page):
 * seeded damage to a real recorded log, and logs whose records are framed correctly (right
 * lengths and CRCs) but hold hostile contents. The contract, from the replay tool's own promise: a
 * log either replays (its intact prefix, the damage reported) or is refused with a ReplayToolError
 * naming the problem; never another error, never a non-integer hash, and never a replay that
 * steps far past what the log's bytes hold (docs/replay-format.md: at most MAX_RECORD_GAP ticks
 * from one record to the next). Found Nov 24: one framed record 3,000,000 ticks after the join
 * made a replay step the empty room for 17 s; one near tick 2^32 would have taken hours.
 */

import { mkdtemp, readFile, rm } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import fc from 'fast-check'
import pino from 'pino'
import { Counter } from 'prom-client'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import { type ReplayReport, ReplayToolError, replayLog } from '../../../server/replay/replay-tool.ts'
import {
  encodePreamble,
  encodeRecord,
  MAX_RECORD_GAP,
  type ReplayRecord,
} from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'

const SEED = 29
let dir: string
let log: Uint8Array
let records: ReplayRecord[]
let head: Uint8Array

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-replay-fuzz-'))
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'fuzz',
    scene: 'tower',
    maxBodies: 400,
    controls: true,
  })
  const recorder = new RoomRecorder('fuzz', sim, {
    dir,
    fsync: 'none',
    keyframeTicks: 40,
    keyframeBudget: 0,
    maxBytes: 1 << 30,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: 'test_replay_fuzz_failures', help: 'test', registers: [] }),
    openNames: new Set(),
  })
  recorder.start(0)
  sim.join(1, 'ada', '#e6194b')
  const top = sim.world
    .bodyIds()
    .filter((id) => sim.world.getBodyType(id) === 'dynamic')
    .pop()!
  while (sim.tick < 200) {
    const t = sim.tick
    if (t === 5) sim.apply(1, { k: 'grab', body: top, lx: 0, ly: 0 })
    else if (t > 5 && t < 60) sim.apply(1, { k: 'move', x: t / 20, y: 12 })
    else if (t === 60) sim.apply(1, { k: 'release' })
    else if (t === 100) sim.apply(1, { k: 'spawn', shape: { type: 'circle', radius: 0.4 }, x: 3, y: 15 })
    sim.runTick()
    if (sim.tick % 50 === 0) await recorder.flush()
  }
  await recorder.close('test done')
  log = new Uint8Array(await readFile(join(dir, recorder.name)))
  const reader = new ReplayLogReader()
  records = reader.push(log)
  head = concat([encodePreamble(reader.preamble!), encodeRecord(records[0])])
}, 60_000)
afterAll(async () => {
  await rm(dir, { recursive: true, force: true })
})

function concat(parts: Uint8Array[]): Uint8Array {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0))
  let at = 0
  for (const p of parts) {
    out.set(p, at)
    at += p.length
  }
  return out
}

/** Replays `bytes`: its report, or the message of a ReplayToolError; anything else is a problem. */
async function outcome(bytes: Uint8Array, problems: string[], what: string): Promise<ReplayReport | string> {
  try {
    const report = await replayLog(bytes, { verify: true })
    if (!Number.isInteger(report.finalHash)) problems.push(`${what}: final hash ${report.finalHash}`)
    if (report.lastTick > report.read.lastTick)
      problems.push(
        `${what}: replayed to tick ${report.lastTick}, past the last record's ${report.read.lastTick}`,
      )
    return report
  } catch (error) {
    if (error instanceof ReplayToolError && error.message.length > 0) return error.message
    problems.push(`${what}: ${(error as Error).name}: ${(error as Error).message}`)
    return `${error}`
  }
}

const damage = fc.array(
  fc.oneof(
    fc.record({ kind: fc.constant('flip' as const), at: fc.nat(), bit: fc.integer({ min: 0, max: 7 }) }),
    fc.record({ kind: fc.constant('cut' as const), at: fc.nat() }),
    fc.record({
      kind: fc.constant('insert' as const),
      at: fc.nat(),
      bytes: fc.uint8Array({ minLength: 1, maxLength: 16 }),
    }),
    fc.record({
      kind: fc.constant('write' as const),
      at: fc.nat(),
      bytes: fc.uint8Array({ minLength: 1, maxLength: 16 }),
    }),
  ),
  { minLength: 1, maxLength: 4 },
)

type Damage = { kind: string; at: number; bit?: number; bytes?: Uint8Array }

function applyDamage(bytes: Uint8Array, ops: Damage[]): Uint8Array {
  let out: Uint8Array = bytes.slice()
  for (const op of ops) {
    const at = out.length === 0 ? 0 : op.at % out.length
    if (op.kind === 'flip') out[at] ^= 1 << (op.bit ?? 0)
    else if (op.kind === 'cut') out = out.slice(0, at)
    else if (op.kind === 'insert') out = concat([out.subarray(0, at), op.bytes!, out.subarray(at)])
    else out.set(op.bytes!.subarray(0, Math.max(0, out.length - at)), at)
  }
  return out
}

const hostile = fc.oneof(
  fc.constantFrom(Number.NaN, Number.POSITIVE_INFINITY, -1, -0, 1e308, 2 ** 53, 0.5, 1e9),
  fc.integer({ min: -10, max: 500 }),
  fc.string({ maxLength: 12 }),
  fc.constant(null),
)
// Hostile values are rare in each field: the reader refuses a record with any bad field, and a
// log should often get far enough for its strange but valid records to reach the room.
const rare = <T>(usual: fc.Arbitrary<T>) =>
  fc.oneof({ weight: 40, arbitrary: usual }, { weight: 1, arbitrary: hostile })
const value = rare(fc.integer({ min: -50, max: 50 }))
const coord = rare(fc.double({ min: -30, max: 30, noNaN: true }))
const body = rare(fc.integer({ min: 0, max: 40 }))
const text = rare(fc.string({ maxLength: 8 }))
const command = fc.oneof(
  { weight: 1, arbitrary: fc.record({ k: fc.constant('bogus'), name: hostile }) },
  ...[
    fc.record({
      k: fc.constant('spawn'),
      shape: fc.oneof(
        fc.record({
          type: fc.constant('circle'),
          radius: rare(fc.double({ min: 0.05, max: 3, noNaN: true })),
        }),
        fc.record({
          type: fc.constant('box'),
          hw: rare(fc.double({ min: 0.05, max: 3, noNaN: true })),
          hh: coord,
        }),
      ),
      x: coord,
      y: coord,
    }),
    fc.record({ k: fc.constant('grab'), body, lx: coord, ly: coord }),
    fc.record({ k: fc.constant('move'), x: coord, y: coord }),
    fc.record({ k: fc.constant('release') }),
    fc.record({ k: fc.constant('delete'), body }),
    fc.record({ k: fc.constant('pin'), a: body, b: body, x: coord, y: coord }),
    fc.record({ k: fc.constant('rope'), a: body, b: body, ax: coord, ay: coord, bx: coord, by: coord }),
    fc.record({ k: fc.constant('unjoint'), joint: body }),
    fc.record({ k: fc.constant('gravity'), x: coord, y: coord }),
    fc.record({
      k: fc.constant('scene'),
      name: rare(fc.constantFrom('tower', 'empty', 'pile', 'joints', 'nope')),
    }),
    fc.record({ k: fc.constant('pause'), paused: rare(fc.boolean()) }),
    fc.record({ k: fc.constantFrom('step', 'reset') }),
  ].map((arbitrary) => ({ weight: 8, arbitrary: arbitrary as fc.Arbitrary<Record<string, unknown>> })),
)
/**
 * Records with hostile contents, framed correctly. Most come 0-60 ticks after the one before
 * (`advance`) from the player who joined, so a log goes deep; some carry a hostile tick instead:
 * backwards, far ahead, not an integer.
 */
const hostileRecord = fc.record({
  type: fc.oneof(
    { weight: 30, arbitrary: fc.constant('command') },
    { weight: 6, arbitrary: fc.constantFrom('join', 'leave', 'hash') },
    { weight: 1, arbitrary: fc.constant('close') },
  ),
  advance: fc.oneof(
    { weight: 40, arbitrary: fc.integer({ min: 0, max: MAX_RECORD_GAP }) },
    { weight: 1, arbitrary: hostile },
    { weight: 1, arbitrary: fc.constantFrom(-1, MAX_RECORD_GAP + 1, 3_000_000, 0xffffffff) },
  ),
  player: fc.oneof({ weight: 10, arbitrary: fc.constant(1) }, { weight: 1, arbitrary: value }),
  cmd: command,
  name: text,
  color: text,
  hash: value,
  step: value,
  reason: text,
  end: rare(fc.nat()),
})

describe('replaying damaged and hostile logs', { timeout: 120_000 }, () => {
  it('the intact log replays with every hash and keyframe checked', async () => {
    const report = await replayLog(log, { verify: true })
    expect(report.divergence).toBe(null)
    expect(report.hashesChecked + report.keyframesChecked).toBeGreaterThan(0)
    expect(report.commands).toBeGreaterThan(50)
  })

  it('a record far ahead of the one before it is cut, not stepped to', async () => {
    const join = records.find((r) => r.type === 'join')!
    for (const ahead of [MAX_RECORD_GAP + 1, 3_000_000, 0xffffffff - join.tick]) {
      const far = encodeRecord({ type: 'hash', tick: join.tick + ahead, hash: 0, step: 0 })
      const report = await replayLog(concat([head, encodeRecord(join), far]))
      expect(report.read.state).toBe('corrupt')
      expect(report.read.reason).toContain(`ticks after the record before it (at most ${MAX_RECORD_GAP})`)
      expect(report.lastTick).toBe(join.tick)
    }
    // At the limit the record is replayed: the room steps to it.
    const near = encodeRecord({ type: 'hash', tick: join.tick + MAX_RECORD_GAP, hash: 0, step: 0 })
    const report = await replayLog(concat([head, encodeRecord(join), near]))
    expect(report.read.state).toBe('end')
    expect(report.lastTick).toBe(join.tick + MAX_RECORD_GAP)
  })

  it('300 seeded kinds of damage (bit flips, cuts, inserted and overwritten bytes): replayed or refused by name', async () => {
    const problems: string[] = []
    let refused = 0
    for (const [n, ops] of fc.sample(damage, { numRuns: 300, seed: SEED }).entries()) {
      if (typeof (await outcome(applyDamage(log, ops), problems, `damage ${n}`)) === 'string') refused++
    }
    expect(problems).toEqual([])
    expect(refused).toBeGreaterThan(0)
  })

  it('300 seeded logs of correctly framed records with hostile contents: replayed or refused by name', async () => {
    const problems: string[] = []
    let framed = 0
    let accepted = 0
    let commands = 0
    const join = records.find((r) => r.type === 'join')!
    for (const [n, list] of fc
      .sample(fc.array(hostileRecord, { minLength: 5, maxLength: 40 }), { numRuns: 300, seed: SEED })
      .entries()) {
      const parts = [head, encodeRecord(join)]
      let tick = join.tick
      for (const { advance, ...r } of list) {
        const inRange =
          Number.isInteger(advance) && (advance as number) >= 0 && (advance as number) <= MAX_RECORD_GAP
        const at = inRange ? tick + (advance as number) : advance
        try {
          parts.push(encodeRecord({ ...r, tick: at } as unknown as ReplayRecord))
          framed++
          if (inRange) tick = at as number
        } catch {
          // The writer refuses what it cannot encode; the reader meets the rest.
        }
      }
      const report = await outcome(concat(parts), problems, `log ${n}`)
      if (typeof report !== 'string') {
        accepted += report.read.records - 2
        commands += report.commands
      }
    }
    expect(problems).toEqual([])
    // The logs went deep (Nov 24: 1,441 of 3,579 framed records passed the reader, 1,176 commands
    // reached the room).
    expect({ framed, accepted: accepted > framed / 3, commands: commands > 800 }).toEqual({
      framed,
      accepted: true,
      commands: true,
    })
  })
})
