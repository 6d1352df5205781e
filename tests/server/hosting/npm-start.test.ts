/*
 * `npm start` as the README tells people to run it: it builds, serves, and a signal sent to npm
 * (a process manager, `kill`, a terminal) reaches the server, which closes cleanly, so npm exits
 * 0 and leaves no server behind. Before the start script exec'd the server, SIGTERM to npm killed
 * only the shell between them and the server kept running without a parent.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { createInterface } from 'node:readline'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'

const started: ChildProcess[] = []
let serverPid = 0

afterAll(() => {
  for (const proc of started) if (proc.exitCode === null) proc.kill('SIGKILL')
  if (serverPid && alive(serverPid)) process.kill(serverPid, 'SIGKILL')
})

/** Whether a process id is still running. */
function alive(pid: number): boolean {
  try {
    process.kill(pid, 0)
    return true
  } catch {
    return false
  }
}

describe('npm start', { timeout: 120_000 }, () => {
  for (const signal of ['SIGTERM', 'SIGINT'] as const) {
    it(`serves, and ${signal} sent to npm closes the server: npm exits 0, no server is left`, async () => {
      // No logs written into the checkout, any free port.
      const args = ['start', '--', '--port', '0', '--record', 'false', '--recover', 'false']
      const npm = spawn('npm', args, { stdio: ['ignore', 'pipe', 'inherit'] })
      started.push(npm)
      const exited = new Promise<number | null>((resolve) => npm.once('exit', (code) => resolve(code)))
      const lines: Array<Record<string, unknown>> = []
      const listening = new Promise<{ port: number; pid: number }>((resolve, reject) => {
        exited.then((code) => reject(new Error(`npm start exited early with ${code}`)))
        createInterface({ input: npm.stdout! }).on('line', (text) => {
          if (!text.startsWith('{')) return // npm's own banner
          const line = JSON.parse(text) as Record<string, unknown>
          lines.push(line)
          if (line.msg === 'listening') resolve({ port: line.port as number, pid: line.pid as number })
        })
      })
      const { port, pid } = await listening
      serverPid = pid
      expect(pid).not.toBe(npm.pid)
      const url = `http://127.0.0.1:${port}`
      expect((await fetch(`${url}/healthz`)).status).toBe(200)
      const bot = await BotClient.connect({ url, room: 'lobby', name: 'visitor' })
      const closed = new Promise<number>((resolve) => bot.ws.once('close', (code) => resolve(code)))
      npm.kill(signal)
      expect(await exited).toBe(0)
      expect(await closed).toBe(1001)
      expect(lines.some((l) => l.msg === 'shutting down' && String(l.reason).includes(signal))).toBe(true)
      expect(lines.at(-1)?.msg).toBe('closed')
      expect(alive(pid)).toBe(false)
    })
  }
})
