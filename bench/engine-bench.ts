/*
 * The engine benchmark (`npm run bench`): Concord against planck (Box2D 2.x in JavaScript),
 * box2d-wasm (Box2D 2.4 in WebAssembly), box2d3-wasm (Box2D v3 in WebAssembly: the package
 * entry's deluxe build with SIMD, and with --engines also box2d3-wasm-compat, its build without
 * SIMD) and Rapier (@dimforge/rapier2d-compat, WebAssembly) on identical scenes, in one process,
 * interleaved.
 *
 * For each scene and each sleep setting, every engine builds the same blueprint from
 * engine/scenes/scenes.ts. All worlds warm up together, then the harness runs rounds: in each round every
 * engine takes a chunk of steps, each step timed alone with performance.now(), and the engine
 * that goes first rotates from round to round. Machine noise (other workers on the two shared
 * cores, turbo, thermal) therefore lands on all engines alike, and all worlds are sampled at the
 * same simulated time, so a scene's busy phase (a pile landing) weighs equally on each.
 *
 * Per step we report the median, p95 and mean (ms) and the process's CPU time during the engine's
 * chunks (ms per step; time spent waiting for a core does not count, so on a loaded machine it is
 * the steadiest figure), and for every peer the ratio concord/peer (Concord's time over the
 * peer's: below 1 Concord is faster) on medians, on means, paired in time (median over rounds of
 * the ratio of the round medians) and on CPU time. The targets (issue 13, sleep off):
 * Concord at most 1.3x box2d3-wasm on pile-1000, pyramid-50 and pyramid-20, and faster than Rapier
 * on every scene; the older ones stay printed (planck/concord >= 5, concord/box2d-wasm <= 2). A
 * fast engine whose pyramid falls is not a fast engine, so each run also checks the scene at the
 * end: how far the pyramid's top box dropped, how far any body drifted, the fastest body, and for
 * the pile how many bodies left the container.
 *
 * Flags: --quick (short smoke run), --scene NAME (pyramid-20 | pyramid-50 | pile-1000),
 * --sleep off|on|both, --engines concord,planck,box2d-wasm,box2d3-wasm,box2d3-wasm-compat,rapier
 * (default all but box2d3-wasm-compat), --out FILE.
 */
import { performance } from 'node:perf_hooks'
import { parseArgs } from 'node:util'
import { pileScene, pyramidScene, type SceneBlueprint } from '../engine/index.ts'
import {
  BOX2D_POSITION_ITERATIONS,
  BOX2D_VELOCITY_ITERATIONS,
  BOX2D_WASM_BUILD,
  BOX2D3_SUB_STEPS,
  Box2D3WasmPeer,
  Box2DWasmPeer,
  ConcordPeer,
  PLANCK_POSITION_ITERATIONS,
  PLANCK_VELOCITY_ITERATIONS,
  PlanckPeer,
  RapierPeer,
  rapierVersion,
} from './peers/index.ts'
import {
  checkScene,
  formatTable,
  type GcPause,
  machineInfo,
  type PeerWorld,
  pairedRatio,
  recordGcPauses,
  type SceneCheck,
  type SceneKind,
  type Summary,
  saveResults,
  summarize,
} from './stats.ts'

const ENGINES = ['concord', 'planck', 'box2d-wasm', 'box2d3-wasm', 'box2d3-wasm-compat', 'rapier'] as const
type EngineName = (typeof ENGINES)[number]
/** What runs without --engines: the compat build only answers how much of box2d3-wasm's lead is SIMD. */
const DEFAULT_ENGINES = ENGINES.filter((name) => name !== 'box2d3-wasm-compat')
type MakePeer = (blueprint: SceneBlueprint, enableSleep: boolean) => Promise<PeerWorld>

interface SceneCase {
  name: string
  make: () => SceneBlueprint
  kind: SceneKind
  /** Timed steps in a full run. */
  steps: number
}

const SCENE_CASES: SceneCase[] = [
  { name: 'pyramid-20', make: () => pyramidScene(20), kind: 'pyramid', steps: 600 },
  { name: 'pyramid-50', make: () => pyramidScene(50), kind: 'pyramid', steps: 300 },
  { name: 'pile-1000', make: () => pileScene(1000), kind: 'pile', steps: 300 },
]
/** Sleep-off targets as the largest allowed concord/peer ratio of medians, per scene (issues 11 and 13). */
const TARGETS: Record<string, Partial<Record<EngineName, number>>> = {
  'pile-1000': { planck: 1 / 5, 'box2d-wasm': 2, 'box2d3-wasm': 1.3, rapier: 1 },
  'pyramid-50': { planck: 1 / 5, 'box2d-wasm': 2, 'box2d3-wasm': 1.3, rapier: 1 },
  'pyramid-20': { 'box2d3-wasm': 1.3, rapier: 1 },
}
/** Steps each engine takes per round before the next engine's turn. */
const CHUNK_STEPS = 10

