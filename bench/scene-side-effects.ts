/*
 * Side effects of a solver variant (`npx tsx bench/scene-side-effects.ts [--engine DIR] [--only a,b]`):
 * prints, for the engine/ folder DIR (default this checkout's), the figures engine/README.md
 * "Robustness" keeps as main's reference, so a change aimed at one scene is measured on the others:
 * - tower: the 20-box tower with 1 m boxes alternately offset by 5 cm (x = 0, 0.05, 0, ...), sleep
 *   off: largest sideways offset from its start x of any box up to 10 s and over 10-30 s, fastest
 *   body at 10 s and at 30 s;
 * - pyramid-30 / pyramid-50: largest drift of any box between 5 s and 10 s, fastest body at 10 s;
 * - pile-1000 seeds 1-4: fastest body over the last 0.5 s of 10 s (sampled every step);
 * - drop-400: the 400:1 drop (20 x 20 m box from 15 m onto two 1 m boxes, thin ground) centre at 10 s
 *   (the test's hand-computed soft rest height is 10.9608 m), fastest body over the last 2 s;
 * - cards: the 4-storey card house's worst card drift after 10 s;
 * - ragdolls: fastest linear and angular speed of three ragdolls after 15 s.
 * Not a test: numbers to compare variants by; the tests hold the limits. Saves the printed lines,
 * the engine folder and the machine to bench/results/scene-side-effects.json (`--out`).
 */

import { resolve } from 'node:path'
import { pathToFileURL } from 'node:url'
import { parseArgs } from 'node:util'
import { driftOver, fastest, type MovingWorld } from '../tests/support/motion-measures.ts'
import { machineInfo, saveResults } from './stats.ts'

/** The part of engine/index.ts this script uses. */
interface Engine {
  createWorld(def: { enableSleep: boolean }): World
  buildScene(world: World, scene: unknown): number[]
  groundDef(): unknown
  box(hx: number, hy: number): unknown
  pyramidScene(rows: number): unknown
  pileScene(count: number, seed: number): unknown
  cardHouseScene(storeys: number): { bodies: { position?: { x: number; y: number } }[] }
  ragdollScene(count: number): unknown
}

/** The part of World this script uses. */
interface World extends MovingWorld {
  createBody(def: unknown): number
}

const { values } = parseArgs({
  options: {
    engine: { type: 'string', default: 'engine' },
    only: { type: 'string', default: '' },
    out: { type: 'string', default: 'bench/results/scene-side-effects.json' },
  },
})
const engine = (await import(pathToFileURL(resolve(values.engine, 'index.ts')).href)) as Engine
const only = values.only === '' ? null : new Set(values.only.split(','))
const want = (name: string): boolean => only === null || only.has(name)

const f4 = (x: number): string => x.toFixed(4)
const lines: string[] = []
/** Prints a result line and keeps it for the saved results. */
function report(line: string): void {
  console.log(line)
  lines.push(line)
}

if (want('tower')) {
  const world = engine.createWorld({ enableSleep: false })
  world.createBody(engine.groundDef())
  const ids: number[] = []
  const starts: number[] = []
  for (let i = 0; i < 20; i++) {
    starts.push((i % 2) * 0.05)
    ids.push(
      world.createBody({
        position: { x: starts[i], y: 0.5 + i },
        shape: engine.box(0.5, 0.5),
        friction: 0.6,
      }),
    )
  }
  let early = 0
  let late = 0
  let at10 = 0
  const samples: string[] = []
  for (let step = 1; step <= 1800; step++) {
    world.step()
    let worst = 0
    ids.forEach((id, i) => {
      worst = Math.max(worst, Math.abs(world.getPosition(id).x - starts[i]))
    })
    if (step <= 600) early = Math.max(early, worst)
    else late = Math.max(late, worst)
    if (step === 600) at10 = fastest(world).v
    if (step % 120 === 0) samples.push(f4(worst))
  }
  report(
    `tower: worst offset to 10 s ${f4(early)} m, 10-30 s ${f4(late)} m, fastest at 10 s ${f4(at10)} m/s, at 30 s ${f4(fastest(world).v)} m/s; offset every 2 s: ${samples.join(' ')}`,
  )
}

for (const rows of [30, 50]) {
  if (!want(`pyramid-${rows}`)) continue
  const world = engine.createWorld({ enableSleep: false })
  const ids = engine.buildScene(world, engine.pyramidScene(rows))
  const drift = driftOver(world, ids, 300, 300)
  report(`pyramid-${rows}: drift 5-10 s ${f4(drift)} m, fastest at 10 s ${f4(fastest(world).v)} m/s`)
}

if (want('pile')) {
  const out: string[] = []
  for (const seed of [1, 2, 3, 4]) {
    const world = engine.createWorld({ enableSleep: false })
    engine.buildScene(world, engine.pileScene(1000, seed))
    let worst = 0
    for (let i = 1; i <= 600; i++) {
      world.step()
      if (i > 570) worst = Math.max(worst, fastest(world).v)
    }
    out.push(worst.toFixed(3))
  }
  report(`pile-1000 seeds 1-4, fastest over the last 0.5 s: ${out.join(' / ')} m/s`)
}

if (want('drop')) {
  const world = engine.createWorld({ enableSleep: false })
  world.createBody({ type: 'static', position: { x: 0, y: -0.005 }, shape: engine.box(100, 0.005) })
  for (const x of [-9, 9]) world.createBody({ position: { x, y: 0.5 }, shape: engine.box(0.5, 0.5) })
  const heavy = world.createBody({ position: { x: 0, y: 25 }, shape: engine.box(10, 10) })
  let late = 0
  for (let i = 1; i <= 600; i++) {
    world.step()
    if (i > 480) late = Math.max(late, fastest(world).v)
  }
  report(
    `drop-400: heavy centre ${f4(world.getPosition(heavy).y)} m (hand 10.9608), fastest over the last 2 s ${f4(late)} m/s`,
  )
}

if (want('cards')) {
  const scene = engine.cardHouseScene(4)
  const world = engine.createWorld({ enableSleep: false })
  const ids = engine.buildScene(world, scene)
  for (let i = 0; i < 600; i++) world.step()
  let drift = 0
  ids.forEach((id, k) => {
    if (k === 0) return
    const s = scene.bodies[k].position ?? { x: 0, y: 0 }
    const p = world.getPosition(id)
    drift = Math.max(drift, Math.hypot(p.x - s.x, p.y - s.y))
  })
  report(`cards: worst card drift at 10 s ${f4(drift)} m`)
}

if (want('ragdolls')) {
  const world = engine.createWorld({ enableSleep: false })
  engine.buildScene(world, engine.ragdollScene(3))
  for (let i = 0; i < 900; i++) world.step()
  const { v, w } = fastest(world)
  report(`ragdolls: at 15 s fastest ${f4(v)} m/s, ${f4(w)} rad/s`)
}

saveResults(values.out, { machine: machineInfo(), engine: resolve(values.engine), lines })
