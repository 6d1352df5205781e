/*
 * The cross-engine comparison (`npm run bench:peers`): Concord and seven peers on the scenes of
 * bench/bench-scenes.ts, sleep off and on, then the pile at 250 to 16,000 bodies for Concord and
 * the two fastest peers.
 *
 * Each engine runs in its own child process (bench/peer-child.ts). The parent interleaves them:
 * every round, each child in turn takes a chunk of steps while the others wait, and the engine
 * that goes first rotates. Machine noise on this shared two-core machine therefore lands on all
 * engines alike, and every engine is sampled at the same simulated time. Warm-up steps are taken
 * the same way and thrown away. Per engine we report mean, median and p95 ms per step, CPU ms per
 * step (process.cpuUsage of the child), peak resident memory of the child, and the scene's end
 * state (bench/scene-quality.ts). Ratios are Concord's time over each peer's: below 1, Concord is
 * faster. Ratios within one run are the numbers to compare; absolute times move with the load.
 *
 * Flags: --quick (few steps: a smoke run), --scenes a,b, --engines a,b, --sleep off|on|both,
 * --scaling only|no|yes, --out FILE (default bench/results/peers.json, peers-quick.json with --quick).
 */
import { type ChildProcess, fork } from 'node:child_process'
import { writeFileSync } from 'node:fs'
import { dirname, join } from 'node:path'
import { parseArgs } from 'node:util'
import { BENCH_SCENES, type BenchScene, benchScene } from './bench-scenes.ts'
import type { ChildCommand, ChildReply } from './peer-child.ts'
import { isPeerEngine, PEER_ENGINES, type PeerEngine } from './peers/index.ts'
import { peersMarkdown } from './peers-markdown.ts'
import { printCases, printScaling } from './peers-report.ts'
import type { SceneQuality } from './scene-quality.ts'
import { machineInfo, type Summary, saveResults, summarize } from './stats.ts'
import { barChart, lineChart } from './svg-chart.ts'

/** Steps each engine takes per round before the next engine's turn. */
const CHUNK_STEPS = 10
/** Pile sizes of the scaling run, with the timed steps at each (fewer at large sizes). */
const SCALING = [
  { count: 250, steps: 100 },
  { count: 1000, steps: 60 },
  { count: 4000, steps: 30 },
  { count: 16000, steps: 15 },
]
const CHILD = new URL('./peer-child.ts', import.meta.url).pathname

/** One engine's numbers on one case. */
export interface EngineRow {
  engine: PeerEngine
  bodies: number
  buildMs: number
  steps: Summary
  cpuMsPerStep: number
  peakRssMB: number
  /** Peak memory over the child's memory after loading Node and before building (MB). */
  sceneRssMB: number
  quality: SceneQuality
}

/** One scene at one body count and sleep setting, every engine interleaved. */
export interface CaseResult {
  scene: string
  count: number
  sleep: boolean
  warmupSteps: number
  timedSteps: number
  rows: EngineRow[]
  /** Concord's mean step time over each peer's (below 1: Concord is faster). */
  concordOverMean: Partial<Record<PeerEngine, number>>
  /** The same on medians. */
  concordOverMedian: Partial<Record<PeerEngine, number>>
}

/** One engine in its child process, answering one command at a time. */
class Child {
  private readonly process: ChildProcess
  private pending: { resolve: (reply: ChildReply) => void; reject: (error: Error) => void } | null = null

  constructor(readonly engine: PeerEngine) {
    this.process = fork(CHILD, [], {
      execArgv: ['--import', 'tsx'],
      stdio: ['ignore', 'inherit', 'inherit', 'ipc'],
    })
    this.process.on('message', (reply: ChildReply) => {
      const pending = this.pending
      this.pending = null
      pending?.resolve(reply)
    })
    this.process.on('exit', (code) => {
      const pending = this.pending
      this.pending = null
      pending?.reject(new Error(`${engine} child exited with code ${code}`))
    })
  }

  async request<T extends ChildReply['type']>(
    command: ChildCommand,
    expect: T,
  ): Promise<Extract<ChildReply, { type: T }>> {
    const reply = await new Promise<ChildReply>((resolve, reject) => {
      this.pending = { resolve, reject }
      this.process.send(command)
    })
    if (reply.type === 'error') throw new Error(`${this.engine}: ${reply.message}`)
    if (reply.type !== expect) throw new Error(`${this.engine}: expected ${expect}, got ${reply.type}`)
    return reply as Extract<ChildReply, { type: T }>
  }

