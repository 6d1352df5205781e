/*
 * The benchmark page (bench.html): the comparison of `npm run bench:peers`, run in the visitor's
 * own browser. Pick a scene, a body count and the engines; every engine builds the same blueprint
 * (bench/bench-scenes.ts through the same adapters as the terminal benchmark) and they run in
 * interleaved rounds on this page's thread: each round every engine takes a few steps, the
 * engine that goes first rotates, then the page draws each scene small beside its live step-time
 * chart. Warm-up rounds are excluded. At the end, a table: mean, median and p95 ms per step,
 * Concord's time over each engine's (the median over rounds of the two engines' times in the same
 * round) with its range over the run's quarters (the spread), and the end state. The default run is
 * 1,000 timed steps: on a 2-core machine at load 9-12, four runs of pyramid-20 at 120 steps read
 * Concord / matter-js from 0.68 to 1.01 (ratio of means: 0.40 to 1.06); at 1,000, within 6.1 % and
 * 0.7 % in two sets of four (ratio of means: 9.8 % and 26.2 %). Each step is timed with performance.now(),
 * which browsers coarsen (to 0.1 ms in Chromium for a page that is not cross-origin isolated, as
 * this one is not): the page measures that resolution and states it, since a step faster than it
 * mostly reads 0 (the mean over many steps still estimates the time; a median can be 0).
 *
 * On every run the page also checks Concord's broadphase: at the end of every quarter of the run
 * it compares the pairs its tree reports with the pairs a brute-force loop finds over the same
 * boxes (bench/broad-phase-check.ts), and shows the result.
 *
 * The wasm peers' binaries are copied next to this page (wasm/), found relative to the page's
 * own address, so the page works under any base path. window.concordBench exposes the state and
 * run() for the browser test.
 */
import { BENCH_SCENES, benchScene } from '../bench-scenes.ts'
import { type BroadPhaseCheck, checkBroadPhase } from '../broad-phase-check.ts'
import { PeerRun } from '../peer-run.ts'
import {
  type ConcordPeer,
  isPeerEngine,
  PEER_DESCRIPTIONS,
  PEER_ENGINES,
  type PeerEngine,
  setWasmLocator,
} from '../peers/index.ts'
import { allBodies, type SceneQuality } from '../scene-quality.ts'
import { medianRoundRatio, quarterRatios, type Summary, summarize } from '../summary.ts'
import { drawScene, drawTimes, sceneBounds } from './bench-view.ts'

/** What to run. */
export interface BenchOptions {
  scene: string
  count: number
  steps: number
  sleep: boolean
  engines: PeerEngine[]
}

/** One engine's outcome. */
export interface PageResult {
  engine: PeerEngine
  steps: Summary | null
  quality: SceneQuality | null
  /** Concord's mean over this engine's mean (below 1: Concord is faster); null when a mean read 0. */
  concordOverThis: number | null
  /**
   * The ratio the table shows: the median over rounds of Concord's round time over this engine's
   * (the engines take turns inside every round, so both meet the same machine load, and a burst of
   * load slows a few rounds, not their median).
   */
  roundRatio: number | null
  /** Its spread: the same median in each quarter of the run, lowest and highest. */
  ratioRange: { low: number; high: number } | null
  error: string | null
}

/** The page's state, read by the browser test. */
export interface BenchState {
  status: 'idle' | 'running' | 'done' | 'error'
  error: string | null
  options: BenchOptions | null
  results: PageResult[]
  broadPhase: BroadPhaseCheck[]
  /** The smallest step of this page's performance.now() (ms), measured when a run starts. */
  timerResolutionMs: number | null
}

const CHUNK_STEPS = 5
const COLORS = ['#ff6b5b', '#5bc0ff', '#7ddc6f', '#ffb347', '#c792ea', '#d4a373', '#f78fb3', '#aab2bf']
const $ = <T extends HTMLElement>(id: string): T => {
  const el = document.getElementById(id)
  if (!el) throw new Error(`bench.html has no #${id}`)
  return el as T
}
const yieldToPage = (): Promise<void> => new Promise((resolve) => setTimeout(resolve, 0))

setWasmLocator((file) => new URL(`wasm/${file}`, document.baseURI).href)

const state: BenchState = {
  status: 'idle',
  error: null,
  options: null,
  results: [],
  broadPhase: [],
  timerResolutionMs: null,
}

/** The smallest step of performance.now() seen in 20 tries (ms): what one timed step can resolve. */
function timerResolutionMs(): number {
  let smallest = Number.POSITIVE_INFINITY
  for (let i = 0; i < 20; i++) {
    const t0 = performance.now()
    let t1 = performance.now()
    while (t1 === t0) t1 = performance.now()
    smallest = Math.min(smallest, t1 - t0)
  }
  return smallest
}

interface Lane {
  engine: PeerEngine
  run: PeerRun | null
  times: number[]
  roundMeans: number[]
  error: string | null
  view: HTMLCanvasElement
  chart: HTMLCanvasElement
  label: HTMLElement
}

