/*
 * Compound, capsule, rounded, concave (outline) and static coloured spawns through the whole
 * chain: a snapshot bot spawns them on a recording server; a lockstep client that was there
 * before, a predicting one and a late joiner (whose sync carries the colours) match every hash
 * checkpoint with no refusals; the room's log replays headless with every hash and keyframe
 * matching. The oracle is the server's own hash at each checkpoint and in the log, computed
 * independently of each replica.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { replayLog } from '../../../server/replay/replay-tool.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { Command } from '../../../shared/index.ts'
import { driveClock } from '../../support/lockstep-bots.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer
let stopClock: () => void
let dir: string

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-shapes-'))
  server = await startTestServer({
    ...inProcessRooms,
    record: true,
    replayDir: dir,
    keyframeTicks: 60,
    defaultScene: 'empty',
  })
  stopClock = driveClock(server, 180)
})
afterAll(async () => {
  stopClock?.()
  await server?.close()
})

/** The spawns under test: every new kind, a concave outline, material and colours, a static line. */
const SPAWNS: Command[] = [
  {
    k: 'spawn',
    shapes: [
      { type: 'box', hw: 1, hh: 0.2 },
      { type: 'circle', radius: 0.35, x: -0.8, y: -0.4, friction: 1.2 },
      { type: 'circle', radius: 0.35, x: 0.8, y: -0.4, rolling: 0.05 },
      { type: 'segment', v: [-1, 0.2, 1, 0.2], sensor: true },
    ],
    x: -4,
    y: 6,
    w: 1.5,
  },
  {
    k: 'spawn',
    shape: { type: 'capsule', v: [-0.6, 0, 0.6, 0], radius: 0.25 },
    x: 0,
    y: 8,
    angle: 0.7,
    color: 0xff8800,
  },
  {
    k: 'spawn',
    shape: { type: 'polygon', v: [0, 0, 1, 0, 1, 1, 0, 1], radius: 0.1, tangent: 1 },
    x: 3,
    y: 5,
  },
  { k: 'spawn', outline: [0, 0, 2, 0, 2, 2, 1.4, 2, 1, 0.6, 0.6, 2, 0, 2], x: 1, y: 10, vx: -1, density: 3 },
  { k: 'spawn', shape: { type: 'box', hw: 0.3, hh: 0.3, filter: [2, 1, 0] }, x: -1, y: 12 },
  {
    k: 'spawn',
    shapes: [
      { type: 'segment', v: [-6, 0, 0, -1] },
      { type: 'segment', v: [0, -1, 6, 0] },
    ],
    x: 0,
    y: 3,
    static: true,
  },
]

describe('lockstep and replay with the new shapes', { timeout: 120_000 }, () => {
  it('lockstep, predict and a late joiner stay bit-identical, and the log replays with every hash matching', async () => {
    const early = await LockstepBot.connect({ url: server.url, room: 'shapes', name: 'early' })
    const predict = await LockstepBot.connect({ url: server.url, room: 'shapes', name: 'ahead' }, 'predict')
    const bot = await BotClient.connect({ url: server.url, room: 'shapes', name: 'maker' })
    for (const cmd of SPAWNS) bot.command(cmd)
    await bot.waitFor(() => bot.mirror.bodies.size === 1 + SPAWNS.length, 'every spawn added')
    const live = server.rooms.get('shapes')!
    const afterSpawns = live.tick
    const late = await LockstepBot.connect({ url: server.url, room: 'shapes', name: 'late' })
    // The late joiner's sync carried the colours: its simulation holds the same as the room's.
    await late.waitFor(() => late.runner.stats.hashesChecked >= 3, 'late checkpoints')
    const colors = live.sim.colorList()
    expect(colors.length).toBe(2 * SPAWNS.length)
    expect(late.runner.sim?.colorList()).toEqual(colors)
    for (const c of [early, predict]) {
      await c.waitFor(
        () => c.runner.stats.verifiedTick > afterSpawns + 300,
        'verified 300 ticks after the spawns',
      )
    }
    for (const c of [early, predict, late]) {
      expect(c.runner.stats.desyncs, c.runner.lastProblem).toBe(0)
      expect(c.runner.stats.refused).toBe(0)
      expect(c.runner.stats.resyncs).toBe(0)
      expect(c.runner.stats.hashesChecked).toBeGreaterThanOrEqual(3)
    }
    expect(early.runner.sim?.colorList()).toEqual(live.sim.colorList())
    // The capsule's own colour; the others the maker's (its roster colour).
    const maker = Number.parseInt(bot.mirror.players.get(bot.mirror.clientId)!.color.slice(1), 16)
    const bodyColors = [...bot.mirror.bodies.values()].filter((b) => b.id !== 1).map((b) => b.color)
    expect(bodyColors).toEqual([maker, 0xff8800, maker, maker, maker, maker])
    await Promise.all([early.close(), predict.close(), late.close(), bot.close()])
    // The log: closed with the server, then replayed headless.
    stopClock()
    await server.close()
    const name = (await listLogNames(dir)).find((n) => n.startsWith('shapes-'))!
    const report = await replayLog(await readFile(join(dir, name)), { verify: true })
    expect(report.divergence).toBeNull()
    expect(report.hashesChecked).toBeGreaterThanOrEqual(5)
    expect(report.keyframesChecked).toBeGreaterThanOrEqual(5)
    expect(report.commands).toBeGreaterThanOrEqual(SPAWNS.length)
  })
})