  kill(): void {
    this.pending = null
    this.process.kill()
  }
}

async function interleave(
  children: Child[],
  steps: number,
  samples: number[][],
  cpu: number[],
): Promise<void> {
  const rounds = Math.ceil(steps / CHUNK_STEPS)
  for (let round = 0; round < rounds; round++) {
    const count = Math.min(CHUNK_STEPS, steps - round * CHUNK_STEPS)
    for (let k = 0; k < children.length; k++) {
      const e = (round + k) % children.length
      const ran = await children[e].request({ type: 'run', steps: count }, 'ran')
      samples[e].push(...ran.times)
      cpu[e] += ran.cpuMs
    }
  }
}

async function runCase(
  scene: BenchScene,
  count: number,
  sleep: boolean,
  engines: readonly PeerEngine[],
  warmupSteps: number,
  timedSteps: number,
): Promise<CaseResult> {
  const children = engines.map((engine) => new Child(engine))
  try {
    const built = []
    for (const child of children) {
      built.push(
        await child.request(
          { type: 'build', engine: child.engine, scene: scene.name, count, sleep },
          'built',
        ),
      )
    }
    await interleave(
      children,
      warmupSteps,
      children.map(() => []),
      children.map(() => 0),
    )
    const samples = children.map(() => [] as number[])
    const cpu = children.map(() => 0)
    await interleave(children, timedSteps, samples, cpu)
    const rows: EngineRow[] = []
    for (const [e, child] of children.entries()) {
      const finished = await child.request({ type: 'finish' }, 'finished')
      rows.push({
        engine: child.engine,
        bodies: built[e].bodies,
        buildMs: built[e].buildMs,
        steps: summarize(samples[e]),
        cpuMsPerStep: cpu[e] / timedSteps,
        peakRssMB: finished.peakRssMB,
        sceneRssMB: finished.peakRssMB - built[e].baseRssMB,
        quality: finished.quality,
      })
    }
    const concord = rows.find((r) => r.engine === 'concord')
    const concordOverMean: CaseResult['concordOverMean'] = {}
    const concordOverMedian: CaseResult['concordOverMedian'] = {}
    for (const row of rows) {
      if (!concord || row === concord) continue
      concordOverMean[row.engine] = concord.steps.mean / row.steps.mean
      concordOverMedian[row.engine] = concord.steps.median / row.steps.median
    }
    return {
      scene: scene.name,
      count,
      sleep,
      warmupSteps,
      timedSteps,
      rows,
      concordOverMean,
      concordOverMedian,
    }
  } finally {
    for (const child of children) child.kill()
  }
}

function parseOptions() {
  const { values } = parseArgs({
    options: {
      quick: { type: 'boolean', default: false },
      scenes: { type: 'string', default: BENCH_SCENES.map((s) => s.name).join(',') },
      engines: { type: 'string', default: PEER_ENGINES.join(',') },
      sleep: { type: 'string', default: 'both' },
      scaling: { type: 'string', default: 'yes' },
      out: { type: 'string' },
    },
  })
  const scenes = values.scenes.split(',').map((name) => benchScene(name.trim()))
  const engines = values.engines.split(',').map((name) => name.trim())
  const unknown = engines.filter((name) => !isPeerEngine(name))
  if (unknown.length > 0)
    throw new Error(`unknown --engines ${unknown.join(',')}; choose from ${PEER_ENGINES.join(',')}`)
  const sleeps = { off: [false], on: [true], both: [false, true] }[values.sleep]
  if (!sleeps) throw new Error(`--sleep must be off, on or both, got ${values.sleep}`)
  if (!['yes', 'no', 'only'].includes(values.scaling))
    throw new Error(`--scaling must be yes, no or only, got ${values.scaling}`)
  const out =
    values.out ?? new URL(`./results/peers${values.quick ? '-quick' : ''}.json`, import.meta.url).pathname
  return {
    quick: values.quick,
    scenes,
    engines: engines as PeerEngine[],
    sleeps,
    scaling: values.scaling,
    out,
  }
}

