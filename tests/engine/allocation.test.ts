/*
 * A warm step allocates nothing: proven by measurement, not by inspection.
 *
 * The engine runs in a separate, quiet `node --expose-gc` process (tests/support/measure-allocation.ts,
 * bundled with esbuild), so that vitest's own work cannot allocate or collect in the measured
 * window. Two scenes (allocation-scenes.ts): a 300-body pile with sleeping off (every body
 * simulated every step), and the server's capacity room without the server (a 100-body pile that
 * never sleeps, five players dragging bodies fast round ellipses with mouse joints, bodies spawned
 * and destroyed between the measured rounds, a hash once a second). The pile has alternating
 * towers of 20 and 50 boxes beside it, so the column search and the column contacts' extra sweeps
 * run every step. After a warm-up, the
 * heap growth over the measured steps (heapUsed with no collection in between) is the bytes the
 * steps allocated; if anything was allocated, V8's sampling heap profiler names the functions.
 * Bound: zero collections, and less than 64 bytes per step on average (one small object per step
 * would be about 32-64 bytes; one per contact several kilobytes). Reading heapUsed itself and
 * late JIT tier-ups account for the slack.
 */
import { dirname } from 'node:path'
import { fileURLToPath } from 'node:url'
import { describe, expect, it } from 'vitest'
import { type AllocationResult, measureAllocation } from '../support/measure-allocation.ts'

/**
 * Warm-up steps, measured steps per round and rounds of each scene. The room's warm-up is long:
 * its rare paths (a sweep that hits, a sleeping body woken, a new shape's first contacts) get
 * compiled by TurboFan only after thousands of steps, and until then run in V8's baseline code,
 * where every intermediate double is a heap number (the least of the rounds: 25 bytes per step
 * after 6,000 warm-up steps, 19 after 12,000; on main before 2026-11-24, a scavenge in the rounds).
 */
const PLAN = {
  pile: [2000, 3000, 3],
  room: [12000, 2000, 5],
  machines: [6000, 2000, 3],
  compound: [2000, 3000, 3],
  chains: [12000, 3000, 3],
} as const

/** Bytes per step above which a step counts as allocating. */
const BOUND = 64

/**
 * Runs one scene in the measuring process. Its young generation is a fixed 16 MB (the harness's
 * setting): V8 starts it at 1 MB and shrinks it again on gc(), and then late JIT work on a loaded
 * machine alone could fill it (CI, Nov 24 00:37: one scavenge in 9,000 steps, while the
 * allocators sampled right after were only the inspector's). The bound that proves the step
 * allocation-free is the heap growth (64 bytes per step); with 16 MB a collection needs 1.8 KB per
 * step, so a real allocation still fails the heap-growth bound (and a large one both).
 */
async function measure(scene: keyof typeof PLAN): Promise<AllocationResult> {
  const [warmup, steps, rounds] = PLAN[scene]
  const result = await measureAllocation({
    resolveDir: dirname(fileURLToPath(import.meta.url)),
    setup: `
import { AllocationScene } from './allocation-scenes.ts'
const scene = new AllocationScene('${scene}')
scene.warmUp(${warmup})
`,
    unit: 'scene.step()',
    units: steps,
    warmup: 0,
    rounds,
    beforeRound: 'scene.beforeRound()',
    facts: 'scene.counts()',
    reportAbove: BOUND,
    timeoutMs: 230_000,
  })
  console.log(
    `allocation (${scene}): ${result.gcCount} collections ${JSON.stringify(result.gcKinds)}, heap growth ${result.heapGrowth} bytes over ${steps} steps (least of ${rounds} rounds` +
      `) (${(result.heapGrowth / steps).toFixed(2)} bytes/step), ${result.facts.bodies} bodies, ${result.facts.contacts} contacts` +
      (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
  )
  return result
}

/** The bound, with the allocating functions in the message. */
function expectNoAllocation(result: AllocationResult): void {
  const where = JSON.stringify(result.allocators)
  expect(result.gcCount, `collections ${JSON.stringify(result.gcKinds)}; ${where}`).toBe(0)
  expect(result.heapGrowth / result.units, where).toBeLessThan(BOUND)
}

describe('allocation', () => {
  // The warm-up is long (2000 steps) so that TurboFan has finished optimizing: the heap growth of
  // the first few thousand steps is compiled code and feedback, not the step's own allocation.
  // Before shapes shared one hidden class (2026-11-22), reading `shape.radius` at a site that saw
  // both circles and polygons allocated about 5 bytes per circle per call (1-26 scavenges and
  // 300-670 bytes/step here). Every shape now has every field in one order (engine/collision/shapes.ts).
  it('a warm 300-body pile and two tall towers (column contacts) step 3 x 3000 times without garbage collection or heap growth', async () => {
    const result = await measure('pile')
    expect(result.facts.contacts).toBeGreaterThan(300) // a real pile, not bodies in free fall
    expectNoAllocation(result)
  }, 240_000)

  // Before 2026-11-24 this scene allocated about 1.7 KB per step (bench:alloc's room-100): double
  // arguments and results of calls V8 did not inline in the continuous collision (heap numbers),
  // pair keys above 2^30 in a Map, the new-contact list's storage dropped by `length = 0`, and the
  // sleep threshold compared as a settings field of unknown representation; and the once-a-second
  // hash boxed each number it wrote (about 3 KB per hash).
  it('a warm capacity room (awake 100-body pile, 5 mouse-joint drags, spawns) steps 5 x 2000 times without heap growth', async () => {
    const result = await measure('room')
    expect(result.facts.contacts).toBeGreaterThan(100)
    expectNoAllocation(result)
  }, 240_000)

  it('a warm machines scene (every joint kind, motors reversed, targets moved, hashed) steps 3 x 2000 times without heap growth', async () => {
    const result = await measure('machines')
    expect(result.facts.contacts).toBeGreaterThan(5)
    expectNoAllocation(result)
  }, 240_000)

  it('a warm pile of compound bodies (dumbbells, capsules, rounded polygons) on conveyor segments, half with rolling resistance, with two sensors (one turning) and contact, hit and sensor events read every step, steps 3 x 3000 times without heap growth', async () => {
    const result = await measure('compound')
    expect(result.facts.contacts).toBeGreaterThan(100)
    expect(result.facts.events).toBeGreaterThan(100)
    expectNoAllocation(result)
  }, 240_000)

  // What remains (about 40 bytes per step, also after 24,000 warm-up steps) is not the chains': the
  // sampled allocators are continuous collision's rare paths (advance, timeOfImpact, sweepArc: the
  // marbles falling between tracks are fast) and the recycler's setTransform (updateCenter, sin,
  // cos), which run too rarely for V8 to optimize, as in the room above. Reading the bodies' poses
  // outside the chain routine (collide.ts collideChainSegmentAt) allocated 807 bytes per step here.
  it('a warm marble run (chain tracks, balls and capsules recycled to the top, a bin sensor read every step) steps 3 x 3000 times without heap growth', async () => {
    const result = await measure('chains')
    expect(result.facts.contacts).toBeGreaterThan(10)
    expect(result.facts.events).toBeGreaterThan(20)
    expectNoAllocation(result)
  }, 240_000)
})
