/*
 * A log rotation writes the new log's preamble and header at once, not at the next timed flush:
 * with the flush timer frozen (fake setInterval), the new file must still get its header, so a
 * crash right after a rotation leaves a log that crash recovery can start from.
 */

import pino from 'pino'
import { Counter } from 'prom-client'
import { afterEach, describe, expect, it, vi } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import type { LogFile } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { waitUntil } from '../../support/raw-client.ts'

afterEach(() => {
  vi.useRealTimers()
})

describe('log rotation', () => {
  it("writes the new log's header at once, without waiting for the flush timer", async () => {
    vi.useFakeTimers({ toFake: ['setInterval', 'clearInterval'] })
    const files = new Map<string, Uint8Array[]>()
    const sim = new RoomSimulation({
      game: sandbox,
      name: 'rot',
      scene: 'pyramid',
      maxBodies: 500,
      controls: true,
    })
    const recorder = new RoomRecorder('rot', sim, {
      dir: '/nonexistent',
      fsync: 'none',
      keyframeTicks: 600,
      maxBytes: 4096,
      keep: 10,
      compress: true,
      log: pino({ level: 'silent' }),
      failures: new Counter({ name: 'test_rotation_failures', help: 'test', registers: [] }),
      openNames: new Set(),
      openLog: async (path): Promise<LogFile> => {
        const chunks: Uint8Array[] = []
        files.set(path, chunks)
        return { write: async (b) => chunks.push(b.slice()), sync: async () => {}, close: async () => {} }
      },
    })
    recorder.start(0)
    await recorder.flush()
    // Ticks until the log passes 4 KiB (the first keyframe does) and rotates.
    for (let i = 0; files.size < 2; i++) {
      sim.runTick()
      if (i > 5_000) throw new Error('no rotation')
    }
    const second = [...files.values()][1]
    await waitUntil(() => second.length > 0, 'the new log gets its header')
    const reader = new ReplayLogReader()
    const records = reader.push(Buffer.concat(second))
    expect(records[0]?.type).toBe('header')
    expect(records[0]?.tick).toBe(sim.tick)
    await recorder.close('test over')
  })
})
