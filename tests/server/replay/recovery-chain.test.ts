/*
 * Crash recovery through chains of delta keyframes, in process: a pyramid room with a player
 * dragging boxes is recorded by the server's recorder (keyframes every 60 ticks, no budget, so
 * the resting pyramid's keyframes are deltas, with bodies spawned in between), with the live world
 * hash kept at every tick. The log is then cut at random
 * byte offsets (a crash at any moment); recoverLog must rebuild each cut log exactly at the last
 * checkpoint its intact prefix holds, whose tick this test finds by reading the prefix, and whose
 * hash must be the live one at that tick.
 */

import { mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { Counter } from 'prom-client'
import { beforeAll, describe, expect, it } from 'vitest'
import { Prng } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import { recoverLog } from '../../../server/replay/recovery.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'

const TICKS = 1500
/** World hash right after each room tick's step (what a checkpoint at that tick records). */
const live = new Map<number, number>()
let dir: string
let log: Uint8Array

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-recovery-chain-'))
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'chain',
    scene: 'pyramid',
    maxBodies: 1500,
    controls: true,
  })
  const recorder = new RoomRecorder('chain', sim, {
    dir,
    fsync: 'none',
    keyframeTicks: 60,
    keyframeBudget: 0,
    maxBytes: 1 << 30,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: 'test_chain_failures', help: 'test', registers: [] }),
    openNames: new Set(),
  })
  recorder.start(0)
  sim.join(1, 'ada', '#e6194b')
  const prng = new Prng(7)
  live.set(0, sim.hash())
  while (sim.tick < TICKS) {
    const t = sim.tick
    if (t === 0) {
      const dynamic = sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')
      sim.apply(1, { k: 'grab', body: dynamic[dynamic.length - 1], lx: 0, ly: 0 })
    } else if (t < 100) sim.apply(1, { k: 'move', x: 3 * Math.sin(t / 20), y: 12 })
    else if (t === 100) sim.apply(1, { k: 'release' })
    else if (t % 90 === 0) {
      // Bodies added off to the side: the saved world grows in its middle (a shifted delta).
      const x = 15 + prng.int(10)
      sim.apply(1, { k: 'spawn', shape: { type: 'box', hw: 0.3, hh: 0.3 }, x, y: 2, vx: 0, vy: 0 })
    }
    sim.runTick()
    live.set(sim.tick, sim.hash())
    if (sim.tick % 25 === 0) await recorder.flush()
  }
  await recorder.flush()
  log = new Uint8Array(await readFile(join(dir, recorder.name)))
}, 60_000)

/** The last checkpoint of a prefix and the delta chain length of its keyframe, read with the reader. */
function lastCheckpoint(bytes: Uint8Array): { tick: number; chain: number } {
  let tick = -1
  let chain = 0
  let chainAtCheckpoint = 0
  new ReplayLogReader().push(bytes, (r) => {
    if (r.type === 'keyframe') chain = r.z === 2 ? chain + 1 : 0
    if (r.type === 'hash' || r.type === 'keyframe' || r.type === 'header') {
      tick = r.tick
      chainAtCheckpoint = chain
    }
  })
  return { tick, chain: chainAtCheckpoint }
}

describe('crash recovery through delta keyframes', () => {
  it('a log cut at 25 random offsets is rebuilt at its last intact checkpoint with the live hash there', async () => {
    const prng = new Prng(99)
    const chains: number[] = []
    // Cuts after the keyframe at tick 600 (the pyramid rests by then: the chains are long).
    let from = 0
    new ReplayLogReader().push(log, (r, end) => {
      if (r.type === 'keyframe' && r.tick === 600) from = end
    })
    expect(from).toBeGreaterThan(0)
    for (let trial = 0; trial < 25; trial++) {
      const cut = from + prng.int(log.length - from)
      const name = `chain-20261123T000000${String(trial).padStart(3, '0')}Z.cclog`
      await writeFile(join(dir, name), log.subarray(0, cut))
      const expected = lastCheckpoint(log.subarray(0, cut))
      const recovered = await recoverLog(dir, name)
      expect(recovered.tick, `cut at ${cut}`).toBe(expected.tick)
      expect(recovered.hash, `cut at ${cut}`).toBe(live.get(expected.tick))
      chains.push(expected.chain)
    }
    // Every trial went through a chain of several deltas.
    expect(Math.min(...chains)).toBeGreaterThanOrEqual(3)
  })
})
