import type { ChildProcess } from 'node:child_process'
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

let child: ChildProcess | null = null

afterAll(() => {
  if (child && child.exitCode === null) child.kill('SIGKILL')
})

describe('shutdown', { timeout: 20_000 }, () => {
  it('SIGTERM closes every client with a reason and the process exits 0 within 5 s', async () => {
    const { process: proc, port } = await startServerProcess([], { DEFAULT_SCENE: 'tower', RECORD: 'false' })
    child = proc
    const url = `http://127.0.0.1:${port}`
    const a = await BotClient.connect({ url, room: 'lobby', name: 'a' })
    const b = await BotClient.connect({ url, room: 'other', name: 'b' })
    const exited = new Promise<number | null>((resolve) => proc.once('exit', (code) => resolve(code)))
    proc.kill('SIGTERM')
    const deadline = new Promise<'timeout'>((resolve) => setTimeout(() => resolve('timeout'), 5000).unref())
    const code = await Promise.race([exited, deadline])
    expect(code).toBe(0)
    await Promise.all([a.closed, b.closed])
    for (const bot of [a, b]) {
      expect(bot.closeCode).toBe(1001)
      expect(bot.closeReason).toContain('shutting down')
    }
  })
})

describe('signals during a shutdown', { timeout: 60_000 }, () => {
  const newestLog = async (dir: string): Promise<string> => join(dir, (await listLogNames(dir)).pop()!)

  it('a second SIGINT (Ctrl-C under npm: npm passes its own on) does not cut the shutdown short', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-ctrlc-'))
    const server = await startServerProcess([
      '--record',
      'true',
      '--replay-dir',
      dir,
      '--default-scene',
      'tower',
    ])
    child = server.process
    const bot = await BotClient.connect({ url: server.url, room: 'lobby', name: 'a' })
    await until(async () => (await listLogNames(dir)).length === 1, 'the lobby log')
    server.process.kill('SIGINT')
    // Two signals sent at once may reach the process as one (a pending signal is not queued twice):
    // the second goes once the shutdown has begun, as npm's copy does.
    await until(() => server.lines.some((l) => l.msg === 'shutting down'), 'the shutdown begun')
    server.process.kill('SIGINT')
    const { code, signal } = await server.exited
    expect({ code, signal }).toEqual({ code: 0, signal: null })
    await bot.closed
    expect(bot.closeCode).toBe(1001)
    expect(bot.closeReason).toContain('shutting down (SIGINT)')
    expect(server.lines.some((l) => l.msg?.startsWith('already shutting down'))).toBe(true)
    // The log ends with its clean close: the next start reopens nothing.
    const reader = new ReplayLogReader()
    reader.push(await readFile(await newestLog(dir)))
    expect(reader.finish()).toMatchObject({ state: 'end', closed: true })
  })

  it('a third signal ends the process at once, saying so (exit code 130)', async () => {
    const server = await startServerProcess(['--drain-seconds', '5'], { RECORD: 'false' })
    child = server.process
    server.process.kill('SIGTERM')
    await until(() => server.lines.some((l) => l.msg === 'shutting down'), 'the shutdown begun')
    server.process.kill('SIGTERM')
    server.process.kill('SIGINT')
    const started = Date.now()
    expect(await server.exited).toEqual({ code: 130, signal: null })
    expect(Date.now() - started).toBeLessThan(4000)
    expect(server.lines.some((l) => l.msg?.startsWith('third signal during shutdown: exiting now'))).toBe(
      true,
    )
  })
})
