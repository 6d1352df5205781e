/*
 * `npm run bots -- --help` (issue 31, fix 11): prints the options with aligned columns and exits 0
 * (it used to fail with "--help needs a value"); an unknown option names itself and points to
 * --help. Run through npm, as the README tells people to.
 */
import { spawnSync } from 'node:child_process'
import { describe, expect, it } from 'vitest'

const run = (args: string[]) =>
  spawnSync('npm', ['run', '--silent', 'bots', '--', ...args], { encoding: 'utf8', timeout: 60_000 })

describe('npm run bots', () => {
  it('--help lists every option in aligned columns and exits 0', () => {
    const result = run(['--help'])
    expect(result.stderr).toBe('')
    expect(result.status).toBe(0)
    const lines = result.stdout.split('\n')
    expect(lines[0]).toBe('Usage: npm run bots -- [options]')
    const header = lines.find((l) => l.trimStart().startsWith('option'))!
    const at = { default: header.indexOf('default'), meaning: header.indexOf('meaning') }
    const rows = lines.filter((l) => /^ {2}--/.test(l))
    expect(rows.map((r) => r.trim().split(' ')[0])).toEqual([
      '--url',
      '--room',
      '--count',
      '--seconds',
      '--rooms',
      '--help',
    ])
    for (const row of rows) {
      // Each column starts where its header does, after at least two spaces.
      expect(row.slice(at.default - 2, at.default), row).toBe('  ')
      expect(row.slice(at.meaning - 2, at.meaning), row).toBe('  ')
      expect(row[at.meaning], row).not.toBe(' ')
    }
    expect(rows.find((r) => r.includes('--url'))!.slice(at.default)).toMatch(/^ws:\/\/127\.0\.0\.1:8080 /)
  })

  it('an unknown option is named, with a pointer to --help, and exits 1', () => {
    const result = run(['--bogus', '1'])
    expect(result.status).toBe(1)
    expect(result.stderr).toContain(
      'bots: unknown option --bogus; use --url, --room, --count, --seconds, --rooms (--help)',
    )
  })
})
