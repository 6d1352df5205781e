/*
 * Room names as a resource (issue 30, point 8), against a real recording server at its defaults
 * (--max-rooms 50, --room-idle-seconds 60, --max-new-rooms-per-ip 30): 50 anonymous connections
 * from one address each join a fresh room name and leave. Before, every one opened a room, the
 * room limit was full for the idle minute (the 50th and every later new name got `full`, from any
 * address), and each junk room left a log that pruning weighed against real recordings. Now the
 * address opens 30 and the other 20 joins get `full` naming the limit, counted in
 * concord_rooms_refused_total and logged at most 3 times; the junk rooms, where no command was
 * ever applied, close within seconds of emptying and leave no log; another address still opens
 * rooms, and a room where something was done stays its idle minute and keeps its log.
 */
import { mkdtemp, readdir } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { decode, encode } from '@msgpack/msgpack'
import { Redis } from 'ioredis'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { defaultConfig } from '../../../server/config/config.ts'
import type { RunningServer } from '../../../server/server.ts'
import { PROTOCOL_VERSION } from '../../../shared/index.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { startRedis } from '../../support/redis-server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'
import { DocClient } from '../protocol/doc-client.ts'

type Message = Record<string, unknown> & { t: string }

let server: RunningServer
let replayDir: string
const { logger, lines } = capturingLogger()
const defaults = defaultConfig()

beforeAll(async () => {
  replayDir = await mkdtemp(join(tmpdir(), 'concord-churn-'))
  server = await startTestServer(
    {
      record: true,
      replayDir,
      maxRooms: defaults.maxRooms,
      roomIdleSeconds: defaults.roomIdleSeconds,
      maxNewRoomsPerIp: defaults.maxNewRoomsPerIp,
      defaultScene: 'empty',
    },
    logger,
  )
})
afterAll(async () => {
  await server.close()
})

/** A socket from `localAddress` that joins `room`; resolves with what it got first, then the close. */
async function visit(
  room: string,
  localAddress: string,
  then: (ws: WebSocket, first: Message) => Promise<void> = async () => {},
  at: RunningServer = server,
): Promise<{ first: Message; close: { code: number; reason: string } }> {
  const ws = new WebSocket(`${at.url.replace('http', 'ws')}/ws?room=${room}`, { localAddress })
  const messages: Message[] = []
  let close: { code: number; reason: string } | null = null
  ws.on('message', (data: Buffer) => messages.push(decode(data) as Message))
  ws.on('close', (code, reason) => {
    close = { code, reason: reason.toString() }
  })
  ws.on('error', () => {})
  await new Promise<void>((resolve, reject) => {
    ws.once('open', () => resolve())
    ws.once('error', reject)
  })
  ws.send(encode({ t: 'join', v: PROTOCOL_VERSION, room: '', name: 'anon', mode: 'snapshot' }))
  const answer = (m: Message): boolean => m.t === 'welcome' || m.t === 'error' || m.t === 'moved'
  await until(() => messages.some(answer), `an answer in ${room}`)
  const first = messages.find(answer)!
  await then(ws, first)
  if (close === null) ws.close()
  await until(() => close !== null, `the close of ${room}`)
  return { first, close: close! }
}

const listed = async (): Promise<string[]> =>
  ((await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string }>).map((r) => r.name).sort()

