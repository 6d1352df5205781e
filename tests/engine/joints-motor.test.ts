/*
 * Motor joint tests against oracles that do not come from the solver (no gravity):
 * - a body driven toward an offset that moves at v, with a force cap F, accelerates at a = F / m
 *   (the sub-steps' exact x = a h^2 n (n + 1) / 2 after n sub-steps) until it is as fast as the
 *   offset, so its lag at t1 = v / a is a t1^2 / 2; time-optimal (bang-bang) control, accelerating
 *   and then braking at a, closes that gap at relative rest sqrt(2) t1 later: it arrives at
 *   (1 + sqrt 2) t1, never sooner, and does not overshoot;
 * - with force to spare it follows the moving offset with no lag;
 * - the angular offset and torque cap: I dw/dt = maxTorque while saturated.
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld } from '../../engine/index.ts'

const DT = 1 / 60

describe('motor joint', () => {
  it('follows a moving offset with the lag its maxForce allows, never sooner than bang-bang control', () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const m = world.getMass(b)
    const F = 2
    const v = 3
    const j = world.createJoint({ type: 'motor', bodyA: null, bodyB: b, maxForce: F, maxTorque: 10 })
    const a = F / m
    const t1 = v / a
    const earliest = t1 * (1 + Math.SQRT2)
    let caught = -1
    let worstEarly = 0
    let overshoot = 0
    for (let i = 1; i <= 900; i++) {
      world.setJointTarget(j, { x: v * i * DT, y: 0 })
      world.step()
      const t = i * DT
      const x = world.getPosition(b).x
      if (t <= t1 - 0.1) {
        const n = 4 * i
        const h = DT / 4
        worstEarly = Math.max(worstEarly, Math.abs(x / ((a * h * h * n * (n + 1)) / 2) - 1))
        const force = world.getJointReaction(j).force
        expect(Math.hypot(force.x, force.y)).toBeCloseTo(F, 9)
      }
      if (caught < 0 && x >= v * t - 0.001) caught = t
      overshoot = Math.max(overshoot, x - v * t)
    }
    const x = world.getPosition(b).x
    const end = v * 900 * DT
    console.log(
      `motor joint: x within ${(worstEarly * 100).toFixed(3)} % of F t^2 / 2m while saturated; within 1 mm of the offset at ${caught.toFixed(3)} s (bang-bang ${earliest.toFixed(3)} s), overshoot ${(overshoot * 1000).toFixed(3)} mm; gap after 15 s ${(end - x).toExponential(2)} m`,
    )
    expect(worstEarly).toBeLessThan(0.01)
    // Within 1 mm: the last millimetre takes sqrt(2 mm / a) when braking to rest at a.
    expect(caught).toBeGreaterThanOrEqual(earliest - Math.sqrt(0.002 / a) - DT)
    expect(caught).toBeLessThan(earliest * 1.02)
    expect(overshoot).toBeLessThan(0.005)
    expect(Math.abs(end - x)).toBeLessThan(0.001)
    expect(world.getLinearVelocity(b).x).toBeCloseTo(v, 2)
  })

  it('with force to spare it follows a moving offset with no lag (under 1 mm)', () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    const b = world.createBody({ position: { x: 1, y: 1 }, shape: box(0.5, 0.5) })
    const j = world.createJoint({ type: 'motor', bodyA: null, bodyB: b, maxForce: 1000, maxTorque: 1000 })
    let worst = 0
    for (let i = 1; i <= 240; i++) {
      const target = { x: 1 + 0.5 * Math.sin(i * DT), y: 1 + i * DT }
      world.setJointTarget(j, target)
      world.step()
      if (i > 60) {
        const p = world.getPosition(b)
        worst = Math.max(worst, Math.hypot(p.x - target.x, p.y - target.y))
      }
    }
    console.log(`motor joint with force to spare: worst gap after 1 s ${(worst * 1000).toFixed(4)} mm`)
    expect(worst).toBeLessThan(0.001)
  })

  it('turns to its angular offset at maxTorque / I while saturated', () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(1, 0.25) })
    const I = world.getInertia(b)
    const T = 0.5
    const j = world.createJoint({
      type: 'motor',
      bodyA: null,
      bodyB: b,
      maxForce: 100,
      maxTorque: T,
      angularOffset: 1,
    })
    for (let i = 0; i < 30; i++) world.step()
    const t = 30 * DT
    const expected = (0.5 * T * t * t) / I
    console.log(
      `motor joint angle after 0.5 s: ${world.getAngle(b).toFixed(5)} rad, T t^2 / 2I = ${expected.toFixed(5)}`,
    )
    expect(Math.abs(world.getAngle(b) / expected - 1)).toBeLessThan(0.01)
    for (let i = 0; i < 600; i++) world.step()
    expect(world.getAngle(b)).toBeCloseTo(1, 3)
    expect(world.getJointAngle(j)).toBeCloseTo(1, 3)
  })
})
