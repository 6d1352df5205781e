/*
 * The replay CLI replays a log of a game loaded with --games DIR: a real server process runs
 * examples/games (hoops) with recording on and rooms on a worker thread, a real client shoots
 * balls, the server shuts down cleanly, and `npm run replay -- FILE --verify --games
 * examples/games` rebuilds the room with the same game module and matches every recorded hash and
 * keyframe. Without --games the tool stops with one line naming the game and the flag.
 */
import { spawnSync } from 'node:child_process'
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join, resolve } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import type { ServerMessage } from '../../../shared/index.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'

let server: ServerProcess | undefined
let file: string

afterAll(() => {
  if (server?.process.exitCode === null) server.process.kill('SIGKILL')
})

function cli(...args: string[]): { status: number | null; stdout: string; stderr: string } {
  const r = spawnSync(process.execPath, ['--import', 'tsx', 'server/replay/replay-cli.ts', ...args], {
    encoding: 'utf8',
  })
  return { status: r.status, stdout: r.stdout, stderr: r.stderr }
}

const isGame = (m: ServerMessage): m is Extract<ServerMessage, { t: 'game' }> => m.t === 'game'

beforeAll(async () => {
  const dir = await mkdtemp(join(tmpdir(), 'concord-cli-games-'))
  server = await startServerProcess([
    ...['--games', 'examples/games', '--workers', '1'],
    ...['--record', 'true', '--replay-dir', dir, '--keyframe-ticks', '120'],
    // A closed log: a planned restart would otherwise leave it open for the next start.
    ...['--keep-rooms', 'false'],
  ])
  const bot = await BotClient.connect({ url: server.url, room: 'court', name: 'shooter', game: 'hoops' })
  // Shots at several angles and speeds (one every half second at most: hoops' rule), each waited
  // for by its game event (scored or missed), so the log holds game commands and their effects.
  for (const [angle, speed] of [
    [0.9, 13],
    [0.7, 12],
    [1.1, 14],
    [0.5, 9],
  ]) {
    const seen = bot.received.filter(isGame).length
    bot.gameCommand('shoot', { angle, speed })
    await bot.waitFor(() => bot.received.filter(isGame).length > seen, 'a hoops event')
    const at = bot.mirror.tick
    await bot.waitFor(() => bot.mirror.tick >= at + 31, 'the shot interval')
  }
  await bot.close()
  server.process.kill('SIGTERM')
  expect((await server.exited).code).toBe(0)
  const name = (await listLogNames(dir)).find((n) => n.startsWith('court-'))
  if (!name) throw new Error('no log of room court')
  file = join(dir, name)
}, 120_000)

describe('the replay CLI and games loaded with --games', { timeout: 120_000 }, () => {
  it('--games examples/games replays a hoops log with every hash and keyframe matching', () => {
    const r = cli(file, '--verify', '--json', '--games', 'examples/games')
    expect(r.status, r.stderr).toBe(0)
    const report = JSON.parse(r.stdout)
    expect(report.divergence).toBeNull()
    expect(report.read.closed).toBe(true)
    expect(report.commands).toBeGreaterThanOrEqual(4)
    // About 4 shots with waits of at least half a second: several once-a-second hashes and
    // 120-tick keyframes.
    expect(report.hashesChecked).toBeGreaterThanOrEqual(2)
    expect(report.keyframesChecked).toBeGreaterThanOrEqual(1)
  })

  it('without --games it stops with one line naming the game and the flag', () => {
    const r = cli(file, '--verify')
    expect(r.status).toBe(2)
    expect(r.stdout).toBe('')
    expect(r.stderr).toBe(`replay: log ${file} was recorded with game "hoops": load it with --games DIR\n`)
  })

  it('a --games directory without that game says so, and a bad directory stops with its loader error', () => {
    const other = cli(file, '--games', 'tests/server/games/loaded')
    expect(other.status).toBe(2)
    expect(other.stderr).toBe(
      `replay: log ${file} was recorded with game "hoops": tests/server/games/loaded has no game of that name\n`,
    )
    const missing = cli(file, '--games', 'no/such/dir')
    expect(missing.status).toBe(2)
    expect(missing.stderr).toBe(`replay: --games ${resolve('no/such/dir')}: no such directory\n`)
  })
})
