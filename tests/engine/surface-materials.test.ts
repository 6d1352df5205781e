/*
 * Per-shape rolling resistance and tangent speed (Box2D v3.1), against closed forms.
 *
 * Tangent speed: a shape's surface moves at its tangentSpeed along the right perpendicular of its
 * outward normal (on a box's top face: +x), and friction drives the bodies' relative tangential
 * speed at the contact to the sum of the two shapes' speeds. A box set down at rest on a static
 * conveyor of speed v with friction mu therefore slides with acceleration mu g until it moves at v
 * (at t = v / (mu g)), having covered v^2 / (2 mu g), and then rides along at exactly v.
 *
 * Rolling resistance: the pair's resistance is Box2D's max(coefficient) x max(shape radius) = c R,
 * a length, and the rolling impulse (an angular impulse between the bodies) is clamped to c R times
 * the contact's normal impulse: a torque of at most c R N against the relative spin. A disc of mass
 * m, radius R and inertia I = m R^2 / 2 rolling on flat ground (N = m g) without slipping (v = -w R)
 * obeys m dv/dt = F (friction at the contact) and I dw/dt = c R N + R F (both torques about the
 * centre; the contact is at (0, -R)); with dw/dt = -(dv/dt) / R this gives
 *   dv/dt = -c m g R^2 / (I + m R^2) = -(2/3) c g,
 * a constant deceleration, and once the spin stops the rolling impulse holds the disc still.
 * On a ramp of angle theta, friction F = m g sin(theta) holds the contact and the rolling torque
 * must balance R F about the centre: it can while tan(theta) <= c. Past that the disc rolls down at
 * (m g sin - c m g cos) R^2 / (I + m R^2) = (2/3) g (sin(theta) - c cos(theta)).
 */
import { describe, expect, it } from 'vitest'
import { atan2, box, circle, cos, createWorld, loadWorld, STEP_SECONDS, sin } from '../../engine/index.ts'

const G = 10

describe('tangent speed (conveyor belts)', () => {
  for (const [v, mu] of [
    [2, 0.5],
    [-3, 0.8],
    [3, 0.8],
    [-3, 0.5],
  ] as const) {
    it(`a box set on a static conveyor of ${v} m/s, friction ${mu}, reaches ${v} m/s at t = v/(mu g) and rides at it`, () => {
      const world = createWorld({ enableSleep: false })
      world.createBody({
        type: 'static',
        position: { x: 0, y: -1 },
        shapes: [{ shape: box(100, 1), friction: mu, tangentSpeed: v }],
      })
      const id = world.createBody({ position: { x: 0, y: 0.1 }, shape: box(0.5, 0.1), friction: mu })
      const reach = Math.abs(v) / (mu * G) // s
      let reachedAt = Number.NaN
      const steps = Math.ceil((reach + 2) / STEP_SECONDS)
      for (let i = 1; i <= steps; i++) {
        world.step()
        const vx = world.getLinearVelocity(id).x
        if (Number.isNaN(reachedAt) && Math.abs(vx - v) < 1e-3) {
          reachedAt = i * STEP_SECONDS
        }
      }
      const end = world.getLinearVelocity(id)
      // Where it is at the end, T = steps / 60 s: the area under v(t), v T - v t_reach / 2, plus
      // the a h t_reach / 2 by which the semi-implicit Euler sum over sub-steps of h = 1/240 s runs
      // ahead of the integral while accelerating.
      const T = steps * STEP_SECONDS
      const a = mu * G
      const xEnd = v * T - (v * reach) / 2 + (Math.sign(v) * a * reach * STEP_SECONDS) / 8
      const x = world.getPosition(id).x
      console.log(
        `conveyor ${v} m/s, mu ${mu}: at ${v} m/s after ${reachedAt.toFixed(4)} s (closed form ${reach.toFixed(4)}), ` +
          `x ${x.toFixed(5)} m at ${T.toFixed(4)} s (closed form ${xEnd.toFixed(5)}), end vx ${end.x}`,
      )
      // Within 0.001 m/s of v no later than two steps after the closed form (the step that crosses v
      // clips the speed), and where the closed form puts it within 0.5 mm.
      expect(Math.abs(reachedAt - reach)).toBeLessThanOrEqual(2 * STEP_SECONDS + 1e-9)
      expect(Math.abs(x - xEnd)).toBeLessThan(0.0005)
      // Then it rides along at the belt's speed, not faster, and stays on the belt.
      expect(Math.abs(end.x - v)).toBeLessThan(1e-6)
      expect(Math.abs(end.y)).toBeLessThan(1e-6)
    })
  }

  it('the speeds of the two shapes add (a box with its own tangent speed on a conveyor)', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({
      type: 'static',
      position: { x: 0, y: -1 },
      shapes: [{ shape: box(100, 1), tangentSpeed: 1 }],
    })
    // The box's bottom face has outward normal (0, -1): its right perpendicular is -x, so its surface
    // there moves at -0.5 m/s relative to the box, and the box must move at 1 + 0.5 m/s to match.
    const id = world.createBody({
      position: { x: 0, y: 0.25 },
      shapes: [{ shape: box(0.25, 0.25), tangentSpeed: 0.5 }],
    })
    for (let i = 0; i < 120; i++) world.step()
    expect(world.getLinearVelocity(id).x).toBeCloseTo(1.5, 6)
  })
})