function makeLane(engine: PeerEngine, index: number): Lane {
  const card = document.createElement('div')
  card.className = 'lane'
  card.innerHTML = `<div class="name" style="color:${COLORS[index % COLORS.length]}">${engine}</div><canvas width="240" height="150"></canvas><canvas width="240" height="60"></canvas><div class="figure"></div>`
  card.title = PEER_DESCRIPTIONS[engine]
  $('lanes').append(card)
  const [view, chart] = card.querySelectorAll('canvas')
  return {
    engine,
    run: null,
    times: [],
    roundMeans: [],
    error: null,
    view,
    chart,
    label: card.querySelector('.figure') as HTMLElement,
  }
}

function showBroadPhase(): void {
  const checks = state.broadPhase
  const last = checks[checks.length - 1]
  const ok = checks.every((c) => c.match)
  $('broadphase').textContent =
    checks.length === 0
      ? 'Broadphase check: Concord was not in this run.'
      : `Broadphase check: ${ok ? 'PASSED' : 'FAILED'} ${checks.length} times; last: the tree found ${last.treePairs} pairs among ${last.proxies} proxies, brute force ${last.bruteForcePairs}${ok ? '' : ` (first difference ${checks.find((c) => !c.match)?.firstDifference})`}.`
  $('broadphase').className = ok ? 'ok' : 'bad'
}

function showTable(): void {
  const fmt = (x: number | null | undefined, d = 3): string =>
    x === null || x === undefined || !Number.isFinite(x) ? '-' : x.toFixed(d)
  const rows = state.results.map((r) => {
    const q = r.quality
    const cells = r.error
      ? [r.engine, `failed: ${r.error}`, '', '', '', '', '', '']
      : [
          r.engine,
          fmt(r.steps?.mean),
          fmt(r.steps?.median),
          fmt(r.steps?.p95),
          `${fmt(r.roundRatio, 2)}${r.ratioRange ? ` (${fmt(r.ratioRange.low, 2)}-${fmt(r.ratioRange.high, 2)})` : ''}`,
          q?.verdict ?? '-',
          fmt(q?.maxDrift, 2),
          fmt(q?.maxStretch, 3),
        ]
    return `<tr>${cells.map((c) => `<td>${c}</td>`).join('')}</tr>`
  })
  $('results').innerHTML =
    `<table><thead><tr><th>engine</th><th>mean ms</th><th>median</th><th>p95</th><th title="The median over rounds of Concord's round time over this engine's; in brackets the lowest and highest of that median over the run's four quarters">concord / this (quarters)</th><th>end state</th><th>drift m</th><th>joint stretch m</th></tr></thead><tbody>${rows.join('')}</tbody></table>`
}

function draw(
  lanes: Lane[],
  bodies: ReturnType<typeof allBodies>,
  bounds: ReturnType<typeof sceneBounds>,
): void {
  const maxMs = Math.max(0.01, ...lanes.flatMap((l) => l.roundMeans))
  lanes.forEach((lane, i) => {
    if (lane.run) drawScene(lane.view, bodies, lane.run.readBodies(), bounds)
    drawTimes(lane.chart, lane.roundMeans, maxMs, COLORS[i % COLORS.length])
    const mean = lane.times.length ? lane.times.reduce((a, b) => a + b, 0) / lane.times.length : Number.NaN
    lane.label.textContent = lane.error
      ? `failed: ${lane.error}`
      : `${Number.isFinite(mean) ? mean.toFixed(2) : '-'} ms/step`
  })
}

