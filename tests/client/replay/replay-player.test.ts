/*
 * The replay player's timeline against the session it replays: a scripted room (two players,
 * spawns, a grab dragged around, a pin, a rope, a scene load, a leave, a reset) is recorded by the
 * server's own recorder while the live hash of every tick is kept. The player must reach those
 * exact hashes whether it plays through, seeks forward through keyframes or seeks back; a torn log
 * plays its intact prefix; a file that is not a log is refused with one line naming the problem.
 *
 * Then a log with no keyframes at all (keyframe-free-log.ts, recorded by the same recorder, with
 * its hash record every 60 ticks): a seek to its end replays every tick, so it must run in slices
 * that let the event loop turn between them (a timer started before the seek runs while it is
 * under way, and finds the world at the live state of some tick each time), a newer seek must
 * stop an older one at a slice boundary and go on from there, and every seek must land on the
 * live hash, that is, where a straight play-through lands.
 */

import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { inflateSync } from 'node:zlib'
import pino from 'pino'
import { Counter } from 'prom-client'
import { beforeAll, describe, expect, it } from 'vitest'
import { ReplayLoadError, ReplayPlayer, readLog } from '../../../client/replay/replay-player.ts'
import { SNAPSHOT_TICKS } from '../../../client/replay/replay-snapshots.ts'
import { Prng } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import { encodeRecord, PREAMBLE_BYTES } from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { type KeyframeFreeLog, recordKeyframeFreeLog, recordWreckingBallLog } from './keyframe-free-log.ts'

const inflate = (bytes: Uint8Array): Uint8Array => new Uint8Array(inflateSync(bytes))
const TICKS = 900
const KEYFRAME_TICKS = 120

/** The live hash at each tick, after that tick's commands (what the player calls "the state at T"). */
const live = new Map<number, number>()
let bytes: Uint8Array

function script(sim: RoomSimulation, dynamic: () => number[]): void {
  const t = sim.tick
  if (t === 5)
    sim.apply(1, { k: 'spawn', shape: { type: 'box', hw: 0.4, hh: 0.3 }, x: 6, y: 9, vx: -1, vy: 0 })
  if (t === 10) sim.apply(1, { k: 'grab', body: dynamic()[0], lx: 0, ly: 0 })
  if (t > 10 && t < 200) sim.apply(1, { k: 'move', x: Math.sin(t / 9) * 4, y: 6 + Math.cos(t / 13) })
  if (t === 200) sim.apply(1, { k: 'release' })
  if (t === 250) sim.apply(2, { k: 'pin', a: 0, b: dynamic()[3], x: 0, y: 1 })
  if (t === 300) {
    const [a, b] = dynamic().slice(5, 7)
    sim.apply(2, { k: 'rope', a, b, ax: 0, ay: 0, bx: 0, by: 0 })
  }
  if (t === 400) sim.apply(2, { k: 'scene', name: 'joints' })
  if (t === 420) sim.apply(2, { k: 'grab', body: dynamic()[0], lx: 0, ly: 0 })
  if (t === 500)
    sim.apply(1, { k: 'spawn', shape: { type: 'circle', radius: 0.3 }, x: 2, y: 8, vx: 0, vy: 0 })
  if (t === 600) sim.leave(2)
  if (t === 700) sim.apply(1, { k: 'reset' })
}

beforeAll(async () => {
  const dir = await mkdtemp(join(tmpdir(), 'concord-player-'))
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'playback',
    scene: 'pyramid',
    maxBodies: 1500,
    controls: true,
  })
  const recorder = new RoomRecorder('playback', sim, {
    dir,
    fsync: 'none',
    keyframeTicks: KEYFRAME_TICKS,
    maxBytes: 1 << 30,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: 'test_failures', help: 'test', registers: [] }),
    openNames: new Set(),
  })
  recorder.start(0)
  sim.join(1, 'ada', '#e6194b')
  sim.join(2, 'bob', '#3cb44b')
  const dynamic = (): number[] => sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')
  while (sim.tick < TICKS) {
    script(sim, dynamic)
    live.set(sim.tick, sim.world.hash())
    sim.runTick()
  }
  live.set(sim.tick, sim.world.hash())
  await recorder.close('test over')
  bytes = new Uint8Array(await readFile(join(dir, recorder.name)))
})

