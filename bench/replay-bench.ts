/*
 * Replay log benchmark (`npm run bench:replay [-- --quick]`): numbers printed and saved to
 * bench/results/replay.json, not pass/fail.
 *
 * Log size. A room's RoomSimulation is recorded by the server's RoomRecorder (fsync none, a
 * temporary directory) for TICKS room ticks (10 minutes) run as fast as the machine allows (sizes
 * are per room tick, so machine load does not change them), by three recorders at once: the
 * server's defaults (keyframe opportunities every --keyframe-ticks, the --keyframe-budget, deflated
 * and delta keyframes), the same without a budget, and without a budget with raw whole keyframes:
 * - busy: a 1,000-body pile with 5 players dragging bodies on the schedule of bots/bots.ts
 *   driveBot (20 Hz: grab a random dynamic body, 79 moves around a circle, release; every 100
 *   steps);
 * - quiet: the 210-box pyramid with one player who does nothing.
 * Each log is read back and its bytes split into the header, keyframes (whole and delta) and
 * everything else (the blocks of commands, joins, leaves and hashes). MB per hour of a one-hour
 * log: (bytes after the header per tick x 216,000) + the header. The budget lets a log exceed it by
 * one keyframe, and a 10-minute session counts that keyframe 6 times: an upper bound.
 *
 * Replay speed. A pyramid room with one player dragging, recorded for SPEED_TICKS with the default
 * keyframes, is replayed with --verify (every hash and keyframe checked; server/replay/replay-tool.ts, the
 * CLI's code) REPS times in this process: median ticks per second, and the first (cold) run.
 */

import { mkdir, mkdtemp, readFile } from 'node:fs/promises'
import { loadavg, tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { Counter } from 'prom-client'
import { Prng, pileScene, pyramidScene, type SceneBlueprint } from '../engine/index.ts'
import { sandbox } from '../games/index.ts'
import { RoomRecorder, replayLog, SETTINGS } from '../server/index.ts'
import { ReplayLogReader, RoomSimulation, worldFromBlueprint } from '../shared/index.ts'
import { formatTable, machineInfo, median, saveResults } from './stats.ts'

const quick = process.argv.includes('--quick')
const TICKS = quick ? 3_600 : 36_000
const SPEED_TICKS = quick ? 1_200 : 3_600
const REPS = 5
const DEFAULT_KEYFRAMES = SETTINGS.find((s) => s.key === 'keyframeTicks')!.fallback as number
/** The default --keyframe-budget, MB per hour. */
const DEFAULT_BUDGET = SETTINGS.find((s) => s.key === 'keyframeBudget')!.fallback as number
/** The recorders run on each room: the defaults, no budget, no budget with raw whole keyframes. */
const VARIANTS = [
  { variant: 'default', keyframeTicks: DEFAULT_KEYFRAMES, budget: DEFAULT_BUDGET, compress: true },
  { variant: 'no budget', keyframeTicks: DEFAULT_KEYFRAMES, budget: 0, compress: true },
  { variant: 'no budget, raw', keyframeTicks: DEFAULT_KEYFRAMES, budget: 0, compress: false },
]
type Variant = (typeof VARIANTS)[number]

let counters = 0

function recorder(room: string, sim: RoomSimulation, dir: string, v: Variant): RoomRecorder {
  const r = new RoomRecorder(room, sim, {
    dir,
    fsync: 'none',
    keyframeTicks: v.keyframeTicks,
    keyframeBudget: v.budget * 1_000_000,
    maxBytes: 2 ** 40,
    compress: v.compress,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: `bench_recorder_failures_${counters++}`, help: 'bench', registers: [] }),
    openNames: new Set(),
  })
  r.start(0)
  return r
}

/**
 * The driveBot schedule (bots/bots.ts) at 20 Hz, applied straight to the simulation: every
 * 3 ticks a step; per 100 steps a grab of a random dynamic body, 79 moves around a circle, a release.
 */
