import type { ChildProcess } from 'node:child_process'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { startServerProcess } from '../../support/server-process.ts'

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
