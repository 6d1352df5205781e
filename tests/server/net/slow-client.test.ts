import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { hardBufferLimit } from '../../../server/config/config.ts'
import type { ClientSession } from '../../../server/net/client-session.ts'
import type { RunningServer } from '../../../server/server.ts'
import { socketOf } from '../../support/slow-socket.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reaches a client's server-side socket through its room.
  server = await startTestServer({
    ...inProcessRooms,
    defaultScene: 'pile',
    snapshotRate: 60,
    clientBandwidth: 10_000_000,
    sendBufferBytes: 32 * 1024,
    slowClientSeconds: 1,
    heartbeatMs: 60_000,
    inputsPerTick: 100,
  })
})
afterAll(async () => {
  await server.close()
})

describe('a client that stops reading', { timeout: 20_000 }, () => {
  it('has its snapshots skipped, is closed, and never holds more than the hard buffer limit', async () => {
    const healthy = await BotClient.connect({ url: server.url, room: 'busy', name: 'reader' })
    const stalled = await BotClient.connect({ url: server.url, room: 'busy', name: 'stalled' })
    const room = server.rooms.get('busy')!
    const session = room.players.get(stalled.mirror.clientId)!
    const ws = (session.conn as ClientSession).ws
    // The client stops reading. Loopback TCP would first absorb megabytes in kernel buffers, so
    // the server end is corked too: from the server's view, exactly a peer that stopped reading.
    socketOf(stalled.ws).pause()
    socketOf(ws).cork()
    let maxBuffered = 0
    let snapshotsMeanwhile = 0
    healthy.onServerMessage = (m) => {
      if (m.t === 'snap') snapshotsMeanwhile++
      // Scene resets send every client the full state: traffic the stalled client cannot absorb.
      if (m.t === 'snap' && snapshotsMeanwhile % 4 === 0) healthy.command({ k: 'reset' })
      maxBuffered = Math.max(maxBuffered, ws.bufferedAmount)
    }
    await healthy.waitFor(() => !room.players.has(session.id), 'the stalled client to be closed')
    const skipped = await server.metrics.registry.getSingleMetricAsString('concord_snapshots_skipped_total')
    expect(Number(skipped.trim().split(' ').pop())).toBeGreaterThan(0)
    expect(maxBuffered).toBeGreaterThan(server.config.sendBufferBytes)
    // Memory stays bounded: unsent data never passes the hard limit, max(8 x send buffer budget, 1 MiB).
    expect(maxBuffered).toBeLessThanOrEqual(hardBufferLimit(server.config))
    // The healthy client in the same room kept receiving snapshots throughout.
    expect(snapshotsMeanwhile).toBeGreaterThan(10)
    await healthy.close()
  })

  it('a peer that answers no heartbeat is closed, and its player leaves the room', async () => {
    // 1 s, not less: on a loaded machine a live client in this process can miss a 100 ms pong.
    const quick = await startTestServer({ heartbeatMs: 1000 })
    try {
      const watcher = await BotClient.connect({ url: quick.url, room: 'beat', name: 'watcher' })
      const dead = await BotClient.connect({ url: quick.url, room: 'beat', name: 'dead' })
      socketOf(dead.ws).pause()
      await watcher.waitFor(() => !watcher.mirror.players.has(dead.mirror.clientId), 'the dead peer to leave')
      expect(watcher.mirror.players.has(watcher.mirror.clientId)).toBe(true)
      await watcher.close()
    } finally {
      await quick.close()
    }
  })
})
