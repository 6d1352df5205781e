/*
 * The engine benchmark (`npm run bench`): Concord against planck (Box2D 2.x in JavaScript) and
 * box2d-wasm (Box2D 2.4 in WebAssembly) on identical scenes, in one process, interleaved.
 *
 * For each scene and each sleep setting, every engine builds the same blueprint from
 * engine/scenes.ts. All worlds warm up together, then the harness runs rounds: in each round every
 * engine takes a chunk of steps, each step timed alone with performance.now(), and the engine
 * that goes first rotates from round to round. Machine noise (other workers on the two shared
 * cores, turbo, thermal) therefore lands on all engines alike, and all worlds are sampled at the
 * same simulated time, so a scene's busy phase (a pile landing) weighs equally on each.
 *
 * Per step we report the median and p95 (ms), and the ratios planck/concord and
 * concord/box2d-wasm on medians. The targets: Concord at least 5x faster than planck and no
 * slower than 2x box2d-wasm on pile-1000 and pyramid-50 with sleeping off. A fast engine whose
 * pyramid falls is not a fast engine, so each run also checks the scene at the end: how far the
 * pyramid's top box dropped, how far any body drifted, the fastest body, and for the pile how
 * many bodies left the container.
 *
 * Flags: --quick (short smoke run), --scene NAME (pyramid-20 | pyramid-50 | pile-1000),
 * --sleep off|on|both, --engines concord,planck,box2d-wasm, --out FILE.
 */
import { performance } from 'node:perf_hooks'
import { parseArgs } from 'node:util'
import { pileScene, pyramidScene, type SceneBlueprint } from '../engine/scenes.ts'
import {
  BOX2D_POSITION_ITERATIONS,
  BOX2D_VELOCITY_ITERATIONS,
  BOX2D_WASM_BUILD,
  Box2DWasmPeer,
} from './peers/box2d-wasm-peer.ts'
import { PLANCK_POSITION_ITERATIONS, PLANCK_VELOCITY_ITERATIONS, PlanckPeer } from './peers/planck-peer.ts'
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

const ENGINES = ['concord', 'planck', 'box2d-wasm'] as const
type EngineName = (typeof ENGINES)[number]
type MakePeer = (blueprint: SceneBlueprint, enableSleep: boolean) => Promise<PeerWorld>
type PeerClass = new (blueprint: SceneBlueprint, enableSleep: boolean) => PeerWorld
const CONCORD_PEER = new URL('./peers/concord-peer.ts', import.meta.url).href

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
/** Scenes and sleep setting the targets apply to. */
const TARGET_SCENES = ['pile-1000', 'pyramid-50']
/** Concord must be at least this many times faster than planck (median). */
const TARGET_PLANCK_OVER_CONCORD = 5
/** Concord may be at most this many times slower than box2d-wasm (median). */
const TARGET_CONCORD_OVER_BOX2D = 2
/** Steps each engine takes per round before the next engine's turn. */
const CHUNK_STEPS = 10

interface EngineResult {
  /** Time to build the scene in this engine (ms). */
  buildMs: number
  /** Per-step times (ms). */
  steps: Summary
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
  planckOverConcord: number | null
  concordOverBox2d: number | null
  /** The same ratios paired in time: median over rounds of the ratio of the engines' chunk medians. */
  pairedRatios: { planckOverConcord: number | null; concordOverBox2d: number | null }
  /** Whether the targets hold, or null when they do not apply or an engine is missing. */
  targetMet: boolean | null
}

async function loadMakers(wanted: readonly EngineName[]): Promise<Map<EngineName, MakePeer>> {
  const makers = new Map<EngineName, MakePeer>()
  for (const name of wanted) {
    if (name === 'planck') makers.set(name, async (bp, sleep) => new PlanckPeer(bp, sleep))
    if (name === 'box2d-wasm') makers.set(name, (bp, sleep) => Box2DWasmPeer.create(bp, sleep))
    if (name === 'concord') {
      try {
        // A non-literal specifier: the peers run (and type-check) before Concord's engine exists.
        const { ConcordPeer } = (await import(CONCORD_PEER)) as { ConcordPeer: PeerClass }
        makers.set(name, async (bp, sleep) => new ConcordPeer(bp, sleep))
      } catch (error) {
        console.error(`concord skipped: engine/index.ts could not be loaded (${(error as Error).message})`)
      }
    }
  }
  return makers
}

