/*
 * A/B timing of engine versions (`npx tsx bench/engine-ab.ts A=dir B=dir ...`): each argument
 * names an engine/ folder (a scratch git worktree's, say `old=/tmp/wt-old/engine`) or a bundled
 * engine, a .js file (`node scripts/const-bindings.mjs engine/index.ts OUT.js [--plain]`); every version
 * builds the same scene from its own `scenes.ts` blueprint and steps it in one process,
 * interleaved in rounds of `--chunk` steps with the first version rotating, so machine load lands
 * on all versions alike. Prints, per scene and version: median ms per step, CPU ms per step
 * (process.cpuUsage, which leaves out time spent waiting for a core), the paired ratio to the first
 * version (median over rounds of the ratio of the round medians), the ratio of the fastest rounds
 * (the least disturbed by other processes; meaningful for scenes whose cost per step is steady,
 * like the pyramids) and the world hash after the last step (equal hashes: the versions stepped bit-identically). Saves bench/results/engine-ab.json.
 *
 * Flags: --scenes pyramid-20,pyramid-50,pile-1000 (also pile-N for any N), --rounds 40,
 * --chunk 10, --warmup 30, --sleep off|on, --out FILE, --runs K.
 *
 * The version listed first reads a few per cent slow (Nov 28: on pile-1000, 2-3 % in either
 * order), whatever the rotation within a run. `--runs K` (K >= 2) settles it in one command: K
 * runs, each in its own process, the order of the versions reversed every other run; then, per
 * scene and version, the geometric mean over the runs of the paired and CPU ratios to the first
 * version named (the same version in every run, whatever its place), with their range. pile-N-awake is the server capacity scene
 * (bench/server-load.ts awakePile): the pile with every dynamic body's enableSleep false, so with
 * --sleep on the world keeps sleeping enabled and still simulates every body. rooms-K is K such
 * worlds with dragging players, stepped in turn as a room worker does (roomsStepper below); its
 * "step" is one step of every room.
 */
