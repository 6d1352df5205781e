/*
 * Who may connect (issue 11, "Also"): the origin allowlist and the join and admin tokens, decided
 * at the WebSocket upgrade of a real server on 127.0.0.1. Refusals are read as raw HTTP status
 * lines; admitted clients are ordinary protocol clients. The replay logs (GET /replays and
 * /replays/NAME) are asked for with and without keys.
 */
import { mkdtemp, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { encode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { loadConfig } from '../../../server/config/config.ts'
import type { RunningServer } from '../../../server/server.ts'
import { PROTOCOL_VERSION, type ServerMessage } from '../../../shared/index.ts'
import { clientFrame, closeOf, rawRequest, rawWebSocket, upgradeRequest } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const JOIN = 'join-secret-7f3a'
const ADMIN = 'admin-secret-91c2'

/** A file in the replay directory with a log's name (its bytes stand for a private room's commands). */
const LOG = 'private-20260101T000000000Z.cclog'
const LOG_BYTES = 'every command of the private room'

let server: RunningServer
let replayDir: string

beforeAll(async () => {
  replayDir = await mkdtemp(join(tmpdir(), 'concord-access-'))
  await writeFile(join(replayDir, LOG), LOG_BYTES)
  server = await startTestServer({
    replayDir,
    joinToken: JOIN,
    adminToken: ADMIN,
    publicRooms: 'lobby,open',
    allowedOrigins: 'https://play.example,http://localhost:5173',
  })
})
afterAll(async () => {
  await server.close()
})

const status = async (target: string, extra: string[] = []): Promise<number> =>
  (await rawRequest(server.port, upgradeRequest(target, extra))).status

describe('the origin allowlist', { timeout: 20_000 }, () => {
  it('admits listed origins and clients without an Origin header, refuses other origins with 403', async () => {
    expect(await status('/ws?room=open', ['Origin: https://evil.example'])).toBe(403)
    expect(await status('/ws?room=open', ['Origin: https://play.example.evil'])).toBe(403)
    expect(await status('/ws?room=open', ['Origin: null'])).toBe(403)
    expect(await status('/ws?room=open', ['Origin: https://play.example'])).toBe(101)
    expect(await status('/ws?room=open', ['Origin: http://localhost:5173'])).toBe(101)
    expect(await status('/ws?room=open')).toBe(101)
    const refused = await server.metrics.registry.getSingleMetricAsString('concord_connections_refused_total')
    expect(refused).toContain('reason="origin"')
  })
})

describe('join and admin tokens', { timeout: 20_000 }, () => {
  it('a token-only room refuses a missing key with 401 and a forged one with 403, at the upgrade', async () => {
    expect(await status('/ws?room=private')).toBe(401)
    expect(await status(`/ws?room=private&key=${JOIN}x`)).toBe(403)
    expect(await status(`/ws?room=private&key=${JOIN.slice(0, -1)}`)).toBe(403)
    expect(await status('/ws?room=private&key=')).toBe(401)
    // A forged key is refused even for a public room: it is never silently ignored.
    expect(await status('/ws?room=open&key=guess-guess-guess')).toBe(403)
    expect(await status(`/ws?room=private&key=${JOIN}`)).toBe(101)
    expect(await status(`/ws?room=private&key=${ADMIN}`)).toBe(101)
    expect(server.host.has('private')).toBe(false)
  })

  it('a plain GET of the upgrade URL answers what the upgrade would, with the reason a page can show', async () => {
    // A browser hides a refused upgrade's status; the page asks here (client/net/connection.ts).
    const get = async (target: string, headers: Record<string, string> = {}) => {
      const answer = await fetch(`http://127.0.0.1:${server.port}${target}`, { headers })
      return { status: answer.status, text: await answer.text() }
    }
    const missing = await get('/ws?room=private')
    expect(missing.status).toBe(401)
    expect(missing.text).toContain('room "private" is open only with')
    const wrong = await get(`/ws?room=private&key=${JOIN}x`)
    expect(wrong.status).toBe(403)
    expect(wrong.text).toContain('the key matches neither the join token nor the admin token')
    const origin = await get('/ws?room=open', { Origin: 'https://evil.example' })
    expect(origin.status).toBe(403)
    expect(origin.text).toContain('https://evil.example')
    const member = await get(`/ws?room=private&key=${JOIN}`)
    expect(member.status).toBe(200)
    expect(member.text).toContain('room controls: need the admin key')
    const admin = await get(`/ws?room=private&key=${ADMIN}`)
    expect(admin.status).toBe(200)
    expect(admin.text).toContain('room controls: allowed')
    expect((await get('/ws?room=open')).status).toBe(200)
    expect(server.host.has('private')).toBe(false)
  })

  it('without a key a public room admits, but a join naming another room is refused with 4005', async () => {
    const visitor = await BotClient.connect({ url: server.url, room: 'open', name: 'visitor' })
    expect(server.host.summaries().find((r) => r.name === 'open')?.players).toBe(1)
    await visitor.close()
    // The URL names no room: the default room is public, so the upgrade passes; the join then
    // names a token-only room.
    const raw = await rawWebSocket(server.port, '/ws')
    raw.socket.write(
      clientFrame(
        encode({ t: 'join', v: PROTOCOL_VERSION, room: 'private', name: 'sneak', mode: 'snapshot' }),
      ),
    )
    await until(() => raw.frames.some((f) => f.opcode === 8), 'a close frame')
    const { code, reason } = closeOf(raw.frames.find((f) => f.opcode === 8)!)
    expect(code).toBe(4005)
    expect(reason.toString()).toContain('needs a key')
    expect(server.host.has('private')).toBe(false)
  })

  it('room controls are admin-only: a joined player is refused, the admin pauses the room', async () => {
    const player = await BotClient.connect({ url: server.url, room: 'club', name: 'member', key: JOIN })
    const seq = player.command({ k: 'pause', paused: true })
    const refusal = await player.nextMessage(
      (m): m is Extract<ServerMessage, { t: 'error' }> => m.t === 'error' && m.seq === seq,
    )
    expect(refusal.code).toBe('refused')
    expect(refusal.reason).toContain('admin key')
    // Other commands still work for the player; the snapshot showing the spawn, sent after the
    // refused pause was handled, shows the room still running.
    player.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 3 })
    await player.waitFor(() => [...player.mirror.bodies.values()].some((b) => b.kind === 2), 'the spawn')
    expect(player.mirror.paused).toBe(false)
    const admin = await BotClient.connect({ url: server.url, room: 'club', name: 'admin', key: ADMIN })
    admin.command({ k: 'pause', paused: true })
    await player.waitFor(() => player.mirror.paused, 'the pause to reach the player')
    await Promise.all([player.close(), admin.close()])
  })

  it('bad token settings are refused at startup with a message naming the setting', () => {
    expect(() => loadConfig(['--join-token', 'short'], {})).toThrow(/join token/)
    expect(() => loadConfig([], { ADMIN_TOKEN: 'has space in it' })).toThrow(/admin token/)
    expect(() => loadConfig(['--join-token', JOIN, '--admin-token', JOIN], {})).toThrow(/must differ/)
    expect(() => loadConfig(['--allowed-origins', 'play.example'], {})).toThrow(/allowed origins/)
    expect(() => loadConfig(['--allowed-origins', 'https://play.example/'], {})).toThrow(/allowed origins/)
    expect(() => loadConfig(['--public-rooms', 'a,../b'], {})).toThrow(/public rooms/)
    expect(loadConfig([], { JOIN_TOKEN: JOIN, PUBLIC_ROOMS: 'lobby, hall' })).toMatchObject({
      joinToken: JOIN,
      publicRooms: 'lobby, hall',
    })
  })
})

