/*
 * The built client SDK (docs/sdk.md) in Node: `npm run build:sdk`'s dist/sdk/index.js, imported as
 * a consumer would, with the `ws` package's WebSocket, against a real server. It joins in each
 * mode, spawns a box that a second SDK session sees, sends a goal-game command (accepted: its
 * effect is in the lockstep game state; refused: the error names the field and carries the seq),
 * hears the goal game's kickoff event in snapshot and lockstep modes, unsubscribes, and fails with
 * clear errors for a bad address, a bad room and a bad option.
 */
import { execFileSync } from 'node:child_process'
import { mkdtemp, readFile, rm, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { pathToFileURL } from 'node:url'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import type { RunningServer } from '../../server/server.ts'
import { startTestServer } from '../support/test-server.ts'
import { until } from '../support/wait.ts'

type Sdk = typeof import('../../sdk/index.ts')
type Session = import('../../sdk/index.ts').Session

let server: RunningServer
let sdk: Sdk
let outdir: string
const open: Session[] = []

beforeAll(async () => {
  outdir = await mkdtemp(join(tmpdir(), 'concord-sdk-'))
  execFileSync(process.execPath, ['scripts/build-sdk.mjs', outdir], { stdio: 'pipe' })
  sdk = (await import(pathToFileURL(join(outdir, 'index.js')).href)) as Sdk
  server = await startTestServer()
}, 120_000)

afterAll(async () => {
  await Promise.all(open.map((s) => s.close()))
  await server?.close()
  if (outdir) await rm(outdir, { recursive: true, force: true })
})

async function enter(room: string, name: string, extra: Partial<Parameters<Sdk['connect']>[0]> = {}) {
  const session = await sdk.connect({ url: server.url, room, name, WebSocket, ...extra })
  open.push(session)
  return session
}

const box = (x: number, y: number) =>
  ({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x, y }) as const

describe('the built SDK', () => {
  it('ships ES modules with type declarations', async () => {
    const types = await readFile(join(outdir, 'index.d.ts'), 'utf8')
    expect(types).toContain('types/sdk/index.js')
    const decl = await readFile(join(outdir, 'types/sdk/index.d.ts'), 'utf8')
    expect(decl).toMatch(/export declare function connect\(options: ConnectOptions\): Promise<Session>/)
    expect(decl).not.toMatch(/from '\.[^']*\.ts'/)
    expect(typeof sdk.connect).toBe('function')
  })

  it('its declarations type-check a consumer (strict, Node16 module resolution)', async () => {
    const consumer = join(outdir, 'consumer.ts')
    await writeFile(
      consumer,
      [
        "import { connect, type Session, type SessionBody } from './index.js'",
        "import { createRenderer } from './render.js'",
        "const session: Session = await connect({ url: 'ws://h', room: 'r', name: 'n', mode: 'predict' })",
        "const seq: number = session.send({ k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 1 })",
        "session.command('kick', { power: seq })",
        "const off: () => void = session.on('event', (e) => console.log(e.tick, e.event))",
        'off()',
        'const bodies: SessionBody[] = session.bodies()',
        "createRenderer(document.createElement('canvas'), session).stop()",
        'export { bodies }',
        '',
      ].join('\n'),
    )
    const tsc = join(process.cwd(), 'node_modules/typescript/bin/tsc')
    const args = ['--noEmit', '--strict', '--module', 'node16', '--target', 'es2022', '--lib', 'es2022,dom']
    const check = (): string => {
      try {
        execFileSync(process.execPath, [tsc, ...args, 'consumer.ts'], { cwd: outdir, stdio: 'pipe' })
        return ''
      } catch (error) {
        return String((error as { stdout?: Buffer }).stdout ?? error)
      }
    }
    expect(check()).toBe('')
    // A wrong call is a type error: the declarations carry the types, not `any`.
    await writeFile(
      consumer,
      "import { connect } from './index.js'\nconnect({ url: 1, room: 'r', name: 'n' })\n",
    )
    expect(check()).toMatch(
      /consumer\.ts\(2,\d+\): error TS2322: Type 'number' is not assignable to type 'string'/,
    )
  }, 120_000)

  it('joins in snapshot mode; a spawned box reaches a second session; unsubscribing stops the calls', async () => {
    const a = await enter('sdk-snap', 'alice')
    const b = await enter('sdk-snap', 'bob')
    expect(a.mode).toBe('snapshot')
    expect(a.id).toBeGreaterThan(0)
    expect(b.id).not.toBe(a.id)
    await until(() => a.players().length === 2, 'both players in alice’s roster')
    expect(
      a
        .players()
        .map((p) => p.name)
        .sort(),
    ).toEqual(['alice', 'bob'])
    let states = 0
    const off = b.on('state', () => states++)
    const before = b.bodies().length
    const seq = a.send(box(3, 5))
    expect(seq).toBe(1)
    await until(() => b.bodies().length === before + 1, 'bob sees the box')
    const spawned = b.bodies().find((body) => body.kind === 2 && body.shapes[0].type === 'box')
    expect(spawned).toBeDefined()
    expect(spawned!.x).toBeCloseTo(3, 1)
    await until(() => states > 2, 'state events')
    off()
    const frozen = states
    const tick = b.tick
    await until(() => b.tick > tick + 3, 'more snapshots')
    expect(states).toBe(frozen)
  })

  it('follows a room in lockstep and predict modes', async () => {
    const l = await enter('sdk-lock', 'lock', { mode: 'lockstep' })
    const p = await enter('sdk-lock', 'pred', { mode: 'predict' })
    await until(() => l.simulation() !== null && p.simulation() !== null, 'both simulations restored')
    const before = l.bodies().length
    p.send(box(-2, 4))
    await until(() => l.bodies().length === before + 1, 'the lockstep session simulates the box')
    await until(() => p.bodies().length === before + 1, 'the predicting session has it')
    const t = l.tick
    await until(() => l.tick > t + 10, 'the lockstep session keeps stepping')
    // Its simulation matches the server's at a hash checkpoint (one every 60 ticks).
    await until(() => (l.runner?.stats.verifiedTick ?? -1) > -1, 'a verified hash checkpoint')
    expect(l.runner?.stats.desyncs).toBe(0)
  })

  it('sends goal-game commands: accepted ones change the game state, refused ones come back as errors', async () => {
    // The lockstep session joins first and syncs; the second player's join starts the match with a
    // kickoff event, which the snapshot session receives and the lockstep session computes itself.
    const lock = await enter('sdk-goal', 'blue', { game: 'goal', mode: 'lockstep' })
    const lockEvents: unknown[] = []
    lock.on('event', (e) => lockEvents.push(e.event))
    await until(() => lock.simulation() !== null, 'lockstep sync')
    const events: unknown[] = []
    const snap = await enter('sdk-goal', 'red', { game: 'goal', on: { event: (e) => events.push(e.event) } })
    expect(snap.rules?.game).toBe('goal')
    expect(snap.rules?.commands).toContain('kick')
    const isKickoff = (e: unknown) => typeof (e as { kickoff?: number } | null)?.kickoff === 'number'
    // The kickoff may come in the same read as the welcome: connect's `on` option hears it.
    await until(() => events.some(isKickoff), 'kickoff (snapshot)')
    const kickoff = events.find(isKickoff)
    expect(snap.gameState()).toEqual(events.at(-1))
    await until(() => lockEvents.some(isKickoff), 'kickoff (lockstep)')
    expect(lockEvents.find(isKickoff)).toEqual(kickoff)
    const errors: Array<{ code: string; reason: string; seq?: number }> = []
    snap.on('error', (e) => errors.push(e))
    const bad = snap.command('kick', { power: 5 })
    await until(() => errors.length > 0, 'the refusal')
    expect(errors[0]).toEqual({ code: 'invalid', reason: 'kick refused: power must be <= 1', seq: bad })
    // Each session's view of the goal game: its own team (the first to join is red), the same
    // score, the match playing.
    await until(() => (snap.view() as { phase?: string } | null)?.phase === 'playing', 'the snapshot view')
    await until(() => (lock.view() as { phase?: string } | null)?.phase === 'playing', 'the lockstep view')
    expect(snap.view()).toMatchObject({ team: 'blue', score: { red: 0, blue: 0 } })
    expect(lock.view()).toMatchObject({ team: 'red', score: { red: 0, blue: 0 } })
    lock.command('run', { x: 3, y: -2 })
    await until(() => {
      const state = lock.gameState() as { players: Record<string, { vx: number; vy: number }> } | null
      const me = state?.players[lock.id]
      return me !== undefined && me.vx === 3 && me.vy === -2
    }, 'the run command in the lockstep game state')
  })

  it('fails with clear errors', async () => {
    await expect(sdk.connect({ url: 'ws://127.0.0.1:1', room: 'x', name: 'n', WebSocket })).rejects.toThrow(
      /closed before the welcome.*is the server running/,
    )
    await expect(sdk.connect({ url: 'not a url', room: 'x', name: 'n', WebSocket })).rejects.toThrow(
      'connect: url "not a url" is not an absolute address',
    )
    await expect(sdk.connect({ url: server.url, room: 'Bad Room!', name: 'n', WebSocket })).rejects.toThrow(
      'connect: room "Bad Room!" is not a room name (1-32 of A-Z a-z 0-9 _ -)',
    )
    await expect(
      sdk.connect({ url: server.url, room: 'sdk-x', name: 'n', WebSocket, game: 'no-such-game' }),
    ).rejects.toThrow(/refused the join: .*no-such-game/)
    await expect(
      sdk.connect({ url: server.url, room: 'sdk-x', name: 'n', WebSocket, mode: 'fast' as never }),
    ).rejects.toThrow("connect: mode must be 'snapshot', 'lockstep' or 'predict', not 'fast'")
    const watcher = await enter('sdk-on', 'watcher', { spectate: true })
    const refusals: Array<{ code: string; reason: string; seq?: number }> = []
    watcher.on('error', (e) => refusals.push(e))
    const seq = watcher.send(box(0, 4))
    await until(() => refusals.length > 0, 'the spectator’s refusal')
    expect(refusals[0]).toEqual({ code: 'refused', reason: 'spectators send no commands', seq })
    expect(watcher.players().some((p) => p.id === watcher.id)).toBe(false)
    await expect(
      sdk.connect({ url: server.url, room: 'sdk-on', name: 'n', WebSocket, on: { nope: () => {} } as never }),
    ).rejects.toThrow('connect: options.on: unknown event "nope"')
    const s = await enter('sdk-on', 'n')
    expect(() => s.on('nope' as never, () => {})).toThrow('on: unknown event "nope"')
    expect(() => s.command('', {})).toThrow('command: kind must be a non-empty string')
  })
})