describe('replay player', () => {
  it('plays a whole log through with every recorded hash matching, reaching the live hash at every tick', async () => {
    const log = await readLog(bytes)
    expect(log.status.reason).toBe('')
    expect(log.status.state).toBe('end')
    expect(log.keyframes.length).toBeGreaterThanOrEqual(Math.floor(TICKS / KEYFRAME_TICKS) - 1)
    const player = await ReplayPlayer.open(log, inflate)
    expect(player.people.get(1)?.name).toBe('ada')
    for (let t = log.firstTick + 1; t <= log.lastTick; t++) {
      await player.forwardTo(t)
      expect(player.tick).toBe(t)
      expect(player.sim.world.hash(), `tick ${t}`).toBe(live.get(t))
    }
    expect(player.checked).toBeGreaterThanOrEqual(TICKS / 60 - 1)
    expect(player.mismatch).toBeNull()
  })

  it('seeks back and forth to any tick and lands on the live state there, through whole and delta keyframes', async () => {
    const log = await readLog(bytes)
    // Seeks below go through chains of delta keyframes (z = 2) after whole ones (z = 1).
    const zs = log.keyframes.map((i) => (log.records[i] as { z: number }).z)
    expect(zs.filter((z) => z === 2).length).toBeGreaterThanOrEqual(2)
    expect(zs).toContain(1)
    const player = await ReplayPlayer.open(log, inflate)
    const targets = [850, 13, 401, 399, 120, 121, 719, 0, 600, 241, 899, 3]
    for (const t of targets) {
      await player.seek(t)
      expect(player.tick).toBe(t)
      expect(player.sim.world.hash(), `seek to ${t}`).toBe(live.get(t))
    }
    expect(player.mismatch).toBeNull()
  })

  it('plays the intact prefix of a torn log and says how far it got', async () => {
    const torn = bytes.subarray(0, Math.floor(bytes.length * 0.6))
    const log = await readLog(torn)
    expect(log.status.state).toBe('torn')
    expect(log.lastTick).toBeGreaterThan(0)
    expect(log.lastTick).toBeLessThan(TICKS)
    const player = await ReplayPlayer.open(log, inflate)
    await player.seek(log.lastTick)
    expect(player.sim.world.hash()).toBe(live.get(log.lastTick))
    await player.forwardTo(TICKS)
    expect(player.tick).toBe(log.lastTick)
  })

  it('turns a file that is not a log into one line naming the problem', async () => {
    await expect(readLog(new TextEncoder().encode('hello, this is not a replay log at all'))).rejects.toThrow(
      ReplayLoadError,
    )
    await expect(readLog(new Uint8Array(3))).rejects.toThrow(/not a replay log/)
  })

  it('notices a log whose hashes do not match the replay and keeps the first mismatching tick', async () => {
    const log = await readLog(bytes)
    const i = log.records.findIndex((r) => r.type === 'hash' && r.tick >= 300)
    const r = log.records[i]
    if (r.type !== 'hash') throw new Error('no hash record')
    log.records[i] = { ...r, hash: (r.hash ^ 1) >>> 0 }
    const player = await ReplayPlayer.open(log, inflate)
    await player.forwardTo(log.lastTick)
    expect(player.mismatch?.tick).toBe(r.tick)
  })
})

