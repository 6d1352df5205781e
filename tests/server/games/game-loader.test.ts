/*
 * --games DIR (server/games/game-loader.ts): game modules loaded from a directory at start. Every
 * kind of bad module stops the start with one error naming its file (and, for the determinism
 * check, the line and rule), checked on directories written by the test; the real command line
 * prints it as one `concord:` line and exits 1. A good directory (tests/server/games/loaded/,
 * written against the SDK only, as a game outside this repository is) runs on a real server with
 * rooms on worker threads: a join names the loaded game, GET /games/NAME.js serves its browser
 * bundle, and a lockstep client that runs that very bundle (imported from the served text)
 * matches every server hash while commands change the game's state. The oracle for the state is
 * worked by hand: marbles dropped at x = -5 come to rest left of 0, those at x = +5 right of it,
 * and the game counts the drops and, once a second, the marbles left of 0.
 */
import { spawnSync } from 'node:child_process'
import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join, relative } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { loadGameDirectory } from '../../../server/games/game-loader.ts'
import { importGameBundle } from '../../../server/games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

const GOOD = 'tests/server/games/loaded'
const work = mkdtempSync(join(tmpdir(), 'concord-games-'))
afterAll(() => rmSync(work, { recursive: true, force: true }))

/** A games directory holding `files` (path inside it -> source); returns its path. */
function gamesDir(name: string, files: Record<string, string>): string {
  const dir = join(work, name)
  for (const [path, text] of Object.entries(files)) {
    mkdirSync(join(dir, path, '..'), { recursive: true })
    writeFileSync(join(dir, path), text)
  }
  return dir
}

const game = (name: string, extra = ''): string =>
  `import { defineGame } from 'concord/game'\n${extra}\nexport default defineGame({ name: '${name}', commands: {} })\n`

/** The error loadGameDirectory throws for `dir`, with the directory's path shown relative to the cwd. */
async function loadError(dir: string): Promise<string> {
  const error = await loadGameDirectory(dir).then(
    () => new Error('loaded'),
    (e: Error) => e,
  )
  expect(error.name).toBe('GameLoadError')
  return error.message.replaceAll(relative(process.cwd(), dir), 'DIR').replaceAll(dir, 'DIR')
}

describe('--games DIR refuses a bad module with one error naming its file', () => {
  it('a syntax error: file, line, column and what esbuild expected', async () => {
    const dir = gamesDir('syntax', {
      'broken/index.ts':
        "import { defineGame } from 'concord/game'\nexport default defineGame({ name: 'x', commands: {}\n",
    })
    expect(await loadError(dir)).toBe('DIR/broken/index.ts:3:1: Expected "}" but found end of file')
  })
  it('an import esbuild cannot resolve: file, line, column and the import', async () => {
    const dir = gamesDir('unresolved', {
      'g/index.ts': game('g', "import { x } from './missing.ts'\nexport const y = x"),
    })
    expect(await loadError(dir)).toBe('DIR/g/index.ts:2:19: Could not resolve "./missing.ts"')
  })
  it('no default export, or one that is not a game', async () => {
    const none = gamesDir('none', { 'g/index.ts': game('g').replace('export default', 'export const g =') })
    expect(await loadError(none)).toBe(
      'DIR/g/index.ts: the default export must be a game made with defineGame (export default defineGame({...})), got no default export',
    )
    const other = gamesDir('other', { 'g/index.js': 'export default { name: "g", commands: {} }\n' })
    expect(await loadError(other)).toBe(
      'DIR/g/index.js: the default export must be a game made with defineGame (export default defineGame({...})), got an object with keys name, commands',
    )
  })
  it("defineGame's RangeError, with the file", async () => {
    const dir = gamesDir('range', { 'g/index.ts': game('Bad Name') })
    expect(await loadError(dir)).toBe(
      'DIR/g/index.ts: game definition refused: game name "Bad Name" must be 1 to 32 lowercase letters, digits or dashes, starting with a letter',
    )
  })
  it("a name clash with a built-in game or another folder's game", async () => {
    expect(await loadError(gamesDir('builtin', { 'g/index.ts': game('sandbox') }))).toBe(
      `DIR/g/index.ts: game name "sandbox" is a built-in game's; choose another name`,
    )
    expect(
      await loadError(gamesDir('twice', { 'a/index.ts': game('same'), 'b/index.ts': game('same') })),
    ).toBe('DIR/b/index.ts: game name "same" is also the game of DIR/a/index.ts')
  })
  it('a determinism break in any file: file, line, column and rule, before any game code runs', async () => {
    const dir = gamesDir('random', {
      'g/index.ts': game('g', "import { roll } from './roll.ts'\nexport const r = roll"),
      'g/roll.ts': 'export function roll(): number {\n  return Math.random()\n}\n',
    })
    expect(await loadError(dir)).toBe(
      'game modules in DIR break the determinism rules (docs/games.md):\nDIR/g/roll.ts:2:10 no-random: Math.random differs everywhere: use ctx.random',
    )
  })
  it('a folder without an index, a loose file, an empty or missing directory', async () => {
    expect(await loadError(gamesDir('noindex', { 'g/game.ts': game('g') }))).toBe(
      'DIR/g: a game folder needs an index.ts or index.js whose default export is the game',
    )
    expect(await loadError(gamesDir('loose', { 'g.ts': game('g') }))).toBe(
      'DIR/g.ts: a game lives in its own folder (DIR/NAME/index.ts); move this file into one',
    )
    expect(await loadError(gamesDir('empty', { 'README.md': 'no games' }))).toBe(
      '--games DIR: no game folders (each game is DIR/NAME/index.ts)',
    )
    expect(await loadError(join(work, 'missing'))).toBe('--games DIR: no such directory')
  })
  it('the command line prints the error as one line and exits 1 (flag and environment variable)', () => {
    const dir = gamesDir('cli', { 'g/index.ts': game('sandbox') })
    const base = ['--import', 'tsx', 'server/main.ts', '--port', '0', '--workers', '0', '--record', 'false']
    for (const [args, env] of [
      [['--games', dir], {}],
      [[], { GAMES_DIR: dir }],
    ] as const) {
      const r = spawnSync(process.execPath, [...base, ...args], {
        encoding: 'utf8',
        timeout: 30_000,
        env: { ...process.env, ...env },
      })
      expect(r.status).toBe(1)
      expect(r.stderr).toBe(
        `concord: ${dir}/g/index.ts: game name "sandbox" is a built-in game's; choose another name\n`,
      )
    }
  })
})

