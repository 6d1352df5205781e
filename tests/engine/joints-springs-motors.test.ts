/*
 * Springs on revolute joints and motors on distance joints, against oracles that do not come from
 * the solver:
 * - a body pinned at its centre of mass with a rotational spring oscillates at the spring's hertz
 *   (Box2D defines the stiffness against the joint's angular mass 1 / (iA + iB), here I_centre);
 * - a horizontal rod on a sprung pin sags to the angle where k theta = m g d cos(theta),
 *   k = I_centre omega^2 (solved by bisection here);
 * - targetAngle moves the rest angle;
 * - a distance motor reels a rope in at its speed, and a weak one lets the load accelerate at
 *   (F - m g) / m.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld } from '../../engine/index.ts'

const DT = 1 / 60
const G = 10

describe('revolute joint: spring', () => {
  it("a body pinned at its centre oscillates at the spring's hertz within 2 %", () => {
    for (const hertz of [0.5, 2]) {
      const world = createWorld({ enableSleep: false })
      const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.6, 0.1), angularVelocity: 1 })
      world.createJoint({
        type: 'revolute',
        bodyA: null,
        bodyB: b,
        anchor: { x: 0, y: 3 },
        enableSpring: true,
        hertz,
        dampingRatio: 0,
      })
      const crossings: number[] = []
      let prev = world.getAngle(b)
      for (let i = 1; i <= 900; i++) {
        world.step()
        const v = world.getAngle(b)
        if (prev > 0 !== v > 0 && prev !== v) crossings.push((i - 1 + prev / (prev - v)) * DT)
        prev = v
      }
      const n = crossings.length - 1
      const measured = n / (2 * (crossings[n] - crossings[0]))
      console.log(`revolute spring ${hertz} Hz: measured ${measured.toFixed(4)} Hz`)
      expect(n).toBeGreaterThanOrEqual(6)
      expect(Math.abs(measured / hertz - 1)).toBeLessThan(0.02)
    }
  })

  it('a horizontal rod on a sprung pin sags to k theta = m g d cos(theta)', () => {
    const world = createWorld({ enableSleep: false })
    const rod = world.createBody({ position: { x: 1, y: 3 }, shape: box(1, 0.05) })
    const hertz = 3
    const j = world.createJoint({
      type: 'revolute',
      bodyA: null,
      bodyB: rod,
      anchor: { x: 0, y: 3 },
      enableSpring: true,
      hertz,
      dampingRatio: 1,
    })
    for (let i = 0; i < 600; i++) world.step()
    const m = world.getMass(rod)
    const k = world.getInertia(rod) * (2 * Math.PI * hertz) ** 2
    // Bisection on f(theta) = k theta - m g d cos(theta) over [0, pi/2] (d = 1 m).
    let lo = 0
    let hi = Math.PI / 2
    for (let i = 0; i < 60; i++) {
      const mid = (lo + hi) / 2
      if (k * mid - m * G * Math.cos(mid) > 0) hi = mid
      else lo = mid
    }
    const measured = -world.getAngle(rod)
    console.log(`sprung pin sag ${measured.toFixed(5)} rad, expected ${lo.toFixed(5)} rad`)
    expect(Math.abs(measured / lo - 1)).toBeLessThan(0.01)
    expect(world.getJointAngle(j)).toBeCloseTo(-measured, 9)
    // Its reaction torque carries the moment m g d cos(theta) (with the pin's force at the pivot).
    expect(world.getJointReaction(j).torque).toBeCloseTo(k * measured, 1)
  })

  it('targetAngle moves where the spring rests; setJointTarget moves it again', () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.2) })
    const j = world.createJoint({
      type: 'revolute',
      bodyA: null,
      bodyB: b,
      anchor: { x: 0, y: 0 },
      enableSpring: true,
      hertz: 2,
      dampingRatio: 1,
      targetAngle: 0.7,
    })
    for (let i = 0; i < 300; i++) world.step()
    expect(world.getAngle(b)).toBeCloseTo(0.7, 4)
    world.setJointTarget(j, -1.2)
    for (let i = 0; i < 300; i++) world.step()
    expect(world.getAngle(b)).toBeCloseTo(-1.2, 4)
    expect(() => world.setJointTarget(j, 4)).toThrow(/targetAngle/)
  })
})

describe('distance joint: motor', () => {
  it('reels a rope in at its speed, and a weak motor lets the load fall at (F - m g) / m', () => {
    const world = createWorld({ enableSleep: false })
    const load = world.createBody({ position: { x: 0, y: 0 }, shape: circle(0.2) })
    const rope = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: load,
      anchorA: { x: 0, y: 5 },
      anchorB: { x: 0, y: 0 },
      minLength: 0,
      maxLength: 5,
      enableMotor: true,
      motorSpeed: -0.8,
      maxMotorForce: 100,
    })
    for (let i = 0; i < 120; i++) world.step()
    const reeled = 5 - world.getJointTranslation(rope)
    console.log(
      `distance motor reeled ${reeled.toFixed(6)} m in 2 s (1.6 expected); speed ${world.getJointSpeed(rope).toFixed(6)}`,
    )
    expect(Math.abs(reeled / 1.6 - 1)).toBeLessThan(0.001)
    expect(world.getJointSpeed(rope)).toBeCloseTo(-0.8, 6)
    // Now a motor of half the weight: the load sinks at g / 2 from rest.
    const m = world.getMass(load)
    const world2 = createWorld({ enableSleep: false })
    const load2 = world2.createBody({ position: { x: 0, y: 0 }, shape: circle(0.2) })
    world2.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: load2,
      anchorA: { x: 0, y: 5 },
      anchorB: { x: 0, y: 0 },
      minLength: 0,
      maxLength: 10,
      enableMotor: true,
      motorSpeed: -5,
      maxMotorForce: 0.5 * m * G,
    })
    for (let i = 0; i < 60; i++) world2.step()
    const fell = -world2.getPosition(load2).y
    console.log(`weak distance motor: fell ${fell.toFixed(5)} m in 1 s, expected ${(0.25 * G).toFixed(5)}`)
    expect(Math.abs(fell / (0.25 * G) - 1)).toBeLessThan(0.01)
  })
})
