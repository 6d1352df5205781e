/*
 * The built SDK's opt-in reconnect (docs/sdk.md, Reconnecting), in Node with the `ws` package
 * against real server processes (tests/support/server-process.ts): a snapshot session and a
 * lockstep session with `reconnect` follow a server that is SIGKILLed and started again on the
 * same port: they report `reconnecting` with the documented backoff (delayMs, then doubled, at
 * most maxDelayMs: worked by hand), `open` is false meanwhile, then `reconnected`, and they
 * receive the new server's state again (bodies, ticks that advance, a spawned box seen). A
 * session without `reconnect` just closes. Nothing reconnects after a deliberate close(), after a
 * refusal another try cannot change (the restarted server wants a key: HTTP 401), or once the
 * retries run out. A bad `reconnect` option is refused naming the field. Through a TCP proxy that
 * cuts the connection while the server stays up, the session rejoins with its reconnect token and
 * gets its old player id back, with no second player left in the room.
 */
import { execFileSync } from 'node:child_process'
import { mkdtemp, rm } from 'node:fs/promises'
import { createConnection, createServer, type Socket } from 'node:net'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { pathToFileURL } from 'node:url'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { type ServerProcess, startServerProcess } from '../support/server-process.ts'
import { inProcessRooms, startTestServer } from '../support/test-server.ts'
import { until } from '../support/wait.ts'
import { recordingSession } from './recording-session.ts'

type Sdk = typeof import('../../sdk/index.ts')
type Session = import('../../sdk/index.ts').Session
type ConnectOptions = import('../../sdk/index.ts').ConnectOptions

let sdk: Sdk
let outdir: string
const servers: ServerProcess[] = []
const sessions: Session[] = []

beforeAll(async () => {
  outdir = await mkdtemp(join(tmpdir(), 'concord-sdk-reconnect-'))
  execFileSync(process.execPath, ['scripts/build-sdk.mjs', outdir], { stdio: 'pipe' })
  sdk = (await import(pathToFileURL(join(outdir, 'index.js')).href)) as Sdk
}, 120_000)

afterAll(async () => {
  await Promise.all(sessions.map((s) => s.close()))
  for (const s of servers)
    if (s.process.exitCode === null && s.process.signalCode === null) s.process.kill('SIGKILL')
  if (outdir) await rm(outdir, { recursive: true, force: true })
})

async function start(args: string[] = []): Promise<ServerProcess> {
  const s = await startServerProcess(args)
  servers.push(s)
  return s
}

async function kill(s: ServerProcess): Promise<void> {
  s.process.kill('SIGKILL')
  await s.exited
}

/** A session of the built SDK that records its events (recording-session.ts). */
async function enter(url: string, room: string, extra: Partial<ConnectOptions> = {}) {
  const recorded = await recordingSession(sdk.connect, url, room, extra)
  sessions.push(recorded.session)
  return recorded
}

const box = (x: number, y: number) =>
  ({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x, y }) as const