async function runBench(options: BenchOptions): Promise<BenchState> {
  if (state.status === 'running') throw new Error('a run is already in progress')
  Object.assign(state, { status: 'running', error: null, options, results: [], broadPhase: [] })
  state.timerResolutionMs = timerResolutionMs()
  ;($('scene') as HTMLSelectElement).value = options.scene
  ;($('count') as HTMLInputElement).value = String(options.count)
  ;($('steps') as HTMLInputElement).value = String(options.steps)
  ;($('sleep') as HTMLInputElement).checked = options.sleep
  for (const e of PEER_ENGINES) ($(`engine-${e}`) as HTMLInputElement).checked = options.engines.includes(e)
  $('lanes').replaceChildren()
  $('results').replaceChildren()
  $('status').textContent = 'building...'
  try {
    const scene = benchScene(options.scene)
    const lanes = options.engines.map((engine, i) => makeLane(engine, i))
    for (const lane of lanes) {
      try {
        lane.run = await PeerRun.start(lane.engine, scene, options.count, options.sleep)
      } catch (error) {
        lane.error = error instanceof Error ? error.message : String(error)
      }
    }
    const running = lanes.filter((l) => l.run !== null)
    const first = running[0]?.run
    const bodies = first ? allBodies(first.instance.blueprint, first.instance.arrivals) : []
    const bounds = sceneBounds(bodies)
    const warmupRounds = Math.ceil(Math.min(20, options.steps / 4) / CHUNK_STEPS)
    const warmup = warmupRounds * CHUNK_STEPS
    const rounds = warmupRounds + Math.ceil(options.steps / CHUNK_STEPS)
    const checkEvery = Math.max(1, Math.ceil(rounds / 4))
    const concord = lanes.find((l) => l.engine === 'concord')?.run?.peer as ConcordPeer | undefined
    for (let round = 0; round < rounds; round++) {
      for (let k = 0; k < running.length; k++) {
        const lane = running[(round + k) % running.length]
        const sink: number[] = []
        ;(lane.run as PeerRun).stepChunk(CHUNK_STEPS, sink)
        if (round >= warmupRounds) lane.times.push(...sink)
        lane.roundMeans.push(sink.reduce((a, b) => a + b, 0) / sink.length)
      }
      if (concord && ((round + 1) % checkEvery === 0 || round === rounds - 1)) {
        state.broadPhase.push(checkBroadPhase(concord.world))
        showBroadPhase()
      }
      $('status').textContent =
        `round ${round + 1} of ${rounds} (${CHUNK_STEPS} steps per engine per round, ${warmup} warm-up steps excluded)`
      draw(lanes, bodies, bounds)
      await yieldToPage()
    }
    const concordLane = lanes.find((l) => l.engine === 'concord' && l.run)
    const concordMean = concordLane?.times
    const cMean = concordMean?.length ? summarize(concordMean).mean : null
    state.results = lanes.map((lane) => {
      if (!lane.run)
        return {
          engine: lane.engine,
          steps: null,
          quality: null,
          concordOverThis: null,
          ratioRange: null,
          roundRatio: null,
          error: lane.error,
        }
      const steps = summarize(lane.times)
      const quality = lane.run.quality()
      lane.run.dispose()
      return {
        engine: lane.engine,
        steps,
        quality,
        concordOverThis: cMean === null || cMean === 0 || steps.mean === 0 ? null : cMean / steps.mean,
        ratioRange: concordLane ? quarterRatios(concordLane.times, lane.times, CHUNK_STEPS) : null,
        roundRatio: concordLane ? medianRoundRatio(concordLane.times, lane.times, CHUNK_STEPS) : null,
        error: null,
      }
    })
    if (concord === undefined) showBroadPhase()
    showTable()
    state.status = 'done'
    $('status').textContent =
      `done: ${options.steps} timed steps of ${scene.name} (${options.count} bodies, sleep ${options.sleep ? 'on' : 'off'}); ` +
      `this browser's timer resolves ${state.timerResolutionMs.toFixed(3)} ms, so a step faster than that mostly reads 0`
  } catch (error) {
    state.status = 'error'
    state.error = error instanceof Error ? error.message : String(error)
    $('status').textContent = `error: ${state.error}`
  }
  return state
}

function readForm(): BenchOptions {
  const count = Number(($('count') as HTMLInputElement).value)
  const steps = Number(($('steps') as HTMLInputElement).value)
  if (!(Number.isInteger(count) && count >= 2 && count <= 20000))
    throw new Error(`body count must be an integer 2..20000, got ${count}`)
  if (!(Number.isInteger(steps) && steps >= 5 && steps <= 5000))
    throw new Error(`steps must be an integer 5..5000, got ${steps}`)
  const engines = PEER_ENGINES.filter((e) => ($(`engine-${e}`) as HTMLInputElement).checked)
  return {
    scene: ($('scene') as HTMLSelectElement).value,
    count,
    steps,
    sleep: ($('sleep') as HTMLInputElement).checked,
    engines,
  }
}

function setUp(): void {
  const select = $('scene') as HTMLSelectElement
  for (const scene of BENCH_SCENES) select.add(new Option(`${scene.name}: ${scene.description}`, scene.name))
  const params = new URLSearchParams(location.search)
  const chosen = params.get('scene')
  if (chosen && BENCH_SCENES.some((s) => s.name === chosen)) select.value = chosen
  const count = $('count') as HTMLInputElement
  const syncCount = (): void => {
    count.value = String(benchScene(select.value).defaultCount)
  }
  syncCount()
  select.addEventListener('change', syncCount)
  if (params.get('count')) count.value = params.get('count') as string
  if (params.get('steps')) ($('steps') as HTMLInputElement).value = params.get('steps') as string
  const wanted = (params.get('engines') ?? PEER_ENGINES.join(',')).split(',').filter(isPeerEngine)
  $('engines').innerHTML = PEER_ENGINES.map(
    (e) =>
      `<label title="${PEER_DESCRIPTIONS[e]}"><input type="checkbox" id="engine-${e}"${wanted.includes(e) ? ' checked' : ''}> ${e}</label>`,
  ).join(' ')
  $('run').addEventListener('click', () => {
    try {
      void runBench(readForm())
    } catch (error) {
      $('status').textContent = error instanceof Error ? error.message : String(error)
    }
  })
}

declare global {
  interface Window {
    /** The benchmark page's state and runner, for the browser test and the console. */
    concordBench: { state: BenchState; run(options: BenchOptions): Promise<BenchState> }
  }
}

setUp()
window.concordBench = { state, run: runBench }