describe('replay player on a log with no keyframes', () => {
  const LONG_TICKS = 30_000
  let long: KeyframeFreeLog
  beforeAll(async () => {
    long = await recordKeyframeFreeLog(LONG_TICKS)
  })

  /** One turn of the event loop's timers: resolves in a macrotask after the ones queued so far. */
  const nextTimer = (): Promise<void> => new Promise((resolve) => setTimeout(resolve, 0))

  it('seeks to the end in slices, letting a timer run between them, each slice ending at a live state', async () => {
    const log = await readLog(long.bytes)
    expect(log.keyframes).toEqual([])
    expect(log.lastTick).toBe(LONG_TICKS)
    const player = await ReplayPlayer.open(log, inflate)
    // A timer started before the seek notes the tick and hash it finds at each turn.
    const seen: Array<{ tick: number; hash: number }> = []
    let ticking = true
    const turn = (): void => {
      seen.push({ tick: player.tick, hash: player.sim.world.hash() })
      if (ticking) setTimeout(turn, 0)
    }
    setTimeout(turn, 0)
    const arrived = await player.seek(log.lastTick)
    ticking = false
    expect(arrived).toBe(true)
    expect(player.tick).toBe(LONG_TICKS)
    expect(player.sim.world.hash()).toBe(long.live[LONG_TICKS])
    const during = seen.filter((s) => s.tick > log.firstTick && s.tick < log.lastTick)
    expect(
      during.length,
      `timer turns while the seek ran: ${JSON.stringify(seen.map((s) => s.tick))}`,
    ).toBeGreaterThanOrEqual(3)
    for (const s of during) expect(s.hash, `between slices at tick ${s.tick}`).toBe(long.live[s.tick])
    expect(player.checked).toBe(log.records.filter((r) => r.type === 'hash').length)
    expect(player.mismatch).toBeNull()
  })

  it('stops a running seek at a slice boundary when a newer one comes, and lands where the newest asked', async () => {
    const log = await readLog(long.bytes)
    // No snapshots of its own: the seek back replays from the header, long enough to be overtaken.
    const player = await ReplayPlayer.open(log, inflate, undefined, { snapshotBudget: 0 })
    const toEnd = player.seek(log.lastTick)
    const ended = { toEnd: -1, back: -1 }
    void toEnd.then(() => (ended.toEnd = player.tick))
    while (player.tick < 10_000) await nextTimer()
    // Back behind it (a restore of the header, then forward), and once that is under way, ahead.
    const back = player.seek(7_777)
    void back.then(() => (ended.back = player.tick))
    while (player.seeking?.target !== 7_777 || player.tick < 1_000) await nextTimer()
    const ahead = player.seek(20_000)
    const late = player.forwardBy(1)
    expect(await toEnd).toBe(false)
    expect(await back).toBe(false)
    expect(await ahead).toBe(true)
    expect(player.tick).toBe(20_000)
    expect(player.sim.world.hash()).toBe(long.live[20_000])
    expect(ended.toEnd).toBeGreaterThanOrEqual(10_000)
    expect(ended.toEnd).toBeLessThan(log.lastTick)
    expect(ended.back).toBeGreaterThanOrEqual(1_000)
    expect(ended.back).toBeLessThan(7_777)
    // A move asked after the last seek runs after it, from where it landed.
    expect(await late).toBe(true)
    expect(player.tick).toBe(20_001)
    expect(player.sim.world.hash()).toBe(long.live[20_001])
    expect(player.busy).toBe(false)
    expect(player.mismatch).toBeNull()
  })

  it('runs seeks asked at once one after the other, never two on the runner together', async () => {
    const log = await readLog(long.bytes)
    const player = await ReplayPlayer.open(log, inflate)
    await player.seek(12_000)
    // A seek back (restore, then forward) and play-forwards asked in the same turn.
    const moves = [player.seek(3_000), player.forwardBy(500), player.forwardTo(4_000)]
    expect(await Promise.all(moves)).toEqual([true, true, true])
    expect(player.tick).toBe(4_000)
    expect(player.sim.world.hash()).toBe(long.live[4_000])
    // Two seeks asked at once: the first never starts.
    const both = [player.seek(LONG_TICKS - 1), player.seek(2_500)]
    expect(await Promise.all(both)).toEqual([false, true])
    expect(player.tick).toBe(2_500)
    expect(player.sim.world.hash()).toBe(long.live[2_500])
    expect(player.mismatch).toBeNull()
  })

  it('stops a running seek at the next slice boundary when the log is closed', async () => {
    const log = await readLog(long.bytes)
    const player = await ReplayPlayer.open(log, inflate)
    const seek = player.seek(log.lastTick)
    await nextTimer()
    player.cancel()
    expect(await seek).toBe(false)
    expect(player.tick).toBeLessThan(log.lastTick)
    expect(player.busy).toBe(false)
  })
})