describe('the replay logs of a server with a join token', { timeout: 20_000 }, () => {
  const get = (path: string, method = 'GET'): Promise<Response> => fetch(`${server.url}${path}`, { method })

  it('the listing and a log are refused without a key (401) and with a wrong one (403), their bytes unsent', async () => {
    for (const path of ['/replays', `/replays/${LOG}`]) {
      const none = await get(path)
      expect(none.status, path).toBe(401)
      const text = await none.text()
      expect(text).toContain('key=')
      expect(text).not.toContain(LOG_BYTES)
      expect(text).not.toContain(LOG)
      expect((await get(path, 'HEAD')).status, `HEAD ${path}`).toBe(401)
      expect((await get(`${path}?key=`)).status, path).toBe(401)
      const forged = await get(`${path}?key=${JOIN}x`)
      expect(forged.status, path).toBe(403)
      expect(await forged.text()).toContain('matches neither')
    }
  })

  it('the join key and the admin key each open the listing and the log', async () => {
    for (const key of [JOIN, ADMIN]) {
      const listing = await get(`/replays?key=${key}`)
      expect(listing.status).toBe(200)
      expect(((await listing.json()) as Array<{ name: string }>).map((l) => l.name)).toEqual([LOG])
      const log = await get(`/replays/${LOG}?key=${encodeURIComponent(key)}`)
      expect(log.status).toBe(200)
      expect(await log.text()).toBe(LOG_BYTES)
    }
  })

  it('without a join token the replays stay public; with only an admin token a wrong key is still 403', async () => {
    const open = await startTestServer({ replayDir, adminToken: ADMIN })
    try {
      expect(await (await fetch(`${open.url}/replays/${LOG}`)).text()).toBe(LOG_BYTES)
      expect((await fetch(`${open.url}/replays`)).status).toBe(200)
      expect((await fetch(`${open.url}/replays?key=${ADMIN}`)).status).toBe(200)
      expect((await fetch(`${open.url}/replays?key=${JOIN}`)).status).toBe(403)
    } finally {
      await open.close()
    }
  })
})