/** Concord plus the two peers with the lowest mean on pile-1000 with sleep off (box2d3-wasm and rapier by default). */
function scalingEngines(cases: readonly CaseResult[], engines: readonly PeerEngine[]): PeerEngine[] {
  const pile = cases.find((c) => c.scene === 'pile-1000' && !c.sleep)
  const peers = pile
    ? pile.rows
        .filter((r) => r.engine !== 'concord')
        .sort((a, b) => a.steps.mean - b.steps.mean)
        .map((r) => r.engine)
    : engines.filter((e): e is PeerEngine => e === 'box2d3-wasm' || e === 'rapier')
  return ['concord', ...peers.slice(0, 2)]
}

function writeCharts(out: string, cases: readonly CaseResult[], scaling: readonly CaseResult[]): string[] {
  const written: string[] = []
  const base = join(dirname(out), out.endsWith('-quick.json') ? 'peers-quick' : 'peers')
  for (const sleep of [false, true]) {
    const chosen = cases.filter((c) => c.sleep === sleep)
    if (chosen.length === 0) continue
    const engines = [...new Set(chosen.flatMap((c) => c.rows.map((r) => r.engine)))]
    const series = engines.map((engine) => ({
      name: engine,
      values: chosen.map((c) => c.rows.find((r) => r.engine === engine)?.steps.mean ?? null),
    }))
    const file = `${base}-sleep-${sleep ? 'on' : 'off'}.svg`
    const title = `Mean ms per 1/60 s step, sleep ${sleep ? 'on' : 'off'} (shorter is faster)`
    writeFileSync(
      file,
      barChart(
        title,
        'ms per step',
        chosen.map((c) => c.scene),
        series,
      ),
    )
    written.push(file)
  }
  if (scaling.length > 0) {
    const engines = [...new Set(scaling.flatMap((c) => c.rows.map((r) => r.engine)))]
    const series = engines.map((engine) => ({
      name: engine,
      points: scaling.flatMap((c) => {
        const row = c.rows.find((r) => r.engine === engine)
        return row ? [[c.count, (row.steps.mean * 1000) / c.count] as const] : []
      }),
    }))
    const file = `${base}-scaling.svg`
    writeFileSync(
      file,
      lineChart('Pile, sleep off: microseconds per body per step', 'bodies', 'us per body', series),
    )
    written.push(file)
  }
  return written
}

async function main(): Promise<void> {
  const options = parseOptions()
  const machine = machineInfo()
  console.error(
    `peers bench on ${machine.cpu} x${machine.cores}, node ${machine.node}, load ${machine.loadAverage.toFixed(2)}`,
  )
  const warmup = options.quick ? 5 : 30
  const cases: CaseResult[] = []
  if (options.scaling !== 'only') {
    for (const scene of options.scenes) {
      for (const sleep of options.sleeps) {
        const steps = options.quick ? 20 : scene.steps
        const t0 = performance.now()
        cases.push(await runCase(scene, scene.defaultCount, sleep, options.engines, warmup, steps))
        const seconds = ((performance.now() - t0) / 1000).toFixed(1)
        console.error(`  ${scene.name} sleep ${sleep ? 'on' : 'off'}: ${steps} steps in ${seconds} s`)
      }
    }
    printCases(cases)
  }
  const scaling: CaseResult[] = []
  if (options.scaling !== 'no') {
    const engines = scalingEngines(cases, options.engines)
    for (const size of options.quick ? SCALING.slice(0, 2) : SCALING) {
      const steps = options.quick ? 10 : size.steps
      const t0 = performance.now()
      scaling.push(await runCase(benchScene('pile-1000'), size.count, false, engines, warmup, steps))
      console.error(
        `  scaling pile ${size.count}: ${steps} steps in ${((performance.now() - t0) / 1000).toFixed(1)} s`,
      )
    }
    printScaling(scaling)
  }
  const finished = { ...machine, loadAverageAtEnd: machineInfo().loadAverage }
  const settings = { stepSeconds: 1 / 60, chunkSteps: CHUNK_STEPS, warmupSteps: warmup, scaling: SCALING }
  saveResults(options.out, {
    benchmark: 'peers',
    quick: options.quick,
    machine: finished,
    settings,
    cases,
    scaling,
  })
  const markdown = options.out.replace(/\.json$/, '.md')
  writeFileSync(markdown, peersMarkdown(cases, scaling))
  const charts = writeCharts(options.out, cases, scaling)
  console.error(`saved ${options.out}, ${markdown} and ${charts.join(', ')}`)
}

await main()
