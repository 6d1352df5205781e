/*
 * One address flooding HTTP requests (issue 11: one client must not stall the others). Before
 * --max-requests-per-ip, one keep-alive connection that pipelined `GET /metrics` 2,000 times per
 * write held the main thread for 5 s (a player's snapshots stopped, /healthz took 5 s to answer)
 * and its queued requests kept the server busy for 20 s after it left. Against a real server on
 * 127.0.0.1: the flooding connection is answered 429 and closed after at most one read of its
 * requests, its address's other HTTP connections are closed, new connections from it are refused
 * without being parsed until the penalty has passed, and meanwhile another address (127.0.0.2)
 * and the address's WebSocket player are served. The work is counted in requests the server's
 * handlers saw, not in milliseconds.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { PENALTY_SECONDS, RequestRate } from '../../../server/http/http-request-rate.ts'
import type { RunningServer } from '../../../server/server.ts'
import { rawConnect, rawRequest, readUntilClosed, upgradeRequest } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const RATE = 20
const HEALTHZ = 'GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n'

describe('RequestRate, against a hand-driven clock', () => {
  it('allows a burst of one second, refills at the rate, and refuses for the penalty once over', () => {
    let now = 0
    const rate = new RequestRate(10, () => now)
    for (let i = 0; i < 10; i++) expect(rate.take('a')).toBe(true)
    expect(rate.allows('b')).toBe(true)
    expect(rate.take('a')).toBe(false)
    // Another address has its own bucket.
    expect(rate.take('b')).toBe(true)
    // Over the rate: nothing for PENALTY_SECONDS, then one request per 1/rate s again.
    now = PENALTY_SECONDS * 1000 - 1
    expect(rate.allows('a')).toBe(false)
    now = PENALTY_SECONDS * 1000 + 1
    expect(rate.allows('a')).toBe(true)
    expect(rate.take('a')).toBe(true)
    expect(rate.take('a')).toBe(false)
  })

  it('forgets addresses whose bucket has filled again, and 0 means no limit and no penalty', () => {
    let now = 0
    const rate = new RequestRate(10, () => now)
    for (const key of ['a', 'b', 'c']) rate.take(key)
    expect(rate.size).toBe(3)
    now = 20_000
    rate.take('d')
    expect(rate.size).toBe(1)
    const open = new RequestRate(0, () => now)
    for (let i = 0; i < 1000; i++) expect(open.take('a')).toBe(true)
    // Nor does a flood penalize an address then (a server behind a proxy sets 0).
    open.penalize('a')
    expect(open.allows('a')).toBe(true)
    expect(open.size).toBe(0)
  })
})

describe('an address flooding HTTP requests', { timeout: 40_000 }, () => {
  let server: RunningServer
  /** Requests the server's handlers were given (refused ones included). */
  let requests = 0

  beforeAll(async () => {
    // A long handshake timeout: idle connections are closed by the request rate, not by it.
    server = await startTestServer({ maxRequestsPerIp: RATE, handshakeTimeoutMs: 60_000 })
    server.http.prependListener('request', () => {
      requests++
    })
  })
  afterAll(async () => {
    await server.close()
  })

  it('is cut at its rate, and the others, its own WebSocket player included, are served', async () => {
    const player = await BotClient.connect({ url: server.url, room: 'rate', name: 'player' })
    const idle = await Promise.all([rawConnect(server.port), rawConnect(server.port)])
    const idleClosed = idle.map((s) => readUntilClosed(s))
    const before = requests

    // 20,000 pipelined requests in one go (about 700 KB) on one keep-alive connection.
    const flood = await rawConnect(server.port)
    const answer = readUntilClosed(flood)
    flood.write(`GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n`.repeat(20_000))
    // The server closes it (before, it answered every request and kept the connection open).
    await answer
    // Node parsed at most about one read (64 KiB, some 1,500 of these requests), not the 20,000.
    expect(requests - before).toBeLessThan(4000)
    expect(requests - before).toBeGreaterThan(RATE)
    // The address's other plain HTTP connections were closed with it.
    await Promise.all(idleClosed)
    const refused = await server.metrics.registry.getSingleMetricAsString('concord_connections_refused_total')
    expect(refused).toContain('reason="max-requests-per-ip"')

    // A new connection from the address is refused as it opens, and nothing it sends is parsed.
    const parsed = requests
    const again = await rawConnect(server.port)
    const againAnswer = readUntilClosed(again)
    again.write(HEALTHZ.repeat(5000))
    const text = (await againAnswer).toString('latin1')
    expect(text).toMatch(/^HTTP\/1\.1 429 /)
    expect(text).toContain(`Retry-After: ${PENALTY_SECONDS}`)
    expect(requests).toBe(parsed)
    // So is a WebSocket upgrade.
    expect((await rawRequest(server.port, upgradeRequest('/ws?room=rate'))).status).toBe(429)

    // Another address is served meanwhile, and the player keeps its socket and its snapshots.
    expect((await rawRequest(server.port, HEALTHZ, '127.0.0.2')).status).toBe(200)
    const seen = player.received.length
    await player.waitFor(() => player.received.slice(seen).some((m) => m.t === 'snap'), 'a snapshot')
    expect(player.closeCode).toBe(0)

    // After the penalty the address is served again.
    await until(
      async () => (await rawRequest(server.port, HEALTHZ)).status === 200,
      'the address to be served again',
      (PENALTY_SECONDS + 10) * 1000,
    )
    await player.close()
  })

  it('a client within the rate is never refused', async () => {
    const other = '127.0.0.3'
    for (let i = 0; i < RATE; i++) {
      expect((await rawRequest(server.port, HEALTHZ, other)).status).toBe(200)
    }
  })
})
