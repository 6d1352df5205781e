/*
 * Wheel joint tests against oracles that do not come from the solver:
 * - static sag: the suspension spring's stiffness is defined, as in Box2D, against the joint's
 *   axial mass m_a = 1 / (1/M + 1/m_w + x^2 / I) (chassis mass M and inertia I, wheel mass m_w,
 *   anchor x from the chassis centre; the wheel's own lever arm is zero at its centre), so
 *   k = m_a (2 pi f)^2 and a load F sags it F / k; by symmetry each of two wheels carries M g / 2;
 * - rolling without slipping: a wheel spun at w relative to the chassis moves it at w r;
 * - a 20-degree ramp of friction 0.9 needs less grip than it has (tan 20 = 0.36), so a car with
 *   torque to spare climbs it at its motor's speed;
 * - the suspension's travel limit keeps the wheel out of the chassis on a hard landing.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, polygon, type World } from '../../engine/index.ts'

const G = 10
const SLOP = 0.005
const R = 0.4
const HALF_W = 1
const HALF_H = 0.25
/** Wheel centres below the chassis centre (m) and either side of it (m). */
const DROP = 0.9
const TRACK = 0.8

interface Car {
  chassis: number
  wheels: [number, number]
  joints: [number, number]
}

function buildCar(world: World, x: number, y: number, settings: Record<string, unknown>, angle = 0): Car {
  const c = Math.cos(angle)
  const s = Math.sin(angle)
  const chassis = world.createBody({ position: { x, y }, angle, shape: box(HALF_W, HALF_H), density: 2 })
  const wheels: number[] = []
  const joints: number[] = []
  for (const side of [-1, 1]) {
    const lx = side * TRACK
    const ly = -DROP
    const p = { x: x + c * lx - s * ly, y: y + s * lx + c * ly }
    const w = world.createBody({ position: p, shape: circle(R), density: 1, friction: 0.9 })
    wheels.push(w)
    joints.push(
      world.createJoint({
        type: 'wheel',
        bodyA: chassis,
        bodyB: w,
        anchor: p,
        axis: { x: -s, y: c },
        ...settings,
      }),
    )
  }
  return { chassis, wheels: [wheels[0], wheels[1]], joints: [joints[0], joints[1]] }
}

describe('wheel joint: suspension', () => {
  it('a chassis resting on its suspension sags by F / (m_axial omega^2) within 2 %', () => {
    for (const hertz of [2, 4]) {
      const world = createWorld({ enableSleep: false })
      world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5), friction: 0.9 })
      const car = buildCar(world, 0, R + DROP, { hertz, dampingRatio: 0.7 })
      for (let i = 0; i < 900; i++) world.step()
      const M = world.getMass(car.chassis)
      const I = world.getInertia(car.chassis)
      const mw = world.getMass(car.wheels[0])
      const omega = 2 * Math.PI * hertz
      const axialMass = 1 / (1 / M + 1 / mw + (TRACK * TRACK) / I)
      const expected = (M * G) / 2 / (axialMass * omega * omega)
      // Measured from the poses: the wheel centre's rise toward the chassis along the chassis' up axis.
      const cp = world.getPosition(car.chassis)
      const a = world.getAngle(car.chassis)
      let sum = 0
      for (let k = 0; k < 2; k++) {
        const wp = world.getPosition(car.wheels[k])
        const anchorY = cp.y + Math.sin(a) * (k === 0 ? -TRACK : TRACK) + Math.cos(a) * -DROP
        sum += (wp.y - anchorY) / Math.cos(a)
      }
      const sag = sum / 2
      console.log(
        `wheel ${hertz} Hz: sag ${(sag * 1000).toFixed(3)} mm, expected ${(expected * 1000).toFixed(3)} mm`,
      )
      expect(Math.abs(sag / expected - 1)).toBeLessThan(0.02)
      expect(world.getJointTranslation(car.joints[0])).toBeCloseTo(sag, 4)
    }
  })

  it('a hard landing never lets a wheel pass into the chassis: travel stays within the limit', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5), friction: 0.9 })
    // Gap between a wheel's top and the chassis' bottom: DROP - R - HALF_H = 0.25 m; limit 0.2 m.
    const car = buildCar(world, 0, 6, {
      hertz: 1,
      dampingRatio: 0.2,
      enableLimit: true,
      lower: -0.2,
      upper: 0.2,
    })
    let most = 0
    let nearest = Number.POSITIVE_INFINITY
    for (let i = 0; i < 300; i++) {
      world.step()
      for (let k = 0; k < 2; k++) {
        most = Math.max(most, world.getJointTranslation(car.joints[k]))
        const cp = world.getPosition(car.chassis)
        const wp = world.getPosition(car.wheels[k])
        nearest = Math.min(nearest, cp.y - HALF_H - (wp.y + R))
      }
    }
    console.log(
      `hard landing: most travel ${(most * 1000).toFixed(2)} mm (limit 200), nearest gap wheel-chassis ${(nearest * 1000).toFixed(2)} mm`,
    )
    expect(most).toBeLessThanOrEqual(0.2 + SLOP)
    expect(nearest).toBeGreaterThan(0)
  })
})

