/*
 * A room worker that cannot start stops the server's startup with an error naming it. The built
 * server is copied without the dist/room-worker.js it loads its workers from (a broken deploy):
 * before, every worker died at once, was replaced by a new one that died the same way, over and
 * over, while the server listened with no room able to open.
 */
import { spawn } from 'node:child_process'
import { rmSync } from 'node:fs'
import { build } from 'esbuild'
import { afterAll, describe, expect, it } from 'vitest'

const DIR = 'test-results/worker-missing'

afterAll(() => rmSync(DIR, { recursive: true, force: true }))

describe('room workers at startup', { timeout: 120_000 }, () => {
  it('a worker that cannot load ends the startup with exit 1, naming the worker and what is missing', async () => {
    // The server bundled as the build bundles it, into a folder of its own inside the checkout
    // (the runtime packages resolve from its node_modules), without room-worker.js beside it.
    await build({
      entryPoints: ['server/main.ts'],
      outfile: `${DIR}/server.js`,
      bundle: true,
      platform: 'node',
      format: 'esm',
      packages: 'external',
      logLevel: 'warning',
    })
    const proc = spawn(
      process.execPath,
      [`${DIR}/server.js`, '--port', '0', '--workers', '2', '--record', 'false', '--recover', 'false'],
      { stdio: ['ignore', 'pipe', 'pipe'] },
    )
    let stdout = ''
    let stderr = ''
    proc.stderr.on('data', (chunk) => {
      stderr += chunk
    })
    // Ends with the process, or at once if it listens (the server it must not become).
    const code = await new Promise<number | null | 'listening'>((resolve) => {
      proc.once('exit', (c) => resolve(c))
      proc.stdout.on('data', (chunk) => {
        stdout += chunk
        if (stdout.includes('"msg":"listening"')) {
          proc.kill('SIGKILL')
          resolve('listening')
        }
      })
    })
    expect(code).toBe(1)
    expect(stderr).toMatch(/room worker \d ended before starting \(exit code 1\): .*room-worker\.js/)
    // Each worker failed once: none was replaced.
    expect(
      stdout.split('\n').filter((l) => l.includes('room worker failed to start')).length,
    ).toBeLessThanOrEqual(2)
    expect(stdout).not.toContain('room worker died')
  })
})
