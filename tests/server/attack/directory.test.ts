/*
 * Room directory claims a client can make (--redis, a real redis-server). A join for a room the
 * server does not have open claims the room in Redis first, and the server refreshes every room it
 * holds for as long as it runs. Claims that no room came of were once held for good: a socket that
 * sent joins for many rooms before its first claim was answered claimed every one of them, and a
 * socket that closed before the answer left its claim behind. Each such name stayed this server's
 * in the directory for every server of the fleet, and the set refreshed at every heartbeat grew
 * without bound (about 600 new names per second per socket, the message rate).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../../server/server.ts'
import { encodeMessage, PROTOCOL_VERSION } from '../../../shared/index.ts'
import { clientFrame, rawWebSocket } from '../../support/raw-client.ts'
import { startRedis, type TestRedis } from '../../support/redis-server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let redis: TestRedis
let server: RunningServer

beforeAll(async () => {
  redis = await startRedis()
  server = await startTestServer({ redisUrl: redis.url, workers: 1 })
})
afterAll(async () => {
  await server?.close()
  await redis?.stop()
})

const join = (room: string): Buffer =>
  clientFrame(encodeMessage({ t: 'join', v: PROTOCOL_VERSION, room, name: 'claimer', mode: 'snapshot' }))

/** The rooms this server holds in the directory, other than the default room. */
const held = (): string[] =>
  server
    .directory!.rooms()
    .filter((r) => r !== 'lobby')
    .sort()

describe('directory claims from one socket', { timeout: 20_000 }, () => {
  it('joins sent while the first claim is pending claim nothing more', async () => {
    const raw = await rawWebSocket(server.port, '/ws')
    raw.socket.write(Buffer.concat(['many-0', 'many-1', 'many-2', 'many-3'].map(join)))
    await until(() => server.host.has('many-0'), 'the first room opened')
    // The three later joins are answered (already joined) only after the first: wait for them.
    await until(() => raw.frames.length >= 4, 'an answer to every join')
    expect(held()).toEqual(['many-0'])
    raw.socket.destroy()
    await raw.closed
    await until(() => held().length === 0, 'the room released once disposed', 8000)
  })

  it('a claim answered after its socket closed is given back', async () => {
    const raw = await rawWebSocket(server.port, '/ws')
    raw.socket.end(join('gone'))
    await raw.closed
    await until(() => held().length === 0 && !server.host.has('gone'), 'the claim given back', 8000)
  })
})
