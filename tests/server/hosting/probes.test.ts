/*
 * The probes: /healthz fails (503, naming the loop) once the tick loop has not ticked for the stall
 * limit and recovers when it ticks again; /readyz fails and new sockets are refused while the
 * server drains after a shutdown request, while players already connected stay until the drain
 * period ends and are then closed with 1001.
 */

import { afterAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { BotClient } from '../../../bots/bot-client.ts'
import { TickHealth } from '../../../server/hosting/tick-health.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const servers: RunningServer[] = []
afterAll(async () => {
  for (const s of servers) await s.close()
})

describe('probes', { timeout: 60_000 }, () => {
  it('a loop is stalled exactly when its last beat is older than the limit (a clock set by hand)', () => {
    let now = 0
    const health = new TickHealth(5000, () => now)
    health.beat('main')
    now = 3000
    health.beat('worker-1')
    now = 5000
    expect(health.problem()).toBeNull()
    now = 5001
    expect(health.stalled()).toEqual([{ loop: 'main', sinceMs: 5001 }])
    now = 9000
    expect(health.problem()).toBe('tick loop stalled: main silent for 9000 ms, worker-1 silent for 6000 ms')
    health.beat('main')
    health.remove('worker-1')
    expect(health.problem()).toBeNull()
  })

  it('/healthz answers 503 naming the stalled loop after the stall limit, and 200 again once it ticks', async () => {
    const server = await startTestServer({ stallSeconds: 1 })
    servers.push(server)
    expect((await fetch(`${server.url}/healthz`)).status).toBe(200)
    server.rooms.clock.stop()
    let body = ''
    await until(async () => {
      const res = await fetch(`${server.url}/healthz`)
      body = await res.text()
      return res.status === 503
    }, '/healthz to fail')
    // The main loop (rooms on workers by default; it still beats for Agones and the probes) is named.
    expect(body).toMatch(/^tick loop stalled: .*\bmain silent for \d+ ms/)
    server.rooms.clock.start()
    await until(async () => (await fetch(`${server.url}/healthz`)).status === 200, '/healthz to recover')
  })

  it('while draining, /readyz is 503, /healthz 200, new sockets get 503, joined players stay until the drain ends', async () => {
    const server = await startTestServer({ drainSeconds: 2 })
    expect((await fetch(`${server.url}/readyz`)).status).toBe(200)
    const bot = await BotClient.connect({ url: server.url, room: 'lobby', name: 'stays' })
    const get = async (path: string): Promise<number> => (await fetch(`${server.url}${path}`)).status
    expect(await get('/readyz')).toBe(200)
    const closing = server.close('test drain')
    expect(await get('/readyz')).toBe(503)
    expect(await get('/healthz')).toBe(200)
    const refused = await new Promise<string>((resolve) => {
      const ws = new WebSocket(`${server.url.replace('http', 'ws')}/ws?room=lobby`)
      ws.on('unexpected-response', (_req, res) => resolve(String(res.statusCode)))
      ws.on('open', () => resolve('open'))
      ws.on('error', (error) => resolve(error.message))
    })
    expect(refused).toBe('503')
    expect(bot.ws.readyState).toBe(WebSocket.OPEN)
    await closing
    await bot.closed
    expect(bot.closeCode).toBe(1001)
  })
})
