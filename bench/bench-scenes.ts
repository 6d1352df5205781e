/*
 * The scenes of the cross-engine comparison (`npm run bench:peers` and the benchmark page), each
 * defined once as data and built identically in every engine.
 *
 * Pyramids, the pile and the tower are the engine's own blueprints (engine/scenes/scenes.ts). Two more
 * live here because only the comparison uses them: a grid of circles pinned to their neighbours
 * by revolute joints and hung from its top corners (Box2D v3's joint-grid benchmark, smaller), and
 * a rain of mixed bodies arriving in rows over time into the pile's container (what a sandbox
 * sees while people spawn things). A rain's arrivals are plain body definitions with the step at
 * which every engine adds them; bodies arrive moving down at 10 m/s, one row every 8 steps, so a
 * row has fallen 1.4 m before the next appears above it.
 */

import {
  type BodyDef,
  box,
  circle,
  type JointDef,
  PI,
  Prng,
  pileScene,
  pyramidScene,
  regularPolygon,
  type SceneBlueprint,
  type Shape,
  towerScene,
} from '../engine/index.ts'

/** Which end-state test a scene gets. */
export type BenchSceneKind = 'pyramid' | 'pile' | 'tower' | 'grid' | 'rain'

/** A body added to the world before the step with this index (0 = before the first step). */
export interface Arrival {
  step: number
  def: BodyDef
}

/** A built comparison scene: the blueprint every engine builds, and bodies that arrive later. */
export interface BenchSceneInstance {
  blueprint: SceneBlueprint
  arrivals: Arrival[]
}

/** A comparison scene: how to build it for a body count, and how long to run it. */
export interface BenchScene {
  name: string
  kind: BenchSceneKind
  description: string
  /** Dynamic bodies in the default build (the pile's and rain's count, the pyramid's boxes ...). */
  defaultCount: number
  make(count: number): BenchSceneInstance
  /** Timed steps in a full terminal run. */
  steps: number
}

/** Rows of a pyramid with about `count` boxes (rows (rows + 1) / 2 >= count). */
export function pyramidRowsFor(count: number): number {
  return Math.max(2, Math.round((Math.sqrt(8 * count + 1) - 1) / 2))
}

/** A grid of `side` x `side` circles (radius 0.4 m, 1 m apart) pinned to their left and upper neighbours. */
export function jointGridScene(side: number): SceneBlueprint {
  const top = side + 1
  const bodies: BodyDef[] = [
    { type: 'static', position: { x: 0, y: -1 }, shape: box(Math.max(100, side), 1) },
  ]
  const joints: JointDef[] = []
  const shape = circle(0.4)
  const index = (row: number, column: number): number => 1 + row * side + column
  for (let row = 0; row < side; row++) {
    for (let column = 0; column < side; column++) {
      const x = column - (side - 1) / 2
      const y = top - row
      bodies.push({ position: { x, y }, shape, friction: 0.6 })
      if (column > 0) {
        joints.push({
          type: 'revolute',
          bodyA: index(row, column - 1),
          bodyB: index(row, column),
          anchor: { x: x - 0.5, y },
        })
      }
      if (row > 0) {
        joints.push({
          type: 'revolute',
          bodyA: index(row - 1, column),
          bodyB: index(row, column),
          anchor: { x, y: y + 0.5 },
        })
      }
    }
  }
  const corners = [0, side - 1]
  for (const column of corners) {
    const x = column - (side - 1) / 2
    joints.push({ type: 'revolute', bodyA: null, bodyB: index(0, column), anchor: { x, y: top + 0.5 } })
  }
  return { name: `joint-grid-${side}`, gravity: { x: 0, y: -10 }, bodies, joints }
}

/** Steps between rain rows. */
export const RAIN_ROW_STEPS = 8
/** Downward speed of arriving rain bodies (m/s). */
export const RAIN_SPEED = 10

/** `count` mixed bodies raining in rows into the container of pileScene(count). */
export function rainScene(count: number, seed = 2): BenchSceneInstance {
  const container = pileScene(count)
  const statics = container.bodies.filter((def) => def.type === 'static')
  const wall = statics.find((def) => (def.position?.x ?? 0) > 0)
  const inner = 2 * ((wall?.position?.x ?? 5) - 0.5)
  const wallTop = 2 * (wall?.position?.y ?? 5)
  const columns = Math.max(1, Math.floor(inner) - 1)
  const prng = new Prng(seed)
  const arrivals: Arrival[] = []
  for (let i = 0; i < count; i++) {
    const row = Math.floor(i / columns)
    const column = i % columns
    const kind = prng.int(3)
    let shape: Shape
    if (kind === 0) shape = circle(prng.range(0.25, 0.45))
    else if (kind === 1) shape = box(prng.range(0.2, 0.45), prng.range(0.2, 0.45))
    else shape = regularPolygon(3 + prng.int(6), prng.range(0.3, 0.45))
    const x = -inner / 2 + 1 + column + prng.range(-0.05, 0.05)
    arrivals.push({
      step: row * RAIN_ROW_STEPS,
      def: {
        position: { x, y: wallTop + 1 },
        angle: prng.range(0, 2 * PI),
        linearVelocity: { x: 0, y: -RAIN_SPEED },
        shape,
        friction: 0.6,
      },
    })
  }
  return { blueprint: { name: `rain-${count}`, gravity: container.gravity, bodies: statics }, arrivals }
}

const still = (blueprint: SceneBlueprint): BenchSceneInstance => ({ blueprint, arrivals: [] })

/** The comparison's scenes, in the order they run. */
export const BENCH_SCENES: readonly BenchScene[] = [
  {
    name: 'pyramid-20',
    kind: 'pyramid',
    description: 'A 20-row pyramid of 1 m boxes',
    defaultCount: 210,
    make: (count) => still(pyramidScene(pyramidRowsFor(count))),
    steps: 200,
  },
  {
    name: 'pyramid-50',
    kind: 'pyramid',
    description: 'A 50-row pyramid of 1 m boxes',
    defaultCount: 1275,
    make: (count) => still(pyramidScene(pyramidRowsFor(count))),
    steps: 100,
  },
  {
    name: 'pile-1000',
    kind: 'pile',
    description: 'Mixed circles, boxes and polygons dropped into a container',
    defaultCount: 1000,
    make: (count) => still(pileScene(count)),
    steps: 120,
  },
  {
    name: 'tower-10',
    kind: 'tower',
    description: 'A tower of 10 boxes',
    defaultCount: 10,
    make: (count) => still(towerScene(count, false)),
    steps: 200,
  },
  {
    name: 'joint-grid',
    kind: 'grid',
    description: 'A 20 x 20 grid of circles linked by revolute joints, hung from two corners',
    defaultCount: 400,
    make: (count) => still(jointGridScene(Math.max(2, Math.round(Math.sqrt(count))))),
    steps: 150,
  },
  {
    name: 'rain',
    kind: 'rain',
    description: '500 mixed bodies arriving in rows over time into a container',
    defaultCount: 500,
    make: (count) => rainScene(count),
    steps: 200,
  },
]

/** The comparison scene with this name; the error lists the names. */
export function benchScene(name: string): BenchScene {
  const scene = BENCH_SCENES.find((s) => s.name === name)
  if (!scene)
    throw new Error(
      `unknown scene ${JSON.stringify(name)}; choose one of ${BENCH_SCENES.map((s) => s.name).join(', ')}`,
    )
  return scene
}