function drag(sim: RoomSimulation, player: number, prng: Prng): void {
  if (sim.tick % 3 !== 0) return
  const phase = (sim.tick / 3 + player * 17) % 100
  if (phase === 0) {
    const dynamic = sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')
    if (dynamic.length > 0)
      sim.apply(player, { k: 'grab', body: dynamic[prng.int(dynamic.length)], lx: 0, ly: 0 })
  } else if (phase === 80) sim.apply(player, { k: 'release' })
  else if (phase < 80) {
    const a = (phase / 80) * 2 * Math.PI
    sim.apply(player, { k: 'move', x: 4 * Math.cos(a), y: 6 + 3 * Math.sin(a) })
  }
}

/** Record `ticks` of a room; returns each log's bytes. */
async function session(
  name: string,
  blueprint: SceneBlueprint,
  players: number,
  dragging: boolean,
  ticks: number,
  variants: readonly Variant[],
): Promise<Uint8Array[]> {
  const sim = new RoomSimulation({ game: sandbox, name, scene: 'empty', maxBodies: 5000, controls: true })
  const built = worldFromBlueprint(blueprint)
  sim.loadWorld(name, built.world, built.joints)
  const dir = await mkdtemp(join(tmpdir(), `concord-replay-bench-${name}-`))
  await Promise.all(variants.map((_, i) => mkdir(join(dir, String(i)))))
  const recorders = variants.map((v, i) => recorder(name, sim, join(dir, String(i)), v))
  const prngs = Array.from({ length: players }, (_, i) => new Prng(i + 1))
  for (let p = 1; p <= players; p++) sim.join(p, `player ${p}`, '#3cb44b')
  while (sim.tick < ticks) {
    if (dragging) for (let p = 1; p <= players; p++) drag(sim, p, prngs[p - 1])
    sim.runTick()
    if (sim.tick % 60 === 0) for (const r of recorders) await r.flush()
  }
  const out = []
  for (const [i, r] of recorders.entries()) {
    await r.close('bench over')
    out.push(new Uint8Array(await readFile(join(dir, String(i), r.name))))
  }
  return out
}

/** Split a log's bytes: whole and delta keyframe records, the header, everything else. */
function anatomy(bytes: Uint8Array): {
  ticks: number
  whole: number[]
  deltas: number[]
  header: number
  other: number
  commands: number
} {
  const reader = new ReplayLogReader()
  const out = { ticks: 0, whole: [] as number[], deltas: [] as number[], header: 0, other: 16, commands: 0 }
  let before = 16
  reader.push(bytes, (r, end) => {
    // Records of one block share its end: the block's bytes count once, with its first record.
    const size = end - before
    before = end
    if (r.type === 'keyframe') (r.z === 2 ? out.deltas : out.whole).push(size)
    else if (r.type === 'header') out.header = size
    else out.other += size
    if (r.type === 'command') out.commands++
    out.ticks = r.tick
  })
  if (!reader.finish().closed) throw new Error('a bench log did not end cleanly')
  return out
}

