/*
 * Crash recovery of a room of a --games game (docs/games.md, "Games in their own directory": "its
 * rooms, lockstep and predicting pages, and crash recovery run them like the built-in ones";
 * README "Crash recovery": the room is rebuilt at its log's last durable checkpoint and reopened,
 * and "Players of the crashed process are recorded as leaving"). A player holds the hill, the
 * server is SIGKILLed, a new server on the same replay and games directories reopens the room: a
 * joiner is told it was restored; the game's leave rule ran for the two players of the killed
 * process (their pucks and times are gone: a per-player score does not survive a crash, which
 * docs/games.md now says); the new player plays on; and the log, across the crash, replays with
 * every hash matching.
 */
import { execFile } from 'node:child_process'
import { mkdtempSync, readdirSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { type ServerProcess, startServerProcess } from '../support/server-process.ts'
import { until } from '../support/wait.ts'
import { HillPlayer, pushesFor } from './hill-player.ts'

const replayDir = mkdtempSync(join(tmpdir(), 'hill-recovery-'))
const args = ['--games', 'tests/games-from-docs/games', '--workers', '1', '--replay-dir', replayDir]
const servers: ServerProcess[] = []

function replay(argv: string[]): Promise<{ code: number; stdout: string; stderr: string }> {
  return new Promise((resolve) => {
    execFile('npm', ['run', '--silent', 'replay', '--', ...argv], (error, stdout, stderr) =>
      resolve({ code: error ? Number(error.code) : 0, stdout, stderr }),
    )
  })
}

afterAll(async () => {
  for (const server of servers)
    if (server.process.exitCode === null && server.process.signalCode === null) {
      server.process.kill('SIGTERM')
      await server.exited
    }
  rmSync(replayDir, { recursive: true, force: true })
})

describe('a room of the hill game after a SIGKILL', { timeout: 120_000 }, () => {
  it('is reopened: the old players have left it, a new one plays on, and its log replays across the crash', async () => {
    const first = await startServerProcess(args)
    servers.push(first)
    const a = await HillPlayer.join(first.url, 'hill-crash', 'ada')
    const b = await HillPlayer.join(first.url, 'hill-crash', 'bob')
    for (const x of pushesFor(6)) await a.push(x, 0)
    await until(() => (a.view?.held[a.id] ?? 0) >= 90, 'ada to hold the hill for 1.5 s')
    const killedAt = a.tick
    first.process.kill('SIGKILL')
    await first.exited

    const second = await startServerProcess(args)
    servers.push(second)
    // The room is rebuilt on the worker after the server listens (or before: either way once).
    await until(
      () => second.lines.some((l) => l.msg === 'room recovered from its log' && l.room === 'hill-crash'),
      'the "room recovered from its log" line',
    )
    const c = await HillPlayer.join(second.url, 'hill-crash', 'cy')
    const welcome = c.received.find((m) => m.t === 'welcome')!
    expect(welcome.notice).toBe('This room was restored after a server restart: what was built here is back.')
    expect(c.rules).toMatchObject({ game: 'hill' })
    expect(c.id).toBeGreaterThan(b.id)
    await until(() => c.view !== null, "the restored room's view")
    // Ada and bob left with the killed process: the game's onLeave took their pucks and times.
    expect(Object.keys(c.view!.held)).toEqual([String(c.id)])
    expect(c.view).toMatchObject({ me: c.id, king: 0, away: 60 })
    // Ada comes back with her token from the killed server: a new player, with a new id and puck.
    const token = a.received.find((m) => m.t === 'welcome')!.token as string
    const back = await HillPlayer.join(second.url, 'hill-crash', 'ada', { token })
    expect(back.id).toBeGreaterThan(c.id)
    await until(() => back.view !== null, "ada's new view")
    expect(back.view).toMatchObject({ me: back.id, away: 60 })
    expect(back.view!.held[a.id]).toBeUndefined()
    await back.close()
    await c.push(1, 0)
    await until(() => c.view?.away === 22, "cy's puck at rest 2.18 m from the hill")
    await c.close()
    second.process.kill('SIGTERM')
    await second.exited

    const logs = readdirSync(replayDir).filter((f) => f.startsWith('hill-crash') && f.endsWith('.cclog'))
    expect(logs).toHaveLength(1)
    const replayed = await replay([
      join(replayDir, logs[0]),
      '--verify',
      '--json',
      '--games',
      'tests/games-from-docs/games',
    ])
    expect(replayed.code, replayed.stderr).toBe(0)
    const report = JSON.parse(replayed.stdout.trim().split('\n').at(-1)!) as Record<string, unknown>
    expect(report).toMatchObject({ room: 'hill-crash', divergence: null })
    expect(Number(report.firstTick)).toBeLessThan(killedAt - 60)
    expect(Number(report.lastTick)).toBeGreaterThan(killedAt)
    expect(Number(report.hashesChecked)).toBeGreaterThan(0)
  })
})