describe('a game loaded from a directory, on a real server with worker threads', { timeout: 90_000 }, () => {
  let server: RunningServer
  beforeAll(async () => {
    server = await startTestServer({ gamesDir: GOOD, workers: 1 })
  })
  afterAll(async () => {
    await server?.close()
  })

  it('serves its bundle, runs its commands, and a lockstep client running the served bundle matches every hash', async () => {
    const http = server.url
    const res = await fetch(`${http}/games/marbles.js`)
    expect(res.status).toBe(200)
    expect(res.headers.get('content-type')).toBe('text/javascript; charset=utf-8')
    const code = await res.text()
    expect((await fetch(`${http}/games/nope.js`)).status).toBe(404)
    const served = await importGameBundle({ file: 'GET /games/marbles.js', code })
    expect(served.name).toBe('marbles')

    const unknown = new BotClient({ url: server.url, room: 'x', name: 'u', game: 'nope' })
    await unknown.opened
    unknown.join()
    const error = await unknown.nextMessage((m): m is ErrorMessage => m.t === 'error')
    expect(error.reason).toBe('unknown game "nope"; this server has sandbox, ball-drop, goal, tower, marbles')
    await unknown.close()

    const player = await BotClient.connect({ url: server.url, room: 'm', name: 'p', game: 'marbles' })
    const welcome = player.received.find((m) => m.t === 'welcome')
    expect(welcome?.t === 'welcome' && welcome.rules).toMatchObject({ game: 'marbles', commands: ['drop'] })
    const follower = await LockstepBot.connect(
      { url: server.url, room: 'm', name: 'f' },
      'lockstep',
      16,
      (n) => (n === 'marbles' ? served : undefined),
    )
    await follower.waitFor(() => follower.runner.sim !== null, 'the sync')
    for (const x of [-5, -5, 5, -5, 5]) player.gameCommand('drop', { x })
    const state = () => follower.runner.sim?.gameState as { dropped: number; left: number } | undefined
    await follower.waitFor(
      () => state()?.dropped === 5 && state()?.left === 3,
      'five drops, three resting left of 0',
    )
    const checked = follower.runner.stats.hashesChecked
    await follower.waitFor(
      () => follower.runner.stats.hashesChecked >= checked + 3,
      'three more hash checkpoints',
    )
    expect(follower.runner.stats.desyncs).toBe(0)
    expect(follower.runner.stats.verifiedTick).toBeGreaterThan(0)
    const rooms = (await (await fetch(`${http}/rooms`)).json()) as Array<{ name: string; game: string }>
    expect(rooms.find((r) => r.name === 'm')?.game).toBe('marbles')
    await Promise.all([player.close(), follower.close()])
  })
})
