/*
 * The predicting client in process, with latency: a RoomSimulation with two scripted bots and a
 * LockstepFeed on the "server"; a PredictClient whose messages travel both ways with a delay of
 * LATENCY_TICKS. The oracle is the server simulation: the client's confirmed state must equal it
 * at every tick the client confirms, after any number of rollbacks; its present must answer its
 * own inputs at once.
 */

import pino from 'pino'
import { describe, expect, it } from 'vitest'
import { CorrectionSmoother } from '../../../client/modes/predict-smoothing.ts'
import { findGame, sandbox } from '../../../games/index.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { LockstepFeed } from '../../../server/rooms/lockstep-feed.ts'
import {
  type ClientMessage,
  cloneSimulation,
  decodeServerMessage,
  type RoomRules,
  RoomSimulation,
  type ServerMessage,
} from '../../../shared/index.ts'
import { PredictClient } from '../../../shared/sim/predict-client.ts'
import { Activity } from '../../support/lockstep-activity.ts'

const LATENCY_TICKS = 3
const TICK_MS = 1000 / 60
const RULES: RoomRules = {
  tickRate: 60,
  snapshotRate: 30,
  maxBodies: 400,
  maxClients: 16,
  inputsPerTick: 8,
  controls: true,
  scenes: [],
  worldHalfExtent: 500,
  game: 'sandbox',
  commands: [],
  builtins: [],
  maxSpectators: 64,
}

class DelayedRoom {
  readonly sim = new RoomSimulation({
    game: sandbox,
    name: 't',
    scene: 'empty',
    maxBodies: 400,
    controls: true,
  })
  readonly feed = new LockstepFeed(this.sim, 't', createMetrics(false), pino({ level: 'silent' }))
  readonly hashes = new Map<number, number>()
  readonly toClient: Array<{ at: number; message: ServerMessage }> = []
  readonly toServer: Array<{ at: number; message: ClientMessage }> = []
  bots = [
    { id: 1, activity: new Activity(101) },
    { id: 2, activity: new Activity(202) },
  ]
  readonly smoother = new CorrectionSmoother()
  now = 0
  readonly client = new PredictClient({
    games: findGame,
    send: (message) => this.toServer.push({ at: this.now + LATENCY_TICKS * TICK_MS, message }),
    onRollback: (before, after) => this.smoother.correct(before, after),
  })

  /** `hold`: the join's hold (the client's own, 30, unless given). */
  constructor(hold?: number) {
    for (const b of this.bots) this.sim.join(b.id, 'bot', '#fff')
    this.sim.join(3, 'me', '#000')
    this.client.handle(
      { t: 'welcome', v: 2, id: 3, token: '', room: 't', rules: RULES, players: [], state: {} as never },
      0,
    )
    this.feed.add(3, {
      send: () => {},
      sendBytes: (b) => {
        const d = decodeServerMessage(b)
        if (!d.ok) throw new Error(d.reason)
        this.toClient.push({ at: this.now + LATENCY_TICKS * TICK_MS, message: d.value })
      },
      sendError: () => {},
      buffered: () => 0,
      close: () => {},
    })
    this.feed.setHold(3, hold ?? this.client.hold)
  }

  view() {
    const w = this.sim.world
    return {
      dynamicBodies: () => w.bodyIds().filter((b) => w.getBodyType(b) === 'dynamic'),
      userJoints: () => [...this.sim.userJoints.keys()],
    }
  }

