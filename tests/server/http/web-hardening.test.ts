/*
 * Web hardening (issue 30, point 11), against real servers on 127.0.0.1: the security headers on
 * every answer (pages, assets, JSON, probes, refusals), the room list behind the join key, /metrics
 * behind its own bearer token, `welcome.rules.controls` as each connection's key makes it, and
 * error reasons in the protocol's words, not a library's (the directory's 1013 quoted ioredis, a
 * malformed frame quoted msgpackr). The browser side of the Content-Security-Policy is checked in
 * tests/browser/security-headers.test.ts.
 */
import { encode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../../server/server.ts'
import { PROTOCOL_VERSION } from '../../../shared/index.ts'
import { rawRequest } from '../../support/raw-client.ts'
import { startRedis } from '../../support/redis-server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { DocClient } from '../protocol/doc-client.ts'

const JOIN = 'join-secret-5e1b'
const ADMIN = 'admin-secret-77d0'
const METRICS = 'metrics-secret-c3a9'

let keyed: RunningServer

beforeAll(async () => {
  keyed = await startTestServer({
    joinToken: JOIN,
    adminToken: ADMIN,
    metricsToken: METRICS,
    publicRooms: 'lobby',
    replayDir: 'tests/server/fixtures', // holds no log: the listing is empty, but answered
  })
})
afterAll(async () => {
  await keyed.close()
})

/** The headers every answer must carry, as the issue asks for them. */
function expectSecurityHeaders(headers: Headers, what: string): void {
  const csp = headers.get('content-security-policy') ?? ''
  expect(csp, what).toContain("frame-ancestors 'none'")
  expect(csp, what).toContain("script-src 'self'")
  expect(csp, what).toContain("default-src 'self'")
  expect(csp, what).not.toContain("'unsafe-eval'")
  expect(headers.get('x-content-type-options'), what).toBe('nosniff')
  expect(headers.get('referrer-policy'), what).toBe('no-referrer')
  expect(headers.get('x-frame-options'), what).toBe('DENY')
}

describe('security headers', { timeout: 20_000 }, () => {
  it('are on every page, asset, route and refusal', async () => {
    const paths: Array<[string, number]> = [
      ['/', 200],
      ['/index.html', 200],
      ['/no-such-asset.js', 404],
      ['/healthz', 200],
      ['/readyz', 200],
      ['/rooms', 401],
      [`/rooms?key=${JOIN}`, 200],
      ['/replays', 401],
      [`/replays?key=${ADMIN}`, 200],
      ['/metrics', 401],
    ]
    for (const [path, status] of paths) {
      const res = await fetch(`${keyed.url}${path}`)
      expect(res.status, path).toBe(status)
      expectSecurityHeaders(res.headers, path)
    }
    // A HEAD of a page, and a request target that does not parse (answered before any route).
    expectSecurityHeaders((await fetch(`${keyed.url}/`, { method: 'HEAD' })).headers, 'HEAD /')
    const bad = await rawRequest(keyed.port, 'GET //% HTTP/1.1\r\nHost: x\r\n\r\n')
    expect(bad.status).toBe(400)
    expect(bad.answer.toLowerCase()).toContain('x-content-type-options: nosniff')
  })
})

describe('the room list and /metrics', { timeout: 20_000 }, () => {
  it('lists rooms only for the join or admin key when the server has a join token', async () => {
    const get = (q: string): Promise<Response> => fetch(`${keyed.url}/rooms${q}`)
    const none = await get('')
    expect(none.status).toBe(401)
    expect(await none.text()).toContain('key=')
    expect((await get('?key=wrong-key-000')).status).toBe(403)
    for (const key of [JOIN, ADMIN]) {
      const res = await get(`?key=${key}`)
      expect(res.status).toBe(200)
      expect(Array.isArray(await res.json())).toBe(true)
    }
  })

  it('serves /metrics only for Authorization: Bearer METRICS_TOKEN when one is set, and to anyone when not', async () => {
    const get = (headers: Record<string, string>): Promise<Response> =>
      fetch(`${keyed.url}/metrics`, { headers })
    const none = await get({})
    expect(none.status).toBe(401)
    expect(none.headers.get('www-authenticate')).toContain('Bearer')
    expect((await get({ authorization: 'Basic Zm9vOmJhcg==' })).status).toBe(401)
    expect((await get({ authorization: `Bearer ${METRICS}x` })).status).toBe(403)
    // The join and admin keys are not the metrics token.
    expect((await get({ authorization: `Bearer ${ADMIN}` })).status).toBe(403)
    const ok = await get({ authorization: `Bearer ${METRICS}` })
    expect(ok.status).toBe(200)
    expect(await ok.text()).toContain('concord_')
    const open = await startTestServer({})
    try {
      expect((await fetch(`${open.url}/metrics`)).status).toBe(200)
      expect((await fetch(`${open.url}/rooms`)).status).toBe(200)
    } finally {
      await open.close()
    }
  })
})

describe('welcome.rules.controls', { timeout: 20_000 }, () => {
  /** Join `room` with `key` (or none) and return the welcome's rules.controls. */
  async function controlsOf(server: RunningServer, room: string, key?: string): Promise<unknown> {
    const c = await DocClient.open(server.url, `${room}${key ? `&key=${key}` : ''}`)
    c.send({ t: 'join', v: PROTOCOL_VERSION, room: '', name: 'x', mode: 'snapshot' })
    const welcome = await c.waitFor((m) => m.t === 'welcome', 'welcome')
    c.end()
    return (welcome.rules as { controls: unknown }).controls
  }

  it('is false for a player whose key does not allow room controls, and its controls are refused', async () => {
    expect(await controlsOf(keyed, 'lobby')).toBe(false)
    expect(await controlsOf(keyed, 'club', JOIN)).toBe(false)
    expect(await controlsOf(keyed, 'club', ADMIN)).toBe(true)
    // What the flag promises: the member's pause is refused, the admin's applied.
    const member = await DocClient.open(keyed.url, `club&key=${JOIN}`)
    member.send({ t: 'join', v: PROTOCOL_VERSION, room: '', name: 'm', mode: 'snapshot' })
    await member.waitFor((m) => m.t === 'welcome', 'welcome')
    member.send({ t: 'input', seq: 9, cmd: { k: 'pause', paused: true } })
    const refused = await member.waitFor((m) => m.t === 'error', 'the refusal')
    expect([refused.code, refused.seq]).toEqual(['refused', 9])
    member.end()
    const open = await startTestServer({})
    const off = await startTestServer({ roomControls: false, adminToken: ADMIN })
    try {
      expect(await controlsOf(open, 'any')).toBe(true)
      expect(await controlsOf(off, 'any', ADMIN)).toBe(false)
    } finally {
      await open.close()
      await off.close()
    }
  })
})

describe('error reasons', { timeout: 30_000 }, () => {
  it('never quote a library: a malformed frame and an unavailable directory are told in the protocol words', async () => {
    const c = await DocClient.joined(keyed.url, 'lobby', 'reasons')
    const ping = encode({ t: 'ping', id: 1, time: 0 })
    c.sendBytes(ping.subarray(0, ping.length - 2)) // truncated
    c.sendBytes(new Uint8Array([...ping, 0x01])) // a byte left over
    await c.waitFor(() => c.all('error').length === 2, 'two errors')
    const reasons = c.all('error').map((e) => String(e.reason))
    expect(reasons).toEqual([
      'not MessagePack: truncated: the frame ends inside a value',
      'not MessagePack: bytes left over after the first value',
    ])
    c.end()

    const redis = await startRedis()
    const server = await startTestServer({ redisUrl: redis.url, directoryTtlSeconds: 2 })
    try {
      await redis.stop()
      const d = await DocClient.open(server.url, 'fresh-room')
      d.send({ t: 'join', v: PROTOCOL_VERSION, room: '', name: 'd', mode: 'snapshot' })
      const error = await d.waitFor((m) => m.t === 'error', 'the refusal')
      const close = await d.closed()
      expect(error.code).toBe('unavailable')
      expect(close.code).toBe(1013)
      for (const text of [String(error.reason), close.reason]) {
        expect(text).not.toMatch(/ioredis|ECONNREFUSED|127\.0\.0\.1|Connection is closed|stream|writeable/i)
      }
      expect(String(error.reason)).toContain('try again')
    } finally {
      await server.close()
    }
  })
})
