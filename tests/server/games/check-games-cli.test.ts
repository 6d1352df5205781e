/*
 * `npm run check-games -- DIR` (docs/games.md, "The determinism rules") checks and loads a game
 * directory as the server does at start, without a server: run here as a real process on the
 * example directory (passes, one line per game, exit 0), on a directory whose game uses
 * Math.random and Math.sin (exit 1, each break named by file, line, column and rule, as the
 * server prints them) and with no directory (usage, exit 2).
 */
import { spawnSync } from 'node:child_process'
import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'

const work = mkdtempSync(join(tmpdir(), 'concord-check-games-'))
afterAll(() => rmSync(work, { recursive: true, force: true }))

function cli(...args: string[]): { status: number | null; stdout: string; stderr: string } {
  const r = spawnSync(process.execPath, ['--import', 'tsx', 'server/games/check-games-cli.ts', ...args], {
    encoding: 'utf8',
  })
  return { status: r.status, stdout: r.stdout, stderr: r.stderr }
}

describe('npm run check-games', { timeout: 60_000 }, () => {
  it('passes the example games, one line each', () => {
    const r = cli('examples/games')
    expect(r.stderr).toBe('')
    expect(r.stdout).toMatch(
      /^check-games: hoops ok \(examples\/games\/hoops\/index\.ts, \d+ bytes bundled\)\n/,
    )
    expect(r.stdout).toContain('check-games: examples/games: 1 game pass\n')
    expect(r.status).toBe(0)
  })

  it('names each determinism break by file, line, column and rule', () => {
    const dir = join(work, 'games')
    mkdirSync(join(dir, 'noisy'), { recursive: true })
    writeFileSync(
      join(dir, 'noisy', 'index.ts'),
      [
        "import { defineGame } from 'concord/game'",
        'export default defineGame({',
        "  name: 'noisy',",
        '  state: () => ({ n: Math.random() }),',
        '  commands: {},',
        '  tick: (ctx) => { ctx.state.n = Math.sin(ctx.state.n) },',
        '})',
        '',
      ].join('\n'),
    )
    const r = cli(dir)
    expect(r.status).toBe(1)
    expect(r.stdout).toBe('')
    const file = join(dir, 'noisy', 'index.ts')
    expect(r.stderr.split('\n')).toEqual([
      `check-games: game modules in ${dir} break the determinism rules (docs/games.md):`,
      `${file}:4:22 no-random: Math.random differs everywhere: use ctx.random`,
      `${file}:6:34 inexact-math: Math.sin differs between JavaScript engines: use the engine's sin, cos and atan2, or + - * / and Math.sqrt`,
      '',
    ])
  })

  it('says how to use it when no directory is given', () => {
    const r = cli()
    expect(r.status).toBe(2)
    expect(r.stderr).toBe('check-games: no directory given\nusage: npm run check-games -- DIR\n')
  })
})
