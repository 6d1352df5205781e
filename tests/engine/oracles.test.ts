/*
 * The engine against independent oracles: closed-form mechanics, not the code under test.
 *
 * - Free fall: semi-implicit Euler with 4 sub-steps has an exact closed form (a sum of an
 *   arithmetic series), and differs from the analytic parabola by exactly g h t / 2 (first order).
 * - Elastic collisions (restitution 1, no gravity, no friction) conserve momentum and kinetic
 *   energy, and a head-on impact of unequal masses matches the 1D textbook result.
 * - A bouncing ball loses energy by e^2 per bounce within a tolerance derived below.
 * - A box on a 20 degree ramp: the contact force balances gravity (m g cos, m g sin), and above
 *   the friction angle the box slides with a = g (sin - mu cos).
 *
 * Sleeping is switched off wherever a slow body must keep moving (a body drifting slower than the
 * 0.05 m/s sleep threshold legitimately falls asleep and stops).
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  circle,
  createWorld,
  DEFAULT_WORLD_DEF,
  groundDef,
  rampScene,
  type Shape,
  STEP_SECONDS,
  type World,
} from '../../engine/index.ts'

const DT = STEP_SECONDS
const SUB_STEPS = DEFAULT_WORLD_DEF.subSteps
const H = DT / SUB_STEPS
const G = 10

function steps(world: World, n: number): void {
  for (let i = 0; i < n; i++) world.step()
}

describe('free fall', () => {
  const y0 = 1000
  const vy0 = 3
  const vx0 = -2

  function fall(stepCount: number) {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    const id = world.createBody({
      shape: circle(0.5),
      position: { x: 0, y: y0 },
      linearVelocity: { x: vx0, y: vy0 },
    })
    steps(world, stepCount)
    return { p: world.getPosition(id), v: world.getLinearVelocity(id) }
  }

  it('equals the exact semi-implicit Euler sum over 4 sub-steps per step', () => {
    for (const stepCount of [1, 7, 60, 600]) {
      const n = stepCount * SUB_STEPS
      // v_k = v0 - g h k;  y_n = y0 + h * sum_{k=1..n} v_k = y0 + v0 n h - g h^2 n (n + 1) / 2
      const yEuler = y0 + vy0 * n * H - (G * H * H * n * (n + 1)) / 2
      const vEuler = vy0 - G * H * n
      const { p, v } = fall(stepCount)
      expect(Math.abs(p.y - yEuler)).toBeLessThan(1e-9)
      expect(Math.abs(v.y - vEuler)).toBeLessThan(1e-9)
      expect(Math.abs(p.x - vx0 * n * H)).toBeLessThan(1e-9)
      expect(v.x).toBe(vx0)
    }
  })

  it('stays within the first-order bound g h t / 2 of the analytic parabola', () => {
    for (const stepCount of [60, 600]) {
      const t = stepCount * DT
      const yExact = y0 + vy0 * t - (G * t * t) / 2
      const { p } = fall(stepCount)
      // Euler with sub-step h lags the parabola by exactly g h t / 2 (the series minus the integral).
      const bound = (G * H * t) / 2
      expect(yExact - p.y).toBeGreaterThan(0)
      expect(yExact - p.y).toBeLessThanOrEqual(bound + 1e-9)
      expect(Math.abs(yExact - p.y - bound)).toBeLessThan(1e-9)
    }
  })

  it('rotates by atan(h w) per sub-step, within (h w)^3 / 3 per sub-step of w t', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 }, enableSleep: false })
    const w = 2
    const id = world.createBody({ shape: box(0.5, 0.25), angularVelocity: w })
    const stepCount = 600
    steps(world, stepCount)
    const n = stepCount * SUB_STEPS
    // Rotating (cos, sin) by (1, h w) and renormalizing turns it by exactly atan(h w).
    const angle = n * Math.atan(H * w)
    const q = world.getRotation(id)
    expect(Math.abs(q.c - Math.cos(angle))).toBeLessThan(1e-9)
    expect(Math.abs(q.s - Math.sin(angle))).toBeLessThan(1e-9)
    const analytic = w * stepCount * DT
    const thirdOrder = (n * (H * w) ** 3) / 3
    const diff = Math.atan2(Math.sin(analytic - angle), Math.cos(analytic - angle))
    expect(Math.abs(diff)).toBeLessThanOrEqual(thirdOrder * 1.001)
  })
})

interface Collision {
  mA: number
  mB: number
  vA: number
  vB: number
  after: { vA: { x: number; y: number }; vB: { x: number; y: number }; wA: number; wB: number }
  inertiaA: number
  inertiaB: number
}

/** Two bodies approaching along x with restitution 1, no gravity, no friction; returns the state after. */
function collide(shapeB: Shape, densityB: number, vA: number, vB: number): Collision {
  const world = createWorld({ gravity: { x: 0, y: 0 }, enableSleep: false })
  const a = world.createBody({
    shape: circle(0.5),
    density: 1,
    position: { x: -2, y: 0 },
    linearVelocity: { x: vA, y: 0 },
    restitution: 1,
    friction: 0,
  })
  const b = world.createBody({
    shape: shapeB,
    density: densityB,
    position: { x: 2, y: 0 },
    linearVelocity: { x: vB, y: 0 },
    restitution: 1,
    friction: 0,
  })
  steps(world, 180)
  expect(world.contacts().length).toBe(0) // the bodies separated again
  return {
    mA: world.getMass(a),
    mB: world.getMass(b),
    vA,
    vB,
    inertiaA: world.getInertia(a),
    inertiaB: world.getInertia(b),
    after: {
      vA: world.getLinearVelocity(a),
      vB: world.getLinearVelocity(b),
      wA: world.getAngularVelocity(a),
      wB: world.getAngularVelocity(b),
    },
  }
}