async function main(): Promise<void> {
  const machine = machineInfo()
  console.log(`replay bench: load ${machine.loadAverage.toFixed(1)}`)
  const rooms = [
    {
      room: 'busy',
      scene: 'pile of 1,000 bodies, 5 players dragging (driveBot schedule, 20 Hz)',
      blueprint: pileScene(1000),
      players: 5,
      dragging: true,
    },
    {
      room: 'quiet',
      scene: 'pyramid of 210 boxes, 1 idle player',
      blueprint: pyramidScene(20),
      players: 1,
      dragging: false,
    },
  ]
  const sizes = []
  const perHour: Array<{
    room: string
    variant: string
    recordsMbPerHour: number
    keyframesMbPerHour: number
    mbPerHour: number
  }> = []
  const mb = (bytes: number, ticks: number): number => Number(((bytes * 216_000) / ticks / 1e6).toFixed(2))
  const sum = (xs: number[]): number => xs.reduce((a, b) => a + b, 0)
  for (const r of rooms) {
    const began = performance.now()
    const logs = await session(r.room, r.blueprint, r.players, r.dragging, TICKS, VARIANTS)
    console.log(`${r.room}: ${TICKS} ticks recorded in ${((performance.now() - began) / 1000).toFixed(1)} s`)
    for (const [i, bytes] of logs.entries()) {
      const a = anatomy(bytes)
      const v = VARIANTS[i]
      const keyframeBytes = sum(a.whole) + sum(a.deltas)
      const row = {
        room: r.room,
        scene: r.scene,
        ...v,
        ticks: a.ticks,
        logBytes: bytes.length,
        headerBytes: a.header,
        wholeKeyframes: a.whole.length,
        wholeKeyframeBytesMedian: a.whole.length ? median(a.whole) : 0,
        deltaKeyframes: a.deltas.length,
        deltaKeyframeBytesMedian: a.deltas.length ? median(a.deltas) : 0,
        commands: a.commands,
        otherBytesPerTick: Number((a.other / a.ticks).toFixed(1)),
      }
      sizes.push(row)
      perHour.push({
        room: r.room,
        variant: v.variant,
        recordsMbPerHour: mb(a.other, a.ticks),
        keyframesMbPerHour: mb(keyframeBytes, a.ticks),
        mbPerHour: Number((mb(bytes.length - a.header, a.ticks) + a.header / 1e6).toFixed(2)),
      })
    }
  }
  console.log(
    formatTable(
      [
        'room',
        'recorder',
        'log bytes',
        'whole kf',
        'median',
        'delta kf',
        'median',
        'commands',
        'other B/tick',
      ],
      sizes.map((s) => [
        s.room,
        s.variant,
        String(s.logBytes),
        String(s.wholeKeyframes),
        String(s.wholeKeyframeBytesMedian),
        String(s.deltaKeyframes),
        String(s.deltaKeyframeBytesMedian),
        String(s.commands),
        s.otherBytesPerTick.toFixed(1),
      ]),
    ),
  )
  console.log('\nlog MB per hour per room:')
  console.log(
    formatTable(
      ['room', 'recorder', 'records', 'keyframes', 'total'],
      perHour.map((p) => [
        p.room,
        p.variant,
        p.recordsMbPerHour.toFixed(2),
        p.keyframesMbPerHour.toFixed(2),
        p.mbPerHour.toFixed(2),
      ]),
    ),
  )

  const [speedLog] = await session('pyramid', pyramidScene(20), 1, true, SPEED_TICKS, [VARIANTS[0]])
  const runs = []
  for (let i = 0; i < REPS; i++) {
    const report = await replayLog(speedLog, { verify: true })
    if (report.divergence) throw new Error(`the pyramid log diverges: ${report.divergence.reason}`)
    runs.push(report)
  }
  const tps = runs.map((r) => r.ticksPerSecond)
  const speed = {
    scene: 'pyramid of 210 boxes, 1 player dragging (driveBot schedule)',
    keyframeTicks: DEFAULT_KEYFRAMES,
    ticks: runs[0].ticks,
    hashesChecked: runs[0].hashesChecked,
    keyframesChecked: runs[0].keyframesChecked,
    coldTicksPerSecond: Math.round(tps[0]),
    medianTicksPerSecond: Math.round(median(tps)),
    realTimeFactor: Number((median(tps) / 60).toFixed(1)),
  }
  console.log(
    `\nreplay --verify of a pyramid log (${speed.ticks} ticks, ${speed.hashesChecked} hashes, ${speed.keyframesChecked} keyframes): median ${speed.medianTicksPerSecond} ticks/s (${speed.realTimeFactor}x real time) over ${REPS} runs, first run ${speed.coldTicksPerSecond} ticks/s`,
  )
  const loadAtEnd = loadavg()[0]
  console.log(
    `load average: ${machine.loadAverage.toFixed(1)} at the start, ${loadAtEnd.toFixed(1)} at the end`,
  )
  saveResults(quick ? 'bench/results/replay-quick.json' : 'bench/results/replay.json', {
    machine,
    loadAverageAtEnd: loadAtEnd,
    ticks: TICKS,
    defaultKeyframeTicks: DEFAULT_KEYFRAMES,
    defaultKeyframeBudgetMbPerHour: DEFAULT_BUDGET,
    sizes,
    perHour,
    replaySpeed: speed,
  })
  console.log(`saved bench/results/${quick ? 'replay-quick' : 'replay'}.json`)
}

await main()
