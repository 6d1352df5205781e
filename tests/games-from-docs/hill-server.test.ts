/*
 * The hill game (games/hill/, written from docs/games.md alone) loaded the way the docs say a
 * developer loads their games: a real server process started with `--games DIR`. Two players on
 * raw WebSockets (hill-player.ts, written from PROTOCOL.md) play a round to its end through the
 * game's own `push` command; bad arguments get the documented errors naming the field; the
 * round's log replays with `npm run replay -- FILE --verify --games DIR` with every hash matching.
 *
 * The oracle for where a push takes a puck is the closed form of linear damping, not the code: a
 * puck of mass m = pi r^2 rho with damping c, given the impulse J, travels J / (m c) before it
 * stops (the engine damps v by 1 / (1 + c h) each step before moving by v h: the geometric series
 * sums to exactly J / (m c)). Pushes add linearly while the puck touches nothing, so pushes of
 * total impulse m c d move a puck d metres. A puck is on the hill while its disc overlaps the
 * hill's: its centre within HILL_RADIUS + PUCK_RADIUS = 2 m of the origin.
 */
import { execFile } from 'node:child_process'
import { mkdtempSync, readdirSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type ServerProcess, startServerProcess } from '../support/server-process.ts'
import { until } from '../support/wait.ts'
import { WIN_TICKS } from './games/hill/layout.ts'
import { HillPlayer, pushesFor } from './hill-player.ts'

const GAMES_DIR = 'tests/games-from-docs/games'
function run(args: string[]): Promise<{ code: number; stdout: string; stderr: string }> {
  return new Promise((resolve) => {
    execFile('npm', ['run', '--silent', 'replay', '--', ...args], (error, stdout, stderr) =>
      resolve({ code: error ? Number(error.code) : 0, stdout, stderr }),
    )
  })
}

let server: ServerProcess
let replayDir: string

beforeAll(async () => {
  replayDir = mkdtempSync(join(tmpdir(), 'hill-replays-'))
  server = await startServerProcess(['--games', GAMES_DIR, '--workers', '1', '--replay-dir', replayDir])
}, 60_000)
afterAll(async () => {
  if (server && server.process.exitCode === null) {
    server.process.kill('SIGTERM')
    await server.exited
  }
  rmSync(replayDir, { recursive: true, force: true })
})