function checkElastic(c: Collision): void {
  const { mA, mB, vA, vB, after } = c
  const p0 = mA * vA + mB * vB
  const e0 = 0.5 * mA * vA * vA + 0.5 * mB * vB * vB
  const px = mA * after.vA.x + mB * after.vB.x
  const py = mA * after.vA.y + mB * after.vB.y
  const e1 =
    0.5 * mA * (after.vA.x ** 2 + after.vA.y ** 2) +
    0.5 * mB * (after.vB.x ** 2 + after.vB.y ** 2) +
    0.5 * c.inertiaA * after.wA ** 2 +
    0.5 * c.inertiaB * after.wB ** 2
  expect(Math.abs(px - p0)).toBeLessThan(1e-9)
  expect(Math.abs(py)).toBeLessThan(1e-9)
  expect(Math.abs(e1 - e0) / e0).toBeLessThan(1e-9)
  // Closed-form 1D elastic collision.
  const vAExpected = ((mA - mB) * vA + 2 * mB * vB) / (mA + mB)
  const vBExpected = ((mB - mA) * vB + 2 * mA * vA) / (mA + mB)
  expect(Math.abs(after.vA.x - vAExpected)).toBeLessThan(1e-9)
  expect(Math.abs(after.vB.x - vBExpected)).toBeLessThan(1e-9)
}

describe('elastic collisions (restitution 1, no gravity, no friction)', () => {
  it('two circles of unequal mass head-on: momentum, energy and the 1D closed form', () => {
    const c = collide(circle(0.8), 2, 3, -1.5)
    expect(c.mB / c.mA).toBeGreaterThan(5) // 2 * 0.8^2 / 0.5^2 = 5.12
    checkElastic(c)
  })

  it('a circle hitting a heavier box squarely on a face: momentum, energy and the 1D closed form', () => {
    checkElastic(collide(box(0.6, 0.9), 3, 4, 0.5))
  })

  it('a heavy circle hitting a light box squarely: both move on in the closed-form directions', () => {
    checkElastic(collide(box(0.3, 0.3), 0.25, 2.5, -2))
  })
})

/** Peaks (height of the lowest point above the ground) of a ball dropped from `h0` with restitution e. */
function bouncePeaks(e: number, h0: number): number[] {
  const world = createWorld({ gravity: { x: 0, y: -G } })
  world.createBody(groundDef())
  const r = 0.5
  const ball = world.createBody({
    shape: circle(r),
    position: { x: 0, y: h0 + r },
    restitution: e,
    friction: 0,
  })
  const peaks = [h0]
  let prevY = h0 + r
  let prevVy = 0
  for (let i = 0; i < 1800; i++) {
    world.step()
    const y = world.getPosition(ball).y
    const vy = world.getLinearVelocity(ball).y
    if (prevVy > 0 && vy <= 0) peaks.push(Math.max(prevY, y) - r)
    prevY = y
    prevVy = vy
  }
  return peaks
}

