/*
 * Prismatic joint tests against oracles that do not come from the solver: kinematics (a motor at
 * speed v moves the body v t; nothing moves across the axis), the limits' positions, and a spring's
 * frequency (the spring's hertz, for a body whose axial mass is its own mass).
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld, type World } from '../../engine/index.ts'

const DT = 1 / 60
/** Linear slop (m), engine/constants.ts: how far a limit may be passed. */
const SLOP = 0.005

function slider(
  world: World,
  axis: { x: number; y: number },
  extra: Record<string, unknown>,
): [number, number] {
  const b = world.createBody({ position: { x: 1, y: 2 }, shape: box(0.3, 0.2), density: 2 })
  const j = world.createJoint({
    type: 'prismatic',
    bodyA: null,
    bodyB: b,
    anchor: { x: 1, y: 2 },
    axis,
    ...extra,
  })
  return [b, j]
}

describe('prismatic joint: motor', () => {
  for (const axis of [
    { x: 1, y: 0 },
    { x: 1, y: 1 },
    { x: -0.3, y: 1 },
  ]) {
    it(`a motor at 1.5 m/s along (${axis.x}, ${axis.y}) moves the body 1.5 t within 0.1 %, under 1 mm across`, () => {
      const world = createWorld({ enableSleep: false })
      const [b, j] = slider(world, axis, { enableMotor: true, motorSpeed: 1.5, maxMotorForce: 1000 })
      const len = Math.hypot(axis.x, axis.y)
      const ux = axis.x / len
      const uy = axis.y / len
      let across = 0
      for (let i = 0; i < 120; i++) {
        world.step()
        const p = world.getPosition(b)
        across = Math.max(across, Math.abs((p.x - 1) * -uy + (p.y - 2) * ux))
      }
      const p = world.getPosition(b)
      const along = (p.x - 1) * ux + (p.y - 2) * uy
      const expected = 1.5 * 120 * DT
      console.log(
        `prismatic motor along (${axis.x}, ${axis.y}): ${along.toFixed(6)} m of ${expected} m, across ${(across * 1000).toFixed(4)} mm`,
      )
      expect(Math.abs(along / expected - 1)).toBeLessThan(0.001)
      expect(across).toBeLessThan(0.001)
      expect(world.getJointTranslation(j)).toBeCloseTo(along, 9)
      expect(world.getJointSpeed(j)).toBeCloseTo(1.5, 6)
      expect(Math.abs(world.getAngle(b))).toBeLessThan(1e-3)
    })
  }

  it("the motor's force never exceeds maxMotorForce: a weak motor lifting a load accelerates at (F - m g) / m", () => {
    const world = createWorld({ enableSleep: false })
    const [b, j] = slider(world, { x: 0, y: 1 }, { enableMotor: true, motorSpeed: 10, maxMotorForce: 6 })
    const m = world.getMass(b)
    const a = (6 - m * 10) / m
    for (let i = 0; i < 60; i++) world.step()
    const t = 1
    const expected = 0.5 * a * t * t
    const rise = world.getPosition(b).y - 2
    console.log(`weak motor: rose ${rise.toFixed(5)} m, expected ${expected.toFixed(5)} m (m = ${m} kg)`)
    expect(Math.abs(rise / expected - 1)).toBeLessThan(0.01)
    const reaction = world.getJointReaction(j)
    expect(reaction.force.y).toBeLessThanOrEqual(6 + 1e-9)
    expect(reaction.force.y).toBeGreaterThan(6 - 1e-9)
  })
})

describe('prismatic joint: limits', () => {
  it('a motor driving into the upper limit, and gravity pulling to the lower, stop within the slop', () => {
    const world = createWorld({ enableSleep: false })
    const [, up] = slider(
      world,
      { x: 1, y: 0 },
      {
        enableMotor: true,
        motorSpeed: 3,
        maxMotorForce: 5000,
        enableLimit: true,
        lower: -0.2,
        upper: 0.5,
      },
    )
    const b2 = world.createBody({ position: { x: 5, y: 2 }, shape: box(0.3, 0.2), density: 2 })
    const down = world.createJoint({
      type: 'prismatic',
      bodyA: null,
      bodyB: b2,
      anchor: { x: 5, y: 2 },
      axis: { x: 0, y: 1 },
      enableLimit: true,
      lower: -0.7,
      upper: 0.3,
    })
    let maxUp = -1
    let minDown = 1
    for (let i = 0; i < 180; i++) {
      world.step()
      maxUp = Math.max(maxUp, world.getJointTranslation(up))
      minDown = Math.min(minDown, world.getJointTranslation(down))
    }
    console.log(
      `prismatic limits: motor stop at ${world.getJointTranslation(up).toFixed(5)} (max ${maxUp.toFixed(5)}), falling stop at ${world.getJointTranslation(down).toFixed(5)} (min ${minDown.toFixed(5)})`,
    )
    expect(maxUp).toBeLessThanOrEqual(0.5 + SLOP)
    expect(Math.abs(world.getJointTranslation(up) - 0.5)).toBeLessThan(SLOP)
    expect(minDown).toBeGreaterThanOrEqual(-0.7 - SLOP)
    expect(Math.abs(world.getJointTranslation(down) + 0.7)).toBeLessThan(SLOP)
    const info = world.joints().find((j) => j.id === down)
    expect(info?.lower).toBe(-0.7)
    expect(info?.upper).toBe(0.3)
    expect(info?.axis?.y).toBeCloseTo(1, 12)
  })
})

describe('prismatic joint: spring', () => {
  for (const hertz of [1, 3]) {
    it(`a ${hertz} Hz spring's free oscillation has its frequency within 2 % (zero crossings)`, () => {
      const world = createWorld({ enableSleep: false })
      const b = world.createBody({
        position: { x: 0, y: 2 },
        shape: box(0.3, 0.2),
        linearVelocity: { x: 0.4, y: 0 },
      })
      const j = world.createJoint({
        type: 'prismatic',
        bodyA: null,
        bodyB: b,
        anchor: { x: 0, y: 2 },
        axis: { x: 1, y: 0 },
        enableSpring: true,
        hertz,
        dampingRatio: 0,
        targetTranslation: 0.1,
      })
      const crossings: number[] = []
      let prev = world.getJointTranslation(j) - 0.1
      for (let i = 1; i <= 600; i++) {
        world.step()
        const v = world.getJointTranslation(j) - 0.1
        if (prev > 0 !== v > 0 && prev !== v) crossings.push((i - 1 + prev / (prev - v)) * DT)
        prev = v
      }
      const n = crossings.length - 1
      const measured = n / (2 * (crossings[n] - crossings[0]))
      console.log(`prismatic spring ${hertz} Hz: measured ${measured.toFixed(4)} Hz over ${n / 2} periods`)
      expect(n).toBeGreaterThanOrEqual(8)
      expect(Math.abs(measured / hertz - 1)).toBeLessThan(0.02)
    })
  }
})
