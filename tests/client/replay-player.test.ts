/*
 * The replay player's timeline against the session it replays: a scripted room (two players,
 * spawns, a grab dragged around, a pin, a rope, a scene load, a leave, a reset) is recorded by the
 * server's own recorder while the live hash of every tick is kept. The player must reach those
 * exact hashes whether it plays through, seeks forward through keyframes or seeks back; a torn log
 * plays its intact prefix; a file that is not a log is refused with one line naming the problem.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { inflateSync } from 'node:zlib'
import pino from 'pino'
import { Counter } from 'prom-client'
import { beforeAll, describe, expect, it } from 'vitest'
import { ReplayLoadError, ReplayPlayer, readLog } from '../../client/replay-player.ts'
import { RoomRecorder } from '../../server/recorder.ts'
import { RoomSimulation } from '../../shared/room-simulation.ts'

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
  const sim = new RoomSimulation({ name: 'playback', scene: 'pyramid', maxBodies: 1500, controls: true })
  const recorder = new RoomRecorder('playback', sim, {
    dir,
    fsync: 'none',
    keyframeTicks: KEYFRAME_TICKS,
    maxBytes: 1 << 30,
    keep: 10,
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
    const log = readLog(bytes)
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
    const log = readLog(bytes)
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
    const log = readLog(torn)
    expect(log.status.state).toBe('torn')
    expect(log.lastTick).toBeGreaterThan(0)
    expect(log.lastTick).toBeLessThan(TICKS)
    const player = await ReplayPlayer.open(log, inflate)
    await player.seek(log.lastTick)
    expect(player.sim.world.hash()).toBe(live.get(log.lastTick))
    await player.forwardTo(TICKS)
    expect(player.tick).toBe(log.lastTick)
  })

  it('turns a file that is not a log into one line naming the problem', () => {
    expect(() => readLog(new TextEncoder().encode('hello, this is not a replay log at all'))).toThrow(
      ReplayLoadError,
    )
    expect(() => readLog(new Uint8Array(3))).toThrow(/not a replay log/)
  })

  it('notices a log whose hashes do not match the replay and keeps the first mismatching tick', async () => {
    const log = readLog(bytes)
    const i = log.records.findIndex((r) => r.type === 'hash' && r.tick >= 300)
    const r = log.records[i]
    if (r.type !== 'hash') throw new Error('no hash record')
    log.records[i] = { ...r, hash: (r.hash ^ 1) >>> 0 }
    const player = await ReplayPlayer.open(log, inflate)
    await player.forwardTo(log.lastTick)
    expect(player.mismatch?.tick).toBe(r.tick)
  })
})