describe('50 anonymous connections joining fresh room names', { timeout: 60_000 }, () => {
  it('open 30 rooms, are refused the rest with the reason, counted and logged; the junk rooms close at once and leave no log', async () => {
    expect([defaults.maxRooms, defaults.roomIdleSeconds, defaults.maxNewRoomsPerIp]).toEqual([50, 60, 30])
    // A real room from another address first: a command applied, then its player leaves.
    const real = await visit('real-room', '127.0.0.2', async (ws) => {
      // Leave only once the spawn is applied (the room's next tick; its events message adds the
      // body): a player who leaves first takes the queued command with it and the room stays
      // untouched (seen under load).
      let applied = false
      ws.on('message', (data: Buffer) => {
        const m = decode(data) as Message
        if (m.t === 'events' && Array.isArray(m.add) && m.add.length > 0) applied = true
      })
      ws.send(
        encode({
          t: 'input',
          seq: 1,
          cmd: { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 3 },
        }),
      )
      await until(() => server.recordings.openNames.size >= 2, 'the real room recorded')
      await until(() => applied, 'the spawn applied')
    })
    expect(real.first.t).toBe('welcome')

    // All at once, as an attacker would. The bucket holds 30 and refills 30 a minute (one per
    // 2 s), so the openings are 30 plus one per 2 s the burst took.
    const started = performance.now()
    const visits = await Promise.all(Array.from({ length: 50 }, (_, i) => visit(`junk-${i}`, '127.0.0.1')))
    const refills = Math.floor((performance.now() - started) / 2000)
    const welcomed = visits.filter((v) => v.first.t === 'welcome')
    const refused = visits.filter((v) => v.first.t === 'error')
    expect(welcomed.length).toBeGreaterThanOrEqual(30)
    expect(welcomed.length).toBeLessThanOrEqual(30 + refills)
    expect(refused).toHaveLength(50 - welcomed.length)
    for (const v of refused) {
      expect(v.first.code).toBe('full')
      expect(String(v.first.reason)).toMatch(
        /^this address opened 30 new rooms within a minute \(--max-new-rooms-per-ip\); join an open room, or open "junk-\d+" in \d+ s$/,
      )
      expect(v.close.code).toBe(4001)
    }
    const metric = await server.metrics.registry.getSingleMetricAsString('concord_rooms_refused_total')
    expect(metric).toContain(`concord_rooms_refused_total{reason="rate"} ${refused.length}`)
    const logged = lines.filter((l) => l.msg === 'room opening refused: over the per-address rate')
    expect(logged.length).toBeGreaterThanOrEqual(1)
    expect(logged.length).toBeLessThanOrEqual(3)

    // Joining an open room costs no opening; another address may still open one.
    expect((await visit('lobby', '127.0.0.1')).first.t).toBe('welcome')
    expect((await visit('other-address', '127.0.0.3')).first.t).toBe('welcome')

    // The untouched rooms go within seconds (not the idle minute) and leave no log; the real
    // room stays, with its log.
    await until(
      async () => (await listed()).join() === 'lobby,real-room',
      'only lobby and real-room open',
      15_000,
    )
    await until(
      async () => !(await readdir(replayDir)).some((f) => f.startsWith('junk-') || f.startsWith('other-')),
      'the junk logs removed',
      10_000,
    )
    const files = await readdir(replayDir)
    expect(files.filter((f) => f.startsWith('real-room-'))).toHaveLength(1)
    expect(files.filter((f) => f.startsWith('lobby-'))).toHaveLength(1)
  })
})

describe('the new-room limit with a room directory (--redis)', { timeout: 60_000 }, () => {
  it('counts only rooms opened here: a join moved to the holder costs nothing, a refused one gives its claim back', async () => {
    const redis = await startRedis()
    const probe = new Redis(redis.url)
    const holder = await startTestServer({ redisUrl: redis.url, maxNewRoomsPerIp: 0 })
    const limited = await startTestServer({ redisUrl: redis.url, maxNewRoomsPerIp: 2 })
    try {
      // A player keeps a room open on the other server.
      const keeper = await DocClient.joined(holder.url, 'held-elsewhere', 'keeper')
      const answers = []
      for (const room of ['mine-1', 'mine-2', 'mine-3'])
        answers.push((await visit(room, '127.0.0.1', undefined, limited)).first)
      expect(answers.map((m) => m.t)).toEqual(['welcome', 'welcome', 'error'])
      expect(answers[2].code).toBe('full')
      expect(await probe.get('concord:room:mine-3')).toBeNull()
      // Out of openings, a join for a room another server holds is still led there.
      const moved = await visit('held-elsewhere', '127.0.0.1', undefined, limited)
      expect(moved.first.t).toBe('moved')
      keeper.end()
    } finally {
      await limited.close()
      await holder.close()
      probe.disconnect()
      await redis.stop()
    }
  })
})
