/*
 * A server whose recording is configured but impossible says so (issue 30, point 7): the Docker
 * image ran as uid 1000 in a root-owned /app, `mkdir replays` failed with EACCES, and recording
 * and crash recovery were off with no more than an error line among the start-up lines. Now one
 * loud line names the directory, the cause and the consequence, and with --require-recording
 * /readyz answers 503 with that reason (the rooms still run: /healthz stays 200, a join works).
 * Reproduced as the image does it (a process running as uid 1000 beside a root-owned directory,
 * when this test runs as root) and in-process with a replay directory under a regular file
 * (ENOTDIR, which no uid can get past).
 */
import { chmodSync, mkdirSync, mkdtempSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { startServerProcess } from '../../support/server-process.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const LOUD =
  /^recording is configured but impossible: the replay directory (\S+) cannot be written \((\w+)\); rooms run unrecorded and crash recovery is off/

/** A directory owned by root, readable by all and writable by root only (like the image's /app). */
function rootOwnedDir(): string {
  const dir = mkdtempSync(join(tmpdir(), 'concord-app-'))
  chmodSync(dir, 0o755)
  return dir
}

const asRoot = process.getuid?.() === 0

describe('recording configured but impossible', { timeout: 60_000 }, () => {
  it('says so in one loud line and, with --require-recording, fails /readyz with the reason while rooms run', async () => {
    const blocker = join(mkdtempSync(join(tmpdir(), 'concord-blocked-')), 'a-file')
    writeFileSync(blocker, 'not a directory')
    const dir = join(blocker, 'replays')
    for (const required of [true, false]) {
      const { logger, lines } = capturingLogger()
      const server = await startTestServer(
        { record: true, replayDir: dir, requireRecording: required },
        logger,
      )
      try {
        const loud = lines.filter((l) => LOUD.test(String(l.msg)))
        expect(loud, 'one loud line').toHaveLength(1)
        expect(loud[0].level).toBe(50) // error
        expect(LOUD.exec(String(loud[0].msg))?.slice(1)).toEqual([dir, 'ENOTDIR'])
        const ready = await fetch(`${server.url}/readyz`)
        const text = await ready.text()
        if (required) {
          expect(ready.status).toBe(503)
          expect(text).toContain(`the replay directory ${dir} cannot be written (ENOTDIR)`)
        } else expect([ready.status, text]).toEqual([200, 'ready\n'])
        expect((await fetch(`${server.url}/healthz`)).status).toBe(200)
        const bot = await BotClient.connect({ url: server.url, room: 'unrecorded', name: 'b' })
        expect(bot.received.some((m) => m.t === 'welcome')).toBe(true)
        await bot.close()
      } finally {
        await server.close()
      }
    }
  })

  it.skipIf(!asRoot)(
    'as the image runs it: uid 1000 beside a root-owned directory, missing or existing (EACCES), is loud and not ready',
    async () => {
      for (const existing of [false, true]) {
        const app = rootOwnedDir()
        const dir = join(app, 'replays')
        if (existing) mkdirSync(dir, { mode: 0o755 }) // mkdir -p succeeds; writing in it does not
        const server = await startServerProcess(
          ['--replay-dir', dir, '--workers', '1', '--require-recording'],
          { HOME: tmpdir() },
          30_000,
          { uid: 1000, gid: 1000 },
        )
        try {
          const loud = server.lines.filter((l) => LOUD.test(String(l.msg)))
          expect(loud, 'one loud line before listening').toHaveLength(1)
          expect(LOUD.exec(String(loud[0].msg))?.slice(1)).toEqual([dir, 'EACCES'])
          const ready = await fetch(`${server.url}/readyz`)
          expect(ready.status).toBe(503)
          expect(await ready.text()).toContain(`the replay directory ${dir} cannot be written (EACCES)`)
          // The room worker found the same and said it quietly: still one loud line once it ran.
          const bot = await BotClient.connect({ url: server.url, room: 'lobby', name: 'b' })
          await bot.close()
          await until(() => server.lines.some((l) => l.msg === 'room created'), 'the room', 10_000)
          expect(server.lines.filter((l) => LOUD.test(String(l.msg)))).toHaveLength(1)
        } finally {
          server.process.kill('SIGTERM')
          await server.exited
        }
      }
    },
  )
})
