/*
 * Lockstep and predict over real sockets: a server on 127.0.0.1, snapshot-mode bots acting through
 * the scripted Activity, and Node lockstep clients running the same runner as the page. The
 * server's clock is driven faster than real time by the test (lockstep-bots.ts driveClock).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { ROOM_SYNC_BURST, SYNC_BURST } from '../../../server/rooms/lockstep-feed.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { RoomSimulation, SyncMessage } from '../../../shared/index.ts'
import type { PredictClient } from '../../../shared/sim/predict-client.ts'
import { ActiveBots, driveClock } from '../../support/lockstep-bots.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer
let stopClock: () => void

beforeAll(async () => {
  // Rooms on the main thread: this file reads room ticks and drives the main tick clock by hand
  // (lockstep-bots.ts driveClock).
  server = await startTestServer({ ...inProcessRooms, roomControls: true, maxRejects: 20 })
  stopClock = driveClock(server, 180)
})

afterAll(async () => {
  stopClock?.()
  await server?.close()
})

const room = (name: string) => server.rooms.get(name)
const desyncMetric = async (): Promise<number> => (await server.metrics.desyncs.get()).values[0]?.value ?? 0

describe('lockstep over real sockets', () => {
  it('a Node lockstep client and a late joiner match every hash with snapshot bots acting, through a scene load', async () => {
    const bots = await ActiveBots.start(server.url, 'ls-sync', 2)
    const early = await LockstepBot.connect({ url: server.url, room: 'ls-sync', name: 'early' })
    await early.waitFor(() => early.runner.stats.hashesChecked >= 5, '5 checkpoints')
    bots.command(0, { k: 'scene', name: 'wrecking-ball' })
    const late = await LockstepBot.connect({ url: server.url, room: 'ls-sync', name: 'late' })
    const start = early.runner.sim?.tick ?? 0
    await early.waitFor(() => (early.runner.sim?.tick ?? 0) > start + 1200, '1,200 more ticks')
    await late.waitFor(() => late.runner.stats.hashesChecked >= 12, 'late joiner checkpoints')
    for (const c of [early, late]) {
      expect(c.runner.stats.desyncs, c.runner.lastProblem).toBe(0)
      expect(c.runner.stats.refused).toBe(0)
      expect(c.runner.stats.resyncs).toBe(0)
      expect(c.runner.sim?.scene).toBe('wrecking-ball')
    }
    expect(early.runner.stats.hashesChecked).toBeGreaterThanOrEqual(20)
    // The bots are snapshot players in the same room and were never disturbed.
    for (const { bot } of bots.bots) expect(bot.failure).toBeNull()
    expect(await desyncMetric()).toBe(0)
    await Promise.all([early.close(), late.close(), bots.stop()])
  })

  it('a client nudged by 1e-12 m is detected within one hash interval, repaired and counted', async () => {
    const bots = await ActiveBots.start(server.url, 'ls-nudge', 1)
    const client = await LockstepBot.connect({ url: server.url, room: 'ls-nudge', name: 'nudged' })
    await client.waitFor(() => client.runner.stats.hashesChecked >= 2, 'two checkpoints')
    const before = await desyncMetric()
    const sim = client.runner.sim as RoomSimulation
    const w = sim.world
    const body = w.bodyIds().find((id) => w.getBodyType(id) === 'dynamic' && w.isAwake(id)) ?? w.bodyIds()[1]
    w.setAwake(body, true)
    const p = w.getPosition(body)
    w.setTransform(body, { x: p.x + 1e-12, y: p.y }, w.getAngle(body))
    const nudgedAt = sim.tick
    await client.waitFor(() => client.runner.stats.desyncs === 1, 'the desync')
    const detectedAt = client.runner.lastProblem.match(/tick (\d+)/)?.[1]
    expect(Number(detectedAt) - nudgedAt).toBeLessThanOrEqual(60)
    await client.waitFor(
      () => client.runner.stats.resyncs === 1 && client.runner.stats.verifiedTick > Number(detectedAt),
      'repair and a verified checkpoint after it',
    )
    expect(await desyncMetric()).toBe(before + 1)
    const metrics = await fetch(`${server.url}/metrics`).then((r) => r.text())
    expect(metrics).toMatch(new RegExp(`concord_desyncs_total ${before + 1}`))
    await Promise.all([client.close(), bots.stop()])
  })

  it('refuses desync reports for ticks that never existed and closes a client that keeps sending them', async () => {
    const bot = await BotClient.connect({
      url: server.url,
      room: 'ls-hostile',
      name: 'liar',
      mode: 'lockstep',
    })
    await bot.waitFor(() => bot.received.some((m) => m.t === 'sync'), 'first sync')
    const before = await desyncMetric()
    bot.send({ t: 'desync', tick: 2 ** 40, hash: 1, server: 2 })
    await bot.waitFor(
      () => bot.mirror.errors.some((e) => /not a recent hash checkpoint/.test(e.reason)),
      'refusal',
    )
    let i = 0
    const lies = setInterval(() => bot.send({ t: 'desync', tick: ++i * 60, hash: 1, server: 2 }), 5)
    await bot.closed
    clearInterval(lies)
    expect(bot.closeCode).toBe(1008)
    expect(await desyncMetric()).toBe(before)
  })

  it('a flood of resync requests gets a bounded number of saved worlds', async () => {
    const bot = await BotClient.connect({
      url: server.url,
      room: 'ls-flood',
      name: 'flood',
      mode: 'lockstep',
    })
    await bot.waitFor(() => bot.received.some((m) => m.t === 'sync'), 'first sync')
    const r = room('ls-flood')
    const startTick = r?.tick ?? 0
    const flood = setInterval(() => {
      for (let i = 0; i < 4; i++) bot.send({ t: 'resync' })
    }, 5)
    await bot.waitFor(() => (r?.tick ?? 0) > startTick + 600 || bot.ws.readyState > 1, '600 ticks of flood')
    clearInterval(flood)
    const syncs = bot.received.filter((m): m is SyncMessage => m.t === 'sync').length
    const seconds = ((r?.tick ?? 0) - startTick) / 60
    // One first sync, then at most the burst and one per 5 s of room time.
    expect(syncs).toBeLessThanOrEqual(1 + SYNC_BURST + Math.ceil(seconds / 5))
    expect(syncs).toBeLessThanOrEqual(ROOM_SYNC_BURST + 2 * Math.ceil(seconds))
    await bot.close()
  })

  it('a predicting client with two bots: its confirmed hash matches every checkpoint after many rollbacks', async () => {
    const bots = await ActiveBots.start(server.url, 'ls-predict', 2)
    const client = await LockstepBot.connect(
      { url: server.url, room: 'ls-predict', name: 'predictor' },
      'predict',
    )
    const runner = client.runner as PredictClient
    await client.waitFor(() => runner.present !== null, 'a present')
    const sim = runner.present as RoomSimulation
    const body = sim.world.bodyIds().find((id) => sim.world.getBodyType(id) === 'dynamic') as number
    runner.input({ k: 'grab', body, lx: 0, ly: 0 }, performance.now())
    let angle = 0
    const drag = setInterval(() => {
      angle += 0.2
      runner.input({ k: 'move', x: 3 * Math.cos(angle), y: 6 + 2 * Math.sin(angle) }, performance.now())
    }, 20)
    await client.waitFor(
      () => runner.stats.hashesChecked >= 20 && runner.predict.rollbacks >= 20,
      '20 checkpoints and 20 rollbacks',
    )
    clearInterval(drag)
    expect(runner.stats.desyncs, runner.lastProblem).toBe(0)
    expect(runner.predict.confirmed).toBeGreaterThan(10)
    expect(runner.present?.tick).toBeGreaterThanOrEqual(runner.sim?.tick as number)
    await Promise.all([client.close(), bots.stop()])
  })
})
