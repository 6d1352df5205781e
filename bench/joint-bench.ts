/*
 * Joint benchmark: step time of the joint scenes (sleep off), and how well the chain holds.
 * Scenes: the 20-link hanging chain under a 100:1 box, 12 ragdolls in a heap, a 40-plank chain
 * bridge, the joints showcase and Newton's cradle. Each scene runs ROUNDS times (rounds
 * interleaved over the scenes), STEPS steps after WARMUP; the table shows the median step time of
 * the best round. Prints a table and writes bench/results/joints.json (with the machine).
 * Run: npx tsx bench/joint-bench.ts
 */
import { performance } from 'node:perf_hooks'
import {
  buildScene,
  CHAIN_LINK_LENGTH,
  CHAIN_TOP,
  chainBridgeScene,
  createWorld,
  hangingChainScene,
  jointsScene,
  newtonsCradleScene,
  ragdollScene,
  type SceneBlueprint,
} from '../engine/index.ts'
import { formatTable, machineInfo, median, saveResults } from './stats.ts'

const WARMUP = 60
const STEPS = 600
const ROUNDS = 3

const SCENES: Array<{ name: string; make: () => SceneBlueprint }> = [
  { name: 'hanging chain 20 links, 100:1', make: () => hangingChainScene(20, 100) },
  { name: 'ragdolls x12', make: () => ragdollScene(12) },
  { name: 'chain bridge 40 planks', make: () => chainBridgeScene(40) },
  { name: 'joints showcase', make: jointsScene },
  { name: "Newton's cradle", make: () => newtonsCradleScene(5) },
]

function run(make: () => SceneBlueprint): number {
  const world = createWorld({ enableSleep: false })
  buildScene(world, make())
  for (let i = 0; i < WARMUP; i++) world.step()
  const samples: number[] = []
  for (let i = 0; i < STEPS; i++) {
    const t0 = performance.now()
    world.step()
    samples.push(performance.now() - t0)
  }
  return median(samples)
}

/** The chain after 10 s: stretch of the box's top edge below the top pin (m) and fastest body (m/s). */
function chainState(): { stretch: number; speed: number } {
  const world = createWorld({ enableSleep: false })
  const ids = buildScene(world, hangingChainScene(20, 100))
  for (let i = 0; i < 600; i++) world.step()
  const box = ids[ids.length - 1]
  const top = world.getWorldPoint(box, { x: 0, y: 0.25 })
  const stretch = Math.hypot(top.x - CHAIN_TOP.x, top.y - CHAIN_TOP.y) - 20 * CHAIN_LINK_LENGTH
  let speed = 0
  for (const id of ids.slice(1)) {
    const v = world.getLinearVelocity(id)
    speed = Math.max(speed, Math.hypot(v.x, v.y))
  }
  return { stretch, speed }
}

const machine = machineInfo()
const best = SCENES.map(() => Number.POSITIVE_INFINITY)
for (let round = 0; round < ROUNDS; round++) {
  SCENES.forEach((scene, i) => {
    best[i] = Math.min(best[i], run(scene.make))
  })
}
const rows = SCENES.map((scene, i) => [scene.name, best[i].toFixed(4)])
console.log(formatTable(['scene (sleep off)', 'median ms/step'], rows))
const chain = chainState()
console.log(
  `hanging chain at 10 s: stretch ${(chain.stretch * 100).toFixed(2)} cm, fastest body ${chain.speed.toFixed(4)} m/s`,
)
saveResults(new URL('./results/joints.json', import.meta.url).pathname, {
  machine,
  scenes: SCENES.map((scene, i) => ({ name: scene.name, medianMs: best[i] })),
  chain,
})
console.log('wrote bench/results/joints.json')