import { spawnSync } from 'node:child_process'
import { cpSync, existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { basename, dirname, join, resolve } from 'node:path'
import { performance } from 'node:perf_hooks'
import { pathToFileURL } from 'node:url'
import { parseArgs } from 'node:util'
import {
  awakeBlueprint,
  type Blueprint,
  type RoomsEngine,
  roomsStepper,
  type Stepper,
} from './rooms-scene.ts'
import { formatTable, machineInfo, median, pairedRatio, saveResults } from './stats.ts'

/**
 * Refuse an engine folder whose nearest package.json does not say `"type": "module"` (say, an
 * engine/ copied alone into /tmp): tsx then compiles it as CommonJS, where every call to an
 * imported function is reached through an export getter (the likely cost); it measured 0.23 against 2.06 ms per step on
 * the same 100-body pile (Nov 24): such a version is not the engine being compared.
 */
function requireModulePackage(label: string, dir: string): void {
  for (let at = resolve(dir); ; at = dirname(at)) {
    const file = join(at, 'package.json')
    if (existsSync(file)) {
      const type = (JSON.parse(readFileSync(file, 'utf8')) as { type?: string }).type
      if (type === 'module') return
      throw new Error(
        `${label}=${dir}: ${file} does not say "type": "module", so tsx would compile it as CommonJS (several times slower)`,
      )
    }
    if (dirname(at) === at)
      throw new Error(
        `${label}=${dir}: no package.json above it says "type": "module", so tsx would compile it as CommonJS (several times slower); put {"type":"module"} in a package.json beside the copy, or use a git worktree`,
      )
  }
}

/**
 * Copies an engine (its folder, or a bundled .js file) into a new temporary folder beside a
 * package.json saying "type": "module"; returns the copy's entry file.
 */
function copyForControl(entry: string, bundled: boolean): string {
  const root = mkdtempSync(join(tmpdir(), 'concord-engine-ab-'))
  writeFileSync(join(root, 'package.json'), '{"type":"module"}\n')
  const target = join(root, 'engine')
  cpSync(bundled ? entry : dirname(entry), bundled ? join(target, basename(entry)) : target, {
    recursive: true,
  })
  return join(target, basename(entry))
}

/** What the benchmark needs from one engine version's index.ts. */
interface EngineModule extends RoomsEngine {
  pyramidScene(rows: number): Blueprint
}

interface Version {
  label: string
  engine: EngineModule
}

interface VersionResult {
  label: string
  medianMs: number
  cpuMsPerStep: number
  pairedToFirst: number
  medianToFirst: number
  cpuToFirst: number
  /** Fastest round (sum of its chunk's steps, ms) over the first version's fastest round. */
  bestToFirst: number
  /** pairedToFirst and cpuToFirst, but to the `--base` version (the first named with --runs). */
  pairedToBase: number
  cpuToBase: number
  hash: number
}

function parseVersion(arg: string): { label: string; dir: string } {
  const eq = arg.indexOf('=')
  if (eq <= 0) throw new Error(`a version is LABEL=ENGINE_DIR, got ${JSON.stringify(arg)}`)
  return { label: arg.slice(0, eq), dir: arg.slice(eq + 1) }
}

function blueprintOf(engine: EngineModule, scene: string): Blueprint {
  const pyramid = /^pyramid-(\d+)$/.exec(scene)
  if (pyramid) return engine.pyramidScene(Number(pyramid[1]))
  const pile = /^pile-(\d+)(-awake)?$/.exec(scene)
  if (pile === null)
    throw new Error(`unknown scene ${JSON.stringify(scene)}: use pyramid-N, pile-N, pile-N-awake or rooms-K`)
  const blueprint = engine.pileScene(Number(pile[1]))
  return pile[2] === undefined ? blueprint : awakeBlueprint(blueprint)
}

function runScene(
  versions: Version[],
  scene: string,
  options: { rounds: number; chunk: number; warmup: number; sleep: boolean; base: number },
): VersionResult[] {
  const rooms = /^rooms-(\d+)$/.exec(scene)
  const worlds: Stepper[] = versions.map(({ engine }) => {
    if (rooms) return roomsStepper(engine, Number(rooms[1]), options.sleep)
    const blueprint = blueprintOf(engine, scene)
    const world = engine.createWorld({ gravity: blueprint.gravity, enableSleep: options.sleep })
    engine.buildScene(world, blueprint)
    return world
  })
  const samples = versions.map(() => [] as number[])
  const cpu = versions.map(() => 0)
  const best = versions.map(() => Number.POSITIVE_INFINITY)
  const total = options.warmup + options.rounds * options.chunk
  for (let round = 0, done = 0; done < total; round++) {
    const count = Math.min(options.chunk, total - done)
    const timed = done >= options.warmup
    for (let k = 0; k < versions.length; k++) {
      const v = (round + k) % versions.length
      const world = worlds[v]
      const cpu0 = process.cpuUsage()
      let sum = 0
      for (let s = 0; s < count; s++) {
        const t0 = performance.now()
        world.step()
        const dt = performance.now() - t0
        sum += dt
        if (timed) samples[v].push(dt)
      }
      const used = process.cpuUsage(cpu0)
      if (timed) cpu[v] += (used.user + used.system) / 1000
      if (timed && count === options.chunk) best[v] = Math.min(best[v], sum)
    }
    done += count
  }
  const steps = samples[0].length
  const base = options.base
  return versions.map((version, v) => ({
    label: version.label,
    medianMs: median(samples[v]),
    cpuMsPerStep: cpu[v] / steps,
    pairedToFirst: pairedRatio(samples[v], samples[0], options.chunk),
    medianToFirst: median(samples[v]) / median(samples[0]),
    cpuToFirst: cpu[v] / cpu[0],
    bestToFirst: best[v] / best[0],
    pairedToBase: pairedRatio(samples[v], samples[base], options.chunk),
    cpuToBase: cpu[v] / cpu[base],
    hash: worlds[v].hash(),
  }))
}

async function main(): Promise<void> {
  const { values, positionals } = parseArgs({
    allowPositionals: true,
    options: {
      scenes: { type: 'string', default: 'pyramid-20,pyramid-50,pile-1000' },
      rounds: { type: 'string', default: '40' },
      chunk: { type: 'string', default: '10' },
      warmup: { type: 'string', default: '30' },
      sleep: { type: 'string', default: 'off' },
      out: { type: 'string' },
      runs: { type: 'string', default: '1' },
      base: { type: 'string' },
    },
  })
  if (positionals.length < 2) throw new Error('give at least two versions: LABEL=ENGINE_DIR ...')
  const runs = Number(values.runs)
  if (!Number.isInteger(runs) || runs < 1)
    throw new Error(`--runs must be a whole number >= 1, got ${values.runs}`)
  if (runs > 1) {
    runInBothOrders(positionals, runs, values)
    return
  }
  const labels = positionals.map((p) => parseVersion(p).label)
  const base = values.base === undefined ? 0 : labels.indexOf(values.base)
  if (base < 0) throw new Error(`--base ${values.base} is not one of the versions (${labels.join(', ')})`)
  const counts = { rounds: Number(values.rounds), chunk: Number(values.chunk), warmup: Number(values.warmup) }
  for (const [name, value] of Object.entries(counts)) {
    if (!Number.isInteger(value) || value < (name === 'warmup' ? 0 : 1)) {
      throw new Error(`--${name} must be a whole number (at least 1, warmup 0), got ${value}`)
    }
  }
  if (values.sleep !== 'off' && values.sleep !== 'on') {
    throw new Error(`--sleep must be off or on, got ${values.sleep}`)
  }
  const versions: Version[] = []
  const loaded = new Set<string>()
  const copies: string[] = []
  for (const { label, dir } of positionals.map(parseVersion)) {
    // A bundled engine (scripts/const-bindings.mjs builds one either way) is imported as it is.
    const bundled = /\.m?js$/.test(dir)
    if (!bundled) requireModulePackage(label, dir)
    let path = bundled ? resolve(dir) : resolve(dir, 'index.ts')
    if (loaded.has(path)) {
      // The same folder again (an A/A control): imported from the same files it would be the same
      // module, sharing the first version's compiled code and type feedback, unlike every other
      // version. A copy in its own folder is its own module. (On pile-1000 at load 1, Nov 28, the
      // two kinds of control read alike within their noise.)
      path = copyForControl(path, bundled)
      copies.push(dirname(path))
      console.error(`${label}: a copy of ${dir} in ${dirname(path)} (its own module)`)
    }
    loaded.add(path)
    versions.push({ label, engine: (await import(pathToFileURL(path).href)) as EngineModule })
  }
  process.on('exit', () => {
    for (const dir of copies) rmSync(dirname(dir), { recursive: true, force: true })
  })
  const machine = machineInfo()
  console.error(`engine A/B, node ${machine.node}, load ${machine.loadAverage.toFixed(2)}`)
  const results: { scene: string; versions: VersionResult[] }[] = []
  const rows: string[][] = []
  for (const scene of values.scenes.split(',')) {
    const t0 = performance.now()
    const out = runScene(versions, scene, { ...counts, sleep: values.sleep === 'on', base })
    console.error(`  ${scene}: ${((performance.now() - t0) / 1000).toFixed(1)} s`)
    results.push({ scene, versions: out })
    for (const r of out) {
      rows.push([
        scene,
        r.label,
        r.medianMs.toFixed(3),
        r.cpuMsPerStep.toFixed(3),
        r.pairedToFirst.toFixed(3),
        r.medianToFirst.toFixed(3),
        r.cpuToFirst.toFixed(3),
        r.bestToFirst.toFixed(3),
        `0x${r.hash.toString(16).padStart(8, '0')}`,
      ])
    }
  }
  const header = [
    'scene',
    'version',
    'median ms',
    'cpu ms',
    'paired/first',
    'median/first',
    'cpu/first',
    'best/first',
    'hash',
  ]
  console.log(formatTable(header, rows))
  const loadAtEnd = machineInfo().loadAverage
  console.log(`load average ${machine.loadAverage.toFixed(2)} at start, ${loadAtEnd.toFixed(2)} at end`)
  const path = values.out ?? new URL('./results/engine-ab.json', import.meta.url).pathname
  saveResults(path, { benchmark: 'engine-ab', machine: { ...machine, loadAtEnd }, counts, results })
}

/**
 * `--runs K`: K runs of this benchmark, one process each (so every run compiles every version
 * afresh), the versions in the given order in even runs and reversed in odd ones; prints and saves,
 * per scene and version, the geometric means and ranges of the paired and CPU ratios to the first
 * version named, and each run's.
 */
function runInBothOrders(
  positionals: string[],
  runs: number,
  values: Record<string, string | undefined>,
): void {
  const base = parseVersion(positionals[0]).label
  const dir = mkdtempSync(join(tmpdir(), 'concord-engine-ab-runs-'))
  const flags = ['scenes', 'rounds', 'chunk', 'warmup', 'sleep'].flatMap((f) => [`--${f}`, String(values[f])])
  const perRun: { order: string[]; results: { scene: string; versions: VersionResult[] }[] }[] = []
  try {
    for (let run = 0; run < runs; run++) {
      const order = run % 2 === 0 ? positionals : [...positionals].reverse()
      const out = join(dir, `run-${run}.json`)
      const labels = order.map((p) => parseVersion(p).label)
      console.error(`run ${run + 1} of ${runs}: ${labels.join(', ')}`)
      const child = spawnSync(
        process.execPath,
        [...process.execArgv, process.argv[1], ...order, ...flags, '--base', base, '--out', out],
        { stdio: ['ignore', 'ignore', 'inherit'] },
      )
      if (child.status !== 0) throw new Error(`run ${run + 1} failed (exit ${child.status ?? child.signal})`)
      const saved = JSON.parse(readFileSync(out, 'utf8')) as {
        results: { scene: string; versions: VersionResult[] }[]
      }
      perRun.push({ order: labels, results: saved.results })
    }
  } finally {
    rmSync(dir, { recursive: true, force: true })
  }
  const geometricMean = (xs: number[]): number =>
    Math.exp(xs.reduce((sum, x) => sum + Math.log(x), 0) / xs.length)
  const range = (xs: number[]): string => `${Math.min(...xs).toFixed(3)}-${Math.max(...xs).toFixed(3)}`
  const rows: string[][] = []
  const summary: {
    scene: string
    label: string
    paired: number
    cpu: number
    pairedRuns: number[]
    cpuRuns: number[]
  }[] = []
  for (const { scene } of perRun[0].results) {
    for (const p of positionals) {
      const label = parseVersion(p).label
      const of = perRun.map(
        (r) =>
          r.results.find((x) => x.scene === scene)?.versions.find((v) => v.label === label) as VersionResult,
      )
      const pairedRuns = of.map((v) => v.pairedToBase)
      const cpuRuns = of.map((v) => v.cpuToBase)
      const paired = geometricMean(pairedRuns)
      const cpu = geometricMean(cpuRuns)
      summary.push({ scene, label, paired, cpu, pairedRuns, cpuRuns })
      rows.push([scene, label, paired.toFixed(3), range(pairedRuns), cpu.toFixed(3), range(cpuRuns)])
    }
  }
  console.log(`${runs} runs, orders alternating; ratios to ${base}, geometric means over the runs`)
  console.log(formatTable(['scene', 'version', `paired/${base}`, 'range', `cpu/${base}`, 'range'], rows))
  const path = values.out ?? new URL('./results/engine-ab.json', import.meta.url).pathname
  saveResults(path, { benchmark: 'engine-ab', runs, base, machine: machineInfo(), summary, perRun })
}

await main()
