/*
 * What the caches and the machine add to a room worker's engine time (npm run bench:room-cache):
 * numbers printed and saved to bench/results/room-cache.json, never pass/fail.
 *
 * The rooms scene (bench/rooms-scene.ts: K worlds of the capacity scene with dragging players,
 * 10 by default, what each of 2 workers holds at 20 rooms) is warmed up and saved. Each round
 * loads the saved worlds twice and steps them `--window` ticks (30) in two orders:
 *   round-robin  tick by tick, every room once per tick, as a worker does: when a room's turn
 *                comes, the other rooms have pushed its data out of the caches;
 *   in turn      each room steps the whole window before the next: its data stays in the caches
 *                after its first tick.
 * Same worlds, same ticks, same hashes (checked): the ratio of the two is what cold caches cost.
 * Every round repeats identical work, so the spread of the round-robin windows is the machine's:
 * beside them, the same rounds time a probe with a fixed memory access pattern (random reads
 * over 4 MB from a fixed index sequence) and a fixed arithmetic loop.
 *
 * Flags: --rooms K (10), --window N (30), --rounds N (30), --warmup N (120).
 */
import { performance } from 'node:perf_hooks'
import { parseArgs } from 'node:util'
import * as engine from '../engine/index.ts'
import { type RoomsEngine, roomsStepper } from './rooms-scene.ts'
import { formatTable, machineInfo, median, saveResults } from './stats.ts'

const { values } = parseArgs({
  options: {
    rooms: { type: 'string', default: '10' },
    window: { type: 'string', default: '30' },
    rounds: { type: 'string', default: '30' },
    warmup: { type: 'string', default: '120' },
  },
})
const counts = {
  rooms: Number(values.rooms),
  window: Number(values.window),
  rounds: Number(values.rounds),
  warmup: Number(values.warmup),
}
for (const [name, value] of Object.entries(counts)) {
  if (!Number.isInteger(value) || value < 1)
    throw new Error(`--${name} must be a positive integer, got ${value}`)
}

const rooms = roomsStepper(engine as unknown as RoomsEngine, counts.rooms, false)
for (let t = 0; t < counts.warmup; t++) rooms.step()
const saved = rooms.worlds.map((w) => w.save().slice())

/** Hash of worlds in order (as Rooms.hash). */
function hashOf(worlds: engine.World[]): number {
  let h = 0
  for (const world of worlds) h = (Math.imul(h, 31) + world.hash()) >>> 0
  return h
}

/** Steps freshly loaded copies of the saved rooms in one order; ms per tick of all rooms, and the hash. */
function window(order: 'round-robin' | 'in turn'): { ms: number; hash: number } {
  const worlds = saved.map((bytes) => engine.loadWorld(bytes))
  const t0 = performance.now()
  if (order === 'round-robin') {
    for (let t = 0; t < counts.window; t++) for (const world of worlds) world.step()
  } else {
    for (const world of worlds) for (let t = 0; t < counts.window; t++) world.step()
  }
  return { ms: (performance.now() - t0) / counts.window, hash: hashOf(worlds) }
}

const PROBE_WORDS = 1 << 19
const probeData = new Float64Array(PROBE_WORDS).fill(1)
const probeIndex = new Int32Array(1 << 20)
for (let i = 0, s = 12345; i < probeIndex.length; i++) {
  s = (Math.imul(s, 1103515245) + 12345) >>> 0
  probeIndex[i] = s % PROBE_WORDS
}
const sink = new Float64Array(1)

/** ms for a fixed sequence of random reads over 4 MB. */
function memoryProbe(): number {
  const t0 = performance.now()
  let x = 0
  for (let i = 0; i < probeIndex.length; i++) x += probeData[probeIndex[i]]
  sink[0] += x
  return performance.now() - t0
}

/** ms for a fixed arithmetic loop that touches no memory. */
function computeProbe(): number {
  const t0 = performance.now()
  let x = 0
  for (let i = 0; i < 2_000_000; i++) x = (x * 1.0000001 + i * 1e-9) % 1000
  sink[0] += x
  return performance.now() - t0
}

// Warm the JIT for the probes and the load path, outside the measured rounds.
for (let i = 0; i < 3; i++) {
  memoryProbe()
  computeProbe()
  window('round-robin')
}
const roundRobin: number[] = []
const inTurn: number[] = []
const memory: number[] = []
const compute: number[] = []
const machine = machineInfo()
for (let round = 0; round < counts.rounds; round++) {
  // Alternate which order goes first, so a slow stretch of the machine lands on both.
  const first = round % 2 === 0 ? 'round-robin' : 'in turn'
  const a = window(first)
  const b = window(first === 'round-robin' ? 'in turn' : 'round-robin')
  if (a.hash !== b.hash) throw new Error(`round ${round}: the two orders stepped to different worlds`)
  const [rr, turn] = first === 'round-robin' ? [a, b] : [b, a]
  roundRobin.push(rr.ms)
  inTurn.push(turn.ms)
  memory.push(memoryProbe())
  compute.push(computeProbe())
}

const spread = (xs: number[]) => ({
  min: Math.min(...xs),
  median: median(xs),
  max: Math.max(...xs),
  maxOverMin: Math.max(...xs) / Math.min(...xs),
})
const result = {
  roundRobinMsPerTick: spread(roundRobin),
  inTurnMsPerTick: spread(inTurn),
  coldOverHot: median(roundRobin) / median(inTurn),
  pairedColdOverHot: median(roundRobin.map((x, i) => x / inTurn[i])),
  memoryProbeMs: spread(memory),
  computeProbeMs: spread(compute),
}
const row = (name: string, s: ReturnType<typeof spread>) => [
  name,
  s.min.toFixed(3),
  s.median.toFixed(3),
  s.max.toFixed(3),
  s.maxOverMin.toFixed(2),
]
console.log(
  `${counts.rooms} rooms of the capacity scene, ${counts.window}-tick windows, ${counts.rounds} rounds (node ${machine.node}, load ${machine.loadAverage.toFixed(2)})`,
)
console.log(
  formatTable(
    ['what', 'min', 'median', 'max', 'max/min'],
    [
      row('round-robin, ms per tick of all rooms', result.roundRobinMsPerTick),
      row('in turn, ms per tick of all rooms', result.inTurnMsPerTick),
      row('memory probe, ms', result.memoryProbeMs),
      row('compute probe, ms', result.computeProbeMs),
    ],
  ),
)
console.log(
  `cold caches cost: round-robin / in turn ${result.coldOverHot.toFixed(3)} (paired by round ${result.pairedColdOverHot.toFixed(3)})`,
)
const path = new URL('./results/room-cache.json', import.meta.url).pathname
saveResults(path, {
  benchmark: 'room-cache',
  machine: { ...machine, loadAtEnd: machineInfo().loadAverage },
  counts,
  result,
})
console.log(`saved ${path}`)
