/*
 * The measuring program of allocation.test.ts. The test bundles it with esbuild and runs it in a
 * separate, quiet `node --expose-gc` process, so that vitest's own work cannot allocate or collect
 * in the measured window. Arguments: the scene (`pile` or `room`), warm-up steps, measured steps
 * per round, rounds; it prints one JSON line (AllocationResult).
 *
 * - pile: a 300-body pile (pileScene(300), sleeping off, so every body is simulated every step) and,
 *   beside it, two alternating towers of 20 and 50 boxes (column contacts, contact-columns.ts).
 *   heapUsed is read, the steps run, heapUsed is read again, with no gc() in between: heapUsed
 *   includes the young generation, so (after - before) is what the steps allocated.
 * - room: the server's capacity room without the server: a 100-body pile whose bodies never sleep
 *   (bench/server-load.ts awakePile) and five players, each dragging a random dynamic body with a
 *   mouse joint round an ellipse (half-axes 4 m and 3 m; a lap in 80 of their 20 Hz steps, about
 *   6 m/s: fast bodies, continuous collision, contacts made and broken); once a second the world
 *   is hashed (the recorder's checkpoint, which writes the whole world into a buffer). Every 600
 *   warm-up steps, and before each measured round, the players let go, a body is spawned above the
 *   pile (the oldest spawned one destroyed past 12) and they grab five new bodies: those commands
 *   allocate (bodies, joints, id lists), so they run outside the measured rounds, while the steps
 *   after them (a new body's first contacts, a grab's first pull) are measured.
 * In both, several rounds run and the least growth is reported (late JIT work lands in one round
 * on a busy machine, while an allocation in the step shows in every round); a PerformanceObserver
 * counts the collections that start inside the rounds. If anything was allocated, V8's sampling
 * heap profiler runs over more steps and names the allocating functions (with file:line).
 */
import { Session } from 'node:inspector'
import { PerformanceObserver, performance } from 'node:perf_hooks'
import {
  type BodyId,
  box,
  buildScene,
  circle,
  createWorld,
  type JointId,
  Prng,
  pileScene,
  polygon,
  type Vec2,
  type World,
} from '../../engine/index.ts'

/** What the program prints. */
export interface AllocationResult {
  scene: string
  steps: number
  bodies: number
  contacts: number
  /** Collections that started inside the measured rounds, and their kinds. */
  gcCount: number
  gcKinds: number[]
  /** Least heap growth of the rounds (bytes). */
  heapGrowth: number
  allocators: { where: string; bytes: number }[]
}

const gc = (globalThis as { gc?: () => void }).gc
if (!gc) throw new Error('run with node --expose-gc')
const [scene, warmupArg, stepsArg, roundsArg] = process.argv.slice(2)
const WARMUP = Number(warmupArg)
const STEPS = Number(stepsArg)
const ROUNDS = Number(roundsArg)
if (scene !== 'pile' && scene !== 'room') throw new Error(`scene must be pile or room, got ${scene}`)
if (!(WARMUP >= 0 && STEPS > 0 && ROUNDS > 0)) {
  throw new Error(`bad warm-up, step or round count: ${warmupArg} ${stepsArg} ${roundsArg}`)
}

/**
 * The room's players (see the file comment). Between rounds, `regrab` releases the grabs, spawns a
 * body (destroying the oldest spawned one past 12) and grabs five random dynamic bodies; in a round,
 * `drag(i)` moves each grab's target (allocation-free), every third step per player.
 */
class RoomSchedule {
  private readonly prng = new Prng(7)
  private readonly grabs: JointId[] = []
  private readonly spawned: BodyId[] = []
  private readonly target: Vec2 = { x: 0, y: 0 }
  private spawns = 0

  constructor(private readonly world: World) {}

  /** Releases every grab, spawns a body (and destroys the oldest spawned one past 12), grabs five. */
  regrab(): void {
    const world = this.world
    for (const joint of this.grabs) if (world.hasJoint(joint)) world.destroyJoint(joint)
    this.grabs.length = 0
    this.spawn()
    const ids = world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic')
    for (let p = 0; p < 5; p++) {
      const body = ids[this.prng.int(ids.length)]
      const target = world.getWorldCenter(body)
      this.grabs.push(
        world.createJoint({ type: 'mouse', body, target, maxForce: 1000 * world.getMass(body) }),
      )
    }
  }

  /** Moves player p's target round its ellipse (a lap in 80 of the player's steps) before step i. */
  drag(i: number): void {
    for (let p = 0; p < this.grabs.length; p++) {
      if ((i + p) % 3 !== 0) continue
      const a = ((((i + p) / 3 + 16 * p) % 80) / 80) * 2 * Math.PI
      this.target.x = 4 * Math.cos(a)
      this.target.y = 6 + 3 * Math.sin(a)
      this.world.setJointTarget(this.grabs[p], this.target)
    }
  }

