/*
 * A log rotation writes the new log's preamble and header at once, not at the next timed flush:
 * with the flush timer frozen (fake setInterval), the new file must still get its header, so a
 * crash right after a rotation leaves a log that crash recovery can start from. The old log's
 * close record is written only after that header (a crash in between leaves the old log
 * unclosed, so recoverable, never a closed log beside an empty one), and a world whose header
 * alone passes the size limit does not rotate at every tick.
 */

import pino from 'pino'
import { Counter } from 'prom-client'
import { afterEach, describe, expect, it, vi } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import type { LogFile } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { until } from '../../support/wait.ts'

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
    await until(() => second.length > 0, 'the new log gets its header')
    const reader = new ReplayLogReader()
    const records = reader.push(Buffer.concat(second))
    expect(records[0]?.type).toBe('header')
    expect(records[0]?.tick).toBe(sim.tick)
    await recorder.close('test over')
  })
})

/** A recorder of a pyramid room writing into memory; `writes` lists every write in order. */
function memoryRecorder(maxBytes: number, keyframeTicks: number) {
  const files = new Map<string, Uint8Array[]>()
  const writes: Array<{ path: string; bytes: Uint8Array }> = []
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'rot',
    scene: 'pyramid',
    maxBodies: 500,
    controls: true,
  })
  const recorder = new RoomRecorder('rot', sim, {
    dir: '/nonexistent',
    fsync: 'interval',
    keyframeTicks,
    maxBytes,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: 'test_rotation_failures', help: 'test', registers: [] }),
    openNames: new Set(),
    openLog: async (path): Promise<LogFile> => {
      const chunks: Uint8Array[] = []
      files.set(path, chunks)
      return {
        write: async (b) => {
          chunks.push(b.slice())
          writes.push({ path, bytes: b.slice() })
          return { bytesWritten: b.length }
        },
        sync: async () => {},
        close: async () => {},
      }
    },
  })
  return { files, writes, sim, recorder }
}

describe('rotation order and rate', () => {
  it("writes the new log's header before the old log's close record", async () => {
    const { files, writes, sim, recorder } = memoryRecorder(4096, 600)
    recorder.start(0)
    for (let i = 0; files.size < 2; i++) {
      sim.runTick()
      if (i > 20_000) throw new Error('no rotation')
    }
    await recorder.flush()
    const [oldPath, newPath] = [...files.keys()]
    const firstNew = writes.findIndex((w) => w.path === newPath)
    const before = Buffer.concat(
      writes
        .slice(0, firstNew)
        .filter((w) => w.path === oldPath)
        .map((w) => w.bytes),
    )
    const after = Buffer.concat(files.get(oldPath)!)
    const reader = (bytes: Uint8Array) => {
      const r = new ReplayLogReader()
      r.push(bytes)
      return r.finish()
    }
    // Until the new header is written the old log is unclosed (a crash there recovers it) ...
    expect(reader(before).closed).toBe(false)
    expect(new ReplayLogReader().push(Buffer.concat(files.get(newPath)!))[0]?.type).toBe('header')
    // ... and afterwards it is closed cleanly.
    expect(reader(after)).toMatchObject({ closed: true })
    await recorder.close('test over')
  })

  it('a header bigger than --replay-max-bytes does not rotate at every tick: at most once per keyframe', async () => {
    const { files, sim, recorder } = memoryRecorder(4096, 60)
    recorder.start(0)
    // Wake the pyramid: its header (its saved world) is over 4 KiB deflated.
    for (const id of sim.world.bodyIds())
      sim.world.applyLinearImpulse(id, { x: 0.5, y: 3 }, sim.world.getPosition(id))
    for (let i = 0; i < 600; i++) sim.runTick()
    await recorder.close('test over')
    let keyframes = 0
    let headers = 0
    for (const chunks of files.values())
      for (const r of new ReplayLogReader().push(Buffer.concat(chunks))) {
        if (r.type === 'keyframe') keyframes++
        if (r.type === 'header') headers++
      }
    expect(headers).toBe(files.size)
    expect(keyframes).toBeGreaterThan(0)
    expect(files.size, `logs for ${keyframes} keyframes`).toBeLessThanOrEqual(1 + keyframes)
  })
})
