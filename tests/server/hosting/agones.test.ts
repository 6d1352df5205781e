/*
 * Agones: a server process started with the SDK sidecar's environment variables marks itself
 * Ready, pings Health from its tick loop, and after SIGTERM drains its clients and then calls
 * Shutdown, against a stand-in sidecar that serves the official SDK's gRPC service definition.
 * Without those variables the server makes no Agones connection at all.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { createInterface } from 'node:readline'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { type FakeSidecar, startFakeSidecar } from '../../support/agones-sidecar.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let child: ChildProcess | null = null
let sidecar: FakeSidecar | null = null

afterAll(async () => {
  if (child && child.exitCode === null) child.kill('SIGKILL')
  await sidecar?.stop()
})

describe('Agones SDK integration', { timeout: 60_000 }, () => {
  it('Ready after listening, a Health ping about every second, Shutdown only after the clients are closed, exit 0', async () => {
    sidecar = await startFakeSidecar()
    const proc = spawn(
      process.execPath,
      ['--import', 'tsx', 'server/main.ts', '--port', '0', '--log-level', 'info', '--default-scene', 'empty'],
      {
        stdio: ['ignore', 'pipe', 'inherit'],
        env: {
          ...process.env,
          RECORD: 'false',
          AGONES_SDK_GRPC_PORT: String(sidecar.port),
          AGONES_SDK_HTTP_PORT: '1',
        },
      },
    )
    child = proc
    let listenedAt = 0
    const port = await new Promise<number>((resolve, reject) => {
      proc.once('exit', (code) => reject(new Error(`server exited early with ${code}`)))
      createInterface({ input: proc.stdout! }).on('line', (line) => {
        const entry = JSON.parse(line) as { msg?: string; port?: number }
        if (entry.msg === 'listening' && entry.port) {
          listenedAt = Date.now()
          resolve(entry.port)
        }
      })
    })
    const side = sidecar
    await until(() => side.count('Ready') === 1, 'Ready')
    expect(side.calls.find((c) => c.method === 'Ready')!.at).toBeGreaterThanOrEqual(listenedAt)
    await until(() => side.count('Health') >= 3, 'three health pings')
    const health = side.calls.filter((c) => c.method === 'Health')
    // One ping per 60 ticks: consecutive pings are about a second apart, never a burst per tick.
    expect(health[2].at - health[0].at).toBeGreaterThan(1000)
    const bot = await BotClient.connect({ url: `http://127.0.0.1:${port}`, room: 'lobby', name: 'a' })
    let clientStateAtShutdown = -1
    side.onShutdown = () => {
      clientStateAtShutdown = bot.ws.readyState
    }
    proc.removeAllListeners('exit')
    const exited = new Promise<number | null>((resolve) => proc.once('exit', (code) => resolve(code)))
    proc.kill('SIGTERM')
    await bot.closed
    expect(bot.closeCode).toBe(1001)
    expect(await exited).toBe(0)
    expect(side.count('Shutdown')).toBe(1)
    // The client had its close frame (CLOSING or CLOSED) before the server asked Agones to shut down.
    expect(clientStateAtShutdown).toBeGreaterThanOrEqual(2)
    expect(side.count('Ready')).toBe(1)
  })

  it('a plain install (no sidecar variables) never connects to Agones', async () => {
    const server = await startTestServer()
    try {
      expect(server.agones()).toBeNull()
      const res = await fetch(`${server.url}/healthz`)
      expect(res.status).toBe(200)
    } finally {
      await server.close()
    }
  })
})
