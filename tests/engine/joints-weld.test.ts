/*
 * Weld joint tests against oracles that do not come from the solver:
 * - a rigid cantilever does not bend: its tip stays where it was built (the bound 2 cm;
 *   Box2D v3 sags 2.89 m in the same scene);
 * - a soft weld's angular spring, about the body's centre of mass, oscillates at its hertz;
 * - welded bodies keep their creation-time relative pose (anchor separation 0, relative angle 0)
 *   whatever the mass ratio.
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld, PI, type World } from '../../engine/index.ts'

const DT = 1 / 60

/** Ten 1 m x 0.25 m boxes welded end to end to a static wall at x = 0; returns the boxes. */
function cantilever(world: World, linearHertz = 0, angularHertz = 0): number[] {
  const wall = world.createBody({ type: 'static', position: { x: -0.5, y: 5 }, shape: box(0.5, 2) })
  const boxes: number[] = []
  let previous = wall
  for (let i = 0; i < 10; i++) {
    const b = world.createBody({ position: { x: 0.5 + i, y: 5 }, shape: box(0.5, 0.125), density: 1 })
    world.createJoint({
      type: 'weld',
      bodyA: previous,
      bodyB: b,
      anchor: { x: i, y: 5 },
      linearHertz,
      angularHertz,
    })
    boxes.push(b)
    previous = b
  }
  return boxes
}

/** World y of the cantilever's free end (the top right corner's mid-height: x 0.5 from the last box). */
function tipY(world: World, last: number): number {
  const p = world.getPosition(last)
  return p.y + Math.sin(world.getAngle(last)) * 0.5
}

describe('weld joint: rigid cantilever', () => {
  it('ten welded boxes hold their shape under gravity: tip sag under 2 cm after 10 s', () => {
    const world = createWorld({ enableSleep: false })
    const boxes = cantilever(world)
    const last = boxes[boxes.length - 1]
    const start = tipY(world, last)
    let worst = 0
    for (let i = 0; i < 600; i++) {
      world.step()
      worst = Math.max(worst, start - tipY(world, last))
    }
    const sag = start - tipY(world, last)
    console.log(
      `cantilever tip sag after 10 s ${(sag * 1000).toFixed(3)} mm, worst ${(worst * 1000).toFixed(3)} mm`,
    )
    expect(sag).toBeLessThan(0.02)
    expect(worst).toBeLessThan(0.02)
    // And it is at rest.
    expect(Math.abs(world.getLinearVelocity(last).y)).toBeLessThan(1e-3)
  })
})

describe('weld joint: soft angular spring', () => {
  it('a body welded at its centre with angularHertz f oscillates at f within 2 %', () => {
    for (const hertz of [1, 2, 4]) {
      const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
      const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.2), angularVelocity: 0.5 })
      world.createJoint({
        type: 'weld',
        bodyA: null,
        bodyB: b,
        anchor: { x: 0, y: 0 },
        angularHertz: hertz,
        angularDampingRatio: 0,
      })
      const crossings: number[] = []
      let prev = world.getAngle(b)
      for (let i = 1; i <= 600; i++) {
        world.step()
        const v = world.getAngle(b)
        if (prev > 0 !== v > 0 && prev !== v) crossings.push((i - 1 + prev / (prev - v)) * DT)
        prev = v
      }
      const n = crossings.length - 1
      expect(n).toBeGreaterThanOrEqual(8)
      const measured = n / (2 * (crossings[n] - crossings[0]))
      console.log(`soft weld ${hertz} Hz: measured ${measured.toFixed(4)} Hz`)
      expect(Math.abs(measured / hertz - 1)).toBeLessThan(0.02)
      // The centre stays put (the linear part is rigid).
      expect(Math.hypot(world.getPosition(b).x, world.getPosition(b).y)).toBeLessThan(1e-3)
    }
  })
})

