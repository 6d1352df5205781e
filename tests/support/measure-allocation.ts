/*
 * Measures how many bytes a unit of work allocates once warm, in a separate quiet
 * `node --expose-gc` process (the code bundled with esbuild), so that vitest's own work cannot
 * allocate or collect in the measured window. The method of tests/engine/allocation.test.ts:
 * warm up, gc() twice, then read heapUsed around rounds of units with no collection in between
 * (heapUsed includes the young generation, so the growth is what the units allocated, as long as
 * no collection ran; a PerformanceObserver counts collections that start inside the rounds, not
 * those V8 runs when the thread goes idle after them: CI, Nov 24 03:10, one scavenge counted in
 * the 100 ms wait after the rounds, with 0.08 bytes per step of heap growth). The least growth of
 * the rounds (three unless told) is kept (late JIT work lands in one round on a busy machine; a
 * real allocation shows in every round). When the growth passes the bound or a collection ran,
 * V8's sampling heap profiler runs over more units and names the functions that allocate, so a
 * failure says where to look. Used by tests/engine/allocation.test.ts (the engine's step) and
 * tests/server/rooms/snapshot-allocation.test.ts (the server's snapshot path).
 */
import { execFile } from 'node:child_process'
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { promisify } from 'node:util'
import { build } from 'esbuild'

/** What to measure: TypeScript run in the measuring process. */
export interface AllocationCase {
  /** Imports and set-up (import paths relative to `resolveDir`). */
  setup: string
  /** The body of one unit of work (a statement list). */
  unit: string
  /** Units measured per round. */
  units: number
  /** Units run before measuring, so that the JIT has finished optimizing. */
  warmup: number
  /** Bytes per unit above which the allocating functions are sampled and reported. */
  reportAbove: number
  /** Directory the set-up's relative imports resolve from. */
  resolveDir: string
  /** Extra V8 flags for the measuring process. */
  flags?: string[]
  /** Measured rounds (default 3). */
  rounds?: number
  /** Statements run before each round, outside its window (work that may allocate). */
  beforeRound?: string
  /** An expression evaluated after the rounds: an object of numbers copied into `facts`. */
  facts?: string
  /** Time limit of the measuring process (ms, default 120,000). */
  timeoutMs?: number
}

/** Collections in the window, least heap growth of three rounds, and the top allocators when over the bound. */
export interface AllocationResult {
  gcCount: number
  /** V8's kinds of the collections in the window (1 scavenge, 2 minor mark-sweep, 4 mark-compact, ...). */
  gcKinds: number[]
  heapGrowth: number
  units: number
  allocators: Array<{ where: string; bytes: number }>
  /** The case's `facts` after the rounds. */
  facts: Record<string, number>
}

function script(c: AllocationCase): string {
  return `
import { PerformanceObserver, performance } from 'node:perf_hooks'
import { Session } from 'node:inspector'
${c.setup}
const unit = () => {
${c.unit}
}
for (let i = 0; i < ${c.warmup}; i++) unit()
const kinds = []
let windowStart = Number.POSITIVE_INFINITY
let windowEnd = Number.POSITIVE_INFINITY
const observer = new PerformanceObserver((list) => {
  for (const e of list.getEntries()) if (e.startTime >= windowStart && e.startTime <= windowEnd) kinds.push(e.detail?.kind ?? 0)
})
observer.observe({ entryTypes: ['gc'] })
globalThis.gc()
globalThis.gc()
await new Promise((r) => setTimeout(r, 10))
windowStart = performance.now()
let heapGrowth = Number.POSITIVE_INFINITY
for (let round = 0; round < ${c.rounds ?? 3}; round++) {
${c.beforeRound ?? ''}
  const before = process.memoryUsage().heapUsed
  for (let i = 0; i < ${c.units}; i++) unit()
  heapGrowth = Math.min(heapGrowth, process.memoryUsage().heapUsed - before)
}
windowEnd = performance.now()
await new Promise((r) => setTimeout(r, 100))
const result = { units: ${c.units}, gcCount: kinds.length, gcKinds: kinds, heapGrowth, allocators: [], facts: ${c.facts ?? '{}'} }
if (result.gcCount > 0 || result.heapGrowth > ${c.reportAbove} * ${c.units}) {
  const session = new Session()
  session.connect()
  const post = (method, params) => new Promise((res, rej) => session.post(method, params, (e, r) => (e ? rej(e) : res(r))))
  await post('HeapProfiler.startSampling', { samplingInterval: 256, includeObjectsCollectedByMajorGC: true, includeObjectsCollectedByMinorGC: true })
  for (let i = 0; i < ${c.units}; i++) unit()
  const { profile } = await post('HeapProfiler.stopSampling')
  const totals = new Map()
  const walk = (node) => {
    const f = node.callFrame
    if (node.selfSize > 0) {
      const key = (f.functionName || '(anonymous)') + ' ' + f.url.split('/').slice(-2).join('/') + ':' + (f.lineNumber + 1)
      totals.set(key, (totals.get(key) ?? 0) + node.selfSize)
    }
    for (const child of node.children) walk(child)
  }
  walk(profile.head)
  result.allocators = [...totals].sort((a, b) => b[1] - a[1]).slice(0, 8).map(([where, bytes]) => ({ where, bytes }))
}
console.log(JSON.stringify(result))
`
}

/**
 * Bundle and run the case in its own process with a fixed 16 MB young generation (V8 starts it at
 * 1 MB and shrinks it on gc(), and then late JIT work alone could fill it).
 */
export async function measureAllocation(c: AllocationCase): Promise<AllocationResult> {
  const dir = mkdtempSync(join(tmpdir(), 'concord-alloc-'))
  try {
    const out = await build({
      stdin: { contents: script(c), resolveDir: c.resolveDir, loader: 'ts', sourcefile: 'measure.ts' },
      bundle: true,
      platform: 'node',
      format: 'esm',
      target: 'node20',
      write: false,
      keepNames: true,
    })
    const bundle = join(dir, 'measure.mjs')
    writeFileSync(bundle, out.outputFiles[0].text)
    // TurboFan compiles on the main thread (--no-concurrent-recompilation), so the warm-up ends
    // with the hot code optimized however loaded the machine is: with background compilation a
    // busy machine (two test files at once) once left a step in baseline code, which boxes doubles.
    const flags = [
      '--expose-gc',
      '--min-semi-space-size=16',
      '--max-semi-space-size=16',
      '--no-concurrent-recompilation',
      ...(c.flags ?? []),
    ]
    const { stdout } = await promisify(execFile)(process.execPath, [...flags, bundle], {
      timeout: c.timeoutMs ?? 120_000,
    })
    return JSON.parse(stdout.trim().split('\n').pop() ?? '{}') as AllocationResult
  } finally {
    rmSync(dir, { recursive: true, force: true })
  }
}