interface EngineResult {
  /** Time to build the scene in this engine (ms). */
  buildMs: number
  /** Per-step times (ms). */
  steps: Summary
  /** CPU time of the process during this engine's timed steps, per step (ms): waiting for a core does not count. */
  cpuMsPerStep: number
  /** Garbage-collection pauses during this engine's steps, averaged per step (ms). */
  gcMsPerStep: number
  check: SceneCheck
}

interface CaseResult {
  scene: string
  bodies: number
  sleep: boolean
  warmupSteps: number
  timedSteps: number
  engines: Partial<Record<EngineName, EngineResult>>
  /** Per peer, Concord's step time over the peer's (below 1: Concord is faster). */
  concordOver: Partial<Record<EngineName, ConcordRatio>>
  /** Per peer with a target here: whether concord/peer (medians) is within it. */
  targets: Partial<Record<EngineName, { limit: number; met: boolean }>>
}

/** Concord's time over one peer's on one case. */
interface ConcordRatio {
  median: number
  mean: number
  /** CPU time per step over the peer's (the steadiest ratio on a loaded machine). */
  cpu: number
  /** Paired in time: median over rounds of the ratio of the two engines' round medians. */
  paired: number
}

async function loadMakers(wanted: readonly EngineName[]): Promise<Map<EngineName, MakePeer>> {
  const makers = new Map<EngineName, MakePeer>()
  for (const name of wanted) {
    if (name === 'planck') makers.set(name, async (bp, sleep) => new PlanckPeer(bp, sleep))
    if (name === 'box2d-wasm') makers.set(name, (bp, sleep) => Box2DWasmPeer.create(bp, sleep))
    if (name === 'box2d3-wasm') makers.set(name, (bp, sleep) => Box2D3WasmPeer.create(bp, sleep))
    if (name === 'box2d3-wasm-compat')
      makers.set(name, (bp, sleep) => Box2D3WasmPeer.create(bp, sleep, 'compat'))
    if (name === 'rapier') makers.set(name, (bp, sleep) => RapierPeer.create(bp, sleep))
    if (name === 'concord') makers.set(name, async (bp, sleep) => new ConcordPeer(bp, sleep))
  }
  return makers
}

/** One engine's chunk of timed steps, on the performance.now() clock. */
interface Chunk {
  engine: number
  start: number
  end: number
}

function timeRounds(
  peers: PeerWorld[],
  steps: number,
  chunks: Chunk[] = [],
  cpuMs: number[] = peers.map(() => 0),
): number[][] {
  const samples = peers.map(() => [] as number[])
  const rounds = Math.ceil(steps / CHUNK_STEPS)
  for (let round = 0; round < rounds; round++) {
    const count = Math.min(CHUNK_STEPS, steps - round * CHUNK_STEPS)
    for (let k = 0; k < peers.length; k++) {
      const e = (round + k) % peers.length
      const peer = peers[e]
      const out = samples[e]
      const start = performance.now()
      const cpu0 = process.cpuUsage()
      for (let s = 0; s < count; s++) {
        const t0 = performance.now()
        peer.step()
        out.push(performance.now() - t0)
      }
      const used = process.cpuUsage(cpu0)
      cpuMs[e] += (used.user + used.system) / 1000
      chunks.push({ engine: e, start, end: performance.now() })
    }
  }
  return samples
}

/** Adds to each engine's result the garbage-collection time that began inside its chunks. */
function attributeGc(result: CaseResult, pauses: GcPause[], chunks: Chunk[]): void {
  const names = ENGINES.filter((name) => result.engines[name])
  for (const pause of pauses) {
    const chunk = chunks.find((c) => pause.start >= c.start && pause.start < c.end)
    const engine = chunk ? result.engines[names[chunk.engine]] : undefined
    if (engine) engine.gcMsPerStep += pause.duration / result.timedSteps
  }
}

