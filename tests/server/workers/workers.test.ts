/*
 * Rooms on worker threads (--workers N), against a real server on 127.0.0.1 with real WebSocket
 * clients: rooms spread over workers play normally; a pathological room delays only the rooms on
 * its own worker (measured in room ticks seen by clients, never in wall time); a worker that dies
 * is reported in the log and /metrics, its clients get error `room-lost` and close 4008, and with
 * recording on its room is rebuilt from its log at the log's last durable checkpoint and can be
 * rejoined and played.
 */
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { Writable } from 'node:stream'
import { Worker } from 'node:worker_threads'
import pino from 'pino'
import { afterEach, describe, expect, it, vi } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames, scanLog } from '../../../server/replay/replay-files.ts'
import type { RunningServer } from '../../../server/server.ts'
import { FLUSH_LEAD_MS } from '../../../server/workers/worker-link.ts'
import { CLOSE_CODES } from '../../../shared/index.ts'
import { readSlowly } from '../../support/slow-socket.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const servers: RunningServer[] = []
const bots: BotClient[] = []
afterEach(async () => {
  await Promise.all(bots.splice(0).map((b) => b.close()))
  await Promise.all(servers.splice(0).map((s) => s.close()))
})

async function start(overrides: Parameters<typeof startTestServer>[0], logger?: pino.Logger) {
  const server = await startTestServer(overrides, logger)
  servers.push(server)
  return server
}

async function bot(server: RunningServer, room: string, name: string): Promise<BotClient> {
  const b = await BotClient.connect({ url: server.url, room, name })
  bots.push(b)
  return b
}

async function metricsText(server: RunningServer): Promise<string> {
  const res = await fetch(`${server.url}/metrics`)
  return res.text()
}

/** A logger whose lines (main thread) the test can read. */
function capture(): { logger: pino.Logger; lines: Array<Record<string, unknown>> } {
  const lines: Array<Record<string, unknown>> = []
  const sink = new Writable({
    write(chunk, _enc, done) {
      for (const line of String(chunk).split('\n')) if (line.trim()) lines.push(JSON.parse(line))
      done()
    },
  })
  return { logger: pino({ level: 'info' }, sink), lines }
}

/** Spawn a box with `b`, wait for it, drag it right, wait until it is seen past x = 5. */
async function spawnAndDrag(b: BotClient): Promise<number> {
  const before = new Set(b.mirror.bodies.keys())
  b.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 3 })
  const spawned = (): number | undefined => [...b.mirror.bodies.keys()].find((id) => !before.has(id))
  await b.waitFor(() => spawned() !== undefined, 'the spawn')
  const id = spawned() as number
  b.command({ k: 'grab', body: id, lx: 0, ly: 0 })
  b.command({ k: 'move', x: 6, y: 4 })
  await b.waitFor(() => (b.mirror.bodies.get(id)?.x ?? 0) > 5, 'the drag')
  b.command({ k: 'release' })
  return id
}

