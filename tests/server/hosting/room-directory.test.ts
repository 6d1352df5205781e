/*
 * Rooms across processes: two server processes share a room directory in a real redis-server.
 * A client that asks either server for a room gets to the one holding it (`moved`, followed by
 * the bot client and by the client SDK), a room name is never open on both servers even when both are asked for it at
 * the same moment, a disposed room is released, and a killed server's rooms are free for the
 * other after the directory's time to live.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { createInterface } from 'node:readline'
import { Redis } from 'ioredis'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { BotClient } from '../../../bots/bot-client.ts'
import { connect } from '../../../sdk/index.ts'
import { decodeServerMessage, encodeMessage, PROTOCOL_VERSION } from '../../../shared/index.ts'
import { startRedis, type TestRedis } from '../../support/redis-server.ts'
import { until } from '../../support/wait.ts'

interface ServerProcess {
  proc: ChildProcess
  url: string
  id: string
}

const children: ChildProcess[] = []
let redis: TestRedis
let a: ServerProcess
let b: ServerProcess
let probe: Redis

/** Start server/main.ts with the directory; resolves with its URL and directory id. */
function startServerProcess(redisUrl: string): Promise<ServerProcess> {
  const proc = spawn(
    process.execPath,
    [
      '--import',
      'tsx',
      'server/main.ts',
      ...[
        '--port',
        '0',
        '--log-level',
        'info',
        '--default-scene',
        'empty',
        '--redis',
        redisUrl,
        '--record',
        'false',
      ],
      ...['--directory-ttl-seconds', '2', '--room-idle-seconds', '1'],
    ],
    { stdio: ['ignore', 'pipe', 'inherit'] },
  )
  children.push(proc)
  return new Promise((resolve, reject) => {
    let id = ''
    proc.once('exit', (code) => reject(new Error(`server exited early with ${code}`)))
    createInterface({ input: proc.stdout! }).on('line', (line) => {
      const entry = JSON.parse(line) as { msg?: string; port?: number; server?: string }
      if (entry.msg === 'room directory joined' && entry.server) id = entry.server
      if (entry.msg === 'listening' && entry.port)
        resolve({ proc, url: `http://127.0.0.1:${entry.port}`, id })
    })
  })
}

async function roomsOf(server: ServerProcess): Promise<Map<string, number>> {
  const list = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string; players: number }>
  return new Map(list.map((r) => [r.name, r.players]))
}

/** A raw join: resolves with the first answer's type ('welcome' or 'moved') and the socket. */
function rawJoin(server: ServerProcess, room: string): Promise<{ answer: string; ws: WebSocket }> {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(`${server.url.replace('http', 'ws')}/ws?room=${room}`)
    ws.on('error', reject)
    ws.on('open', () =>
      ws.send(encodeMessage({ t: 'join', v: PROTOCOL_VERSION, room, name: 'raw', mode: 'snapshot' })),
    )
    ws.on('message', (data: Buffer) => {
      const decoded = decodeServerMessage(data)
      if (decoded.ok && (decoded.value.t === 'welcome' || decoded.value.t === 'moved'))
        resolve({ answer: decoded.value.t, ws })
    })
  })
}

beforeAll(async () => {
  redis = await startRedis()
  probe = new Redis(redis.url)
  a = await startServerProcess(redis.url)
  b = await startServerProcess(redis.url)
})

afterAll(async () => {
  for (const child of children) if (child.exitCode === null) child.kill('SIGKILL')
  probe?.disconnect()
  await redis?.stop()
})

