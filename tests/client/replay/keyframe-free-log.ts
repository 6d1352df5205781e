/*
 * A long log with no keyframes, written by the server's own recorder: a wrecking ball swinging
 * (it never sleeps, so every tick costs a real step) while one player now and then grabs a box and
 * drags it about. The recorder writes a hash record at every multiple of 60 ticks, with the right
 * hashes; its keyframe interval is longer than the log, so a seek anywhere replays from the header.
 * The live hash at every tick is kept ("the state at T": after T's commands, before the step).
 * Shared by the player's unit test and the browser test. recordWreckingBallLog records the same
 * room with keyframes (whole and delta) every so many ticks.
 */

import { mkdtemp, readFile, rm } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { Counter } from 'prom-client'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'

/** A recorded log and the live world hash at every tick it covers. */
export interface KeyframeFreeLog {
  bytes: Uint8Array
  /** Live hash by room tick, from the header's tick to the last. */
  live: Float64Array
}

/** Drags a box now and then: a grab at tick 100 of every 3,000, moves every 10 ticks, a release. */
function drag(sim: RoomSimulation): void {
  const t = sim.tick % 3_000
  if (t === 100) {
    const box = sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')[2]
    if (box !== undefined) sim.apply(1, { k: 'grab', body: box, lx: 0, ly: 0 })
  }
  if (t > 100 && t < 400 && t % 10 === 0) sim.apply(1, { k: 'move', x: Math.sin(sim.tick / 50) * 3, y: 3 })
  if (t === 400) sim.apply(1, { k: 'release' })
}

/** Record `ticks` ticks of the wrecking-ball room (see the file comment). */
export function recordKeyframeFreeLog(ticks: number): Promise<KeyframeFreeLog> {
  return recordWreckingBallLog(ticks, 100 * ticks)
}

/** The same room with the recorder's keyframes every `keyframeTicks` ticks (no keyframe budget). */
export async function recordWreckingBallLog(ticks: number, keyframeTicks: number): Promise<KeyframeFreeLog> {
  const dir = await mkdtemp(join(tmpdir(), 'concord-no-keyframes-'))
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'long',
    scene: 'wrecking-ball',
    maxBodies: 200,
    controls: true,
  })
  const recorder = new RoomRecorder('long', sim, {
    dir,
    fsync: 'none',
    keyframeTicks,
    maxBytes: 1 << 30,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: 'keyframe_free_failures', help: 'test', registers: [] }),
    openNames: new Set(),
  })
  recorder.start(0)
  sim.join(1, 'ada', '#e6194b')
  const live = new Float64Array(ticks + 1)
  while (sim.tick < ticks) {
    drag(sim)
    live[sim.tick] = sim.world.hash()
    sim.runTick()
  }
  live[sim.tick] = sim.world.hash()
  await recorder.close('test over')
  const bytes = new Uint8Array(await readFile(join(dir, recorder.name)))
  await rm(dir, { recursive: true })
  return { bytes, live }
}
