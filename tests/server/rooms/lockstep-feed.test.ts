/*
 * The lockstep feed and the lockstep client, in process: a RoomSimulation driven by scripted
 * players streams through a LockstepFeed into LockstepClients over fake connections that encode
 * and decode every message with the real codec. The oracle is the server simulation itself: the
 * client's world hash must equal the server's at every tick it reaches, not only at checkpoints.
 */

import pino from 'pino'
import { describe, expect, it } from 'vitest'
import { findGame, sandbox } from '../../../games/index.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { LockstepFeed, ROOM_SYNC_BURST, SYNC_BURST } from '../../../server/rooms/lockstep-feed.ts'
import type { PlayerConnection } from '../../../server/rooms/player-connection.ts'
import { decodeServerMessage, type RoomRules, RoomSimulation } from '../../../shared/index.ts'
import { LockstepClient } from '../../../shared/sim/lockstep-client.ts'
import { Activity } from '../../support/lockstep-activity.ts'

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

/** A room in process: simulation, feed, players with scripted activity, followers. */
class Harness {
  readonly sim: RoomSimulation
  readonly metrics = createMetrics(false)
  readonly feed: LockstepFeed
  readonly serverHashes = new Map<number, number>()
  readonly bytes = new Map<number, number>()
  readonly activities: Array<{ id: number; activity: Activity }> = []
  now = 0
  /** The bots act on every `actEvery`-th tick. */
  actEvery = 2

  constructor(scene = 'pyramid') {
    this.sim = new RoomSimulation({ game: sandbox, name: 'test', scene, maxBodies: 400, controls: true })
    this.feed = new LockstepFeed(this.sim, 'test', this.metrics, pino({ level: 'silent' }))
  }

  addBot(id: number, seed: number): void {
    this.sim.join(id, `bot ${id}`, '#fff')
    this.activities.push({ id, activity: new Activity(seed) })
  }

  /** A lockstep follower; with `hold`, joined with that hold and a playout delay of at least as much. */
  addFollower(id: number, hold?: number): LockstepClient {
    const client: LockstepClient = new LockstepClient({
      games: findGame,
      ...(hold === undefined ? {} : { hold, playout: { minDelay: hold } }),
      send: (m) => {
        if (m.t === 'desync') this.feed.reportDesync(id, m.tick, m.hash, m.server)
        if (m.t === 'resync') this.feed.requestSync(id)
      },
    })
    const conn: PlayerConnection = {
      send: () => {},
      sendBytes: (b) => {
        this.bytes.set(id, (this.bytes.get(id) ?? 0) + b.length)
        const decoded = decodeServerMessage(b)
        if (!decoded.ok) throw new Error(decoded.reason)
        client.handle(decoded.value, this.now)
      },
      sendError: () => {},
      buffered: () => 0,
      close: () => {},
    }
    this.sim.join(id, `follower ${id}`, '#000')
    client.handle(
      { t: 'welcome', v: 2, id, token: '', room: 'test', rules: RULES, players: [], state: {} as never },
      this.now,
    )
    this.feed.add(id, conn)
    this.feed.setHold(id, client.hold)
    return client
  }

  /** One room tick: the bots act (one command each every other tick), the sim ticks, the feed streams. */
  tick(): void {
    for (const { id, activity } of this.activities) {
      if (this.sim.tick % this.actEvery !== 0) continue
      const cmd = activity.next({
        dynamicBodies: () =>
          this.sim.world.bodyIds().filter((b) => this.sim.world.getBodyType(b) === 'dynamic'),
        userJoints: () => [...this.sim.userJoints.keys()],
      })
      if (cmd) this.sim.apply(id, cmd)
    }
    this.sim.runTick()
    this.feed.endTick()
    if (this.sim.tick % 5 === 0) this.serverHashes.set(this.sim.tick, this.sim.world.hash())
    this.now += 1000 / 60
  }
}

/** Let pending promises (inflating a sync) settle. */
const settle = (): Promise<void> => new Promise((resolve) => setImmediate(resolve))