/** One engine's chunk of timed steps, on the performance.now() clock. */
interface Chunk {
  engine: number
  start: number
  end: number
}

function timeRounds(peers: PeerWorld[], steps: number, chunks: Chunk[] = []): number[][] {
  const samples = peers.map(() => [] as number[])
  const rounds = Math.ceil(steps / CHUNK_STEPS)
  for (let round = 0; round < rounds; round++) {
    const count = Math.min(CHUNK_STEPS, steps - round * CHUNK_STEPS)
    for (let k = 0; k < peers.length; k++) {
      const e = (round + k) % peers.length
      const peer = peers[e]
      const out = samples[e]
      const start = performance.now()
      for (let s = 0; s < count; s++) {
        const t0 = performance.now()
        peer.step()
        out.push(performance.now() - t0)
      }
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
  const samples = timeRounds(peers, timedSteps, chunks)
  const engines: CaseResult['engines'] = {}
  names.forEach((name, e) => {
    const check = checkScene(scene.kind, blueprint, starts[e], peers[e].readBodies(), peers[e].awakeCount())
    engines[name] = { buildMs: buildMs[e], steps: summarize(samples[e]), gcMsPerStep: 0, check }
    peers[e].dispose()
  })
  const concord = engines.concord?.steps.median
  const planck = engines.planck?.steps.median
  const box2d = engines['box2d-wasm']?.steps.median
  const planckOverConcord = concord !== undefined && planck !== undefined ? planck / concord : null
  const concordOverBox2d = concord !== undefined && box2d !== undefined ? concord / box2d : null
  const paired = (a: EngineName, b: EngineName): number | null => {
    const ia = names.indexOf(a)
    const ib = names.indexOf(b)
    return ia < 0 || ib < 0 ? null : pairedRatio(samples[ia], samples[ib], CHUNK_STEPS)
  }
  const pairedRatios = {
    planckOverConcord: paired('planck', 'concord'),
    concordOverBox2d: paired('concord', 'box2d-wasm'),
  }
  const applies = !sleep && TARGET_SCENES.includes(scene.name)
  const targetMet =
    applies && planckOverConcord !== null && concordOverBox2d !== null
      ? planckOverConcord >= TARGET_PLANCK_OVER_CONCORD && concordOverBox2d <= TARGET_CONCORD_OVER_BOX2D
      : null
  const bodies = blueprint.bodies.length
  return {
    scene: scene.name,
    bodies,
    sleep,
    warmupSteps,
    timedSteps,
    engines,
    planckOverConcord,
    concordOverBox2d,
    pairedRatios,
    targetMet,
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
    'gc ms',
    'awake',
    'top dx m',
    'top dy m',
    'drift m',
    'max|v|',
  ]
  console.log(`\n${formatTable([...header, 'end state'], rows)}\n`)
  const ratioRows = results.map((r) => [
    `${r.scene} sleep ${r.sleep ? 'on' : 'off'}`,
    fmt(r.planckOverConcord),
    fmt(r.pairedRatios.planckOverConcord),
    fmt(r.concordOverBox2d),
    fmt(r.pairedRatios.concordOverBox2d),
    ENGINES.map((name) => r.engines[name]?.check.awake ?? '-').join('/'),
    r.targetMet === null ? '' : r.targetMet ? 'MET' : 'MISSED',
  ])
  const ratioHeader = [
    'scene',
    'planck/concord',
    '(paired)',
    'concord/box2d-wasm',
    '(paired)',
    'awake c/p/b',
    'target',
  ]
  console.log(`${formatTable(ratioHeader, ratioRows)}`)
  console.log(`target: planck/concord >= 5 and concord/box2d-wasm <= 2 (medians), sleep off\n`)
}

function parseOptions() {
  const { values } = parseArgs({
    options: {
      quick: { type: 'boolean', default: false },
      scene: { type: 'string' },
      sleep: { type: 'string', default: 'both' },
      engines: { type: 'string', default: ENGINES.join(',') },
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
    targets: { scenes: TARGET_SCENES, sleep: false, planckOverConcord: 5, concordOverBox2d: 2 },
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