  private spawn(): void {
    const world = this.world
    const kind = this.spawns++ % 3
    const shape =
      kind === 0
        ? circle(this.prng.range(0.3, 0.6))
        : kind === 1
          ? box(this.prng.range(0.3, 0.6), this.prng.range(0.3, 0.6))
          : polygon([
              { x: -0.4, y: -0.3 },
              { x: 0.4, y: -0.3 },
              { x: 0, y: 0.5 },
            ])
    const position = { x: this.prng.range(-5, 5), y: this.prng.range(8, 12) }
    this.spawned.push(world.createBody({ type: 'dynamic', shape, position }))
    if (this.spawned.length > 12) world.destroyBody(this.spawned.shift()!)
  }
}

const world = createWorld(scene === 'pile' ? { enableSleep: false } : {})
if (scene === 'pile') {
  buildScene(world, pileScene(300))
  for (const [x, height] of [
    [40, 20],
    [45, 50],
  ]) {
    for (let i = 0; i < height; i++)
      world.createBody({ position: { x: x + (i % 2) * 0.05, y: 0.5 + i }, shape: box(0.5, 0.5) })
  }
} else {
  const pile = pileScene(100)
  buildScene(world, {
    ...pile,
    bodies: pile.bodies.map((b) => (b.type === 'static' ? b : { ...b, enableSleep: false })),
  })
}
const schedule = scene === 'room' ? new RoomSchedule(world) : null
let tick = 0
/** Steps between the room's regrabs in the warm-up (the measured rounds regrab once, first). */
const REGRAB_STEPS = 600
/** One step of the scene: in the room, the players' drags, the step, and once a second a hash. */
function step(): void {
  schedule?.drag(tick)
  world.step()
  if (schedule !== null && tick % 60 === 0) world.hash()
  tick++
}
for (let i = 0; i < WARMUP; i++) {
  if (i % REGRAB_STEPS === 0) schedule?.regrab()
  step()
}

/** Heap growth of STEPS steps (the room regrabs first: its commands allocate, so outside). */
function round(): number {
  schedule?.regrab()
  const before = process.memoryUsage().heapUsed
  for (let i = 0; i < STEPS; i++) step()
  return process.memoryUsage().heapUsed - before
}

// Collections that start inside the measured rounds. Entries reach the observer late (on a loaded
// machine after a 10 ms wait, so the two gc() calls below once counted as collections in the
// window): each is kept only if it started after the rounds began and before they ended. V8 also
// collects when the thread is idle, as in the 100 ms wait after the rounds (CI, Nov 24 03:10: one
// scavenge counted with 0.08 bytes per step of heap growth and only the inspector's allocations
// sampled after): that is not the steps' garbage.
const kinds: number[] = []
let windowStart = Number.POSITIVE_INFINITY
let windowEnd = Number.POSITIVE_INFINITY
const observer = new PerformanceObserver((list) => {
  for (const e of list.getEntries()) {
    const kind = (e as { detail?: { kind?: number } }).detail?.kind ?? 0
    if (e.startTime >= windowStart && e.startTime <= windowEnd) kinds.push(kind)
  }
})
observer.observe({ entryTypes: ['gc'] })
gc()
gc()
await new Promise((r) => setTimeout(r, 10))
windowStart = performance.now()
let heapGrowth = Number.POSITIVE_INFINITY
for (let r = 0; r < ROUNDS; r++) heapGrowth = Math.min(heapGrowth, round())
windowEnd = performance.now()
await new Promise((r) => setTimeout(r, 100))
const result: AllocationResult = {
  scene,
  steps: STEPS,
  bodies: world.bodyCount,
  contacts: world.contacts().length,
  gcCount: kinds.length,
  gcKinds: kinds,
  heapGrowth,
  allocators: [],
}
if (result.gcCount > 0 || heapGrowth > 64 * STEPS) result.allocators = await allocators()
console.log(JSON.stringify(result))

/** The eight functions that allocate most over 1000 more steps (V8's sampling heap profiler). */
async function allocators(): Promise<{ where: string; bytes: number }[]> {
  const session = new Session()
  session.connect()
  const post = (method: string, params?: object): Promise<unknown> =>
    new Promise((resolve, reject) => session.post(method, params, (e, r) => (e ? reject(e) : resolve(r))))
  await post('HeapProfiler.startSampling', {
    samplingInterval: 256,
    includeObjectsCollectedByMajorGC: true,
    includeObjectsCollectedByMinorGC: true,
  })
  for (let i = 0; i < 1000; i++) step()
  const { profile } = (await post('HeapProfiler.stopSampling')) as { profile: { head: ProfileNode } }
  const totals = new Map<string, number>()
  const walk = (node: ProfileNode): void => {
    const f = node.callFrame
    if (node.selfSize > 0) {
      const key = `${f.functionName || '(anonymous)'} ${f.url.split('/').slice(-2).join('/')}:${f.lineNumber + 1}`
      totals.set(key, (totals.get(key) ?? 0) + node.selfSize)
    }
    for (const child of node.children) walk(child)
  }
  walk(profile.head)
  return [...totals]
    .sort((a, b) => b[1] - a[1])
    .slice(0, 8)
    .map(([where, bytes]) => ({ where, bytes }))
}

interface ProfileNode {
  callFrame: { functionName: string; url: string; lineNumber: number }
  selfSize: number
  children: ProfileNode[]
}
