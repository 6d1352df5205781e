/*
 * Replay seek benchmark (`npm run bench:replay-seek`): a 10-minute session of a 210-body pyramid
 * room with a player dragging bodies around and spawning, recorded by the server's recorder with
 * keyframes every 300, 600 (the default) and 1,200 ticks under the default keyframe budget, and
 * every 600 with no budget, at once (four recorders on one room), then the player's seek
 * (client/replay/replay-player.ts, the code the browser runs) timed to random ticks of each log, in Node.
 * Also the chain cost: a seek to exactly the keyframe with the longest delta chain (a restore
 * through the chain, no ticks replayed). Prints and saves bench/results/replay-seek.json: log
 * sizes, keyframes (whole, delta, the longest gap and chain) and seek times (median, p95, max).
 * Wall-clock figures from a shared machine: compare within one run.
 */

import { mkdir, mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { cpus, loadavg, tmpdir } from 'node:os'
import { join } from 'node:path'
import { performance } from 'node:perf_hooks'
import { inflateSync } from 'node:zlib'
import pino from 'pino'
import { Counter } from 'prom-client'
import { ReplayPlayer, readLog } from '../client/index.ts'
import { Prng } from '../engine/index.ts'
import { sandbox } from '../games/index.ts'
import { RoomRecorder, SETTINGS } from '../server/index.ts'
import { RoomSimulation } from '../shared/index.ts'

const TICKS = Number(process.env.SEEK_BENCH_TICKS ?? 36_000)
const BUDGET = (SETTINGS.find((s) => s.key === 'keyframeBudget')!.fallback as number) * 1_000_000
const VARIANTS = [
  { keyframeTicks: 300, budget: BUDGET },
  { keyframeTicks: 600, budget: BUDGET },
  { keyframeTicks: 1200, budget: BUDGET },
  { keyframeTicks: 600, budget: 0 },
]
const SEEKS = 15

const inflate = (bytes: Uint8Array): Uint8Array => new Uint8Array(inflateSync(bytes))
const quantile = (sorted: number[], q: number): number =>
  sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))]

async function record(): Promise<Array<{ keyframeTicks: number; budget: number; bytes: Uint8Array }>> {
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'seek',
    scene: 'pyramid',
    maxBodies: 1500,
    controls: true,
  })
  const recorders = await Promise.all(
    VARIANTS.map(async ({ keyframeTicks, budget }, i) => {
      const dir = await mkdtemp(join(tmpdir(), `concord-seek-${keyframeTicks}-`))
      const recorder = new RoomRecorder('seek', sim, {
        dir,
        fsync: 'none',
        keyframeTicks,
        keyframeBudget: budget,
        maxBytes: 1 << 30,
        compress: true,
        log: pino({ level: 'silent' }),
        failures: new Counter({ name: `bench_failures_${i}`, help: 'bench', registers: [] }),
        openNames: new Set(),
      })
      recorder.start(0)
      return { keyframeTicks, budget, dir, recorder }
    }),
  )
  sim.join(1, 'dragger', '#e6194b')
  const rng = new Prng(7)
  let grabbed = 0
  while (sim.tick < TICKS) {
    const t = sim.tick
    if (t % 600 === 10) {
      const dynamic = sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')
      grabbed = dynamic[Math.floor(rng.next() * dynamic.length)] ?? 0
      if (grabbed) sim.apply(1, { k: 'grab', body: grabbed, lx: 0, ly: 0 })
    }
    if (grabbed && t % 2 === 0)
      sim.apply(1, { k: 'move', x: Math.sin(t / 40) * 6, y: 4 + Math.cos(t / 55) * 2 })
    if (t % 600 === 400) {
      sim.apply(1, { k: 'release' })
      grabbed = 0
    }
    if (t % 1800 === 900)
      sim.apply(1, { k: 'spawn', shape: { type: 'circle', radius: 0.4 }, x: 0, y: 14, vx: 0, vy: 0 })
    if (t % 18_000 === 17_000) sim.apply(1, { k: 'reset' })
    sim.runTick()
    // The event loop turns as in a server (compression results come back between ticks).
    if (sim.tick % 60 === 0) await Promise.all(recorders.map((r) => r.recorder.flush()))
  }
  const out = []
  for (const r of recorders) {
    await r.recorder.close('bench over')
    out.push({
      keyframeTicks: r.keyframeTicks,
      budget: r.budget,
      bytes: new Uint8Array(await readFile(join(r.dir, r.recorder.name))),
    })
  }
  return out
}

