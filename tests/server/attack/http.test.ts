/*
 * HTTP-level attacks on a real server on 127.0.0.1 (issue 11, items 2 and 6): request targets
 * that made `new URL` throw, and raw TCP connections that never complete a request. Requests are
 * written byte for byte on raw sockets.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { healthy, rawConnect, rawRequest, readUntilClosed, upgradeRequest } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer()
})
afterAll(async () => {
  await server.close()
})

describe('request targets that made URL parsing throw', { timeout: 20_000 }, () => {
  for (const target of ['//%', '//[', '//%/ws', '//[::1]:x/ws?room=a', 'http://[/ws', '*']) {
    it(`GET ${target} gets 400, with and without upgrade headers, and the server carries on`, async () => {
      const plain = await rawRequest(
        server.port,
        `GET ${target} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n`,
      )
      expect(plain.status).toBe(400)
      const upgrade = await rawRequest(server.port, upgradeRequest(target))
      expect(upgrade.status).toBe(400)
      expect(await healthy(server.url)).toBe(true)
    })
  }

  it('CONNECT gets 405 (this is not a proxy), not a silent close, and the server carries on', async () => {
    const connect = await rawRequest(
      server.port,
      'CONNECT 127.0.0.1:22 HTTP/1.1\r\nHost: 127.0.0.1:22\r\n\r\n',
    )
    expect(connect.status).toBe(405)
    expect(connect.answer).toMatch(/^Allow: GET, HEAD$/m)
    expect(await healthy(server.url)).toBe(true)
  })

  it('a request line Node cannot parse gets 400', async () => {
    const bad = await rawRequest(server.port, 'GET /\x01 HTTP/1.1\r\n\r\n')
    expect(bad.status).toBe(400)
    expect(await healthy(server.url)).toBe(true)
  })
})

describe('connections that never complete a request', { timeout: 30_000 }, () => {
  it('are closed with 408 after the handshake timeout, and count against --max-connections meanwhile', async () => {
    const tight = await startTestServer({
      maxConnections: 4,
      maxConnectionsPerIp: 0,
      handshakeTimeoutMs: 800,
    })
    try {
      const silent = await Promise.all([rawConnect(tight.port), rawConnect(tight.port)])
      const half = await Promise.all([rawConnect(tight.port), rawConnect(tight.port)])
      for (const s of half) s.write('GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ')
      const answers = [...silent, ...half].map((s) => readUntilClosed(s))
      await until(() => tight.guard.count === 4, 'four connections counted')
      // The four unfinished connections fill the cap: a fifth connection, even a WebSocket, is refused.
      const fifth = await rawRequest(tight.port, upgradeRequest('/ws?room=a'))
      expect(fifth.status).toBe(503)
      const bot = new BotClient({ url: tight.url, room: 'a', name: 'late' })
      await expect(bot.opened).rejects.toThrow(/503/)
      // Each is answered 408 and closed by the server (no client-side timeout involved).
      for (const answer of await Promise.all(answers))
        expect(answer.toString('latin1')).toMatch(/^HTTP\/1\.1 408/)
      await until(() => tight.guard.count === 0, 'the connections to be released')
      const player = await BotClient.connect({ url: tight.url, room: 'a', name: 'after' })
      await player.close()
    } finally {
      await tight.close()
    }
  })
})

describe('the per-address connection cap', { timeout: 20_000 }, () => {
  it('answers 429 beyond --max-connections-per-ip and admits again once a connection closes', async () => {
    const capped = await startTestServer({ maxConnectionsPerIp: 3 })
    try {
      const bots = await Promise.all(
        [1, 2, 3].map((i) => BotClient.connect({ url: capped.url, room: 'cap', name: `p${i}` })),
      )
      const fourth = await rawRequest(capped.port, upgradeRequest('/ws?room=cap'))
      expect(fourth.status).toBe(429)
      expect(fourth.answer).toContain('Retry-After')
      const http = await rawRequest(capped.port, 'GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n')
      expect(http.status).toBe(429)
      const refused = await capped.metrics.registry.getSingleMetricAsString(
        'concord_connections_refused_total',
      )
      expect(refused).toContain('reason="max-connections-per-ip"')
      await bots[0].close()
      await until(() => capped.guard.countOf('127.0.0.1') === 2, 'the closed connection to be released')
      const again = await BotClient.connect({ url: capped.url, room: 'cap', name: 'again' })
      await Promise.all([again.close(), bots[1].close(), bots[2].close()])
    } finally {
      await capped.close()
    }
  })
})
