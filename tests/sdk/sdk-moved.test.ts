/*
 * The SDK follows `moved` (docs/sdk.md, Rooms on another server), in Node with the `ws` package
 * against real in-process servers. A WebSocket relay in front of server A passes frames both ways
 * and can, like a server handing its room over (server/net/transport.ts moveRoom), send its
 * clients `moved` with another URL and close them with 4006; in its answering mode it answers
 * every join with `moved` itself, as a server that does not hold the room does.
 *
 * - A joined session, without `reconnect`, moved to server B: `reconnecting` {attempt 1, delayMs 0,
 *   code 4006}, `reconnected`, and it is then a player of B's room and sees a box spawned there.
 * - Moved to an address where nothing listens: a session without `reconnect` emits the documented
 *   error and closes; one with `reconnect` goes on trying the new address (every attempt's socket
 *   goes there, none to the relay) until its retries run out.
 * - A first join answered with `moved` resolves at B's welcome; a relay that keeps answering with
 *   `moved` to itself is refused after MAX_MOVES moves with the documented message.
 * The two-server case with a real Redis directory is in tests/server/hosting/room-directory.test.ts.
 */
import { createServer } from 'node:net'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket, { WebSocketServer } from 'ws'
import { type ConnectOptions, connect, MAX_MOVES, type Session } from '../../sdk/index.ts'
import type { RunningServer } from '../../server/server.ts'
import { decodeClientMessage, encodeMessage } from '../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../support/test-server.ts'
import { until } from '../support/wait.ts'
import { recordingSession } from './recording-session.ts'

/** A WebSocket relay to `target` (ws://host:port) that can hand its clients over with `moved`. */
class Relay {
  readonly url: string
  /** When set, every join is answered with `moved` to this URL (and close 4006), not relayed. */
  answerMoved: string | null = null
  /** Connections the relay accepted (relayed or answered). */
  accepted = 0
  private readonly pairs: Array<{ client: WebSocket; room: string }> = []

  private constructor(
    private readonly server: WebSocketServer,
    target: string,
  ) {
    const address = server.address()
    if (address === null || typeof address === 'string') throw new Error('no relay port')
    this.url = `ws://127.0.0.1:${address.port}`
    server.on('connection', (client, request) => {
      this.accepted++
      const room = new URL(request.url ?? '/', 'ws://x').searchParams.get('room') ?? ''
      client.on('error', () => {})
      if (this.answerMoved !== null) {
        const to = this.answerMoved
        client.on('message', (data: Buffer) => {
          const join = decodeClientMessage(new Uint8Array(data))
          if (!join.ok || join.value.t !== 'join') return
          client.send(encodeMessage({ t: 'moved', room, url: to }))
          client.close(4006, `room ${room} moved to another server`)
        })
        return
      }
      const upstream = new WebSocket(`${target}${request.url}`)
      upstream.on('error', () => client.terminate())
      const early: Buffer[] = []
      client.on('message', (data: Buffer) => {
        if (upstream.readyState === WebSocket.OPEN) upstream.send(data)
        else early.push(data)
      })
      upstream.on('open', () => {
        for (const data of early.splice(0)) upstream.send(data)
      })
      upstream.on('message', (data: Buffer) => client.send(data))
      upstream.on('close', () => client.close())
      client.on('close', () => upstream.close())
      this.pairs.push({ client, room })
    })
  }

  static async start(target: string): Promise<Relay> {
    const server = new WebSocketServer({ host: '127.0.0.1', port: 0 })
    await new Promise<void>((resolve) => server.once('listening', () => resolve()))
    return new Relay(server, target)
  }

  /** Hand every relayed client over: `moved` to `url`, then close 4006 (PROTOCOL.md, `moved`). */
  move(url: string): void {
    for (const { client, room } of this.pairs.splice(0)) {
      client.send(encodeMessage({ t: 'moved', room, url }))
      client.close(4006, `room ${room} moved to another server`)
    }
  }

  close(): Promise<void> {
    for (const c of this.server.clients) c.terminate()
    return new Promise((resolve) => this.server.close(() => resolve()))
  }
}

/** A ws:// address where nothing listens (a port taken and released). */
async function deadUrl(): Promise<string> {
  const probe = createServer()
  await new Promise<void>((resolve) => probe.listen(0, '127.0.0.1', resolve))
  const address = probe.address()
  if (address === null || typeof address === 'string') throw new Error('no port')
  await new Promise<void>((resolve) => probe.close(() => resolve()))
  return `ws://127.0.0.1:${address.port}`
}

