/*
 * A delta keyframe is encoded after the loop tick that takes it, not inside it: the tick only
 * saves the world (its state at that tick), and the byte delta (1.2 ms for a 100-body awake pile,
 * 17 ms for 1,000 bodies) runs once the tick's event-loop turn is over, so it never lengthens the
 * tick that every room on the thread shares. The log still holds the keyframe, in its place, and
 * it decodes to the world as saved at its tick.
 */

import { inflateSync } from 'node:zlib'
import pino from 'pino'
import { Counter } from 'prom-client'
import { describe, expect, it, vi } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import type { LogFile } from '../../../server/replay/replay-files.ts'
import { decodeByteDelta } from '../../../shared/replay/byte-delta.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'

const encodes = vi.hoisted(() => ({ count: 0 }))
vi.mock('../../../shared/replay/byte-delta.ts', async (original) => {
  const real = await original<typeof import('../../../shared/replay/byte-delta.ts')>()
  return {
    ...real,
    encodeByteDelta: (base: Uint8Array, target: Uint8Array) => {
      encodes.count++
      return real.encodeByteDelta(base, target)
    },
  }
})

describe('delta keyframes', () => {
  it('are encoded after the tick that takes them, and land in the log in their place', async () => {
    const chunks: Uint8Array[] = []
    const sim = new RoomSimulation({
      game: sandbox,
      name: 'kf',
      scene: 'pyramid',
      maxBodies: 500,
      controls: true,
    })
    const recorder = new RoomRecorder('kf', sim, {
      dir: '/nonexistent',
      fsync: 'none',
      keyframeTicks: 60,
      maxBytes: 1 << 30,
      compress: true,
      log: pino({ level: 'silent' }),
      failures: new Counter({ name: 'test_keyframe_failures', help: 'test', registers: [] }),
      openNames: new Set(),
      openLog: async (): Promise<LogFile> => ({
        write: async (b) => chunks.push(b.slice()),
        sync: async () => {},
        close: async () => {},
      }),
    })
    // The log starts once the pyramid has settled: its keyframes are then small deltas.
    while (sim.tick < 240) sim.runTick()
    recorder.start(0)
    // Tick up to the first keyframe tick in one synchronous run, as a loop tick runs its rooms.
    const saved: Uint8Array[] = []
    while (sim.tick < 300) sim.runTick()
    saved.push(sim.world.save())
    expect(encodes.count).toBe(0)
    // The rest of the event-loop turn: the delta is encoded then.
    await new Promise((resolve) => setImmediate(resolve))
    expect(encodes.count).toBe(1)
    // A second later in a live room the first keyframe is long written (its size settles the
    // keyframe policy's estimate); here, wait for it.
    await recorder.flush()
    while (sim.tick < 360) sim.runTick()
    saved.push(sim.world.save())
    await recorder.close('test over')
    expect(encodes.count).toBe(2)
    // The keyframes are deltas against the header's world and then the first keyframe, and decode
    // to the worlds saved at their ticks.
    const records = new ReplayLogReader().push(Buffer.concat(chunks))
    const header = records.find((r) => r.type === 'header')
    const keyframes = records.filter((r) => r.type === 'keyframe')
    expect(keyframes.map((k) => [k.tick, k.z])).toEqual([
      [300, 2],
      [360, 2],
    ])
    if (header?.type !== 'header' || keyframes[0].type !== 'keyframe' || keyframes[1].type !== 'keyframe')
      throw new Error('records missing')
    expect(records.indexOf(keyframes[0])).toBeLessThan(records.indexOf(keyframes[1]))
    // z 1: a deflated saved world; z 2: a deflated delta against the previous keyframe's world.
    expect(header.z).toBe(1)
    const first = decodeByteDelta(inflateSync(header.world), inflateSync(keyframes[0].world))
    expect(Buffer.compare(first, saved[0])).toBe(0)
    expect(Buffer.compare(decodeByteDelta(first, inflateSync(keyframes[1].world)), saved[1])).toBe(0)
  })
})
