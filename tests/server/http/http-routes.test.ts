import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { meanTickMs } from '../../../client/net/server-stats.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer()
})
afterAll(async () => {
  await server.close()
})

describe('HTTP routes', { timeout: 20_000 }, () => {
  it('probes answer, metrics are Prometheus text, and /rooms lists open rooms with player counts', async () => {
    expect((await fetch(`${server.url}/healthz`)).status).toBe(200)
    expect((await fetch(`${server.url}/readyz`)).status).toBe(200)
    const bot = await BotClient.connect({ url: server.url, room: 'listed', name: 'x' })
    const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{
      name: string
      players: number
      scene: string
    }>
    expect(rooms.find((r) => r.name === 'listed')?.players).toBe(1)
    // A room just opened on a worker is listed with its scene at once (not after the next stats).
    expect(rooms.find((r) => r.name === 'listed')?.scene).toBe('empty')
    expect(rooms.find((r) => r.name === 'lobby')?.players).toBe(0)
    // Rooms on workers report their metrics once a second: wait for the first report.
    let metrics = ''
    await until(async () => {
      metrics = await (await fetch(`${server.url}/metrics`)).text()
      // A series whose first report has no tick counted yet has no mean: wait for one with ticks.
      return (
        metrics.includes('concord_room_tick_seconds_bucket') && (meanTickMs(metrics, null)?.meanMs ?? 0) > 0
      )
    }, 'the room metrics')
    // Rooms tick only on the workers: every room tick series names its worker, and the page's HUD
    // (client/net/server-stats.ts) reads a mean tick time from the text (not an empty series of this thread).
    const roomTick = metrics.split('\n').filter((l) => l.startsWith('concord_room_tick_seconds'))
    expect(roomTick.length).toBeGreaterThan(0)
    for (const line of roomTick) expect(line).toMatch(/\{(.*,)?worker="\d+"/)
    expect(meanTickMs(metrics, null)?.meanMs).toBeGreaterThan(0)
    for (const name of [
      'concord_rooms 2',
      'concord_clients 1',
      'concord_room_tick_seconds_bucket',
      'concord_bytes_sent_total',
    ]) {
      expect(metrics).toContain(name)
    }
    await bot.close()
  })

  it('static files come only from the static directory', async () => {
    const index = await fetch(`${server.url}/`)
    expect(index.status).toBe(200)
    expect(index.headers.get('content-type')).toContain('text/html')
    expect(await index.text()).toContain('fixture')
    expect((await fetch(`${server.url}/missing.js`)).status).toBe(404)
    expect((await fetch(`${server.url}/%2e%2e/%2e%2e/package.json`)).status).toBe(404)
    expect((await fetch(`${server.url}/healthz`, { method: 'POST' })).status).toBe(405)
  })

  it('upgrades only on /ws with a valid room name', async () => {
    const bad = new BotClient({ url: server.url, room: 'no spaces allowed', name: 'x' })
    await expect(bad.opened).rejects.toThrow()
  })

  it('an empty room is disposed after the idle time; the default room stays', async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'brief', name: 'x' })
    const watcher = await BotClient.connect({ url: server.url, room: 'lobby', name: 'w' })
    await bot.close()
    await until(() => !server.host.has('brief'), 'disposal')
    expect(server.host.has('lobby')).toBe(true)
    const listed = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string }>
    expect(listed.map((r) => r.name)).not.toContain('brief')
    expect(listed.map((r) => r.name)).toContain('lobby')
    await watcher.close()
  })
})
