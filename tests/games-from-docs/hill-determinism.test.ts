/*
 * The determinism check docs/games.md describes ("What the server does with DIR at start": step 2,
 * and "The determinism rules") runs over a game loaded with --games: the hill game as written
 * passes it (checkGameDirectory, server/games/determinism-check.ts), and a copy of it outside this
 * repository with two breaks written into it stops the server with exit code 1, before it
 * listens, naming each break's file, line, column and rule on a line of its own.
 */
import { spawn } from 'node:child_process'
import { cpSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { checkGameDirectory, formatViolation } from '../../server/games/determinism-check.ts'

const dirs: string[] = []
afterAll(() => {
  for (const dir of dirs) rmSync(dir, { recursive: true, force: true })
})

/** Runs the server on `gamesDir` until it exits; its exit code and what it wrote. */
function startOn(gamesDir: string): Promise<{ code: number | null; stdout: string; stderr: string }> {
  const child = spawn(
    process.execPath,
    ['--import', 'tsx', 'server/main.ts', '--port', '0', '--record', 'false', '--games', gamesDir],
    { stdio: ['ignore', 'pipe', 'pipe'] },
  )
  let stdout = ''
  let stderr = ''
  child.stdout.on('data', (c: Buffer) => {
    stdout += c.toString()
    // A server that got as far as listening passed the check: stop it (the test then fails).
    if (stdout.includes('"msg":"listening"')) child.kill('SIGTERM')
  })
  child.stderr.on('data', (c: Buffer) => {
    stderr += c.toString()
  })
  return new Promise((resolve) => child.once('exit', (code) => resolve({ code, stdout, stderr })))
}

describe('the determinism check over a --games directory', { timeout: 60_000 }, () => {
  it('passes the hill game as written', () => {
    expect(checkGameDirectory('tests/games-from-docs/games').map(formatViolation)).toEqual([])
  })

  it('names each break in a copy of the hill game, with its file, line, column and rule, and stops the server', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'hill-broken-'))
    dirs.push(dir)
    cpSync('tests/games-from-docs/games/hill', join(dir, 'hill'), { recursive: true })
    const layout = join(dir, 'hill', 'layout.ts')
    // Line numbers of the two lines added at the end of layout.ts.
    const lines = readFileSync(layout, 'utf8').split('\n')
    const first = lines.length + (lines.at(-1) === '' ? 0 : 1)
    writeFileSync(
      layout,
      `${readFileSync(layout, 'utf8')}export const JITTER = Math.random()\nexport const TILT = Math.sin(0.5)\n`,
    )
    const result = await startOn(dir)
    expect(result.code, result.stderr).toBe(1)
    expect(result.stdout).not.toContain('"msg":"listening"')
    const said = result.stderr.trim().split('\n')
    const file = join(dir, 'hill', 'layout.ts')
    // One `concord:` line naming the directory, then one line per break (not one line in all, as
    // docs/games.md said before this check: see the stranger's notes).
    expect(said[0]).toBe(`concord: game modules in ${dir} break the determinism rules (docs/games.md):`)
    expect(said.slice(1)).toEqual([
      `${file}:${first}:23 no-random: Math.random differs everywhere: use ctx.random`,
      expect.stringMatching(new RegExp(`^${file}:${first + 1}:21 inexact-math: Math.sin differs`)),
    ])
  })
})
