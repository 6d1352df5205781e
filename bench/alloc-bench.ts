/*
 * Bytes allocated per step (npm run bench:alloc): numbers printed and saved to
 * bench/results/alloc.json, never pass/fail.
 *
 * tests/engine/allocation.test.ts proves that a warm step of a plain pile allocates nothing. A
 * server room is not a plain pile: players spawn mixed shapes and drag bodies with mouse joints.
 * This measures both, the same way as the test: after a warm-up, two gc() calls, then heapUsed
 * before and after a run of steps with no collection in between (a 128 MB young generation,
 * `--max-semi-space-size`; a run in which the heap shrank inside a step had a collection and is
 * reported as such, not as a figure).
 * - pile-300: pileScene(300) with sleeping off, world.step() only (the test's scene);
 * - room-100: the capacity benchmark's room (a 100-body pile that never sleeps) in a
 *   RoomSimulation with 5 players on the bots' schedule (3 spawns of a circle, box or triangle,
 *   then grab a random dynamic body, drag it round a circle for 80 steps, release, every 100
 *   steps); the players' commands are applied outside the measured window, so only the room's
 *   ticks (the step with the grabs, and the room's housekeeping) are counted; and, in another
 *   such room, world.step() alone; and world.step() alone again in a fourth room after 12,000
 *   warm-up steps (the steady state, once V8 has optimized the rare paths). A first room of the
 *   kind runs unmeasured to warm the JIT.
 */

import { mkdirSync, writeFileSync } from 'node:fs'
import { loadavg } from 'node:os'
import { botCommand } from '../bots/index.ts'
import { buildScene, createWorld, Prng, pileScene, type World } from '../engine/index.ts'
import { sandbox } from '../games/index.ts'
import { RoomSimulation, worldFromBlueprint } from '../shared/index.ts'
import { awakePile } from './server-load.ts'

const gc = (globalThis as { gc?: () => void }).gc
if (!gc) throw new Error('run with node --expose-gc (npm run bench:alloc does)')
const WARMUP = 600
const STEPS = 600
/**
 * Warm-up of the steady-state room figure: the engine's rare paths (a sweep that hits, a body woken
 * in collide, a first visit of a branch) stay in V8's baseline tier, or are deoptimized and
 * re-optimized, for thousands of steps, and in that time allocate heap numbers.
 */
const LONG_WARMUP = 12000

/** Bytes per call of `run` over STEPS calls after `warmup` calls, or null when a collection ran. */
function measure(run: (i: number) => void, between: (i: number) => void, warmup = WARMUP): number | null {
  for (let i = 0; i < warmup; i++) {
    between(i)
    run(i)
  }
  gc?.()
  gc?.()
  let bytes = 0
  let collected = false
  for (let i = warmup; i < warmup + STEPS; i++) {
    between(i)
    const h0 = process.memoryUsage().heapUsed
    run(i)
    const d = process.memoryUsage().heapUsed - h0
    // A collection inside the step shows as the heap shrinking.
    if (d < 0) collected = true
    bytes += d
  }
  return collected ? null : bytes / STEPS
}

/** The empty measurement: what reading heapUsed around nothing allocates. */
const baseline = measure(
  () => {},
  () => {},
)

const pile: World = createWorld({ enableSleep: false })
buildScene(pile, pileScene(300))
const pileBytes = measure(
  () => pile.step(),
  () => {},
)

/** A fresh room-100 (see the file comment): its simulation and the players' commands for tick i. */
function room(): { sim: RoomSimulation; between: (i: number) => void } {
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'alloc',
    scene: 'empty',
    maxBodies: 1000,
    controls: true,
  })
  const blueprint = awakePile(100)
  const built = worldFromBlueprint(blueprint)
  sim.loadWorld(blueprint.name, built.world, built.joints)
  const players = [1, 2, 3, 4, 5].map((id) => {
    sim.join(id, `player ${id}`, '#888888')
    return { id, prng: new Prng(id), step: 0 }
  })
  const between = (i: number): void => {
    // The players' 20 Hz loops, spread over the ticks (as bench/room-tick-bench.ts).
    for (let k = 0; k < players.length; k++) {
      if ((i + k) % 3 !== 0) continue
      const player = players[k]
      const cmd = botCommand(player.prng, player.step++, () =>
        sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic'),
      )
      if (cmd) sim.apply(player.id, cmd)
    }
  }
  return { sim, between }
}
// A first room, not measured, takes the engine's and the room's code through every path the
// players' schedule reaches (spawns of each shape, grabs, releases), so that the measured rooms
// see optimized code: measured in the first room, JIT warm-up alone showed as a collection.
const warm = room()
for (let i = 0; i < 3 * WARMUP; i++) {
  warm.between(i)
  warm.sim.runTick()
}
const whole = room()
const roomBytes = measure(() => whole.sim.runTick(), whole.between)
const stepOnly = room()
const stepBytes = measure(() => stepOnly.sim.world.step(), stepOnly.between)
const steady = room()
const steadyBytes = measure(() => steady.sim.world.step(), steady.between, LONG_WARMUP)

const net = (x: number | null): number | null =>
  x === null || baseline === null ? null : Math.round(Math.max(0, x - baseline))
const summary = {
  baselineBytes: baseline === null ? null : Math.round(baseline),
  pile300BytesPerStep: net(pileBytes),
  room100BytesPerTick: net(roomBytes),
  room100WorldStepBytes: net(stepBytes),
  room100WorldStepBytesSteady: net(steadyBytes),
  room100Bodies: whole.sim.world.bodyCount,
  load1: loadavg()[0],
}
const show = (x: number | null): string => (x === null ? 'a collection ran: no figure' : `${x} bytes`)
console.log(
  `allocation per step after ${WARMUP} warm-up steps, ${STEPS} measured (heapUsed, less ${summary.baselineBytes} bytes for reading it): ` +
    `pile-300 world.step ${show(summary.pile300BytesPerStep)}; ` +
    `room-100 with 5 players (${summary.room100Bodies} bodies) sim.runTick ${show(summary.room100BytesPerTick)}, ` +
    `of which world.step ${show(summary.room100WorldStepBytes)} (measured alone in a third room); ` +
    `world.step after ${LONG_WARMUP} warm-up steps ${show(summary.room100WorldStepBytesSteady)}`,
)
mkdirSync('bench/results', { recursive: true })
const file = 'bench/results/alloc.json'
writeFileSync(
  file,
  `${JSON.stringify({ started: new Date().toISOString(), node: process.version, warmup: WARMUP, steps: STEPS, summary }, null, 2)}\n`,
)
console.log(`saved ${file}`)