describe('wheel joint: a car', () => {
  it('drives on flat ground at motor speed x radius within 2 %', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(200, 0.5), friction: 0.9 })
    const speed = -10
    const car = buildCar(world, 0, R + DROP, {
      hertz: 4,
      dampingRatio: 0.7,
      enableMotor: true,
      motorSpeed: speed,
      maxMotorTorque: 40,
    })
    for (let i = 0; i < 300; i++) world.step()
    const x0 = world.getPosition(car.chassis).x
    for (let i = 0; i < 120; i++) world.step()
    const v = (world.getPosition(car.chassis).x - x0) / 2
    console.log(
      `car on flat ground: ${v.toFixed(4)} m/s, expected ${-speed * R} m/s; wheel speed ${world.getJointSpeed(car.joints[0]).toFixed(4)} rad/s`,
    )
    expect(Math.abs(v / (-speed * R) - 1)).toBeLessThan(0.02)
    expect(world.getJointSpeed(car.joints[0])).toBeCloseTo(speed, 1)
    world.setJointMotorSpeed(car.joints[0], 0)
    world.setJointMotorSpeed(car.joints[1], 0)
    for (let i = 0; i < 180; i++) world.step()
    expect(Math.abs(world.getLinearVelocity(car.chassis).x)).toBeLessThan(0.05)
  })

  it('climbs a 20-degree ramp of friction 0.9 at its motor speed', () => {
    const world = createWorld({ enableSleep: false })
    const slope = (20 * Math.PI) / 180
    world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(10, 0.5), friction: 0.9 })
    // Ramp from (10, 0) rising at 20 degrees for 30 m.
    const len = 30
    world.createBody({
      type: 'static',
      position: { x: 10, y: 0 },
      shape: polygon([
        { x: 0, y: 0 },
        { x: len * Math.cos(slope), y: len * Math.sin(slope) },
        { x: len * Math.cos(slope), y: -1 },
        { x: 0, y: -1 },
      ]),
      friction: 0.9,
    })
    const car = buildCar(world, 4, R + DROP, {
      hertz: 4,
      dampingRatio: 0.7,
      enableMotor: true,
      motorSpeed: -10,
      maxMotorTorque: 60,
    })
    const mass = world.getMass(car.chassis) + 2 * world.getMass(car.wheels[0])
    // Torque the climb needs in all: m g sin(20) r (the motors have 120 N m).
    console.log(
      `ramp: total mass ${mass.toFixed(3)} kg, needs ${(mass * G * Math.sin(slope) * R).toFixed(2)} N m of 120`,
    )
    let reached = -1
    for (let i = 0; i < 900 && reached < 0; i++) {
      world.step()
      if (world.getPosition(car.chassis).y > 6) reached = i
    }
    expect(reached).toBeGreaterThan(0)
    // Along the slope at motor speed: 5 more seconds.
    const p0 = world.getPosition(car.chassis)
    for (let i = 0; i < 60; i++) world.step()
    const p1 = world.getPosition(car.chassis)
    const along = Math.hypot(p1.x - p0.x, p1.y - p0.y)
    console.log(
      `ramp: reached 6 m height at ${(reached / 60).toFixed(2)} s; speed along the slope ${along.toFixed(4)} m/s (motor 4 m/s)`,
    )
    expect(p1.y).toBeGreaterThan(p0.y)
    expect(Math.abs(along / 4 - 1)).toBeLessThan(0.02)
  })

  it('does not climb it when the motors have less torque than m g sin(20) r', () => {
    const world = createWorld({ enableSleep: false })
    const slope = (20 * Math.PI) / 180
    world.createBody({
      type: 'static',
      position: { x: 0, y: 0 },
      shape: polygon([
        { x: -20, y: -20 * Math.tan(slope) },
        { x: 20, y: 20 * Math.tan(slope) },
        { x: 20, y: -10 },
        { x: -20, y: -10 },
      ]),
      friction: 0.9,
    })
    // Masses from the shapes: chassis 2 kg/m^2 x 2 m x 0.5 m, wheels 1 kg/m^2 x pi r^2.
    const mass = 2 * (2 * HALF_W) * (2 * HALF_H) + 2 * Math.PI * R * R
    const needed = mass * G * Math.sin(slope) * R
    const up = R + DROP
    // 80 % of the needed torque, split over the two wheels: the car rolls back down.
    const car = buildCar(
      world,
      -Math.sin(slope) * up,
      Math.cos(slope) * up,
      { hertz: 4, dampingRatio: 0.7, enableMotor: true, motorSpeed: -10, maxMotorTorque: (0.8 * needed) / 2 },
      slope,
    )
    expect(world.getMass(car.chassis) + 2 * world.getMass(car.wheels[0])).toBeCloseTo(mass, 9)
    const y0 = world.getPosition(car.chassis).y
    for (let i = 0; i < 180; i++) world.step()
    const y1 = world.getPosition(car.chassis).y
    console.log(`ramp with 80 % of the torque: height change ${(y1 - y0).toFixed(3)} m in 3 s`)
    expect(y1).toBeLessThan(y0)
    expect(world.getJointReaction(car.joints[0]).torque).toBeCloseTo((-0.8 * needed) / 2, 6)
  })
})