describe('replay player snapshots of its own', () => {
  const LONG_TICKS = 30_000
  let long: KeyframeFreeLog
  beforeAll(async () => {
    long = await recordKeyframeFreeLog(LONG_TICKS)
  })

  /** Seek to `target` and return the room ticks the seek ran, checking it lands on the live hash. */
  async function seekCounting(player: ReplayPlayer, target: number): Promise<number> {
    const before = player.ticksRun
    expect(await player.seek(target)).toBe(true)
    expect(player.tick).toBe(target)
    expect(player.sim.world.hash(), `seek to ${target}`).toBe(long.live[target])
    return player.ticksRun - before
  }

  it('takes one every SNAPSHOT_TICKS on a keyframe-free log, so a seek back replays fewer ticks than that', async () => {
    const log = await readLog(long.bytes)
    expect(log.keyframes).toEqual([])
    const player = await ReplayPlayer.open(log, inflate)
    // Without snapshots a seek back replays from the header: the first pass to the end does.
    expect(await seekCounting(player, LONG_TICKS)).toBe(LONG_TICKS)
    const grid = Array.from({ length: LONG_TICKS / SNAPSHOT_TICKS - 1 }, (_, i) => (i + 1) * SNAPSHOT_TICKS)
    expect(player.snapshotTicks.filter((t) => t < LONG_TICKS)).toEqual(grid)
    // Back near the end: from the snapshot at 29,400, not from the header 29,990 ticks away, and
    // applying exactly the records after it (its hash records are counted as checked).
    const checked = player.checked
    expect(await seekCounting(player, LONG_TICKS - 10)).toBe(LONG_TICKS - 10 - 29_400)
    const after = log.records.filter((r) => r.type === 'hash' && r.tick > 29_400 && r.tick <= LONG_TICKS - 10)
    expect(player.checked - checked).toBe(after.length)
    // Random seeks, back and forth: each starts from the grid point at or before it or from where
    // the player is, whichever is nearer.
    const rng = new Prng(5)
    for (let i = 0; i < 20; i++) {
      const target = Math.floor(rng.next() * LONG_TICKS)
      const from = Math.max(target - (target % SNAPSHOT_TICKS), target >= player.tick ? player.tick : 0)
      expect(await seekCounting(player, target), `seek from ${player.tick} to ${target}`).toBe(target - from)
    }
    expect(player.mismatch).toBeNull()
  })

  it('takes the snapshot a move stopped on before a seek leaves it', async () => {
    const log = await readLog(long.bytes)
    const player = await ReplayPlayer.open(log, inflate)
    expect(await seekCounting(player, 2 * SNAPSHOT_TICKS)).toBe(2 * SNAPSHOT_TICKS)
    expect(player.snapshotTicks).toEqual([SNAPSHOT_TICKS])
    expect(await seekCounting(player, 100)).toBe(100)
    expect(player.snapshotTicks).toEqual([SNAPSHOT_TICKS, 2 * SNAPSHOT_TICKS])
    expect(await seekCounting(player, 2 * SNAPSHOT_TICKS + 500)).toBe(500)
    expect(player.mismatch).toBeNull()
  })

  it('plays on from a snapshot across a delta keyframe after it (it needs a delta base) to the live hash', async () => {
    const sparse = await recordWreckingBallLog(6_000, 1_500)
    const log = await readLog(sparse.bytes)
    const kf = log.keyframes.map((i) => log.records[i] as { tick: number; z: number })
    const delta = kf.find((k) => k.z === 2)
    if (!delta) throw new Error(`no delta keyframe: ${JSON.stringify(kf)}`)
    const player = await ReplayPlayer.open(log, inflate)
    await player.forwardTo(log.lastTick)
    const before = player.snapshotTicks.filter((t) => t < delta.tick).at(-1)
    if (before === undefined || before <= (kf.filter((k) => k.tick < delta.tick).at(-1)?.tick ?? 0))
      throw new Error(
        `no snapshot between keyframes before ${delta.tick}: ${player.snapshotTicks.join(', ')}`,
      )
    // Back to just before the delta keyframe (from the snapshot), then forward across it.
    const ran = player.ticksRun
    await player.seek(delta.tick - 10)
    expect(player.ticksRun - ran).toBe(delta.tick - 10 - before)
    expect(await player.forwardTo(delta.tick + 100)).toBe(true)
    expect(player.sim.world.hash()).toBe(sparse.live[delta.tick + 100])
    expect(player.mismatch).toBeNull()
  })

  it('keeps its snapshots under a byte budget, spread over the log, and its seeks still land on the live hash', async () => {
    const log = await readLog(long.bytes)
    const full = await ReplayPlayer.open(log, inflate)
    await full.seek(LONG_TICKS)
    const budget = Math.floor(full.snapshotBytes / 5)
    const player = await ReplayPlayer.open(log, inflate, undefined, { snapshotBudget: budget })
    // Forward in steps, the budget checked after each.
    for (let t = 1_000; t <= LONG_TICKS; t += 1_000) {
      await player.forwardTo(t)
      expect(player.snapshotBytes, `at ${t}`).toBeLessThanOrEqual(budget)
    }
    const ticks = player.snapshotTicks
    expect(ticks.length).toBeGreaterThanOrEqual(5)
    // Spread: no stretch between start points (header, snapshots, end) is longer than twice the
    // stretch an even spacing of this many snapshots would leave.
    const points = [log.firstTick, ...ticks, log.lastTick]
    const stretches = points.slice(1).map((t, i) => t - points[i])
    const even = (log.lastTick - log.firstTick) / (ticks.length + 1)
    expect(Math.max(...stretches), `snapshots at ${ticks.join(', ')}`).toBeLessThanOrEqual(2 * even)
    const longest = Math.max(...stretches)
    const rng = new Prng(9)
    for (let i = 0; i < 20; i++) {
      const target = Math.floor(rng.next() * LONG_TICKS)
      expect(await seekCounting(player, target)).toBeLessThanOrEqual(longest)
      expect(player.snapshotBytes).toBeLessThanOrEqual(budget)
    }
    expect(player.mismatch).toBeNull()
  })
})