let a: RunningServer
let b: RunningServer
const wsOf = (s: RunningServer): string => `ws://127.0.0.1:${s.port}`
const sessions: Session[] = []

beforeAll(async () => {
  a = await startTestServer(inProcessRooms)
  b = await startTestServer(inProcessRooms)
})
afterAll(async () => {
  await Promise.all(sessions.map((s) => s.close()))
  await a?.close()
  await b?.close()
})

/** A session through `url` that records its events (recording-session.ts). */
async function enter(url: string, room: string, extra: Partial<ConnectOptions> = {}) {
  const recorded = await recordingSession(connect, url, room, { name: 'm', ...extra })
  sessions.push(recorded.session)
  return recorded
}

const playersOf = (s: RunningServer, room: string): number[] => [
  ...(s.rooms.get(room)?.sim.players.keys() ?? []),
]

describe('the SDK follows moved', { timeout: 60_000 }, () => {
  it('a joined session without reconnect is handed to another server and plays on there', async () => {
    const relay = await Relay.start(wsOf(a))
    try {
      const m = await enter(relay.url, 'hand')
      expect(playersOf(a, 'hand')).toEqual([m.session.id])
      relay.move(wsOf(b))
      await until(() => m.of('reconnected').length === 1, 'the session joined at B')
      expect(m.of('reconnecting')).toEqual([
        { attempt: 1, delayMs: 0, code: 4006, reason: 'room hand moved to another server' },
      ])
      expect(m.of('reconnected')[0]).toEqual({ id: m.session.id, attempts: 1 })
      expect(m.of('close')).toEqual([])
      expect(m.session.open).toBe(true)
      expect(playersOf(b, 'hand')).toEqual([m.session.id])
      // B's room is the one it now sees: a box spawned there arrives.
      const before = m.session.bodies().length
      m.session.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 3 })
      await until(() => m.session.bodies().length === before + 1, 'the box spawned at B')
      await m.session.close()
    } finally {
      await relay.close()
    }
  })

  it('moved to an address where nothing listens: closes without reconnect, retries there with it', async () => {
    const relay = await Relay.start(wsOf(a))
    const dead = await deadUrl()
    try {
      const once = await enter(relay.url, 'nowhere')
      const retrying = await enter(relay.url, 'nowhere', { reconnect: { retries: 2, delayMs: 20 } })
      const accepted = relay.accepted
      relay.move(dead)
      await until(() => once.of('close').length === 1, 'the session without reconnect to close')
      expect(once.of('reconnecting')).toMatchObject([{ attempt: 1, delayMs: 0, code: 4006 }])
      expect(once.of('error').map((e) => e.reason)).toEqual([
        `could not join the room at ${dead}/ws?room=nowhere after it moved (close 1006)`,
      ])
      expect(once.session.open).toBe(false)

      await until(() => retrying.of('close').length === 1, 'the reconnecting session to give up')
      // The move's own attempt, then the retries as after a drop (20 ms, then 40 ms), all at the
      // dead address.
      expect(retrying.of('reconnecting')).toMatchObject([
        { attempt: 1, delayMs: 0, code: 4006 },
        { attempt: 1, delayMs: 20, code: 1006 },
        { attempt: 2, delayMs: 40, code: 1006 },
      ])
      expect(retrying.of('error').map((e) => e.reason)).toEqual([
        'gave up reconnecting after 2 attempts (last: close 1006)',
      ])
      expect(relay.accepted).toBe(accepted)
    } finally {
      await relay.close()
    }
  })

  it('a first join answered with moved resolves at the other server; endless moves are refused', async () => {
    const relay = await Relay.start(wsOf(a))
    try {
      relay.answerMoved = wsOf(b)
      const m = await enter(relay.url, 'first')
      expect(m.of('reconnecting')).toEqual([])
      expect(playersOf(b, 'first')).toEqual([m.session.id])
      expect(playersOf(a, 'first')).toEqual([])
      await m.session.close()

      relay.answerMoved = relay.url
      const accepted = relay.accepted
      await expect(enter(relay.url, 'loop')).rejects.toThrow(
        `connect: room loop moved ${MAX_MOVES + 1} times in a row (last to ${relay.url}/ws?room=loop); the servers' room directory disagrees`,
      )
      expect(relay.accepted - accepted).toBe(MAX_MOVES + 1)
    } finally {
      await relay.close()
    }
  })
})
