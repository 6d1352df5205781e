/*
 * Broadphase benchmark: the dynamic AABB tree against a brute-force pair loop on a pile-like
 * scene (mostly similar-size bodies, 0.4-0.9 m, packed in a container about 1.25 sqrt(n) m wide,
 * plus a few huge static bodies: the ground, two walls, a shelf). Every frame 30% of the dynamic
 * bodies, chosen at random, move by their velocity (a random walk, at most 3 m/s, 1/60 s steps).
 *
 * Tree frame: moveProxy for every dynamic body (as the world does for every awake body), then
 * updatePairs. Brute-force frame: the same fat-AABB update, then the O(n^2) loop over all pairs
 * (already sorted, because bodies are visited in id order). Prints a table and writes
 * bench/results/broad-phase.json. Run: npx tsx bench/broad-phase-bench.ts
 *
 * Second part: every broadphase call Concord's own world makes while pileScene(1000) falls and
 * settles is recorded (by wrapping the BroadPhase methods for the recording run only), then
 * replayed into a fresh BroadPhase and into the brute-force loop, step by step.
 */
import { writeFileSync } from 'node:fs'
import os from 'node:os'
import { buildScene, createWorld, Prng, pileScene } from '../engine/index.ts'
import { BroadPhase, PairBuffer } from '../engine/internal.ts'

const SIZES = [250, 500, 1000, 2000, 4000]
const MARGIN = 0.1
const DT = 1 / 60
const MAX_SPEED = 3 // m/s
const MOVING_FRACTION = 0.3

/** Bodies as flat arrays: half extents, centres, velocities; statics first. */
interface Pile {
  n: number
  statics: number
  hx: Float64Array
  hy: Float64Array
  x: Float64Array
  y: Float64Array
  vx: Float64Array
  vy: Float64Array
  width: number
  height: number
}

function buildPile(n: number, seed: number): Pile {
  const prng = new Prng(seed)
  const columns = Math.ceil(Math.sqrt(n) * 1.25)
  const rows = Math.ceil(n / columns)
  const width = columns + 1
  const height = rows + 2
  const statics = 4
  const total = n + statics
  const p: Pile = {
    n: total,
    statics,
    hx: new Float64Array(total),
    hy: new Float64Array(total),
    x: new Float64Array(total),
    y: new Float64Array(total),
    vx: new Float64Array(total),
    vy: new Float64Array(total),
    width,
    height,
  }
  const set = (i: number, x: number, y: number, hx: number, hy: number): void => {
    p.x[i] = x
    p.y[i] = y
    p.hx[i] = hx
    p.hy[i] = hy
  }
  set(0, 0, -1, 100, 1) // ground, 200 m
  set(1, -width / 2 - 0.5, height / 2, 0.5, height / 2)
  set(2, width / 2 + 0.5, height / 2, 0.5, height / 2)
  set(3, 0, height * 0.6, width / 4, 0.25) // a shelf across the middle of the pile
  for (let i = 0; i < n; i++) {
    const b = statics + i
    const column = i % columns
    const row = Math.floor(i / columns)
    set(b, -width / 2 + 1 + column, 0.5 + row, prng.range(0.2, 0.45), prng.range(0.2, 0.45))
    p.vx[b] = prng.range(-MAX_SPEED, MAX_SPEED) / 2
    p.vy[b] = prng.range(-MAX_SPEED, MAX_SPEED) / 2
  }
  return p
}

/** Moves a random 30% of the dynamic bodies one step; velocities random-walk, bounded by the walls. */
function stepPile(p: Pile, prng: Prng): void {
  const halfW = p.width / 2
  for (let i = p.statics; i < p.n; i++) {
    if (prng.next() >= MOVING_FRACTION) continue
    let vx = p.vx[i] + prng.range(-0.5, 0.5)
    let vy = p.vy[i] + prng.range(-0.5, 0.5)
    vx = Math.max(-MAX_SPEED, Math.min(MAX_SPEED, vx))
    vy = Math.max(-MAX_SPEED, Math.min(MAX_SPEED, vy))
    let x = p.x[i] + vx * DT
    let y = p.y[i] + vy * DT
    if (x < -halfW + 0.5 || x > halfW - 0.5) vx = -vx
    if (y < 0.5 || y > p.height) vy = -vy
    x = Math.max(-halfW + 0.5, Math.min(halfW - 0.5, x))
    y = Math.max(0.5, Math.min(p.height, y))
    p.x[i] = x
    p.y[i] = y
    p.vx[i] = vx
    p.vy[i] = vy
  }
}