async function runCase(
  scene: SceneCase,
  sleep: boolean,
  makers: Map<EngineName, MakePeer>,
  warmupSteps: number,
  timedSteps: number,
  chunks: Chunk[],
): Promise<CaseResult> {
  const blueprint = scene.make()
  // The peers build bodies only; a scene with joints would silently differ between engines.
  if (((blueprint as { joints?: unknown[] }).joints?.length ?? 0) > 0) {
    throw new Error(`scene ${scene.name} has joints, which the peer adapters do not build`)
  }
  const names = [...makers.keys()]
  const peers: PeerWorld[] = []
  const buildMs: number[] = []
  for (const name of names) {
    const t0 = performance.now()
    peers.push(await makers.get(name)!(blueprint, sleep))
    buildMs.push(performance.now() - t0)
  }
  const starts = peers.map((p) => p.readBodies())
  timeRounds(peers, warmupSteps)
  const cpuMs = peers.map(() => 0)
  const samples = timeRounds(peers, timedSteps, chunks, cpuMs)
  const engines: CaseResult['engines'] = {}
  names.forEach((name, e) => {
    const check = checkScene(scene.kind, blueprint, starts[e], peers[e].readBodies(), peers[e].awakeCount())
    const steps = summarize(samples[e])
    engines[name] = { buildMs: buildMs[e], steps, cpuMsPerStep: cpuMs[e] / steps.n, gcMsPerStep: 0, check }
    peers[e].dispose()
  })
  const concordOver: CaseResult['concordOver'] = {}
  const targets: CaseResult['targets'] = {}
  const ci = names.indexOf('concord')
  const concord = engines.concord
  names.forEach((name, e) => {
    const peer = engines[name]
    if (name === 'concord' || concord === undefined || peer === undefined) return
    const ratio = {
      median: concord.steps.median / peer.steps.median,
      mean: concord.steps.mean / peer.steps.mean,
      cpu: concord.cpuMsPerStep / peer.cpuMsPerStep,
      paired: pairedRatio(samples[ci], samples[e], CHUNK_STEPS),
    }
    concordOver[name] = ratio
    const limit = sleep ? undefined : TARGETS[scene.name]?.[name]
    if (limit !== undefined) targets[name] = { limit, met: ratio.median <= limit }
  })
  const bodies = blueprint.bodies.length
  return {
    scene: scene.name,
    bodies,
    sleep,
    warmupSteps,
    timedSteps,
    engines,
    concordOver,
    targets,
  }
}

const fmt = (x: number | null | undefined, digits = 2): string =>
  x === null || x === undefined || !Number.isFinite(x) ? '-' : x.toFixed(digits)

function printResults(results: CaseResult[]): void {
  const rows: string[][] = []
  for (const r of results) {
    for (const name of ENGINES) {
      const e = r.engines[name]
      if (!e) continue
      const c = e.check
      rows.push([
        `${r.scene} sleep ${r.sleep ? 'on' : 'off'}`,
        name,
        fmt(e.steps.median, 3),
        fmt(e.steps.p95, 3),
        fmt(e.steps.mean, 3),
        fmt(e.cpuMsPerStep, 3),
        fmt(e.gcMsPerStep, 3),
        String(c.awake),
        fmt(c.topDx, 3),
        fmt(c.topDy, 3),
        fmt(c.maxDrift, 2),
        fmt(c.maxSpeed, 3),
        c.verdict,
      ])
    }
  }
  const header = [
    'scene',
    'engine',
    'median ms',
    'p95 ms',
    'mean ms',
    'cpu ms',
    'gc ms',
    'awake',
    'top dx m',
    'top dy m',
    'drift m',
    'max|v|',
  ]
  console.log(`\n${formatTable([...header, 'end state'], rows)}\n`)
  const peers = ENGINES.filter((name) => name !== 'concord' && results.some((r) => r.concordOver[name]))
  const ratioRows = results.map((r) => [
    `${r.scene} sleep ${r.sleep ? 'on' : 'off'}`,
    ...peers.flatMap((name) => {
      const ratio = r.concordOver[name]
      const target = r.targets[name]
      const mark = target === undefined ? '' : target.met ? ' ok' : ' MISSED'
      return [`${fmt(ratio?.median)}${mark}`, fmt(ratio?.mean), fmt(ratio?.paired), fmt(ratio?.cpu)]
    }),
  ])
  const ratioHeader = [
    'concord / peer',
    ...peers.flatMap((name) => [`${name} median`, 'mean', 'paired', 'cpu']),
  ]
  console.log(`${formatTable(ratioHeader, ratioRows)}`)
  console.log(
    'concord/peer below 1: Concord is faster. Targets (sleep off, medians): box2d3-wasm <= 1.3 on\n' +
      'pile-1000 and both pyramids, rapier < 1, planck/concord >= 5 and box2d-wasm <= 2 on pile-1000\n' +
      'and pyramid-50; "ok" or "MISSED" marks each.\n',
  )
}