describe('reading a log', () => {
  it('reads a big log in slices: the event loop turns, progress is told, the records are the reader’s', async () => {
    // The real log's preamble and header, then 200,000 hash records each framed alone (4.2 MB, as
    // a crafted or a very long log may be): parsing it takes many slices.
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength)
    const headerEnd = PREAMBLE_BYTES + 8 + view.getUint32(PREAMBLE_BYTES, true)
    const header = (await readLog(bytes)).header
    const parts = [bytes.subarray(0, headerEnd)]
    for (let i = 0; i < 200_000; i++)
      parts.push(encodeRecord({ type: 'hash', tick: header.tick + (i >> 1), hash: 7, step: 7 }))
    const big = new Uint8Array(parts.reduce((n, p) => n + p.length, 0))
    let at = 0
    for (const p of parts) {
      big.set(p, at)
      at += p.length
    }
    let turns = 0
    let counting = true
    const count = (): void => {
      if (!counting) return
      turns++
      setTimeout(count, 0)
    }
    setTimeout(count, 0)
    const told: number[] = []
    const log = await readLog(big, (fraction) => told.push(fraction))
    counting = false
    // The same records and ending as the reader given the whole file at once.
    const whole = new ReplayLogReader()
    const expected = whole.push(big)
    expect(log.status).toEqual(whole.finish())
    expect(log.records).toEqual(expected.slice(1))
    expect(turns).toBeGreaterThanOrEqual(3)
    expect(told.length).toBeGreaterThanOrEqual(3)
    expect(told).toEqual([...told].sort((a, b) => a - b))
    expect(told.every((f) => f > 0 && f < 1)).toBe(true)
  })
})