interface Run {
  times: number[]
  pairsPerFrame: number
  movedPerFrame: number
}

function runTree(n: number, frames: number, warmup: number): Run & { height: number } {
  const pile = buildPile(n, 1)
  const prng = new Prng(2)
  const bp = new BroadPhase(MARGIN)
  const proxies = new Int32Array(pile.n)
  for (let i = 0; i < pile.n; i++) {
    const x = pile.x[i]
    const y = pile.y[i]
    const hx = pile.hx[i]
    const hy = pile.hy[i]
    proxies[i] = bp.createProxy(x - hx, y - hy, x + hx, y + hy, i + 1, i < pile.statics)
  }
  const pairs = new PairBuffer()
  bp.updatePairs(pairs)
  const times: number[] = []
  let pairTotal = 0
  let movedTotal = 0
  for (let f = 0; f < warmup + frames; f++) {
    stepPile(pile, prng)
    const t0 = performance.now()
    let moved = 0
    for (let i = pile.statics; i < pile.n; i++) {
      const x = pile.x[i]
      const y = pile.y[i]
      const hx = pile.hx[i]
      const hy = pile.hy[i]
      if (bp.moveProxy(proxies[i], x - hx, y - hy, x + hx, y + hy)) moved++
    }
    const count = bp.updatePairs(pairs)
    const t1 = performance.now()
    if (f >= warmup) {
      times.push(t1 - t0)
      pairTotal += count
      movedTotal += moved
    }
  }
  return {
    times,
    pairsPerFrame: pairTotal / frames,
    movedPerFrame: movedTotal / frames,
    height: bp.treeHeight,
  }
}

function runBruteForce(n: number, frames: number, warmup: number): Run {
  const pile = buildPile(n, 1)
  const prng = new Prng(2)
  const total = pile.n
  const fat = new Float64Array(4 * total)
  for (let i = 0; i < total; i++) {
    const r = i < pile.statics ? 0 : MARGIN
    fat[4 * i] = pile.x[i] - pile.hx[i] - r
    fat[4 * i + 1] = pile.y[i] - pile.hy[i] - r
    fat[4 * i + 2] = pile.x[i] + pile.hx[i] + r
    fat[4 * i + 3] = pile.y[i] + pile.hy[i] + r
  }
  const pairs = new PairBuffer(1 << 16)
  const times: number[] = []
  let pairTotal = 0
  let movedTotal = 0
  for (let f = 0; f < warmup + frames; f++) {
    stepPile(pile, prng)
    const t0 = performance.now()
    const moved = refitFatBoxes(pile, fat)
    const count = bruteForcePairs(fat, total, pile.statics, pairs)
    const t1 = performance.now()
    if (f >= warmup) {
      times.push(t1 - t0)
      pairTotal += count
      movedTotal += moved
    }
  }
  return { times, pairsPerFrame: pairTotal / frames, movedPerFrame: movedTotal / frames }
}

/** The same fat-AABB rule as the tree: re-fatten only when the tight box leaves the fat one. */
function refitFatBoxes(pile: Pile, fat: Float64Array): number {
  let moved = 0
  for (let i = pile.statics; i < pile.n; i++) {
    const x0 = pile.x[i] - pile.hx[i]
    const y0 = pile.y[i] - pile.hy[i]
    const x1 = pile.x[i] + pile.hx[i]
    const y1 = pile.y[i] + pile.hy[i]
    const o = 4 * i
    if (fat[o] <= x0 && fat[o + 1] <= y0 && x1 <= fat[o + 2] && y1 <= fat[o + 3]) continue
    fat[o] = x0 - MARGIN
    fat[o + 1] = y0 - MARGIN
    fat[o + 2] = x1 + MARGIN
    fat[o + 3] = y1 + MARGIN
    moved++
  }
  return moved
}