async function main(): Promise<void> {
  const began = performance.now()
  const logs = await record()
  console.log(
    `recorded ${TICKS} ticks (${(TICKS / 3600).toFixed(1)} min) in ${((performance.now() - began) / 1000).toFixed(1)} s`,
  )
  const rng = new Prng(11)
  const targets = Array.from({ length: SEEKS }, () => Math.floor(rng.next() * TICKS))
  const rows = []
  for (const { keyframeTicks, budget, bytes } of logs) {
    const log = await readLog(bytes)
    // Without the player's own snapshots (which earlier seeks would leave behind): this times
    // seeks through the log's keyframes, as the keyframe interval and budget set them.
    const player = await ReplayPlayer.open(log, inflate, undefined, { snapshotBudget: 0 })
    // Keyframe ticks, kinds, the longest gap between them and the longest delta chain.
    const kf = log.keyframes.map((i) => log.records[i] as { tick: number; z: number })
    let gap = 0
    let chain = 0
    let longest = { length: 0, tick: 0 }
    kf.forEach((k, i) => {
      gap = Math.max(gap, k.tick - (i === 0 ? log.firstTick : kf[i - 1].tick))
      chain = k.z === 2 ? chain + 1 : 0
      if (chain > longest.length) longest = { length: chain, tick: k.tick }
    })
    gap = Math.max(gap, log.lastTick - (kf.at(-1)?.tick ?? log.firstTick))
    await player.seek(0)
    const chainStart = performance.now()
    await player.seek(longest.tick)
    const chainMs = performance.now() - chainStart
    const times: number[] = []
    for (const t of targets) {
      const start = performance.now()
      await player.seek(t)
      times.push(performance.now() - start)
    }
    times.sort((a, b) => a - b)
    const row = {
      keyframeTicks,
      keyframeBudgetMbPerHour: budget / 1e6,
      logBytes: bytes.length,
      bytesPerHour: Math.round((bytes.length * 216_000) / TICKS),
      keyframes: log.keyframes.length,
      deltaKeyframes: kf.filter((k) => k.z === 2).length,
      longestGapTicks: gap,
      longestChain: longest.length,
      chainRestoreMs: Number(chainMs.toFixed(1)),
      seekMsMedian: Number(quantile(times, 0.5).toFixed(1)),
      seekMsP95: Number(quantile(times, 0.95).toFixed(1)),
      seekMsMax: Number(times[times.length - 1].toFixed(1)),
      hashMismatch: player.mismatch,
    }
    rows.push(row)
    console.log(
      `keyframes every ${keyframeTicks} ticks, budget ${budget ? `${budget / 1e6} MB/h` : 'none'}: log ${(bytes.length / 1e6).toFixed(2)} MB (${(row.bytesPerHour / 1e6).toFixed(1)} MB/h), ${row.keyframes} keyframes (${row.deltaKeyframes} deltas, longest gap ${gap} ticks, longest chain ${longest.length}: restored in ${row.chainRestoreMs} ms), seek median ${row.seekMsMedian} ms, p95 ${row.seekMsP95} ms, max ${row.seekMsMax} ms`,
    )
  }
  const result = {
    date: new Date().toISOString(),
    machine: `${cpus().length} x ${cpus()[0]?.model ?? 'cpu'}, load ${loadavg()[0].toFixed(1)}`,
    node: process.version,
    scene: 'pyramid (210 bodies), one player dragging and spawning',
    ticks: TICKS,
    seeks: SEEKS,
    rows,
  }
  await mkdir('bench/results', { recursive: true })
  await writeFile('bench/results/replay-seek.json', `${JSON.stringify(result, null, 2)}\n`)
  console.log('saved bench/results/replay-seek.json')
}

await main()