describe('the SDK reconnects when asked to', () => {
  it('snapshot and lockstep sessions follow a killed server restarted on the same port; one without reconnect closes', async () => {
    const first = await start()
    const reconnect = { retries: 100, delayMs: 100, maxDelayMs: 400 }
    const snap = await enter(first.url, 'again', { reconnect })
    const lock = await enter(first.url, 'again', { reconnect, mode: 'lockstep' })
    const plain = await enter(first.url, 'again')
    await until(() => (lock.session.simulation()?.tick ?? 0) > 0, 'the lockstep simulation')
    await until(() => snap.session.bodies().length > 0, 'the snapshot bodies')

    await kill(first)
    // Backoff by hand: 100, 200, 400, 400 ... ms (doubled, at most 400).
    await until(() => snap.of('reconnecting').length >= 4, 'four snapshot attempts')
    expect(
      snap
        .of('reconnecting')
        .slice(0, 4)
        .map((r) => [r.attempt, r.delayMs]),
    ).toEqual([
      [1, 100],
      [2, 200],
      [3, 400],
      [4, 400],
    ])
    expect(snap.of('reconnecting')[0].code).toBe(1006)
    expect(snap.session.open).toBe(false)
    expect(snap.session.reconnecting).toBe(true)
    expect(snap.of('close')).toEqual([])
    await until(() => plain.of('close').length === 1, 'the plain session closing')
    expect(plain.of('reconnecting')).toEqual([])
    expect(plain.session.open).toBe(false)

    const second = await start(['--port', String(first.port)])
    await until(() => snap.of('reconnected').length === 1, 'the snapshot session back')
    await until(() => lock.of('reconnected').length === 1, 'the lockstep session back')
    expect(snap.session.open).toBe(true)
    expect(snap.session.reconnecting).toBe(false)
    expect(snap.of('reconnected')[0].attempts).toBe(snap.of('reconnecting').length)
    expect(snap.of('close')).toEqual([])

    // State again: the new server's bodies, ticks that advance, a box spawned now seen in both.
    const tick = snap.session.tick
    await until(() => snap.session.tick > tick + 30, 'snapshot ticks after the reconnect')
    expect(snap.session.bodies().length).toBeGreaterThan(0)
    const simTick = lock.session.simulation()?.tick ?? 0
    await until(() => (lock.session.simulation()?.tick ?? 0) > simTick + 30, 'lockstep ticks after it')
    const before = snap.session.bodies().length
    snap.session.send(box(0, 6))
    await until(() => snap.session.bodies().length > before, 'the new box in the snapshot session')
    await until(() => lock.session.bodies().length > before, 'the new box in the lockstep session')
    await kill(second)
  }, 180_000)

  it('not after close(), not after a refusal another try cannot change, not past its retries', async () => {
    const first = await start()
    const closing = await enter(first.url, 'final', { reconnect: { retries: 5, delayMs: 50 } })
    const refused = await enter(first.url, 'final', {
      reconnect: { retries: 100, delayMs: 100, maxDelayMs: 200 },
    })
    await closing.session.close()
    expect(closing.of('close').length).toBe(1)

    // The server comes back wanting a key: the attempt is refused (401) and the session closes.
    await kill(first)
    await until(() => refused.of('reconnecting').length >= 1, 'an attempt')
    const second = await start(['--port', String(first.port), '--join-token', 'open-sesame'])
    await until(() => refused.of('close').length === 1, 'the refused session closing')
    const attempts = refused.of('reconnecting').length
    expect(refused.of('reconnected')).toEqual([])
    expect(refused.of('error').at(-1)?.reason).toMatch(/refused the join: 401/)
    expect(closing.of('reconnecting')).toEqual([])

    // Out of retries: three attempts against a server that is gone, then an error and close.
    const third = await start()
    const gone = await enter(third.url, 'final', { reconnect: { retries: 3, delayMs: 20, maxDelayMs: 40 } })
    await kill(third)
    await until(() => gone.of('close').length === 1, 'giving up')
    expect(gone.of('reconnecting').map((r) => [r.attempt, r.delayMs])).toEqual([
      [1, 20],
      [2, 40],
      [3, 40],
    ])
    expect(gone.of('error').at(-1)?.reason).toMatch(/^gave up reconnecting after 3 attempts/)
    // Nothing more once closed: the refused session made no attempt after its close.
    expect(refused.of('reconnecting').length).toBe(attempts)
    await kill(second)
  }, 180_000)

  it('refuses a bad reconnect option naming the field', async () => {
    const url = 'ws://127.0.0.1:1'
    await expect(
      sdk.connect({ url, room: 'r', name: 'n', WebSocket, reconnect: { retries: 0 } }),
    ).rejects.toThrow('connect: reconnect.retries must be an integer from 1 to 1000, not 0')
    await expect(
      sdk.connect({ url, room: 'r', name: 'n', WebSocket, reconnect: { delayMs: 500, maxDelayMs: 100 } }),
    ).rejects.toThrow('connect: reconnect.maxDelayMs must be an integer from 500 to 600000, not 100')
    await expect(
      sdk.connect({ url, room: 'r', name: 'n', WebSocket, reconnect: 'yes' as never }),
    ).rejects.toThrow('connect: reconnect must be true, false or { retries?, delayMs?, maxDelayMs? }')
  })

  it('a cut connection to a server still up: the session rejoins with its token and keeps its player id', async () => {
    const server = await startTestServer(inProcessRooms)
    // A TCP proxy in front of the server, whose connections the test can cut.
    const pairs: Socket[][] = []
    const proxy = createServer((client) => {
      const upstream = createConnection(server.port, '127.0.0.1')
      client.pipe(upstream)
      upstream.pipe(client)
      const pair = [client, upstream]
      for (const end of pair) end.on('error', () => {})
      pairs.push(pair)
    })
    await new Promise<void>((resolve) => proxy.listen(0, '127.0.0.1', resolve))
    const address = proxy.address()
    if (address === null || typeof address === 'string') throw new Error('no proxy port')
    try {
      const a = await enter(`http://127.0.0.1:${address.port}`, 'cut', {
        reconnect: { retries: 20, delayMs: 50 },
      })
      const id = a.session.id
      expect(id).toBeGreaterThan(0)
      for (const pair of pairs.splice(0)) for (const end of pair) end.destroy()
      await until(() => a.of('reconnected').length === 1, 'the session back')
      expect(a.of('reconnecting')[0]).toMatchObject({ attempt: 1, delayMs: 50, code: 1006 })
      expect(a.of('reconnected')[0]).toEqual({ id, attempts: a.of('reconnecting').length })
      expect(a.session.id).toBe(id)
      await until(() => a.session.players().length > 0, 'the roster')
      expect(a.session.players().map((p) => p.id)).toEqual([id])
      expect([...(server.rooms.get('cut')?.sim.players.keys() ?? [])]).toEqual([id])
      await a.session.close()
    } finally {
      proxy.close()
      await server.close()
    }
  }, 120_000)
})
