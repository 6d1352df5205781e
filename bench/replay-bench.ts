/*
 * Replay log benchmark (`npm run bench:replay [-- --quick]`): numbers printed and saved to
 * bench/results/replay.json, not pass/fail.
 *
 * Log size. A room's RoomSimulation is recorded by the server's RoomRecorder (fsync none, a
 * temporary directory) with keyframes every KEYFRAMES ticks, deflated and raw, for TICKS room ticks
 * run as fast as the machine allows (sizes are per room tick, so machine load does not change
 * them):
 * - busy: a 1,000-body pile with 5 players dragging bodies on the schedule of server/bots.ts
 *   driveBot (20 Hz: grab a random dynamic body, 79 moves around a circle, release; every 100
 *   steps);
 * - quiet: the 210-box pyramid with one player who does nothing.
 * Each log is read back and its bytes split into keyframes and everything else; bytes per hour for
 * a keyframe interval K are (other bytes per tick x 216,000) + (median keyframe record x
 * 216,000 / K), so intervals not recorded are computed from the measured parts.
 *
 * Replay speed. A pyramid room with one player dragging, recorded for SPEED_TICKS with the default
 * keyframes, is replayed with --verify (every hash and keyframe checked; server/replay-tool.ts, the
 * CLI's code) REPS times in this process: median ticks per second, and the first (cold) run.
 */
import { mkdir, mkdtemp, readFile } from 'node:fs/promises'
import { loadavg, tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { Counter } from 'prom-client'
import { Prng, pileScene, pyramidScene, type SceneBlueprint } from '../engine/index.ts'
import { SETTINGS } from '../server/config.ts'
import { RoomRecorder } from '../server/recorder.ts'
import { replayLog } from '../server/replay-tool.ts'
import { ReplayLogReader } from '../shared/replay-log-reader.ts'
import { RoomSimulation, worldFromBlueprint } from '../shared/room-simulation.ts'
import { formatTable, machineInfo, median, saveResults } from './stats.ts'

const quick = process.argv.includes('--quick')
const TICKS = quick ? 600 : 2_400
const SPEED_TICKS = quick ? 1_200 : 3_600
const REPS = 5
const DEFAULT_KEYFRAMES = SETTINGS.find((s) => s.key === 'keyframeTicks')!.fallback as number
const KEYFRAMES = quick ? 300 : 600
const INTERVALS = [300, 600, 1200, 1800, 3600, 7200]

let counters = 0

function recorder(
  room: string,
  sim: RoomSimulation,
  dir: string,
  keyframeTicks: number,
  compress: boolean,
): RoomRecorder {
  const r = new RoomRecorder(room, sim, {
    dir,
    fsync: 'none',
    keyframeTicks,
    maxBytes: 2 ** 40,
    keep: 10,
    compress,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: `bench_recorder_failures_${counters++}`, help: 'bench', registers: [] }),
    openNames: new Set(),
  })
  r.start(0)
  return r
}

/**
 * The driveBot schedule (server/bots.ts) at 20 Hz, applied straight to the simulation: every
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
  variants: Array<{ keyframeTicks: number; compress: boolean }>,
): Promise<Uint8Array[]> {
  const sim = new RoomSimulation({ name, scene: 'empty', maxBodies: 5000, controls: true })
  const built = worldFromBlueprint(blueprint)
  sim.loadWorld(name, built.world, built.joints)
  const dir = await mkdtemp(join(tmpdir(), `concord-replay-bench-${name}-`))
  await Promise.all(variants.map((_, i) => mkdir(join(dir, String(i)))))
  const recorders = variants.map((v, i) =>
    recorder(name, sim, join(dir, String(i)), v.keyframeTicks, v.compress),
  )
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

/** Split a log's bytes: keyframe records (and their sizes), the header, everything else. */
function anatomy(bytes: Uint8Array): {
  ticks: number
  keyframes: number[]
  header: number
  other: number
  commands: number
} {
  const reader = new ReplayLogReader()
  const out = { ticks: 0, keyframes: [] as number[], header: 0, other: 16, commands: 0 }
  let before = 16
  reader.push(bytes, (r, end) => {
    const size = end - before
    before = end
    if (r.type === 'keyframe') out.keyframes.push(size)
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
  const variants = [
    { keyframeTicks: KEYFRAMES, compress: true },
    { keyframeTicks: KEYFRAMES, compress: false },
  ]
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
  const perHour: Array<{ room: string; compressed: boolean; keyframeTicks: number; mbPerHour: number }> = []
  for (const r of rooms) {
    const began = performance.now()
    const logs = await session(r.room, r.blueprint, r.players, r.dragging, TICKS, variants)
    console.log(`${r.room}: ${TICKS} ticks recorded in ${((performance.now() - began) / 1000).toFixed(1)} s`)
    for (const [i, bytes] of logs.entries()) {
      const a = anatomy(bytes)
      const keyframe = median(a.keyframes)
      const otherPerTick = a.other / a.ticks
      const row = {
        room: r.room,
        scene: r.scene,
        compressed: variants[i].compress,
        ticks: a.ticks,
        logBytes: bytes.length,
        headerBytes: a.header,
        keyframes: a.keyframes.length,
        keyframeBytesMedian: keyframe,
        commands: a.commands,
        otherBytesPerTick: Number(otherPerTick.toFixed(1)),
        otherMbPerHour: Number(((otherPerTick * 216_000) / 1e6).toFixed(2)),
      }
      sizes.push(row)
      for (const k of INTERVALS)
        perHour.push({
          room: r.room,
          compressed: variants[i].compress,
          keyframeTicks: k,
          mbPerHour: Number(((otherPerTick * 216_000 + (keyframe * 216_000) / k) / 1e6).toFixed(1)),
        })
    }
  }
  console.log(
    formatTable(
      ['room', 'keyframes', 'ticks', 'log bytes', 'keyframe bytes', 'commands', 'other MB/h'],
      sizes.map((s) => [
        s.room,
        s.compressed ? 'deflated' : 'raw',
        String(s.ticks),
        String(s.logBytes),
        String(s.keyframeBytesMedian),
        String(s.commands),
        s.otherMbPerHour.toFixed(2),
      ]),
    ),
  )
  console.log('\nlog MB per hour per room by keyframe interval (ticks):')
  console.log(
    formatTable(
      ['room', 'keyframes', ...INTERVALS.map(String)],
      rooms.flatMap((r) =>
        [true, false].map((c) => [
          r.room,
          c ? 'deflated' : 'raw',
          ...INTERVALS.map((k) =>
            perHour
              .find((p) => p.room === r.room && p.compressed === c && p.keyframeTicks === k)!
              .mbPerHour.toFixed(1),
          ),
        ]),
      ),
    ),
  )

  const [speedLog] = await session('pyramid', pyramidScene(20), 1, true, SPEED_TICKS, [
    { keyframeTicks: DEFAULT_KEYFRAMES, compress: true },
  ])
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
    recordedKeyframeTicks: KEYFRAMES,
    defaultKeyframeTicks: DEFAULT_KEYFRAMES,
    sizes,
    perHour,
    replaySpeed: speed,
  })
  console.log(`saved bench/results/${quick ? 'replay-quick' : 'replay'}.json`)
}

await main()