  /** One server tick, then deliveries, then one client frame; returns the confirmed ticks it stepped. */
  async frame(): Promise<number> {
    while (this.toServer.length > 0 && this.toServer[0].at <= this.now) {
      const m = (this.toServer.shift() as { message: ClientMessage }).message
      if (m.t === 'input') this.sim.apply(3, m.cmd)
      if (m.t === 'desync') this.feed.reportDesync(3, m.tick, m.hash, m.server)
      if (m.t === 'resync') this.feed.requestSync(3)
    }
    if (this.sim.tick % 2 === 0) {
      for (const b of this.bots) {
        const cmd = b.activity.next(this.view())
        if (cmd) this.sim.apply(b.id, cmd)
      }
    }
    this.sim.runTick()
    this.feed.endTick()
    if (this.sim.tick % 3 === 0) this.hashes.set(this.sim.tick, this.sim.world.hash())
    this.now += TICK_MS
    while (this.toClient.length > 0 && this.toClient[0].at <= this.now) {
      this.client.handle((this.toClient.shift() as { message: ServerMessage }).message, this.now)
    }
    await new Promise((resolve) => setImmediate(resolve))
    // A sync inflates asynchronously: wait for it here, so that no run depends on how many frames
    // a loaded machine takes to inflate it (the comparisons below differed from run to run).
    while (this.client.state === 'loading') await new Promise((resolve) => setTimeout(resolve, 1))
    const stepped = this.client.advance(this.now)
    this.smoother.decay(TICK_MS)
    return stepped
  }
}