describe('bouncing ball with restitution e < 1', () => {
  /*
   * Tolerance on (h[k+1] / h[k]) / e^2, with v = sqrt(2 g h[k]) the impact speed and dt = 1/60 s:
   *  - restitution acts on the normal velocity at the start of the step, which differs from the
   *    true impact speed by at most g dt: the squared ratio moves by up to 2 g dt / v;
   *  - contact points exist only within the 0.02 m speculative distance, so the ball can sink up
   *    to d = v dt into the ground before the contact acts; it falls from h + d and rebounds from
   *    -d: h' = e^2 (h + d) - d, a relative error (1/e^2 - 1) d / h = 2 (1/e^2 - 1) g dt / v;
   *  - sub-stepped semi-implicit Euler on the way down and up: g h_sub t / 2 each, about g dt / (2 v);
   *  - sampling the peak at 1/60 s reads it low by at most g dt^2 / 8, (g dt / v)^2 / 4 relative.
   * Total: (2.5 + 2 (1/e^2 - 1)) g dt / v + (g dt / v)^2. Checked while v >= 3 m/s (well above the
   * 1 m/s restitution threshold, so the bounce happens at all).
   */
  function tolerance(e: number, h: number): number {
    const v = Math.sqrt(2 * G * h)
    const x = (G * DT) / v
    return (2.5 + 2 * (1 / (e * e) - 1)) * x + x * x
  }

  for (const [e, h0] of [
    [0.8, 10],
    [0.5, 10],
    [0.9, 5],
  ] as const) {
    it(`e = ${e} from ${h0} m: strictly decreasing peaks, energy ratio e^2 within the derived tolerance`, () => {
      const peaks = bouncePeaks(e, h0)
      expect(peaks.length).toBeGreaterThanOrEqual(4)
      for (let k = 1; k < peaks.length; k++) expect(peaks[k]).toBeLessThan(peaks[k - 1])
      let checked = 0
      for (let k = 0; k + 1 < peaks.length; k++) {
        if (Math.sqrt(2 * G * peaks[k]) < 3) break
        const ratio = peaks[k + 1] / peaks[k] / (e * e)
        expect(Math.abs(ratio - 1), `bounce ${k}: h ${peaks[k]} -> ${peaks[k + 1]}`).toBeLessThanOrEqual(
          tolerance(e, peaks[k]),
        )
        checked++
      }
      expect(checked).toBeGreaterThanOrEqual(2)
    })
  }
})

describe('box on a 20 degree ramp', () => {
  const theta = (20 * Math.PI) / 180

  /** Sum of the contact impulses on body `id` over the last step, as a world force (N). */
  function contactForce(world: World, id: number) {
    let fx = 0
    let fy = 0
    for (const c of world.contacts()) {
      if (c.bodyA !== id && c.bodyB !== id) continue
      const sign = c.bodyB === id ? 1 : -1 // the normal points from A to B
      const tx = c.normal.y
      const ty = -c.normal.x
      for (const p of c.points) {
        fx += (sign * (p.normalImpulse * c.normal.x + p.tangentImpulse * tx)) / DT
        fy += (sign * (p.normalImpulse * c.normal.y + p.tangentImpulse * ty)) / DT
      }
    }
    return { fx, fy }
  }

  it('friction 0.6 (above tan 20° = 0.364): stays put, normal force m g cos θ and friction m g sin θ within 2%', () => {
    const world = createWorld({ enableSleep: false })
    const ids = buildScene(world, rampScene(theta, 0.6))
    const boxId = ids[2]
    const start = world.getPosition(boxId)
    steps(world, 60)
    const settled = world.getPosition(boxId)
    // The first second only settles the box into its contact (about the slop).
    expect(Math.hypot(settled.x - start.x, settled.y - start.y)).toBeLessThan(0.005)
    steps(world, 240)
    const end = world.getPosition(boxId)
    expect(Math.hypot(end.x - settled.x, end.y - settled.y)).toBeLessThan(1e-4)
    const m = world.getMass(boxId)
    const { fx, fy } = contactForce(world, boxId)
    // Decompose along the ramp normal n = (-sin, cos) and up the slope t = (cos, sin).
    const normal = -fx * Math.sin(theta) + fy * Math.cos(theta)
    const along = fx * Math.cos(theta) + fy * Math.sin(theta)
    const mgCos = m * G * Math.cos(theta)
    const mgSin = m * G * Math.sin(theta)
    expect(Math.abs(normal - mgCos) / mgCos).toBeLessThan(0.02)
    expect(Math.abs(along - mgSin) / mgSin).toBeLessThan(0.02)
  })

  it('friction 0.3 (below tan 20°): slides with acceleration g (sin θ - μ cos θ) within 1%', () => {
    const mu = 0.3
    const world = createWorld({ enableSleep: false })
    const ids = buildScene(world, rampScene(theta, mu))
    const a = G * (Math.sin(theta) - mu * Math.cos(theta))
    for (const seconds of [2, 4]) {
      steps(world, 120)
      const v = world.getLinearVelocity(ids[2])
      const speed = Math.hypot(v.x, v.y)
      expect(Math.abs(speed - a * seconds) / (a * seconds)).toBeLessThan(0.01)
      // The velocity points down the slope.
      expect(v.x).toBeLessThan(0)
      expect(Math.abs(v.y / v.x - Math.tan(theta))).toBeLessThan(1e-3)
    }
  })
})