/** Largest anchor separation (m) and relative-angle change (rad) of the welds in `pairs`. */
function weldError(
  world: World,
  pairs: Array<[number, number, number]>,
  angles0: number[],
): [number, number] {
  let gap = 0
  let turn = 0
  for (let k = 0; k < pairs.length; k++) {
    const info = world.joints().find((j) => j.id === pairs[k][2])
    if (!info) throw new Error('weld missing')
    gap = Math.max(gap, Math.hypot(info.anchorA.x - info.anchorB.x, info.anchorA.y - info.anchorB.y))
    const rel = world.getAngle(pairs[k][1]) - world.getAngle(pairs[k][0])
    let d = rel - angles0[k]
    while (d > PI) d -= 2 * PI
    while (d < -PI) d += 2 * PI
    turn = Math.max(turn, Math.abs(d))
  }
  return [gap, turn]
}

describe('weld joint: mass ratios', () => {
  it('a welded tower of boxes alternating 1:10 in mass, knocked over on the ground, stays welded over 60 s', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5) })
    const pairs: Array<[number, number, number]> = []
    let previous = -1
    for (let i = 0; i < 6; i++) {
      const b = world.createBody({
        position: { x: 0.3 * i, y: 0.5 + i },
        angle: 0.3,
        shape: box(0.5, 0.5),
        density: i % 2 === 0 ? 1 : 10,
      })
      if (previous >= 0) {
        const j = world.createJoint({
          type: 'weld',
          bodyA: previous,
          bodyB: b,
          anchor: { x: 0.3 * i - 0.15, y: i },
        })
        pairs.push([previous, b, j])
      }
      previous = b
    }
    const angles0 = pairs.map(([a, b]) => world.getAngle(b) - world.getAngle(a))
    let worstGap = 0
    let worstTurn = 0
    let fallGap = 0
    for (let s = 0; s < 600; s++) {
      world.step()
      fallGap = Math.max(fallGap, weldError(world, pairs, angles0)[0])
    }
    // After the fall (10 s), resting on the ground for 50 s: no drift.
    for (let s = 600; s < 3600; s++) {
      world.step()
      if (s % 10 === 0) {
        const [gap, turn] = weldError(world, pairs, angles0)
        worstGap = Math.max(worstGap, gap)
        worstTurn = Math.max(worstTurn, turn)
      }
    }
    console.log(
      `1:10 welded tower: anchors apart at most ${(fallGap * 1000).toFixed(3)} mm while falling (10 s), then over 50 s at most ${(worstGap * 1000).toFixed(3)} mm, turned ${worstTurn.toExponential(2)} rad`,
    )
    // The impact shoves the welds apart for a moment (contacts are solved after the joints in each
    // sweep, so a contact impulse on one box opens its welds until the next sub-step).
    expect(fallGap).toBeLessThan(0.1)
    expect(worstGap).toBeLessThan(0.005)
    expect(worstTurn).toBeLessThan(0.005)
  })

  it('a heavy box (10x) hanging from a light welded arm does not drift over 60 s', () => {
    const world = createWorld({ enableSleep: false })
    const arm = world.createBody({ position: { x: 1, y: 5 }, shape: box(1, 0.1), density: 1 })
    const load = world.createBody({ position: { x: 2.5, y: 5 }, shape: box(0.5, 0.5), density: 10 })
    const j1 = world.createJoint({ type: 'weld', bodyA: null, bodyB: arm, anchor: { x: 0, y: 5 } })
    const j2 = world.createJoint({ type: 'weld', bodyA: arm, bodyB: load, anchor: { x: 2, y: 5 } })
    const start = world.getPosition(load)
    let worst = 0
    for (let s = 0; s < 3600; s++) {
      world.step()
      const p = world.getPosition(load)
      worst = Math.max(worst, Math.hypot(p.x - start.x, p.y - start.y))
    }
    const [gap] = weldError(world, [[arm, load, j2]], [0])
    expect(world.hasJoint(j1)).toBe(true)
    console.log(
      `heavy load on a welded arm: moved at most ${(worst * 1000).toFixed(3)} mm, anchors apart ${(gap * 1000).toFixed(4)} mm`,
    )
    expect(worst).toBeLessThan(0.005)
  })
})
