/*
 * A warm step allocates nothing: proven by measurement, not by inspection.
 *
 * The engine runs in a separate, quiet `node --expose-gc` process (allocation-measure.ts, bundled
 * with esbuild), so that vitest's own work cannot allocate or collect in the measured window. Two
 * scenes: a 300-body pile with sleeping off (every body simulated every step), and the server's
 * capacity room without the server (a 100-body pile that never sleeps, five players dragging
 * bodies fast round ellipses with mouse joints, bodies spawned and destroyed between the measured
 * rounds, a hash once a second). The pile has alternating towers of 20 and 50 boxes beside it, so
 * the column search and the column contacts' extra sweeps run every step. After a warm-up, the
 * heap growth over the measured steps (heapUsed with no collection in between) is the bytes the
 * steps allocated; if anything was allocated, V8's sampling heap profiler names the functions.
 * Bound: zero collections, and less than 64 bytes per step on average (one small object per step
 * would be about 32-64 bytes; one per contact several kilobytes). Reading heapUsed itself and
 * late JIT tier-ups account for the slack.
 */
import { execFile } from 'node:child_process'
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { promisify } from 'node:util'
import { build } from 'esbuild'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { AllocationResult } from './allocation-measure.ts'

const HERE = dirname(fileURLToPath(import.meta.url))
/**
 * Warm-up steps, measured steps per round and rounds of each scene. The room's warm-up is long:
 * its rare paths (a sweep that hits, a sleeping body woken, a new shape's first contacts) get
 * compiled by TurboFan only after thousands of steps, and until then run in V8's baseline code,
 * where every intermediate double is a heap number (the least of the rounds: 25 bytes per step
 * after 6,000 warm-up steps, 19 after 12,000; on main before 2026-11-24, a scavenge in the rounds).
 */
const PLAN = { pile: [2000, 3000, 3], room: [12000, 2000, 5] } as const

let dir: string
let bundlePath: string

beforeAll(async () => {
  dir = mkdtempSync(join(tmpdir(), 'concord-alloc-'))
  bundlePath = join(dir, 'measure.mjs')
  const out = await build({
    entryPoints: [join(HERE, 'allocation-measure.ts')],
    bundle: true,
    platform: 'node',
    format: 'esm',
    target: 'node20',
    write: false,
    sourcemap: false,
    minify: false,
    keepNames: true,
  })
  writeFileSync(bundlePath, out.outputFiles[0].text)
})

afterAll(() => {
  if (dir) rmSync(dir, { recursive: true, force: true })
})

/** Runs the measuring program on one scene and returns its result. */
async function measure(scene: 'pile' | 'room'): Promise<AllocationResult> {
  // A young generation of a fixed 16 MB: V8 starts it at 1 MB and shrinks it again on gc(), and
  // then late JIT work on a loaded machine alone could fill it (CI, Nov 24 00:37: one scavenge
  // in 9,000 steps, while the allocators sampled right after were only the inspector's). The
  // bound that proves the step allocation-free is the heap growth below (64 bytes per step);
  // with 16 MB a collection needs 1.8 KB per step, so a real allocation still fails the
  // heap-growth bound (and a large one both).
  const flags = ['--expose-gc', '--min-semi-space-size=16', '--max-semi-space-size=16']
  const { stdout } = await promisify(execFile)(
    process.execPath,
    [...flags, bundlePath, scene, ...PLAN[scene].map(String)],
    { timeout: 230_000 },
  )
  const result = JSON.parse(stdout.trim().split('\n').pop() ?? '{}') as AllocationResult
  console.log(
    `allocation (${scene}): ${result.gcCount} collections ${JSON.stringify(result.gcKinds)}, heap growth ${result.heapGrowth} bytes over ${result.steps} steps (least of ${PLAN[scene][2]} rounds` +
      `) (${(result.heapGrowth / result.steps).toFixed(2)} bytes/step), ${result.bodies} bodies, ${result.contacts} contacts` +
      (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
  )
  return result
}

/** The bound, with the allocating functions in the message. */
function expectNoAllocation(result: AllocationResult): void {
  const where = JSON.stringify(result.allocators)
  expect(result.gcCount, `collections ${JSON.stringify(result.gcKinds)}; ${where}`).toBe(0)
  expect(result.heapGrowth / result.steps, where).toBeLessThan(64)
}

describe('allocation', () => {
  // The warm-up is long (2000 steps) so that TurboFan has finished optimizing: the heap growth of
  // the first few thousand steps is compiled code and feedback, not the step's own allocation.
  // Before shapes shared one hidden class (2026-11-22), reading `shape.radius` at a site that saw
  // both circles and polygons allocated about 5 bytes per circle per call (1-26 scavenges and
  // 300-670 bytes/step here). Every shape now has every field in one order (engine/shapes.ts).
  it('a warm 300-body pile and two tall towers (column contacts) step 3 x 3000 times without garbage collection or heap growth', async () => {
    const result = await measure('pile')
    expect(result.contacts).toBeGreaterThan(300) // a real pile, not bodies in free fall
    expectNoAllocation(result)
  }, 240_000)

  // Before 2026-11-24 this scene allocated about 1.7 KB per step (bench:alloc's room-100): double
  // arguments and results of calls V8 did not inline in the continuous collision (heap numbers),
  // pair keys above 2^30 in a Map, the new-contact list's storage dropped by `length = 0`, and the
  // sleep threshold compared as a settings field of unknown representation; and the once-a-second
  // hash boxed each number it wrote (about 3 KB per hash).
  it('a warm capacity room (awake 100-body pile, 5 mouse-joint drags, spawns) steps 5 x 2000 times without heap growth', async () => {
    const result = await measure('room')
    expect(result.contacts).toBeGreaterThan(100)
    expectNoAllocation(result)
  }, 240_000)
})