describe('predicting client', () => {
  it('rolls back whenever others act, and its confirmed state equals the server at every tick', async () => {
    const room = new DelayedRoom()
    const mine = new Activity(303)
    let compared = 0
    for (let i = 0; i < 1200; i++) {
      await room.frame()
      const c = room.client
      if (c.present && i % 3 === 0) {
        const w = c.present.world
        const cmd = mine.next({
          dynamicBodies: () => w.bodyIds().filter((b) => w.getBodyType(b) === 'dynamic'),
          userJoints: () => [...(c.present as RoomSimulation).userJoints.keys()],
        })
        if (cmd) c.input(cmd, room.now)
      }
      const t = c.sim?.tick ?? -1
      if (room.hashes.has(t)) {
        expect(c.sim?.world.hash(), `confirmed hash at tick ${t}`).toBe(room.hashes.get(t))
        compared++
      }
    }
    // Quiet: the bots stop; once the last inputs are confirmed the present is the server's future.
    for (const b of room.bots) b.activity = new Activity(0, 'quiet')
    for (let i = 0; i < 60; i++) await room.frame()
    const presentHashes = new Map<number, number>()
    for (let i = 0; i < 30; i++) {
      await room.frame()
      const present = room.client.present as RoomSimulation
      presentHashes.set(present.tick, present.world.hash())
    }
    for (let i = 0; i < 30; i++) await room.frame()
    let checked = 0
    for (const [tick, hash] of presentHashes) {
      if (!room.hashes.has(tick)) continue
      expect(hash, `present hash at tick ${tick}`).toBe(room.hashes.get(tick))
      checked++
    }
    expect(checked).toBeGreaterThanOrEqual(5)
    const c = room.client
    expect(c.stats.desyncs).toBe(0)
    expect(c.stats.hashesChecked).toBeGreaterThanOrEqual(20)
    expect(c.predict.rollbacks).toBeGreaterThan(100)
    expect(c.predict.maxDepth).toBeGreaterThanOrEqual(LATENCY_TICKS)
    expect(c.predict.confirmed).toBeGreaterThan(100)
    expect(c.present?.tick).toBeGreaterThan(c.sim?.tick as number)
    expect(compared).toBeGreaterThan(300)
  })

  it('in a quiet room with sporadic own inputs, holding empty runs (30) costs no rollbacks, depth or lead', async () => {
    const run = async (hold: number) => {
      const room = new DelayedRoom(hold)
      for (const b of room.bots) b.activity = new Activity(0, 'quiet')
      const mine = new Activity(404)
      let depthSum = 0
      let rollbacks = 0
      for (let i = 0; i < 1800; i++) {
        await room.frame()
        const c = room.client
        if (c.predict.rollbacks > rollbacks) {
          rollbacks = c.predict.rollbacks
          depthSum += c.predict.lastDepth
        }
        if (c.present && i % 45 === 0) {
          const w = c.present.world
          const cmd = mine.next({
            dynamicBodies: () => w.bodyIds().filter((b) => w.getBodyType(b) === 'dynamic'),
            userJoints: () => [...(c.present as RoomSimulation).userJoints.keys()],
          })
          if (cmd) c.input(cmd, room.now)
        }
        const t = c.sim?.tick ?? -1
        if (room.hashes.has(t))
          expect(c.sim?.world.hash(), `hold ${hold}, tick ${t}`).toBe(room.hashes.get(t))
      }
      const c = room.client
      expect(c.stats.desyncs).toBe(0)
      expect(c.stats.hashesChecked).toBeGreaterThanOrEqual(29)
      return { rollbacks, depthSum, mispredicted: c.predict.mispredicted, lead: c.lead }
    }
    // Measured: 29 rollbacks of 275 ticks in all, lead 8, against 110 of 892 with a hold of 2 (each
    // empty run confirmed while an own input was still on its way counted as a misprediction).
    // Leads measured from the newest tick received instead of the playout estimate gave 24 here.
    const held = await run(30)
    const every2 = await run(2)
    expect(held.rollbacks).toBeGreaterThan(20)
    expect(held.rollbacks).toBeLessThanOrEqual(every2.rollbacks)
    expect(held.depthSum).toBeLessThanOrEqual(every2.depthSum)
    expect(held.mispredicted).toBeLessThanOrEqual(every2.mispredicted)
    expect(held.lead).toBeLessThanOrEqual(every2.lead)
  })

  it('spreads a held run of empty ticks over frames: at most 4 confirmed ticks a frame, none behind for long', async () => {
    const room = new DelayedRoom(30)
    // Bodies to simulate: the bots spawn and drag for a while, then fall quiet.
    for (let i = 0; i < 240; i++) await room.frame()
    for (const b of room.bots) b.activity = new Activity(0, 'quiet')
    for (let i = 0; i < 60; i++) await room.frame()
    const c = room.client
    let most = 0
    let lag = 0
    const rollbacks = c.predict.rollbacks
    for (let i = 0; i < 600; i++) {
      most = Math.max(most, await room.frame())
      lag = Math.max(lag, c.newestTick - (c.sim?.tick ?? 0))
      const t = c.sim?.tick ?? -1
      if (room.hashes.has(t)) expect(c.sim?.world.hash(), `tick ${t}`).toBe(room.hashes.get(t))
    }
    // A run of 30 confirmed at once would step 30 ticks in one frame; an eighth of the backlog a
    // frame, at least 2, is 4, 4, 3, 3, 2, ... and the backlog is gone in 12 frames, long before the
    // next run, 30 frames later.
    expect(most).toBe(4)
    expect(lag).toBeLessThanOrEqual(30)
    expect(c.sim?.tick).toBeGreaterThanOrEqual(c.newestTick - 2)
    expect(c.stats.desyncs).toBe(0)
    expect(c.predict.rollbacks).toBe(rollbacks)
    expect(c.present?.tick).toBeGreaterThan(c.sim?.tick as number)
  })

  it('applies its own grab and move to the present at once: the body moves in the next frame', async () => {
    const room = new DelayedRoom()
    for (let i = 0; i < 60; i++) await room.frame()
    const c = room.client
    const present = c.present as RoomSimulation
    const body = present.world
      .bodyIds()
      .find((b) => present.world.getBodyType(b) === 'dynamic' && present.world.getPosition(b).y > 3) as number
    c.input({ k: 'grab', body, lx: 0, ly: 0 }, room.now)
    await room.frame()
    const start = (c.present as RoomSimulation).world.getPosition(body)
    const target = { x: start.x + 3, y: start.y + 2 }
    const without = cloneSimulation(c.present as RoomSimulation, { maxBodies: 400, controls: true, name: '' })
    c.input({ k: 'move', x: target.x, y: target.y }, room.now)
    const presentTick = (c.present as RoomSimulation).tick
    await room.frame()
    const after = c.present as RoomSimulation
    while (without.tick < after.tick) without.runTick()
    const moved = after.world.getPosition(body)
    const still = without.world.getPosition(body)
    const dist = (p: { x: number; y: number }): number => Math.hypot(p.x - target.x, p.y - target.y)
    expect(after.tick).toBeGreaterThan(presentTick)
    expect(dist(moved)).toBeLessThan(dist(still) - 1e-3)
  })
})