describe('rooms on worker threads', { timeout: 60_000 }, () => {
  it('places rooms on the least loaded worker; rooms on two workers play normally; /rooms and /metrics show them', async () => {
    const server = await start({ workers: 2 })
    expect(server.pool?.workerIds).toEqual([1, 2])
    const a = await bot(server, 'alpha', 'ada')
    const b = await bot(server, 'beta', 'bob')
    // The default room opened first: alpha goes to the other worker, beta to the default room's.
    expect(server.pool?.workerOf('lobby')).toBe(1)
    expect(server.pool?.workerOf('alpha')).toBe(2)
    expect(server.pool?.workerOf('beta')).toBe(1)
    // Nothing runs on the main thread.
    expect(server.rooms.list()).toHaveLength(0)
    await Promise.all([spawnAndDrag(a), spawnAndDrag(b)])
    // A second player in alpha sees what the first does.
    const c = await bot(server, 'alpha', 'cyd')
    expect([...c.mirror.bodies.values()].filter((x) => x.kind === 2)).toHaveLength(1)
    await until(async () => {
      const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{
        name: string
        players: number
        bodies: number
      }>
      const alpha = rooms.find((r) => r.name === 'alpha')
      // Bodies count the ground: the empty scene's ground and the spawned circle.
      return (
        alpha?.players === 2 &&
        alpha.bodies === 2 &&
        rooms.some((r) => r.name === 'beta' && r.players === 1 && r.bodies === 2)
      )
    }, '/rooms to list alpha with 2 players and 2 bodies, beta with 1 player and 2 bodies')
    await until(async () => {
      const text = await metricsText(server)
      return (
        /concord_room_tick_seconds_count\{worker="1"\} [1-9]/.test(text) &&
        /concord_room_tick_seconds_count\{worker="2"\} [1-9]/.test(text)
      )
    }, 'per-worker tick histograms in /metrics')
    expect(a.failure ?? b.failure ?? c.failure).toBeNull()
  })

  /** Ticks the neighbour and the hog advance while the hog's room busy-waits 200 ms per tick. */
  async function hogAndNeighbour(workers: number): Promise<{ hog: number; calm: number; same: boolean }> {
    const server = await start({ workers, roomTickBudgetMs: 0 })
    const hog = await bot(server, 'hog', 'hog')
    const calm = await bot(server, 'calm', 'calm')
    const same = server.pool?.workerOf('hog') === server.pool?.workerOf('calm')
    server.pool?.fault('hog', { kind: 'busy', room: 'hog', ms: 200 })
    // Let the fault take hold: the hog's ticks slow down.
    const t0 = hog.mirror.tick
    await hog.waitFor(() => hog.mirror.tick >= t0 + 2, 'the hog to tick')
    const hog0 = hog.mirror.tick
    const calm0 = calm.mirror.tick
    await hog.waitFor(() => hog.mirror.tick >= hog0 + 12, 'the hog to advance 12 ticks')
    return { hog: hog.mirror.tick - hog0, calm: calm.mirror.tick - calm0, same }
  }

  it("a client's inputs go to its room's worker in about one message per tick, in order, none lost", async () => {
    const server = await start({ workers: 2 })
    const b = await bot(server, 'flow', 'ada')
    const body = await spawnAndDrag(b)
    b.command({ k: 'grab', body, lx: 0, ly: 0 })
    // 100 moves 4 ms apart (about 4 a tick, under the input budget), each in its own event-loop
    // turn on the server; the last one takes the body back to x = -6.
    const posts = vi.spyOn(Worker.prototype, 'postMessage')
    const started = performance.now()
    for (let i = 1; i <= 100; i++) {
      b.command({ k: 'move', x: 6 - (12 * i) / 100, y: 4 })
      await new Promise((resolve) => setTimeout(resolve, 4))
    }
    const ticks = (performance.now() - started) / (1000 / 60)
    await b.waitFor(() => (b.mirror.bodies.get(body)?.x ?? 0) < -5, 'the last move')
    const sent = posts.mock.calls.length
    posts.mockRestore()
    // One by one that was at least 100 messages (one per event-loop turn, and the bot's acks);
    // held until 3 ms before the worker's next tick, it is one a tick plus the moves that arrive
    // within those 3 ms, which go at once.
    expect(sent).toBeLessThan(ticks + 100 * (FLUSH_LEAD_MS / (1000 / 60)) + 15)
    expect(sent).toBeLessThan(75)
    expect(b.received.some((m) => m.t === 'error')).toBe(false)
  })

  it('a room that hogs its worker does not slow a room on another worker', async () => {
    const { hog, calm, same } = await hogAndNeighbour(2)
    expect(same).toBe(false)
    // At 200 ms a tick the hog runs at most 5 ticks a second; the neighbour runs 60.
    expect(calm).toBeGreaterThanOrEqual(4 * hog)
  })

  it('control: on one shared worker the same hog slows its neighbour too', async () => {
    const { hog, calm, same } = await hogAndNeighbour(1)
    expect(same).toBe(true)
    expect(calm).toBeLessThan(2 * hog)
  })

  it('the tick budget holds on a worker: a room over it again and again is closed with overloaded and 4007, its neighbour plays on', async () => {
    // The default budget (50 ms) and few overruns: a calm room does not come near it even when the
    // machine is loaded.
    const server = await start({ workers: 2, roomTickBudgetMs: 50, roomOverrunTicks: 4 })
    const hog = await bot(server, 'greedy', 'gus')
    const calm = await bot(server, 'modest', 'mo')
    expect(server.pool?.workerOf('greedy')).not.toBe(server.pool?.workerOf('modest'))
    // Every tick of this room now takes 120 ms, over twice its budget: closed at its fourth such tick.
    server.pool?.fault('greedy', { kind: 'busy', room: 'greedy', ms: 120 })
    await until(() => hog.closeCode !== 0, 'the greedy room to be closed')
    expect(hog.closeCode).toBe(CLOSE_CODES.overloaded)
    const notice = hog.received.find((m) => m.t === 'error' && m.code === 'overloaded')
    expect(notice, 'error overloaded before the close').toBeDefined()
    expect(hog.closeReason).toContain('greedy')
    await until(() => !server.host.has('greedy'), 'the greedy room to be gone')
    await until(
      async () => /concord_rooms_closed_over_budget_total\{worker="\d"\} 1/.test(await metricsText(server)),
      'the closed room counted in /metrics',
    )
    const t0 = calm.mirror.tick
    await calm.waitFor(() => calm.mirror.tick >= t0 + 30, 'the neighbour to play on')
    expect(calm.failure).toBeNull()
    expect(calm.closeCode).toBe(0)
  })

  it('/healthz fails naming a worker whose loop is silent', async () => {
    const server = await start({ workers: 2, roomTickBudgetMs: 0, stallSeconds: 2 })
    const stuck = await bot(server, 'stuck', 'sam')
    const healthy = async (): Promise<{ status: number; text: string }> => {
      const res = await fetch(`${server.url}/healthz`)
      return { status: res.status, text: await res.text() }
    }
    // Healthy first (with a 2 s stall limit, a loop can be late on a loaded machine: wait for it).
    await until(async () => (await healthy()).status === 200, '/healthz to pass before the fault')
    const worker = server.pool?.workerOf('stuck')
    // One tick of this room now holds its worker for 8 s: no batch, no beat for longer than 2 s.
    server.pool?.fault('stuck', { kind: 'busy', room: 'stuck', ms: 8000 })
    // (On a loaded machine another loop may be late too; the stuck one must be named.)
    await until(async () => {
      const { status, text } = await healthy()
      return status === 503 && text.includes(`worker-${worker} silent for`)
    }, '/healthz to fail naming the stuck worker')
    expect(stuck.failure).toBeNull()
  })

  it('the slow-reader rule works across the thread boundary: a client that reads slowly is skipped and closed, a normal one stays', async () => {
    // As tests/server/net/slow-reader.test.ts, with the room on a worker: the worker's room sees the
    // unread bytes the main thread measures from the client's acks.
    const server = await start({
      workers: 2,
      snapshotRate: 60,
      clientBandwidth: 10_000_000,
      sendBufferBytes: 64 * 1024,
      slowClientSeconds: 1,
      heartbeatMs: 600_000,
      inputsPerTick: 100,
    })
    /** The sum of a metric's series from the workers (worker label). */
    const sum = async (name: string): Promise<number> => {
      let total = 0
      for (const line of (await metricsText(server)).split('\n'))
        if (line.startsWith(`${name}{`) && line.includes('worker="')) total += Number(line.split(' ').pop())
      return total
    }
    const normal = await bot(server, 'slow', 'normal')
    normal.command({ k: 'scene', name: 'pyramid' })
    await normal.waitFor(() => normal.mirror.bodies.size > 200, 'the pyramid')
    const slow = await bot(server, 'slow', 'slow')
    let snapshots = 0
    normal.onServerMessage = (m) => {
      if (m.t === 'snap' && ++snapshots % 6 === 0) normal.command({ k: 'reset' })
    }
    // The slow reader: one chunk at once, then one every 1.5 s.
    const reader = readSlowly(slow.ws, 1500)
    const players = async (): Promise<number> => {
      const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{
        name: string
        players: number
      }>
      return rooms.find((r) => r.name === 'slow')?.players ?? -1
    }
    try {
      await until(async () => (await players()) === 1, 'the slow reader to be closed', 60_000)
    } finally {
      reader.stop()
      slow.ws.terminate()
    }
    expect(reader.chunks()).toBeGreaterThan(0)
    // Closed by the room's rule on its worker (not by the main thread's hard limit); worker metrics arrive once a second.
    await until(async () => (await sum('concord_slow_clients_closed_total')) === 1, 'the slow-reader metric')
    expect(await sum('concord_snapshots_skipped_total')).toBeGreaterThan(0)
    const tick = normal.mirror.tick
    await normal.waitFor(() => normal.mirror.tick >= tick + 10, 'more snapshots for the normal reader')
    expect(await players()).toBe(1)
  })

  it('a worker that dies is reported, its clients get 4008, and its recorded room comes back from its log', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-workers-'))
    const { logger, lines } = capture()
    const server = await start({ workers: 2, record: true, recover: true, replayDir: dir }, logger)
    const first = await bot(server, 'phoenix', 'ada')
    const body = await spawnAndDrag(first)
    // Wait until the log holds a checkpoint after the spawn: that state is durable.
    const spawnTick = first.mirror.tick
    let durable = { tick: -1, hash: 0 }
    const logName = async (): Promise<string | undefined> =>
      (await listLogNames(dir)).filter((n) => n.startsWith('phoenix-')).pop()
    const hashes = async (): Promise<Map<number, number>> => {
      const out = new Map<number, number>()
      const name = await logName()
      if (name) await scanLog(join(dir, name), (r) => r.type === 'hash' && out.set(r.tick, r.hash))
      return out
    }
    await until(async () => {
      for (const [tick, hash] of await hashes()) if (tick > spawnTick + 60) durable = { tick, hash }
      return durable.tick > 0
    }, 'a checkpoint after the spawn in the log')
    const worker = server.pool?.workerOf('phoenix')
    // The workers take turns: their clocks tick half a tick apart.
    expect(server.pool?.workerPhases).toEqual([0, 0.5])
    server.pool?.fault('phoenix', { kind: 'exit' })

    await first.closed
    expect(first.closeCode).toBe(CLOSE_CODES.roomLost)
    expect(first.received.some((m) => m.t === 'error' && m.code === 'room-lost')).toBe(true)
    await until(
      () => lines.some((l) => l.msg === 'room worker died; its rooms are lost'),
      'the death log line',
    )
    const died = lines.find((l) => l.msg === 'room worker died; its rooms are lost') as Record<
      string,
      unknown
    >
    expect(died.worker).toBe(worker)
    expect(died.rooms).toContain('phoenix')
    expect(await metricsText(server)).toMatch(/concord_room_workers_failed_total 1/)
    expect(server.pool?.workerIds).toHaveLength(2)
    expect(server.pool?.workerIds).not.toContain(worker)
    // The new worker takes the dead one's turn.
    expect(server.pool?.workerPhases).toEqual([0, 0.5])

    await until(
      () => lines.some((l) => l.msg === 'room rebuilt from its log on a worker' && l.room === 'phoenix'),
      'the rebuild',
    )
    const rebuilt = lines.find((l) => l.msg === 'room rebuilt from its log on a worker') as {
      tick: number
      hash: number
    }
    // The rebuilt room is the log's last durable checkpoint: at or after the one seen, same hash as written.
    expect(rebuilt.tick).toBeGreaterThanOrEqual(durable.tick)
    expect((await hashes()).get(rebuilt.tick)).toBe(rebuilt.hash)

    const again = await bot(server, 'phoenix', 'ada again')
    expect(again.mirror.tick).toBeGreaterThanOrEqual(rebuilt.tick)
    expect(again.mirror.bodies.has(body)).toBe(true)
    await spawnAndDrag(again)
    expect(again.failure).toBeNull()
  })
})
