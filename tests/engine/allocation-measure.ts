/*
 * The measuring program of allocation.test.ts. The test bundles it with esbuild and runs it in a
 * separate, quiet `node --expose-gc` process, so that vitest's own work cannot allocate or collect
 * in the measured window. Arguments: the scene (`pile` or `room`), warm-up steps, measured steps
 * per round, rounds; it prints one JSON line (AllocationResult).
 *
 * - pile: a 300-body pile (pileScene(300), sleeping off, so every body is simulated every step).
 *   heapUsed is read, the steps run, heapUsed is read again, with no gc() in between: heapUsed
 *   includes the young generation, so (after - before) is what the steps allocated.
 * - room: the server's capacity room without the server: a 100-body pile whose bodies never sleep
 *   (bench/server-load.ts awakePile), and five players who, every third step (their 20 Hz loop),
 *   grab a random dynamic body with a mouse joint, drag it round an ellipse of half-axes 4 m and 3 m in 80 of their steps
 *   (about 6 m/s: fast bodies, continuous collision, contacts made and broken) and release it,
 *   while a body is spawned above the pile every 50 steps and the oldest spawned one destroyed
 *   once there are more than 12. The players' commands allocate (joints, bodies, id lists) and
 *   run between the steps, so heapUsed is read around each world.step() alone, and once more
 *   right after: what a read allocates after taking its figure shows between the last two reads
 *   and is subtracted.
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
  /**
   * Least heap growth of the rounds (bytes), without what reading heapUsed allocates (room); rounds
   * with a collection inside a step have no figure, and if every round had one this is null.
   */
  heapGrowth: number | null
  /** Mean bytes one heapUsed read allocates after taking its figure (room; 0 for pile). */
  baseline: number
  /** Steps during which the heap shrank (a collection inside the step; room only). */
  shrunkSteps: number
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

/** The room's players, spawns and removals (see the file comment); `act(i)` runs before step i. */
class RoomSchedule {
  private readonly prng = new Prng(7)
  private readonly grabs: (JointId | null)[] = [null, null, null, null, null]
  private readonly spawned: BodyId[] = []
  private readonly target: Vec2 = { x: 0, y: 0 }

  constructor(private readonly world: World) {}

  act(i: number): void {
    const world = this.world
    if (i % 50 === 0) this.spawn(i)
    for (let p = 0; p < this.grabs.length; p++) {
      if ((i + p) % 3 !== 0) continue
      const phase = ((i + p) / 3 + 20 * p) % 100
      const joint = this.grabs[p]
      if (phase === 0) {
        const ids = world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic')
        const body = ids[this.prng.int(ids.length)]
        const target = world.getWorldCenter(body)
        this.grabs[p] = world.createJoint({
          type: 'mouse',
          body,
          target,
          maxForce: 1000 * world.getMass(body),
        })
      } else if (joint !== null && !world.hasJoint(joint)) {
        this.grabs[p] = null
      } else if (joint !== null && phase === 80) {
        world.destroyJoint(joint)
        this.grabs[p] = null
      } else if (joint !== null && phase < 80) {
        const a = (phase / 80) * 2 * Math.PI
        this.target.x = 4 * Math.cos(a)
        this.target.y = 6 + 3 * Math.sin(a)
        world.setJointTarget(joint, this.target)
      }
    }
  }

  private spawn(i: number): void {
    const world = this.world
    const kind = (i / 50) % 3
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
    if (this.spawned.length > 12) {
      const doomed = this.spawned.shift()!
      if (world.hasBody(doomed)) world.destroyBody(doomed)
    }
  }
}

const world = createWorld(scene === 'pile' ? { enableSleep: false } : {})
if (scene === 'pile') buildScene(world, pileScene(300))
else {
  const pile = pileScene(100)
  buildScene(world, {
    ...pile,
    bodies: pile.bodies.map((b) => (b.type === 'static' ? b : { ...b, enableSleep: false })),
  })
}
const schedule = scene === 'room' ? new RoomSchedule(world) : null
let tick = 0
for (let i = 0; i < WARMUP; i++) {
  schedule?.act(tick++)
  world.step()
}

/** Bytes the heapUsed reads of the room's rounds allocated after taking their figures. */
let baseline = 0

/** Heap growth of STEPS steps: the whole window (pile) or the sum around each step (room). */
function round(): { growth: number; shrunk: number } {
  if (schedule === null) {
    const before = process.memoryUsage().heapUsed
    for (let i = 0; i < STEPS; i++) world.step()
    return { growth: process.memoryUsage().heapUsed - before, shrunk: 0 }
  }
  let growth = 0
  let shrunk = 0
  for (let i = 0; i < STEPS; i++) {
    schedule.act(tick++)
    const h0 = process.memoryUsage().heapUsed
    world.step()
    const h1 = process.memoryUsage().heapUsed
    const h2 = process.memoryUsage().heapUsed
    // What a read allocates after taking its figure (h2 - h1, nothing between) is in h1 - h0 too.
    if (h1 < h0 || h2 < h1) shrunk++
    growth += h1 - h0 - (h2 - h1)
    baseline += h2 - h1
  }
  return { growth, shrunk }
}

// Collections that start inside the measured rounds. Entries reach the observer late (on a loaded
// machine after a 10 ms wait, so the two gc() calls below once counted as collections in the
// window): each is kept only if it started after the rounds began.
const kinds: number[] = []
let windowStart = Number.POSITIVE_INFINITY
const observer = new PerformanceObserver((list) => {
  for (const e of list.getEntries()) {
    const kind = (e as { detail?: { kind?: number } }).detail?.kind ?? 0
    if (e.startTime >= windowStart) kinds.push(kind)
  }
})
observer.observe({ entryTypes: ['gc'] })
gc()
gc()
await new Promise((r) => setTimeout(r, 10))
windowStart = performance.now()
let heapGrowth = Number.POSITIVE_INFINITY
let shrunkSteps = 0
for (let r = 0; r < ROUNDS; r++) {
  const { growth, shrunk } = round()
  // A round with a collection inside a step has no figure (its heap shrank).
  if (shrunk === 0) heapGrowth = Math.min(heapGrowth, growth)
  shrunkSteps += shrunk
}
await new Promise((r) => setTimeout(r, 100))
const result: AllocationResult = {
  scene,
  steps: STEPS,
  bodies: world.bodyCount,
  contacts: world.contacts().length,
  gcCount: kinds.length,
  gcKinds: kinds,
  heapGrowth: Number.isFinite(heapGrowth) ? heapGrowth : null,
  baseline: Math.round(baseline / (ROUNDS * STEPS)),
  shrunkSteps,
  allocators: [],
}
if (result.gcCount > 0 || shrunkSteps > 0 || heapGrowth > 64 * STEPS) result.allocators = await allocators()
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
  for (let i = 0; i < 1000; i++) {
    schedule?.act(tick++)
    world.step()
  }
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