/** Every overlapping pair, not static-static, in (a, b) order because i < j are visited in id order. */
function bruteForcePairs(fat: Float64Array, n: number, statics: number, pairs: PairBuffer): number {
  let count = 0
  for (let i = 0; i < n; i++) {
    const x0 = fat[4 * i]
    const y0 = fat[4 * i + 1]
    const x1 = fat[4 * i + 2]
    const y1 = fat[4 * i + 3]
    for (let j = i < statics ? statics : i + 1; j < n; j++) {
      const o = 4 * j
      if (x0 > fat[o + 2] || fat[o] > x1 || y0 > fat[o + 3] || fat[o + 1] > y1) continue
      if (count === pairs.a.length) {
        pairs.count = count
        pairs.reserve(count + 1)
      }
      pairs.a[count] = i + 1
      pairs.b[count] = j + 1
      count++
    }
  }
  pairs.count = count
  return count
}

function percentile(times: number[], q: number): number {
  const sorted = [...times].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))]
}

function round(x: number, digits = 4): number {
  const s = 10 ** digits
  return Math.round(x * s) / s
}

/** Runs `trials` interleaved trials and keeps the one with the lowest median (load only adds time). */
function bestOf<T extends Run>(trials: number, run: () => T): T & { trialMedians: number[] } {
  let best: T | null = null
  const medians: number[] = []
  for (let t = 0; t < trials; t++) {
    const r = run()
    medians.push(round(percentile(r.times, 0.5)))
    if (best === null || percentile(r.times, 0.5) < percentile(best.times, 0.5)) best = r
  }
  return { ...(best as T), trialMedians: medians }
}

const TRIALS = 3
const loadBefore = os.loadavg()
const results = []
console.log(
  'bodies | tree median / p95 ms | brute median / p95 ms | speed-up | reinserted/frame | new pairs/frame | all pairs | height',
)
for (const n of SIZES) {
  const tree = bestOf(TRIALS, () => runTree(n, 600, 120))
  const bruteFrames = n <= 1000 ? 300 : n <= 2000 ? 120 : 60
  const brute = bestOf(TRIALS, () => runBruteForce(n, bruteFrames, 20))
  const row = {
    bodies: n,
    staticBodies: 4,
    tree: {
      medianMs: round(percentile(tree.times, 0.5)),
      p95Ms: round(percentile(tree.times, 0.95)),
      frames: tree.times.length,
      trialMedians: tree.trialMedians,
      reinsertedPerFrame: round(tree.movedPerFrame, 1),
      newPairsPerFrame: round(tree.pairsPerFrame, 1),
      height: tree.height,
    },
    bruteForce: {
      medianMs: round(percentile(brute.times, 0.5)),
      p95Ms: round(percentile(brute.times, 0.95)),
      frames: brute.times.length,
      trialMedians: brute.trialMedians,
      allPairsPerFrame: round(brute.pairsPerFrame, 1),
    },
  }
  results.push(row)
  console.log(
    [
      String(n).padStart(6),
      `${row.tree.medianMs.toFixed(4)} / ${row.tree.p95Ms.toFixed(4)}`.padStart(20),
      `${row.bruteForce.medianMs.toFixed(3)} / ${row.bruteForce.p95Ms.toFixed(3)}`.padStart(21),
      `${(row.bruteForce.medianMs / row.tree.medianMs).toFixed(1)}x`.padStart(8),
      String(row.tree.reinsertedPerFrame).padStart(16),
      String(row.tree.newPairsPerFrame).padStart(15),
      String(row.bruteForce.allPairsPerFrame).padStart(9),
      String(row.tree.height).padStart(6),
    ].join(' | '),
  )
}

// Op codes of a recorded trace: op, then its arguments; CREATE also stores the proxy id returned.
const STEP = 0
const CREATE = 1
const MOVE = 2
const TOUCH = 3
const DESTROY = 4
const UPDATE = 5

