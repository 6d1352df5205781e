/*
 * Joints under mass ratios (issue 13), against oracles that do not come from the solver:
 * - geometry: a chain of 20 pinned 0.5 m links hangs 10 m long at rest (rigid pins: no stretch);
 * - statics: the top pin carries the whole weight, sum of m g;
 * - rest: nothing moves after 10 s (the chain started at rest; the ragdolls fell and tumbled);
 * - energy: a chain released horizontally never rises above its release height (no energy gain);
 * - limits: every limited joint of a ragdoll at rest lies within its limits.
 * Sleep is off, so "at rest" is the solver's doing, not the sleep timer's.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  CHAIN_LINK_LENGTH,
  CHAIN_TOP,
  createWorld,
  hangingChainScene,
  ragdollScene,
  type World,
} from '../../engine/index.ts'
import { fastest } from '../support/motion-measures.ts'

const G = 10

/** Largest distance between a joint's two world anchors (m): how far the pins have come apart. */
function maxJointGap(world: World): number {
  let gap = 0
  for (const j of world.joints())
    gap = Math.max(gap, Math.hypot(j.anchorA.x - j.anchorB.x, j.anchorA.y - j.anchorB.y))
  return gap
}

describe('a chain of 20 pinned links holding a box 100 times heavier than a link', () => {
  const links = 20
  const world = createWorld({ enableSleep: false })
  const ids = buildScene(world, hangingChainScene(links, 100))
  const heavy = ids[ids.length - 1]
  for (let i = 0; i < 600; i++) world.step()

  it('the box is 100 times heavier than a link', () => {
    expect(world.getMass(heavy) / world.getMass(ids[1])).toBeCloseTo(100, 9)
  })

  it('after 10 s hangs 10 m long within 5 mm (Box2D v3: 30 cm), pins within 1 mm', () => {
    const top = world.getWorldPoint(heavy, { x: 0, y: 0.25 })
    const length = Math.hypot(top.x - CHAIN_TOP.x, top.y - CHAIN_TOP.y)
    expect(Math.abs(length - links * CHAIN_LINK_LENGTH)).toBeLessThan(0.005)
    expect(maxJointGap(world)).toBeLessThan(0.001)
  })

  it('after 10 s is still: every body slower than 1 mm/s (Box2D v3: 0.2 m/s)', () => {
    const { v, w } = fastest(world)
    expect(v).toBeLessThan(0.001)
    expect(w).toBeLessThan(0.001)
  })

  it('the top pin carries the whole weight, sum of m g', () => {
    let weight = 0
    for (const id of ids.slice(1)) weight += world.getMass(id) * G
    const force = world.getJointReaction(world.jointIds()[0]).force
    expect(force.y).toBeCloseTo(weight, 6)
    expect(Math.abs(force.x)).toBeLessThan(1e-6 * weight)
  })

  it('also holds at 1000:1: 10 m within 5 mm, still', () => {
    const w2 = createWorld({ enableSleep: false })
    const ids2 = buildScene(w2, hangingChainScene(links, 1000))
    for (let i = 0; i < 600; i++) w2.step()
    const top = w2.getWorldPoint(ids2[ids2.length - 1], { x: 0, y: 0.25 })
    expect(Math.abs(Math.hypot(top.x - CHAIN_TOP.x, top.y - CHAIN_TOP.y) - 10)).toBeLessThan(0.005)
    expect(fastest(w2).v).toBeLessThan(0.001)
  })
})

describe('a chain released horizontally with a heavy box at its end', () => {
  /** Kinetic plus potential energy of every body (J), with the potential zero at y = 0. */
  function energy(world: World): number {
    let e = 0
    for (const id of world.bodyIds()) {
      const m = world.getMass(id)
      const v = world.getLinearVelocity(id)
      const w = world.getAngularVelocity(id)
      e +=
        m * G * world.getWorldCenter(id).y +
        0.5 * m * (v.x * v.x + v.y * v.y) +
        0.5 * world.getInertia(id) * w * w
    }
    return e
  }

  it('swings with its pins within 3 cm (Gauss-Seidel alone: 15 cm) and never gains energy', () => {
    const world = createWorld({ enableSleep: false })
    const y = 30
    let prev: number | null = null
    for (let i = 0; i < 20; i++) {
      const id = world.createBody({ position: { x: (i + 0.5) * 0.5, y }, shape: box(0.25, 0.05) })
      world.createJoint({ type: 'revolute', bodyA: prev, bodyB: id, anchor: { x: i * 0.5, y } })
      prev = id
    }
    const heavy = world.createBody({ position: { x: 10.25, y }, shape: box(0.25, 0.25), density: 20 })
    world.createJoint({ type: 'revolute', bodyA: prev, bodyB: heavy, anchor: { x: 10, y } })
    const e0 = energy(world)
    let gap = 0
    let most = Number.NEGATIVE_INFINITY
    let fastestSeen = 0
    for (let i = 0; i < 600; i++) {
      world.step()
      gap = Math.max(gap, maxJointGap(world))
      most = Math.max(most, energy(world))
      const v = world.getLinearVelocity(heavy)
      fastestSeen = Math.max(fastestSeen, Math.hypot(v.x, v.y))
    }
    expect(gap).toBeLessThan(0.03)
    // Energy: the soft step may lose energy, never make it (0.1% of the 10 m drop's worth).
    expect(most - e0).toBeLessThan(0.001 * 6 * G * 10)
    // It did swing: sqrt(2 g 10 m) = 14 m/s at the bottom for a point mass on a rigid rod.
    expect(fastestSeen).toBeGreaterThan(10)
  })
})

describe('ragdolls: trees of revolute joints with limits', () => {
  const count = 3
  const world = createWorld({ enableSleep: false })
  const scene = ragdollScene(count)
  buildScene(world, scene)
  for (let i = 0; i < 900; i++) world.step()

  it('three ragdolls dropped in a heap come to rest within 15 s', () => {
    const { v, w } = fastest(world)
    expect(v).toBeLessThan(0.005)
    expect(w).toBeLessThan(0.02)
  })

  it('their pins hold within 2 mm and every joint is within its limits (0.05 rad slop)', () => {
    expect(maxJointGap(world)).toBeLessThan(0.002)
    const joints = scene.joints ?? []
    for (const [k, info] of world.joints().entries()) {
      const def = joints[k]
      if (def.type !== 'revolute' || info.bodyA === null)
        throw new Error('ragdoll joints are pins between parts')
      // Parts start unrotated, so the joint angle is the difference of the body angles.
      const angle = world.getAngle(info.bodyB) - world.getAngle(info.bodyA)
      const wrapped = Math.atan2(Math.sin(angle), Math.cos(angle))
      expect(wrapped).toBeGreaterThan((def.lowerAngle ?? 0) - 0.05)
      expect(wrapped).toBeLessThan((def.upperAngle ?? 0) + 0.05)
    }
  })
})
