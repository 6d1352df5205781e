/*
 * Breaking joints. The oracle is the joint's own read-back, getJointReaction, in a second world
 * that is identical except that its rope never breaks (the same load, growing 1 % per step) (a break threshold changes nothing until the
 * break): the breakable rope must break on the first step whose reaction exceeds the threshold,
 * never before, and be listed exactly once. Then a bridge of pinned planks that breaks under a
 * load keeps both halves hanging from their pins, while the load falls freely.
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld, type World } from '../../engine/index.ts'

const G = 10

/** A bucket (a 1 m plate) on a 3 m rope from the world; returns [bucket, rope]. */
function bucketOnRope(world: World, breakForce?: number): [number, number] {
  const bucket = world.createBody({ position: { x: 0, y: 2 }, shape: box(0.5, 0.05), density: 20 })
  const rope = world.createJoint({
    type: 'distance',
    bodyA: null,
    bodyB: bucket,
    anchorA: { x: 0, y: 5 },
    anchorB: { x: 0, y: 2 },
    minLength: 0,
    maxLength: 3,
    breakForce,
  })
  return [bucket, rope]
}

describe('breaking joints', () => {
  it('a rope holding a bucket filled step by step breaks on the first step its reaction exceeds breakForce', () => {
    const F = 30
    const reference = createWorld()
    const breaking = createWorld()
    const [, refRope] = bucketOnRope(reference)
    const [bucket, rope] = bucketOnRope(breaking, F)
    let expected = -1
    let brokeAt = -1
    const listed: number[] = []
    for (let step = 1; step <= 600 && brokeAt < 0; step++) {
      // Filling: the load grows 1 % per step (as sand poured in at a steady rate; gravity scaled).
      for (const w of [reference, breaking]) w.setGravity({ x: 0, y: -G * (1 + 0.01 * step) })
      reference.step()
      breaking.step()
      const r = reference.getJointReaction(refRope).force
      const magnitude = Math.hypot(r.x, r.y)
      if (expected < 0 && magnitude > F) expected = step
      const broken = breaking.jointEvents().broken
      listed.push(...broken)
      if (broken.length > 0) brokeAt = step
      else {
        expect(breaking.hasJoint(rope)).toBe(true)
        // Still identical to the reference until the break.
        const rb = breaking.getJointReaction(rope).force
        expect(Math.hypot(rb.x, rb.y)).toBe(magnitude)
      }
    }
    console.log(
      `rope (breakForce ${F} N): reference reaction first above it at step ${expected}, broke at step ${brokeAt}`,
    )
    expect(expected).toBeGreaterThan(0)
    expect(brokeAt).toBe(expected)
    // By hand: the 2 kg bucket weighs 20 (1 + 0.01 s) N at step s, which first exceeds 30 N at s = 51.
    expect(expected).toBe(51)
    expect(listed).toEqual([rope])
    expect(breaking.hasJoint(rope)).toBe(false)
    expect(breaking.isAwake(bucket)).toBe(true)
    breaking.step()
    expect(breaking.jointEvents().broken).toEqual([])
    // The bucket now falls freely.
    const v0 = breaking.getLinearVelocity(bucket).y
    for (let i = 0; i < 6; i++) breaking.step()
    expect(breaking.getLinearVelocity(bucket).y).toBeLessThan(v0)
  })

  it('a break threshold of Infinity never breaks (the bucket falls asleep on its rope); a negative or NaN one is refused', () => {
    const world = createWorld()
    const [bucket, rope] = bucketOnRope(world, Number.POSITIVE_INFINITY)
    for (let i = 0; i < 300; i++) world.step()
    expect(world.isAwake(bucket)).toBe(false)
    expect(world.hasJoint(rope)).toBe(true)
    expect(() => bucketOnRope(world, -1)).toThrow(/breakForce/)
    expect(() => bucketOnRope(world, Number.NaN)).toThrow(/breakForce/)
  })

  it('a bridge that breaks under a load: both halves keep hanging from their pins, the load falls freely', () => {
    const world = createWorld({ enableSleep: false })
    const planks: number[] = []
    const joints: number[] = []
    let previous: number | null = null
    for (let i = 0; i < 8; i++) {
      const p = world.createBody({ position: { x: 0.5 + i, y: 5 }, shape: box(0.5, 0.05), density: 2 })
      joints.push(
        world.createJoint({
          type: 'revolute',
          bodyA: previous,
          bodyB: p,
          anchor: { x: i, y: 5 },
          breakForce: 300,
        }),
      )
      planks.push(p)
      previous = p
    }
    joints.push(
      world.createJoint({
        type: 'revolute',
        bodyA: null,
        bodyB: previous as number,
        anchor: { x: 8, y: 5 },
        breakForce: 300,
      }),
    )
    for (let i = 0; i < 120; i++) world.step()
    expect(world.jointEvents().broken).toEqual([])
    // A 100 kg box dropped on the middle.
    const load = world.createBody({ position: { x: 4, y: 5.6 }, shape: box(0.5, 0.5), density: 100 })
    const broken: number[] = []
    let fallStart = -1
    for (let i = 0; i < 300; i++) {
      world.step()
      const events = world.jointEvents().broken
      for (let k = 1; k < events.length; k++) expect(events[k]).toBeGreaterThan(events[k - 1])
      broken.push(...events)
      if (fallStart < 0 && world.getPosition(load).y < 3) fallStart = i
    }
    console.log(`bridge: joints ${broken.join(', ')} broke; load below 3 m at step ${fallStart}`)
    expect(broken.length).toBeGreaterThan(0)
    expect(new Set(broken).size).toBe(broken.length)
    for (const j of broken) expect(world.hasJoint(j)).toBe(false)
    // The load falls freely once clear: g t.
    const v0 = world.getLinearVelocity(load).y
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getLinearVelocity(load).y - v0).toBeCloseTo(-G * 0.5, 1)
    // What remains of the bridge hangs from its pins: every remaining joint holds (anchors within 1 cm).
    let worst = 0
    for (const info of world.joints())
      worst = Math.max(worst, Math.hypot(info.anchorA.x - info.anchorB.x, info.anchorA.y - info.anchorB.y))
    const remaining = world.joints().length
    console.log(`bridge: ${remaining} pins remain, anchors apart at most ${(worst * 1000).toFixed(3)} mm`)
    expect(remaining).toBe(joints.length - broken.length)
    expect(worst).toBeLessThan(0.01)
    for (const p of planks)
      expect(Number.isFinite(world.getPosition(p).x + world.getPosition(p).y)).toBe(true)
  })
})