/** Every BroadPhase call a world makes while pileScene(n) runs `steps` steps, as a flat op list. */
function recordWorldPile(n: number, steps: number): Float64Array {
  const ops: number[] = []
  const proto = BroadPhase.prototype
  const saved = {
    createProxy: proto.createProxy,
    moveProxy: proto.moveProxy,
    touchProxy: proto.touchProxy,
    destroyProxy: proto.destroyProxy,
    updatePairs: proto.updatePairs,
  }
  proto.createProxy = function (x0, y0, x1, y1, body, isStatic) {
    const proxy = saved.createProxy.call(this, x0, y0, x1, y1, body, isStatic)
    ops.push(CREATE, x0, y0, x1, y1, body, isStatic ? 1 : 0, proxy)
    return proxy
  }
  proto.moveProxy = function (proxy, x0, y0, x1, y1) {
    ops.push(MOVE, proxy, x0, y0, x1, y1)
    return saved.moveProxy.call(this, proxy, x0, y0, x1, y1)
  }
  proto.touchProxy = function (proxy) {
    ops.push(TOUCH, proxy)
    saved.touchProxy.call(this, proxy)
  }
  proto.destroyProxy = function (proxy) {
    ops.push(DESTROY, proxy)
    saved.destroyProxy.call(this, proxy)
  }
  proto.updatePairs = function (pairs) {
    ops.push(UPDATE)
    return saved.updatePairs.call(this, pairs)
  }
  try {
    const world = createWorld({ gravity: { x: 0, y: -10 } })
    buildScene(world, pileScene(n))
    for (let i = 0; i < steps; i++) {
      ops.push(STEP)
      world.step()
    }
  } finally {
    Object.assign(proto, saved)
  }
  return new Float64Array(ops)
}

/** Replays a trace into a BroadPhase (tree) or the brute-force loop; returns ms per step. */
function replay(ops: Float64Array, useTree: boolean): { times: number[]; reinserts: number[] } {
  const bp = new BroadPhase(MARGIN)
  const pairs = new PairBuffer(1 << 12)
  const cap = 1 << 16
  const fat = new Float64Array(4 * cap)
  const isStatic = new Uint8Array(cap)
  const alive = new Uint8Array(cap)
  const times: number[] = []
  const reinserts: number[] = []
  let t0 = 0
  let moved = 0
  let maxProxy = 0
  for (let i = 0; i < ops.length; ) {
    const op = ops[i++]
    if (op === STEP) {
      if (t0 > 0) times.push(performance.now() - t0)
      if (t0 > 0) reinserts.push(moved)
      moved = 0
      t0 = performance.now()
    } else if (op === CREATE) {
      const proxy = useTree
        ? bp.createProxy(ops[i], ops[i + 1], ops[i + 2], ops[i + 3], ops[i + 4], ops[i + 5] === 1)
        : ops[i + 6]
      const r = ops[i + 5] === 1 ? 0 : MARGIN
      fat.set([ops[i] - r, ops[i + 1] - r, ops[i + 2] + r, ops[i + 3] + r], 4 * proxy)
      isStatic[proxy] = ops[i + 5]
      alive[proxy] = 1
      maxProxy = Math.max(maxProxy, proxy + 1)
      i += 7
    } else if (op === MOVE) {
      const proxy = ops[i]
      if (useTree) {
        if (bp.moveProxy(proxy, ops[i + 1], ops[i + 2], ops[i + 3], ops[i + 4])) moved++
      } else if (refitOne(fat, 4 * proxy, ops, i + 1, isStatic[proxy] === 1 ? 0 : MARGIN)) moved++
      i += 5
    } else if (op === TOUCH) {
      if (useTree) bp.touchProxy(ops[i])
      i += 1
    } else if (op === DESTROY) {
      if (useTree) bp.destroyProxy(ops[i])
      alive[ops[i]] = 0
      i += 1
    } else if (op === UPDATE) {
      if (useTree) bp.updatePairs(pairs)
      else bruteForceSlots(fat, isStatic, alive, maxProxy, pairs)
    }
  }
  return { times, reinserts }
}