function parseOptions() {
  const { values } = parseArgs({
    options: {
      quick: { type: 'boolean', default: false },
      scene: { type: 'string' },
      sleep: { type: 'string', default: 'both' },
      engines: { type: 'string', default: DEFAULT_ENGINES.join(',') },
      out: { type: 'string' },
    },
  })
  const scenes = values.scene ? SCENE_CASES.filter((s) => s.name === values.scene) : SCENE_CASES
  if (scenes.length === 0) {
    throw new Error(
      `unknown --scene ${values.scene}; choose one of ${SCENE_CASES.map((s) => s.name).join(', ')}`,
    )
  }
  const sleeps = { off: [false], on: [true], both: [false, true] }[values.sleep]
  if (!sleeps) throw new Error(`--sleep must be off, on or both, got ${values.sleep}`)
  const engines = values.engines.split(',').map((e) => e.trim())
  const unknown = engines.filter((e) => !(ENGINES as readonly string[]).includes(e))
  if (unknown.length > 0)
    throw new Error(`unknown --engines ${unknown.join(',')}; choose from ${ENGINES.join(',')}`)
  const suffix = values.quick ? '-quick' : values.scene ? `-${values.scene}` : ''
  const out = values.out ?? new URL(`./results/engine${suffix}.json`, import.meta.url).pathname
  return { quick: values.quick, scenes, sleeps, engines: engines as EngineName[], out }
}

async function main(): Promise<void> {
  const options = parseOptions()
  const machine = machineInfo()
  const makers = await loadMakers(options.engines)
  const warmupSteps = options.quick ? 10 : 60
  console.error(
    `engine bench on ${machine.cpu} x${machine.cores}, node ${machine.node}, load ${machine.loadAverage}`,
  )
  const results: CaseResult[] = []
  const chunksOf = new Map<CaseResult, Chunk[]>()
  const gc = recordGcPauses()
  for (const scene of options.scenes) {
    for (const sleep of options.sleeps) {
      const timedSteps = options.quick ? Math.max(20, scene.steps / 10) : scene.steps
      const t0 = performance.now()
      const chunks: Chunk[] = []
      const result = await runCase(scene, sleep, makers, warmupSteps, timedSteps, chunks)
      results.push(result)
      chunksOf.set(result, chunks)
      const seconds = ((performance.now() - t0) / 1000).toFixed(1)
      console.error(`  ${scene.name} sleep ${sleep ? 'on' : 'off'}: ${timedSteps} steps in ${seconds} s`)
    }
  }
  const pauses = await gc.stop()
  for (const result of results) attributeGc(result, pauses, chunksOf.get(result)!)
  printResults(results)
  const settings = {
    stepSeconds: 1 / 60,
    chunkSteps: CHUNK_STEPS,
    concord: 'createWorld defaults (4 sub-steps, soft contacts)',
    planck: {
      velocityIterations: PLANCK_VELOCITY_ITERATIONS,
      positionIterations: PLANCK_POSITION_ITERATIONS,
    },
    box2dWasm: {
      velocityIterations: BOX2D_VELOCITY_ITERATIONS,
      positionIterations: BOX2D_POSITION_ITERATIONS,
      build: BOX2D_WASM_BUILD,
    },
    box2d3Wasm: {
      subSteps: BOX2D3_SUB_STEPS,
      workerCount: 'default (0: single-threaded)',
      builds: {
        'box2d3-wasm': 'package entry (deluxe in Node: SIMD, pthreads)',
        'box2d3-wasm-compat': 'compat',
      },
    },
    rapier: {
      version: options.engines.includes('rapier') ? await rapierVersion() : null,
      settings: 'defaults (4 solver iterations, 1/60 s)',
    },
    targets: { sleep: false, maxConcordOverPeer: TARGETS },
  }
  const finished = { ...machine, loadAverageAtEnd: machineInfo().loadAverage }
  saveResults(options.out, {
    benchmark: 'engine',
    quick: options.quick,
    machine: finished,
    settings,
    results,
  })
  console.error(`saved ${options.out}`)
}

await main()
// box2d3-wasm's pthread pool keeps Node alive; the results are saved, so leave now.
process.exit(0)
