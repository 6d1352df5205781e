/*
 * Room-name churn against the room limit, with rooms on a worker thread. A client that sends
 * `join` for a new room and drops its socket at once (before the worker has answered the join)
 * once left the room counted against --max-rooms for good: the main thread lost track of the
 * unanswered join, so it ignored the worker's `disposed` and kept the room placed. A few such
 * clients filled the limit, and every later join for a new room got `full` (close 4001).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { encodeMessage, PROTOCOL_VERSION } from '../../../shared/index.ts'
import { clientFrame, rawWebSocket } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let server: RunningServer

beforeAll(async () => {
  // One worker: the rooms run on a worker thread, where joins are answered asynchronously.
  server = await startTestServer({ workers: 1, maxRooms: 3, roomIdleSeconds: 1 })
})
afterAll(async () => {
  await server.close()
})

/** The names /rooms lists. */
async function listedRooms(): Promise<string[]> {
  const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string }>
  return rooms.map((r) => r.name).sort()
}

describe('joins abandoned before the worker answers', { timeout: 20_000 }, () => {
  it('do not keep their rooms counted against --max-rooms once the rooms are disposed', async () => {
    for (const room of ['churn-1', 'churn-2']) {
      const raw = await rawWebSocket(server.port, `/ws?room=${room}`)
      const join = encodeMessage({ t: 'join', v: PROTOCOL_VERSION, room, name: 'churn', mode: 'snapshot' })
      raw.socket.end(clientFrame(join))
      await raw.closed
    }
    // Empty rooms are disposed after --room-idle-seconds (1 s); then only the default room is open.
    await until(async () => (await listedRooms()).join() === 'lobby', 'the churned rooms disposed', 8000)
    // Two new rooms fit under the limit of 3 (lobby included).
    for (const room of ['after-1', 'after-2']) {
      const bot = await BotClient.connect({ url: server.url, room, name: 'after' })
      expect(bot.mirror.clientId).toBeGreaterThan(0)
      await bot.close()
    }
  })
})