describe('room directory in Redis, two server processes', { timeout: 60_000 }, () => {
  it('the first server holds the default room; asking the second one for it leads to the first', async () => {
    expect(await probe.get('concord:room:lobby')).toBe(a.id)
    expect((await roomsOf(b)).has('lobby')).toBe(false)
    const raw = await rawJoin(b, 'lobby')
    expect(raw.answer).toBe('moved')
    const closed = await new Promise<number>((resolve) => raw.ws.once('close', (code) => resolve(code)))
    expect(closed).toBe(4006)
    const bot = await BotClient.connect({ url: b.url, room: 'lobby', name: 'via-b' })
    expect(bot.options.url).toBe(a.url.replace('http', 'ws'))
    expect((await roomsOf(a)).get('lobby')).toBe(1)
    expect((await roomsOf(b)).has('lobby')).toBe(false)
    // The client SDK follows it too (docs/sdk.md, Rooms on another server).
    const session = await connect({ url: b.url, room: 'lobby', name: 'sdk', WebSocket: WebSocket as never })
    expect(session.open).toBe(true)
    expect((await roomsOf(a)).get('lobby')).toBe(2)
    expect((await roomsOf(b)).has('lobby')).toBe(false)
    await until(() => session.players().length === 2, "the SDK session's roster")
    expect(
      session
        .players()
        .map((p) => p.name)
        .sort(),
    ).toEqual(['sdk', 'via-b'])
    await session.close()
    await bot.close()
  })

  it('a new room asked of both servers at once opens on exactly one of them with every player', async () => {
    const joins = []
    for (let i = 0; i < 12; i++) joins.push(rawJoin(i % 2 === 0 ? a : b, 'arena'))
    const answers = await Promise.all(joins)
    const holder = (await roomsOf(a)).has('arena') ? a : b
    const other = holder === a ? b : a
    expect((await roomsOf(other)).has('arena')).toBe(false)
    expect(await probe.get('concord:room:arena')).toBe(holder.id)
    // Everyone who asked the holder was welcomed; everyone who asked the other was moved.
    const welcomed = answers.filter((x) => x.answer === 'welcome').length
    expect(welcomed).toBe(6)
    expect((await roomsOf(holder)).get('arena')).toBe(6)
    for (const x of answers) x.ws.close()
  })

  it('a room disposed after its last player leaves is released from the directory', async () => {
    const bot = await BotClient.connect({ url: b.url, room: 'brief', name: 'x' })
    const holder = (await roomsOf(a)).has('brief') ? a : b
    expect(await probe.get('concord:room:brief')).toBe(holder.id)
    await bot.close()
    await until(async () => (await probe.get('concord:room:brief')) === null, 'the room key to be deleted')
    expect((await roomsOf(holder)).has('brief')).toBe(false)
  })

  it('after Redis loses its data, each server takes its own rooms back at the next heartbeat and keeps them open', async () => {
    await probe.flushall()
    await until(async () => (await probe.get('concord:room:lobby')) === a.id, 'the lobby claim to come back')
    expect(await probe.get(`concord:server:${a.id}`)).toBe(a.url.replace('http', 'ws'))
    expect((await roomsOf(a)).has('lobby')).toBe(true)
  })

  it('a killed server releases its rooms after the time to live; the other server then opens them', async () => {
    a.proc.kill('SIGKILL')
    // Until the key expires, the room is still A's: B does not open a second copy.
    expect(await probe.get('concord:room:lobby')).toBe(a.id)
    expect(await probe.pttl('concord:room:lobby')).toBeGreaterThan(0)
    await until(async () => (await probe.get('concord:room:lobby')) === null, 'the dead server key to expire')
    const bot = await BotClient.connect({ url: b.url, room: 'lobby', name: 'after' }, 0)
    expect(bot.mirror.clientId).toBeGreaterThan(0)
    expect(await probe.get('concord:room:lobby')).toBe(b.id)
    expect((await roomsOf(b)).get('lobby')).toBe(1)
    await bot.close()
  })

  it('a server whose Redis cannot be reached refuses to start, naming the URL', async () => {
    const proc = spawn(
      process.execPath,
      [
        '--import',
        'tsx',
        'server/main.ts',
        '--port',
        '0',
        '--redis',
        'redis://127.0.0.1:1',
        '--record',
        'false',
      ],
      {
        stdio: ['ignore', 'ignore', 'pipe'],
      },
    )
    children.push(proc)
    let stderr = ''
    proc.stderr?.on('data', (d) => {
      stderr += d
    })
    const code = await new Promise<number | null>((resolve) => proc.once('exit', resolve))
    expect(code).not.toBe(0)
    expect(stderr).toContain('cannot reach the room directory at redis://127.0.0.1:1')
  })
})
