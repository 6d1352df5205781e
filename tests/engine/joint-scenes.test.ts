/*
 * The joint scenes (engine/scenes/scenes.ts) do what their descriptions say, checked against physics:
 * the cradle passes the raised ball's speed sqrt(2 g L (1 - cos 30 deg)) down the row, the spring
 * ball rests g / omega^2 below its rest length, the hinged arm rests on its limit, the card house
 * stands. Then determinism with every joint type and a bullet: two runs are bit-identical, a
 * golden hash is pinned, and save/load in the middle of the run continues bit-identically.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  circle,
  createWorld,
  loadWorld,
  PI,
  SCENES,
  type SceneBlueprint,
  type World,
} from '../../engine/index.ts'

const G = 10

function build(scene: SceneBlueprint, enableSleep = true): { world: World; ids: number[] } {
  const world = createWorld({ enableSleep })
  return { world, ids: buildScene(world, scene) }
}

function speed(world: World, id: number): number {
  const v = world.getLinearVelocity(id)
  return Math.hypot(v.x, v.y)
}

describe('joint scenes', () => {
  it('are registered with descriptions and build their joints', () => {
    for (const name of ['joints', 'wrecking-ball', 'newtons-cradle', 'chain-bridge', 'card-house']) {
      expect(SCENES[name].description.length).toBeGreaterThan(10)
      const scene = SCENES[name].make()
      const { world } = build(scene)
      expect(world.jointIds().length).toBe(scene.joints?.length ?? 0)
    }
  })

  it("Newton's cradle passes the first ball's speed to the last one, the others stay nearly still", () => {
    const { world, ids } = build(SCENES['newtons-cradle'].make(), false)
    const balls = ids.slice(1)
    const v0 = Math.sqrt(2 * G * 4 * (1 - Math.cos(PI / 6)))
    let best = 0
    let othersAtBest = 0
    for (let i = 0; i < 90; i++) {
      world.step()
      const v = speed(world, balls[4])
      if (v > best) {
        best = v
        othersAtBest = Math.max(...balls.slice(0, 4).map((id) => speed(world, id)))
      }
    }
    expect(Math.abs(best / v0 - 1)).toBeLessThan(0.05)
    expect(othersAtBest).toBeLessThan(0.1 * v0)
  })

  it('joints scene: the spring ball rests g / omega^2 below its rest length, the arm on its limit', () => {
    const { world, ids } = build(SCENES.joints.make())
    for (let i = 0; i < 600; i++) world.step()
    const omega = 2 * PI * 1.5
    // Within 5 mm: it falls asleep once slower than 0.05 m/s, an amplitude of 0.05 / omega.
    expect(world.getPosition(ids[3]).y).toBeCloseTo(8 - 2 - G / (omega * omega), 2)
    expect(world.getAngle(ids[2])).toBeCloseTo(-PI / 4, 2)
    // The paddle keeps turning at its motor speed between hits.
    expect(world.getAngularVelocity(ids[1])).toBeCloseTo(1.5, 1)
  })

  it('wrecking ball: the rope never stretches and the tower is knocked down', () => {
    const { world, ids } = build(SCENES['wrecking-ball'].make())
    let stretch = 0
    for (let i = 0; i < 240; i++) {
      world.step()
      const p = world.getPosition(ids[1])
      stretch = Math.max(stretch, Math.hypot(p.x + 4, p.y - 10) - 8)
    }
    expect(stretch).toBeLessThan(0.01)
    const moved = ids.slice(2).filter((id) => Math.abs(world.getPosition(id).x + 2) > 2).length
    expect(moved).toBeGreaterThan(4)
  })

  it('chain bridge: the planks stay pinned end to end under load', () => {
    const { world, ids } = build(SCENES['chain-bridge'].make())
    for (let i = 0; i < 240; i++) world.step()
    let worst = 0
    for (let i = 1; i < 20; i++) {
      const right = world.getWorldPoint(ids[i], { x: 0.5, y: 0 })
      const left = world.getWorldPoint(ids[i + 1], { x: -0.5, y: 0 })
      worst = Math.max(worst, Math.hypot(right.x - left.x, right.y - left.y))
    }
    expect(worst).toBeLessThan(0.01)
  })

  it('card house: stands (every card within 5 cm of its start) and falls asleep', () => {
    const scene = SCENES['card-house'].make()
    const { world, ids } = build(scene)
    let drift = 0
    for (let i = 0; i < 300; i++) {
      world.step()
      for (let k = 1; k < ids.length; k++) {
        const p = world.getPosition(ids[k])
        const p0 = scene.bodies[k].position ?? { x: 0, y: 0 }
        drift = Math.max(drift, Math.hypot(p.x - p0.x, p.y - p0.y))
      }
    }
    expect(drift).toBeLessThan(0.05)
    expect(world.awakeBodyCount()).toBe(0)
  })
})

/** The joints scene plus a rod, a rope, a grab and a bullet: every joint type and continuous collision. */
function everything(): { world: World; grab: number } {
  const world = createWorld()
  const ids = buildScene(world, SCENES.joints.make())
  const a = world.createBody({ position: { x: 10, y: 6 }, shape: box(0.3, 0.3) })
  const b = world.createBody({ position: { x: 11, y: 5 }, shape: circle(0.3), angularVelocity: 2 })
  world.createJoint({
    type: 'distance',
    bodyA: null,
    bodyB: a,
    anchorA: { x: 10, y: 8 },
    anchorB: { x: 10, y: 6.3 },
  })
  world.createJoint({
    type: 'distance',
    bodyA: a,
    bodyB: b,
    anchorA: { x: 10, y: 6 },
    anchorB: { x: 11, y: 5 },
    minLength: 0,
    maxLength: 2,
  })
  const grab = world.createJoint({ type: 'mouse', body: ids[4], target: { x: -7, y: 6 }, maxForce: 200 })
  world.createBody({ type: 'static', position: { x: 20, y: 2 }, shape: box(0.025, 2) })
  world.createBody({
    position: { x: 14, y: 1 },
    shape: circle(0.05),
    linearVelocity: { x: 300, y: 0 },
    bullet: true,
  })
  return { world, grab }
}

/** Steps with a moving grab target; returns the hash after every step. */
function run(world: World, grab: number, from: number, to: number): number[] {
  const hashes: number[] = []
  for (let i = from; i < to; i++) {
    world.setJointTarget(grab, { x: -7 + 0.02 * i, y: 6 + 0.01 * i })
    world.step()
    hashes.push(world.hash())
  }
  return hashes
}

describe('determinism with every joint type and a bullet', () => {
  it('two runs are bit-identical and match the golden hash', () => {
    const one = everything()
    const two = everything()
    const h1 = run(one.world, one.grab, 0, 240)
    const h2 = run(two.world, two.grab, 0, 240)
    expect(h2).toEqual(h1)
    // Golden: changes only when the engine's arithmetic changes on purpose (update it then).
    expect(h1[h1.length - 1], `actual golden hash: ${h1[h1.length - 1]}`).toBe(GOLDEN)
  })

  it('save/load in the middle continues bit-identically, joints and their impulses included', () => {
    const original = everything()
    run(original.world, original.grab, 0, 100)
    const copy = loadWorld(original.world.save())
    expect(copy.hash()).toBe(original.world.hash())
    expect(copy.jointIds()).toEqual(original.world.jointIds())
    expect(run(copy, original.grab, 100, 220)).toEqual(run(original.world, original.grab, 100, 220))
  })
})

const GOLDEN = 102102048