describe('rolling resistance', () => {
  const R = 0.5
  const V0 = 5
  const C = 0.05
  const A = (2 / 3) * C * G // m/s^2, the deceleration derived above

  function rollingBall(c = C) {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(200, 1) })
    const id = world.createBody({
      position: { x: 0, y: R },
      linearVelocity: { x: V0, y: 0 },
      angularVelocity: -V0 / R,
      shapes: [{ shape: circle(R), rollingResistance: c }],
    })
    return { world, id }
  }

  it('a disc rolling on flat ground decelerates at (2/3) c g and then stays stopped', () => {
    const { world, id } = rollingBall()
    const stopAt = V0 / A // 15 s
    for (const t of [2, 5, 10]) {
      while (world.tick * STEP_SECONDS < t - 1e-9) world.step()
      const v = world.getLinearVelocity(id).x
      const x = world.getPosition(id).x
      const vExpected = V0 - A * t
      const xExpected = V0 * t - (A * t * t) / 2
      console.log(
        `rolling resistance ${C}: t ${t} s v ${v.toFixed(5)} (closed form ${vExpected.toFixed(5)}), x ${x.toFixed(4)} (${xExpected.toFixed(4)})`,
      )
      // The speed lost within 0.5 % of the closed form, the distance within 0.2 % (the disc without
      // resistance loses 0.07 % of its speed in 5 s to the soft contact).
      expect(Math.abs(V0 - v - A * t)).toBeLessThan(0.005 * A * t)
      expect(Math.abs(x - xExpected)).toBeLessThan(0.002 * xExpected)
    }
    while (world.tick * STEP_SECONDS < stopAt + 5) world.step()
    const x = world.getPosition(id).x
    console.log(`stopped at x ${x.toFixed(4)} m (closed form ${((V0 * V0) / (2 * A)).toFixed(4)})`)
    expect(Math.abs(world.getLinearVelocity(id).x)).toBeLessThan(1e-3)
    expect(Math.abs(world.getAngularVelocity(id))).toBeLessThan(1e-3 / R)
    expect(Math.abs(x - (V0 * V0) / (2 * A))).toBeLessThan(0.002 * ((V0 * V0) / (2 * A)))
  })

  it('without rolling resistance the disc keeps rolling at its speed', () => {
    const { world, id } = rollingBall(0)
    for (let i = 0; i < 300; i++) world.step()
    // The soft contact of a rolling disc costs it a little (0.07 % in 5 s); nothing like (2/3) c g t.
    const v = world.getLinearVelocity(id).x
    console.log(`no rolling resistance: ${v} m/s after 5 s`)
    expect(Math.abs(v - V0)).toBeLessThan(0.01 * A * 5)
  })

  it('a save in mid-roll carries the rolling impulse: the loaded world continues bit for bit', () => {
    const { world } = rollingBall()
    for (let i = 0; i < 100; i++) world.step()
    const copy = loadWorld(world.save())
    for (let i = 0; i < 200; i++) {
      world.step()
      copy.step()
      expect(copy.hash()).toBe(world.hash())
    }
  })

  /** A disc of radius R with resistance c set on a static ramp of slope `slope` (rise over run). */
  function discOnRamp(c: number, slope: number) {
    const theta = atan2(slope, 1)
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', angle: -theta, shape: box(40, 0.5), friction: 0.9 })
    // On the ramp's top face: 0.5 + R along the ramp normal (sin, cos) from a point up the slope.
    const start = {
      x: -15 * cos(theta) + (0.5 + R) * sin(theta),
      y: 15 * sin(theta) + (0.5 + R) * cos(theta),
    }
    const id = world.createBody({
      position: start,
      shapes: [{ shape: circle(R), rollingResistance: c, friction: 0.9 }],
    })
    return { world, id, start, theta }
  }

  it('holds a disc on a ramp with tan(theta) < c, and lets it roll at (2/3) g (sin - c cos) past that', () => {
    const held = discOnRamp(0.2, 0.15)
    for (let i = 0; i < 300; i++) held.world.step()
    const p = held.world.getPosition(held.id)
    const moved = Math.hypot(p.x - held.start.x, p.y - held.start.y)
    console.log(`tan 0.15 < c 0.2: moved ${moved.toExponential(3)} m in 5 s`)
    expect(moved).toBeLessThan(0.001) // settling into the soft contact (0.04 mm), not rolling (without c: about 12 m)

    const rolling = discOnRamp(0.2, 0.25)
    const seconds = 2
    for (let i = 0; i < seconds * 60; i++) rolling.world.step()
    const q = rolling.world.getPosition(rolling.id)
    const travelled = Math.hypot(q.x - rolling.start.x, q.y - rolling.start.y)
    const a = (2 / 3) * G * (sin(rolling.theta) - 0.2 * cos(rolling.theta))
    console.log(
      `tan 0.25 > c 0.2: ${travelled.toFixed(4)} m in 2 s, closed form ${((a * seconds * seconds) / 2).toFixed(4)}`,
    )
    expect(Math.abs(travelled - (a * seconds * seconds) / 2)).toBeLessThan(
      0.01 * ((a * seconds * seconds) / 2),
    )
  })

  it('a save while rolling resistance holds a disc on a ramp (impulse below its limit) continues bit for bit', () => {
    const { world } = discOnRamp(0.2, 0.15)
    for (let i = 0; i < 100; i++) world.step()
    const copy = loadWorld(world.save())
    for (let i = 0; i < 200; i++) {
      world.step()
      copy.step()
      expect(copy.hash()).toBe(world.hash())
    }
  })
})