function refitOne(fat: Float64Array, o: number, ops: Float64Array, k: number, r: number): boolean {
  if (fat[o] <= ops[k] && fat[o + 1] <= ops[k + 1] && ops[k + 2] <= fat[o + 2] && ops[k + 3] <= fat[o + 3])
    return false
  fat[o] = ops[k] - r
  fat[o + 1] = ops[k + 1] - r
  fat[o + 2] = ops[k + 2] + r
  fat[o + 3] = ops[k + 3] + r
  return true
}

/** The brute-force loop over proxy slots (creation order is body order in this scene). */
function bruteForceSlots(
  fat: Float64Array,
  isStatic: Uint8Array,
  alive: Uint8Array,
  n: number,
  pairs: PairBuffer,
): number {
  let count = 0
  for (let i = 0; i < n; i++) {
    if (alive[i] === 0) continue
    const o = 4 * i
    for (let j = i + 1; j < n; j++) {
      const q = 4 * j
      if (alive[j] === 0 || (isStatic[i] & isStatic[j]) === 1) continue
      if (fat[o] > fat[q + 2] || fat[q] > fat[o + 2] || fat[o + 1] > fat[q + 3] || fat[q + 1] > fat[o + 3])
        continue
      if (count === pairs.a.length) {
        pairs.count = count
        pairs.reserve(count + 1)
      }
      pairs.a[count] = i
      pairs.b[count] = j
      count++
    }
  }
  pairs.count = count
  return count
}

const WORLD_STEPS = 360
const FALLING_STEPS = 120
console.log(`\nrecording pileScene(1000) in Concord's world for ${WORLD_STEPS} steps...`)
const trace = recordWorldPile(1000, WORLD_STEPS)
const phases = (r: { times: number[]; reinserts: number[] }) => {
  const summary = (a: number, b: number) => ({
    steps: `${a}-${b - 1}`,
    medianMs: round(percentile(r.times.slice(a, b), 0.5)),
    p95Ms: round(percentile(r.times.slice(a, b), 0.95)),
    reinsertedPerStep: round(r.reinserts.slice(a, b).reduce((x, y) => x + y, 0) / (b - a), 1),
  })
  return { falling: summary(0, FALLING_STEPS), settling: summary(FALLING_STEPS, r.times.length) }
}
let worldTree = replay(trace, true)
for (let t = 1; t < TRIALS; t++) {
  const again = replay(trace, true)
  if (again.times.reduce((x, y) => x + y, 0) < worldTree.times.reduce((x, y) => x + y, 0)) worldTree = again
}
const worldPile = { tree: phases(worldTree), bruteForce: phases(replay(trace, false)) }
for (const [name, r] of Object.entries(worldPile)) {
  for (const [phase, x] of Object.entries(r)) {
    console.log(
      `world pile 1000, ${name.padEnd(10)} ${phase.padEnd(8)} steps ${x.steps.padEnd(8)}: median ${x.medianMs.toFixed(4)} ms, p95 ${x.p95Ms.toFixed(4)} ms, re-fattened/step ${x.reinsertedPerStep}`,
    )
  }
}

const report = {
  benchmark: 'broad-phase',
  scene:
    'pile-like: 0.4-0.9 m boxes in a ~1.25 sqrt(n) m container, 4 huge statics; each frame a random 30% of ' +
    'the bodies move one 1/60 s step at a random-walk velocity of at most 3 m/s; tree = moveProxy for all ' +
    'dynamic bodies + updatePairs, brute force = the same fat-box update + the O(n^2) pair loop',
  margin: MARGIN,
  method: `best of ${TRIALS} trials by median (the machine is shared with other jobs: load only adds time)`,
  machine: {
    cpu: os.cpus()[0]?.model ?? 'unknown',
    cores: os.cpus().length,
    node: process.version,
    os: `${os.platform()} ${os.release()}`,
    loadAverageBefore: loadBefore.map((x) => round(x, 2)),
    loadAverageAfter: os.loadavg().map((x) => round(x, 2)),
  },
  date: new Date().toISOString(),
  results,
  worldPile1000: worldPile,
}
writeFileSync(new URL('./results/broad-phase.json', import.meta.url), `${JSON.stringify(report, null, 2)}\n`)
console.log('wrote bench/results/broad-phase.json')