describe('king of the hill, loaded with --games', { timeout: 120_000 }, () => {
  it('is loaded, refuses bad arguments naming the field, plays a round to its end, and replays', async () => {
    expect(server.lines.find((l) => l.msg === 'games loaded')).toMatchObject({ games: ['hill'] })

    const a = await HillPlayer.join(server.url, 'hill-match', 'ada')
    expect(a.rules).toMatchObject({ game: 'hill', commands: ['push', 'restart'] })
    const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as unknown
    expect(JSON.stringify(rooms)).toContain('"hill"')

    // Arguments the schema refuses: `invalid`, the reason naming the field (PROTOCOL.md, cmd, 2).
    const refusedBy = async (k: string, args: unknown) => a.refusal(a.command(k, args), `${k} refusal`)
    expect(await refusedBy('push', { x: 5, y: 0 })).toEqual(
      expect.objectContaining({ code: 'invalid', reason: 'push refused: x must be <= 1' }),
    )
    expect(await refusedBy('push', { x: 0 })).toEqual(
      expect.objectContaining({ code: 'invalid', reason: 'push refused: y is required' }),
    )
    expect(await refusedBy('push', { x: 0, y: 0, z: 1 })).toEqual(
      expect.objectContaining({ code: 'invalid', reason: 'push refused: z is not allowed' }),
    )
    expect(await refusedBy('push', { x: 'left', y: 0 })).toEqual(
      expect.objectContaining({ code: 'invalid', reason: 'push refused: x must be number' }),
    )
    expect(await refusedBy('jump', {})).toEqual(
      expect.objectContaining({ code: 'invalid', reason: 'game hill has no jump command' }),
    )
    // The game's own rule: `refused`, with the game's reason, at the tick (cmd, 4).
    expect(await refusedBy('push', { x: 0.8, y: 0.8 })).toEqual(
      expect.objectContaining({ code: 'refused', reason: 'a push is at most 1 long' }),
    )
    expect(await refusedBy('restart', {})).toEqual(
      expect.objectContaining({ code: 'refused', reason: 'the round is not over' }),
    )

    const b = await HillPlayer.join(server.url, 'hill-match', 'bob')
    await until(
      () => a.events.some((e) => (e as { start?: number }).start !== undefined),
      'the round to start',
    )
    const kings = () =>
      a.events
        .filter((e) => (e as object) && 'king' in (e as object))
        .map((e) => (e as { king: number }).king)

    // Ada (spot (-6, 0)) pushes 6 m to the right: she comes to rest on the hill's centre, alone.
    for (const x of pushesFor(6)) await a.push(x, 0)
    await until(() => kings().length === 1, 'ada to be king')
    expect(kings()).toEqual([a.id])

    // Bob (spot (6, 0)) pushes 4.5 m to the left: 1.5 m from the centre he is on the hill too
    // (1.5 < 2), 1.5 m from ada's centre (> 1 m, the pucks do not touch): nobody is king.
    for (const x of pushesFor(4.5)) await b.push(-x, 0)
    await until(() => kings().length === 2, 'the hill to be contested')
    expect(kings()).toEqual([a.id, 0])
    // Game events are sent every tick, views only with snapshots: read ada's time from a view of
    // the contest's tick or later (the view before it can be one tick short).
    const contestTick = a.eventTicks[a.events.findIndex((e) => (e as { king?: number }).king === 0)]
    await until(() => a.viewTick >= contestTick, "a view of the contest's tick")
    const heldWhenContested = a.view!.held[a.id]
    expect(heldWhenContested).toBeGreaterThan(0)
    expect(heldWhenContested).toBeLessThan(WIN_TICKS)
    const contestedAt = a.tick
    await until(() => a.tick >= contestedAt + 30, 'half a second of contest')
    expect(a.view!.held[a.id]).toBe(heldWhenContested)
    expect(a.view!.held[b.id]).toBe(0)

    // Bob leaves the hill (3.8 m back to the right: 5.3 m from the centre); ada holds it to the end.
    await b.push(1, 0)
    await until(() => a.view?.phase === 'over', 'the round to end', 60_000)
    expect(kings()).toEqual([a.id, 0, a.id])
    expect(a.events.at(-1)).toEqual({ over: a.id, seconds: WIN_TICKS / 60 })
    expect(a.view).toMatchObject({ phase: 'over', winner: a.id, held: { [a.id]: WIN_TICKS, [b.id]: 0 } })
    await until(() => b.view?.phase === 'over', "bob's view of the end")
    expect(b.view).toMatchObject({ winner: a.id, me: b.id })
    expect(await b.refusal(b.command('push', { x: 1, y: 0 }), 'a push after the end')).toMatchObject({
      code: 'refused',
      reason: 'the round is over',
    })
    const endTick = a.tick
    await a.close()
    await b.close()

    // Stop the server (SIGTERM: the room's log is flushed to its last tick, README "What survives
    // what"), then replay the log.
    server.process.kill('SIGTERM')
    await server.exited
    const logs = readdirSync(replayDir).filter((f) => f.startsWith('hill-match') && f.endsWith('.cclog'))
    expect(logs).toHaveLength(1)
    const file = join(replayDir, logs[0])
    const replayed = await run([file, '--verify', '--json', '--games', GAMES_DIR])
    expect(replayed.code, replayed.stderr).toBe(0)
    const report = JSON.parse(replayed.stdout.trim().split('\n').at(-1)!) as Record<string, unknown>
    expect(report).toMatchObject({ room: 'hill-match' })
    // Every command the room applied (ada's two pushes, bob's three; no refused one), every
    // recorded hash checked and matched, through the tick the round ended.
    expect(report).toMatchObject({ commands: 5, divergence: null })
    expect(Number(report.hashesChecked)).toBeGreaterThan(0)
    expect(Number(report.lastTick)).toBeGreaterThanOrEqual(endTick)

    const without = await run([file, '--verify'])
    expect(without.code).toBe(2)
    expect(without.stdout + without.stderr).toContain(
      `replay: log ${file} was recorded with game "hill": load it with --games DIR`,
    )
  })
})
