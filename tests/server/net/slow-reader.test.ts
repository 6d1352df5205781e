/*
 * The slow-reader rule (issue 11, item 7) against a real server on 127.0.0.1, with a real slow
 * reader: an ordinary protocol client (it acks every snapshot it reads and would answer pings)
 * whose socket reads one chunk at a time with pauses between, so the kernel's buffers fill while
 * the client keeps reading. Nothing on the server side is corked: the server must notice from
 * the client's acks that it is behind, skip its snapshots, and close it after
 * --slow-client-seconds over the send-buffer budget, while a normal reader in the same room is
 * left alone. The heartbeat is set long so that only the slow-reader rule can close anybody.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { readSlowly } from '../../support/slow-socket.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

const capture = capturingLogger('info')
let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reads the room's players and the slow-reader log line
  // (the same rule across the thread boundary: workers.test.ts).
  server = await startTestServer(
    {
      ...inProcessRooms,
      // Only the room under test runs a scene that moves: the default room stays empty.
      defaultScene: 'empty',
      snapshotRate: 60,
      clientBandwidth: 10_000_000,
      sendBufferBytes: 64 * 1024,
      slowClientSeconds: 1,
      heartbeatMs: 600_000,
      inputsPerTick: 100,
    },
    capture.logger,
  )
})
afterAll(async () => {
  await server.close()
})

async function counter(name: string): Promise<number> {
  const text = await server.metrics.registry.getSingleMetricAsString(name)
  return Number(text.trim().split('\n').pop()!.split(' ').pop())
}

describe('a client that reads, but slowly', { timeout: 90_000 }, () => {
  it('has its snapshots skipped and is closed by the slow-reader rule; a normal reader stays', async () => {
    const normal = await BotClient.connect({ url: server.url, room: 'slow', name: 'normal' })
    normal.command({ k: 'scene', name: 'pyramid' })
    await normal.waitFor(() => normal.mirror.bodies.size > 200, 'the pyramid')
    const slow = await BotClient.connect({ url: server.url, room: 'slow', name: 'slow' })
    const skippedBefore = await counter('concord_snapshots_skipped_total')
    const closedBefore = await counter('concord_slow_clients_closed_total')
    // Traffic: the normal reader resets the pyramid every few snapshots, so full states go out to
    // everyone.
    let snapshots = 0
    normal.onServerMessage = (m) => {
      if (m.t === 'snap' && ++snapshots % 6 === 0) normal.command({ k: 'reset' })
    }
    // The slow reader: one chunk (at most 64 KiB) at once, then one every 1.5 s, paused between.
    const reader = readSlowly(slow.ws, 1500)
    // Wait on the server's side: the slow client's own socket sees the close only once it has
    // read through its backlog.
    const room = server.rooms.get('slow')!
    try {
      await until(() => !room.players.has(slow.mirror.clientId), 'the slow reader to be closed', 60_000)
    } finally {
      reader.stop()
      slow.ws.terminate()
    }
    // It kept reading while it was behind (it was not a dead peer) ...
    expect(reader.chunks()).toBeGreaterThan(0)
    // ... its snapshots were skipped first, then the slow-reader rule closed it: nothing else can
    // close a peer here (the heartbeat is 10 minutes away, nobody misbehaved).
    expect((await counter('concord_snapshots_skipped_total')) - skippedBefore).toBeGreaterThan(0)
    expect((await counter('concord_slow_clients_closed_total')) - closedBefore).toBe(1)
    const closing = capture.lines.find((l) => l.msg === 'closing a client that stopped reading')
    expect(closing).toBeDefined()
    // It was over the budget for more than --slow-client-seconds before the close.
    expect(closing!.rule).toBe('slow-client-seconds')
    expect(closing!.buffered as number).toBeGreaterThan(server.config.sendBufferBytes)
    // The normal reader in the same room was never closed and still gets snapshots.
    const tick = normal.mirror.tick
    await normal.waitFor(() => normal.mirror.tick >= tick + 10, 'more snapshots for the normal reader')
    expect(room.players.size).toBe(1)
    await normal.close()
  })
})
