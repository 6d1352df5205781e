import { mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { request } from 'node:http'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { type LogFile, listLogNames } from '../../../server/replay/replay-files.ts'
import { replayLog } from '../../../server/replay/replay-tool.ts'
import type { RunningServer } from '../../../server/server.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

const servers: RunningServer[] = []
afterAll(async () => {
  await Promise.all(servers.map((s) => s.close()))
})

async function start(overrides: Parameters<typeof startTestServer>[0]): Promise<RunningServer> {
  // Rooms on the main thread: this file compares the live room's world with its log.
  const server = await startTestServer({ ...inProcessRooms, ...overrides })
  servers.push(server)
  return server
}

/** A raw GET (the path is sent exactly as given, no client-side normalization). */
function get(server: RunningServer, path: string): Promise<{ status: number; body: Buffer }> {
  return new Promise((resolve, reject) => {
    const req = request({ host: '127.0.0.1', port: server.port, path, method: 'GET' }, (res) => {
      const chunks: Buffer[] = []
      res.on('data', (c: Buffer) => chunks.push(c))
      res.on('end', () => resolve({ status: res.statusCode ?? 0, body: Buffer.concat(chunks) }))
    })
    req.on('error', reject)
    req.end()
  })
}

async function metric(server: RunningServer, name: string): Promise<number> {
  const text = await server.metrics.registry.getSingleMetricAsString(name)
  return Number(text.trim().split(' ').pop())
}

/** A session with every kind of command, until the room passes `ticks`. */
async function playSession(server: RunningServer, room: string, ticks: number): Promise<void> {
  const a = await BotClient.connect({ url: server.url, room, name: 'ada' })
  const b = await BotClient.connect({ url: server.url, room, name: 'bob' })
  const dynamic = (): number[] => [...a.mirror.bodies.values()].filter((x) => x.kind === 2).map((x) => x.id)
  a.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 12, vx: 2 })
  await a.waitFor(() => dynamic().length >= 21, 'spawn')
  const [first, second, third] = dynamic()
  a.command({ k: 'grab', body: first, lx: 0, ly: 0 })
  b.command({ k: 'pin', a: 0, b: second, x: 0, y: 1 })
  b.command({ k: 'rope', a: second, b: third, ax: 0, ay: 1, bx: 0, by: 2 })
  const live = server.rooms.get(room)!
  let i = 0
  while (live.tick < ticks) {
    i++
    a.command({ k: 'move', x: Math.sin(i / 5) * 3, y: 5 + Math.cos(i / 7) })
    if (i === 20) b.command({ k: 'delete', body: third })
    if (i === 30) b.command({ k: 'gravity', x: 1, y: -9 })
    if (i === 40) b.command({ k: 'scene', name: 'joints' })
    if (i === 60) a.command({ k: 'reset' })
    await a.waitFor(() => a.mirror.tick > live.tick - 1)
    await new Promise((r) => setTimeout(r, 20))
  }
  await Promise.all([a.close(), b.close()])
}

describe('recording', { timeout: 60_000 }, () => {
  it('a recorded session replays with every hash and keyframe matching; /replays lists and serves it, never a file outside', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-rec-'))
    const recording = await start({ record: true, replayDir: dir, keyframeTicks: 60, defaultScene: 'tower' })
    await playSession(recording, 'rec', 300)
    const during = JSON.parse((await get(recording, '/replays')).body.toString())
    expect(during.find((l: { room: string }) => l.room === 'rec').status).toBe('recording')
    await recording.close()
    const name = (await listLogNames(dir)).find((n) => n.startsWith('rec-'))!
    const bytes = await readFile(join(dir, name))
    const report = await replayLog(bytes, { verify: true })
    expect(report.read).toMatchObject({ closed: true, state: 'end' })
    expect(report.divergence).toBeNull()
    expect(report.lastTick).toBeGreaterThanOrEqual(300)
    expect(report.hashesChecked).toBeGreaterThanOrEqual(4)
    expect(report.keyframesChecked).toBeGreaterThanOrEqual(4)
    expect(report.players).toBe(2)
    expect(report.commands).toBeGreaterThan(50)
    // The routes, from a server that only reads the directory.
    const reader = await start({ replayDir: dir })
    const list = JSON.parse((await get(reader, '/replays')).body.toString())
    const entry = list.find((l: { name: string }) => l.name === name)
    expect(entry).toMatchObject({ room: 'rec', status: 'clean', size: bytes.length })
    expect(entry.duration).toBeCloseTo(report.ticks / 60, 6)
    const download = await get(reader, `/replays/${name}`)
    expect(download.status).toBe(200)
    expect(Buffer.compare(download.body, bytes)).toBe(0)
    await writeFile(join(dir, '..', 'secret.cclog'), 'secret')
    for (const [path, status] of [
      ['/replays/..%2Fsecret.cclog', 400],
      ['/replays/%2e%2e%2fsecret.cclog', 400],
      ['/replays/%2Fetc%2Fpasswd', 400],
      ['/replays/..%5Csecret.cclog', 400],
      [`/replays/${name}%00`, 400],
      ['/replays/%E0%A4%A', 400],
      ['/replays/package.json', 404],
      ['/replays/rec-20260101T000000000Z.cclog', 404],
      ['/replays/', 400],
    ] as const) {
      const res = await get(reader, path)
      expect(res.status, path).toBe(status)
      expect(res.body.toString()).not.toContain('secret')
    }
    // Raw `..` segments never reach the replay route's directory.
    const raw = await get(reader, '/replays/../../secret.cclog')
    expect(raw.status).toBe(404)
    expect(raw.body.toString()).not.toContain('secret')
  })

  it('a failing disk stops recording for that room only, with a metric; the room keeps running', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-fail-'))
    const server = await start({ record: true, replayDir: dir })
    let writes = 0
    server.recordings.openLog = async (): Promise<LogFile> => ({
      write: async () => {
        if (++writes > 1)
          throw Object.assign(new Error('ENOSPC: no space left on device'), { code: 'ENOSPC' })
      },
      sync: async () => {},
      close: async () => {},
    })
    const bot = await BotClient.connect({ url: server.url, room: 'doomed', name: 'x' })
    bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 5 })
    await bot.waitFor(() => writes > 1, 'a second write')
    await bot.waitFor(() => server.recordings.recorders.get('doomed')?.failed === true, 'recorder stops')
    expect(await metric(server, 'concord_recorder_failures_total')).toBe(1)
    const tick = bot.mirror.tick
    bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 2, y: 5 })
    await bot.waitFor(() => bot.mirror.tick > tick + 60 && bot.mirror.bodies.size === 3, 'room still running')
    // The default room's recorder (opened before the injection) is unaffected.
    expect(server.recordings.recorders.get('lobby')?.failed).toBe(false)
    await bot.close()
  })

  it('a replay directory that cannot be created turns recording off; rooms run', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-nodir-'))
    await writeFile(join(dir, 'file'), 'x')
    const server = await start({ record: true, replayDir: join(dir, 'file', 'replays') })
    expect(await metric(server, 'concord_recorder_failures_total')).toBe(1)
    const bot = await BotClient.connect({ url: server.url, room: 'fine', name: 'x' })
    await bot.waitFor(() => bot.mirror.tick > 30, 'ticks')
    expect(server.recordings.recorders.size).toBe(0)
    await bot.close()
  })
})