describe('lockstep feed and client in process', () => {
  it('a client replaying the stream has the server hash at every tick it reaches, over 2,000 ticks with a scene load', async () => {
    const h = new Harness()
    h.addBot(1, 11)
    h.addBot(2, 22)
    const client = h.addFollower(3)
    let compared = 0
    for (let i = 0; i < 2000; i++) {
      h.tick()
      if (i === 1000) h.sim.apply(1, { k: 'scene', name: 'pile' })
      await settle()
      client.advance(h.now)
      const t = client.sim?.tick ?? -1
      const expected = h.serverHashes.get(t)
      if (expected !== undefined) {
        expect(client.sim?.world.hash(), `hash at tick ${t}`).toBe(expected)
        compared++
      }
    }
    expect(client.state).toBe('running')
    expect(client.stats.desyncs).toBe(0)
    expect(client.stats.refused).toBe(0)
    expect(client.stats.hashesChecked).toBeGreaterThanOrEqual(30)
    expect(compared).toBeGreaterThan(300)
    expect(client.sim?.tick).toBeGreaterThan(1990)
    expect(client.sim?.scene).toBe('pile')
    expect(h.sim.userJoints.size + h.sim.world.bodyCount).toBeGreaterThan(0)
  })

  it('followers with holds 1, 2, 7, 30 and 60 in one room, bots acting now and then: every hash matches; fewer bytes the longer the hold', async () => {
    const h = new Harness('tower')
    h.actEvery = 11
    h.addBot(1, 31)
    h.addBot(2, 32)
    const holds = [1, 2, 7, 30, 60]
    const clients = holds.map((hold, i) => h.addFollower(10 + i, hold))
    const compared = holds.map(() => 0)
    for (let i = 0; i < 1500; i++) {
      h.tick()
      await settle()
      clients.forEach((c, k) => {
        c.advance(h.now)
        const t = c.sim?.tick ?? -1
        const expected = h.serverHashes.get(t)
        if (expected !== undefined && t > 0) {
          expect(c.sim?.world.hash(), `hold ${holds[k]}, hash at tick ${t}`).toBe(expected)
          compared[k]++
        }
      })
    }
    const bytes = holds.map((_, k) => h.bytes.get(10 + k) ?? 0)
    for (const [k, c] of clients.entries()) {
      expect(c.stats.desyncs).toBe(0)
      expect(c.stats.refused).toBe(0)
      expect(c.stats.resyncRequests).toBe(0)
      // 25 checkpoints in 1,500 ticks; the hold-60 client plays at least 60 ticks behind.
      expect(c.stats.hashesChecked).toBeGreaterThanOrEqual(22)
      expect(compared[k]).toBeGreaterThan(200)
      if (k > 0) expect(bytes[k], `hold ${holds[k]} against ${holds[k - 1]}`).toBeLessThan(bytes[k - 1])
    }
  })

  it('a client nudged by 1e-12 m is caught at the next checkpoint, counted and repaired', async () => {
    const h = new Harness()
    h.addBot(1, 5)
    const client = h.addFollower(2)
    for (let i = 0; i < 200; i++) {
      h.tick()
      await settle()
      client.advance(h.now)
    }
    expect(client.stats.desyncs).toBe(0)
    const sim = client.sim as RoomSimulation
    const body = sim.world
      .bodyIds()
      .find((id) => sim.world.isAwake(id) && sim.world.getBodyType(id) === 'dynamic')
    expect(body).toBeDefined()
    const p = sim.world.getPosition(body as number)
    sim.world.setTransform(body as number, { x: p.x + 1e-12, y: p.y }, sim.world.getAngle(body as number))
    const nudgedAt = sim.tick
    let detectedAt = -1
    for (let i = 0; i < 400; i++) {
      h.tick()
      await settle()
      client.advance(h.now)
      if (detectedAt < 0 && client.stats.desyncs > 0) detectedAt = client.sim?.tick ?? -1
    }
    expect(detectedAt).toBeGreaterThan(nudgedAt)
    expect(detectedAt - nudgedAt).toBeLessThanOrEqual(60)
    expect(client.stats.desyncs).toBe(1)
    expect(client.stats.resyncs).toBe(1)
    expect(client.state).toBe('running')
    expect(client.stats.verifiedTick).toBeGreaterThan(detectedAt)
    expect((await h.metrics.desyncs.get()).values[0].value).toBe(1)
  })

  it('refuses desync reports for ticks that were never checkpoints, wrong hashes and repeats', () => {
    const h = new Harness()
    h.addFollower(1)
    for (let i = 0; i < 130; i++) h.tick()
    expect(h.sim.tick).toBe(130)
    const sent = h.serverHashes.get(120) as number
    expect(h.feed.reportDesync(1, 1_000_000, 1, sent)).toMatch(/not a recent hash checkpoint/)
    expect(h.feed.reportDesync(1, 61, 1, sent)).toMatch(/not a recent hash checkpoint/)
    expect(h.feed.reportDesync(9, 120, 1, sent)).toMatch(/lockstep and predict players/)
    expect(h.feed.reportDesync(1, 120, 1, (sent + 1) >>> 0)).toMatch(/was \d+, not/)
    expect(h.feed.reportDesync(1, 120, sent, sent)).toMatch(/not a desync/)
    expect(h.feed.reportDesync(1, 120, (sent + 1) >>> 0, sent)).toBeNull()
    expect(h.feed.reportDesync(1, 120, (sent + 1) >>> 0, sent)).toMatch(/already reported/)
    expect(h.feed.reportDesync(1, 60, (sent + 1) >>> 0, h.serverHashes.get(60) as number)).toMatch(
      /already reported/,
    )
  })

  it('a flood of resync requests gets at most the bucket sizes of saved worlds', async () => {
    const h = new Harness()
    const clients = [h.addFollower(1), h.addFollower(2), h.addFollower(3), h.addFollower(4), h.addFollower(5)]
    const syncs = (): number => [...h.feed.followers.values()].reduce((n, f) => n + f.syncs, 0)
    const seconds = 10
    for (let i = 0; i < seconds * 60; i++) {
      for (let id = 1; id <= 5; id++) for (let k = 0; k < 50; k++) h.feed.requestSync(id)
      h.tick()
      await settle()
    }
    // Per follower: SYNC_BURST at once, then one per 5 s; per room: the burst plus 2 per second.
    const perFollower = SYNC_BURST + seconds / 5
    const perRoom = ROOM_SYNC_BURST + 2 * seconds
    expect(syncs()).toBeLessThanOrEqual(Math.min(5 * perFollower, perRoom))
    for (const f of h.feed.followers.values()) expect(f.syncs).toBeLessThanOrEqual(perFollower)
    expect(syncs()).toBeGreaterThanOrEqual(5)
    expect(clients.every((c) => c.stats.syncBytes > 0)).toBe(true)
  })
})
