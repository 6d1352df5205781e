import { type ChildProcess, spawn } from 'node:child_process'
import { createInterface } from 'node:readline'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../server/bot-client.ts'

let child: ChildProcess | null = null

afterAll(() => {
  if (child && child.exitCode === null) child.kill('SIGKILL')
})

/** Start server/main.ts in its own Node process (through tsx) and resolve with its port. */
function startServerProcess(): Promise<{ process: ChildProcess; port: number }> {
  const proc = spawn(
    process.execPath,
    ['--import', 'tsx', 'server/main.ts', '--port', '0', '--log-level', 'info'],
    {
      stdio: ['ignore', 'pipe', 'inherit'],
      env: { ...process.env, DEFAULT_SCENE: 'tower', RECORD: 'false' },
    },
  )
  child = proc
  return new Promise((resolve, reject) => {
    proc.once('exit', (code) => reject(new Error(`server exited early with ${code}`)))
    createInterface({ input: proc.stdout! }).on('line', (line) => {
      const entry = JSON.parse(line) as { msg?: string; port?: number }
      if (entry.msg === 'listening' && entry.port) resolve({ process: proc, port: entry.port })
    })
  })
}

describe('shutdown', { timeout: 20_000 }, () => {
  it('SIGTERM closes every client with a reason and the process exits 0 within 5 s', async () => {
    const { process: proc, port } = await startServerProcess()
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
