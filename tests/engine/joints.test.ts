/*
 * Joint tests against oracles that do not come from the solver:
 * - the physical pendulum's period T = 2 pi sqrt(I_pivot / (m g d)) (small amplitude) and the
 *   simple pendulum's T = 2 pi sqrt(L / g);
 * - a spring's static deflection g / omega^2 and its frequency, as requested by the user;
 * - Newton's second law for rotation (torque = I dw/dt) for the motor's cap and its spin-up time;
 * - momentum (a rope between two free bodies: if it never pushes, their velocities never change);
 * - a damped spring dragged at constant speed lags by 2 zeta v / omega (the mouse joint);
 * - statics (two players holding one box each carry half its weight).
 * Force and torque read-backs are checked against the bodies' own momentum change, so a joint that
 * applies more than its cap is caught even if its bookkeeping claims otherwise.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, PI, type World } from '../../engine/index.ts'

const DT = 1 / 60
const G = 10
/** How far a revolute limit may be overrun transiently when an arm slams into it (rad, ~1.1 degrees). */
const LIMIT_SLOP = 0.02

/** Times (s) at which a sampled signal crosses zero, linearly interpolated between steps. */
function zeroCrossings(world: World, steps: number, signal: () => number): number[] {
  const times: number[] = []
  let prev = signal()
  for (let i = 1; i <= steps; i++) {
    world.step()
    const v = signal()
    if (prev > 0 !== v > 0 && prev !== v) times.push((i - 1 + prev / (prev - v)) * DT)
    prev = v
  }
  return times
}

/** Mean period (s) from zero crossings (two per period). */
function periodOf(crossings: number[]): number {
  const n = crossings.length - 1
  return (2 * (crossings[n] - crossings[0])) / n
}

describe('revolute joint: physical pendulum', () => {
  it('a rod swinging about one end has period 2 pi sqrt(I_pivot / (m g d)) within 2%', () => {
    const world = createWorld({ enableSleep: false })
    const halfWidth = 0.05
    const halfLength = 0.5
    const theta0 = 0.05
    const rod = world.createBody({
      position: { x: halfLength * Math.sin(theta0), y: 2 - halfLength * Math.cos(theta0) },
      angle: theta0,
      shape: box(halfWidth, halfLength),
    })
    world.createJoint({ type: 'revolute', bodyA: null, bodyB: rod, anchor: { x: 0, y: 2 } })
    // Oracle from the shape alone: a uniform w x l plate, pivot at distance d = l/2 from its centre.
    const w = 2 * halfWidth
    const l = 2 * halfLength
    const iPivotPerMass = (w * w + l * l) / 12 + halfLength * halfLength
    const expected = 2 * PI * Math.sqrt(iPivotPerMass / (G * halfLength))
    const crossings = zeroCrossings(world, 600, () => world.getAngle(rod))
    expect(crossings.length).toBeGreaterThanOrEqual(10)
    const measured = periodOf(crossings)
    expect(Math.abs(measured / expected - 1)).toBeLessThan(0.02)
    // The pivot holds: the rod's top end stays at the anchor.
    const top = world.getWorldPoint(rod, { x: 0, y: halfLength })
    expect(Math.hypot(top.x, top.y - 2)).toBeLessThan(0.005)
  })

  it('a box pinned off-centre (d = 0.3 m) matches the formula too', () => {
    const world = createWorld({ enableSleep: false })
    const theta0 = -0.04
    const d = 0.3
    const b = world.createBody({
      position: { x: d * Math.sin(theta0), y: -d * Math.cos(theta0) },
      angle: theta0,
      shape: box(0.4, 0.4),
    })
    world.createJoint({ type: 'revolute', bodyA: null, bodyB: b, anchor: { x: 0, y: 0 } })
    const iPivotPerMass = (0.8 * 0.8 + 0.8 * 0.8) / 12 + d * d
    const expected = 2 * PI * Math.sqrt(iPivotPerMass / (G * d))
    const measured = periodOf(zeroCrossings(world, 600, () => world.getAngle(b)))
    expect(Math.abs(measured / expected - 1)).toBeLessThan(0.02)
  })
})

describe('distance joint: rod, rope', () => {
  it('a ball on a rod is a simple pendulum, T = 2 pi sqrt(L / g) within 2%', () => {
    const world = createWorld({ enableSleep: false })
    const L = 2
    const theta0 = 0.05
    const p = { x: L * Math.sin(theta0), y: -L * Math.cos(theta0) }
    // A small ball attached at its centre: its rotation does not couple, a point mass on a string.
    const ball = world.createBody({ position: p, shape: circle(0.05) })
    world.createJoint({ type: 'distance', bodyA: null, bodyB: ball, anchorA: { x: 0, y: 0 }, anchorB: p })
    const expected = 2 * PI * Math.sqrt(L / G)
    const measured = periodOf(zeroCrossings(world, 720, () => world.getPosition(ball).x))
    expect(Math.abs(measured / expected - 1)).toBeLessThan(0.02)
  })

  it('a rod keeps its length within slop while swinging a heavy box through large angles', () => {
    const world = createWorld({ enableSleep: false })
    const L = 1.5
    const heavy = world.createBody({ position: { x: L, y: 0 }, shape: box(0.3, 0.3), density: 50 })
    world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: heavy,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: L, y: 0 },
    })
    let worst = 0
    let maxForce = 0
    for (let i = 0; i < 240; i++) {
      world.step()
      const c = world.getPosition(heavy)
      worst = Math.max(worst, Math.abs(Math.hypot(c.x, c.y) - L))
      const f = world.joints()[0].force
      maxForce = Math.max(maxForce, Math.hypot(f.x, f.y))
    }
    expect(worst).toBeLessThan(0.005)
    // Dropped from horizontal, the bottom tension is 3 m g for a point mass (the box is close to one).
    const weight = world.getMass(heavy) * G
    expect(maxForce / weight).toBeGreaterThan(2.8)
    expect(maxForce / weight).toBeLessThan(3.2)
  })

  it('a compressed rope exerts zero impulse: two free bodies keep their velocities exactly', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 }, enableSleep: false })
    const a = world.createBody({
      position: { x: -1, y: 0 },
      shape: circle(0.1),
      linearVelocity: { x: 1, y: 0.2 },
    })
    const b = world.createBody({
      position: { x: 1, y: 0 },
      shape: circle(0.1),
      linearVelocity: { x: -1, y: 0.1 },
    })
    const rope = world.createJoint({
      type: 'distance',
      bodyA: a,
      bodyB: b,
      anchorA: { x: -1, y: 0 },
      anchorB: { x: 1, y: 0 },
      minLength: 0,
      maxLength: 2,
      collideConnected: false,
    })
    // They approach, pass each other (collideConnected is off) and stay under 2 m apart
    // for 1.9 s: the rope is slack all that time.
    for (let i = 0; i < 110; i++) {
      world.step()
      expect(world.getLinearVelocity(a)).toEqual({ x: 1, y: 0.2 })
      expect(world.getLinearVelocity(b)).toEqual({ x: -1, y: 0.1 })
      const { force } = world.joints()[0]
      expect(Math.abs(force.x) + Math.abs(force.y)).toBe(0)
    }
    // Then the rope goes taut and pulls: momentum is conserved and the distance stays <= 2 m.
    for (let i = 0; i < 120; i++) world.step()
    const pa = world.getPosition(a)
    const pb = world.getPosition(b)
    expect(Math.hypot(pb.x - pa.x, pb.y - pa.y)).toBeLessThan(2 + 0.005)
    const ma = world.getMass(a)
    const va = world.getLinearVelocity(a)
    const vb = world.getLinearVelocity(b)
    expect(ma * (va.x + vb.x)).toBeCloseTo(0, 12)
    expect(ma * (va.y + vb.y)).toBeCloseTo(ma * 0.3, 12)
    expect(world.hasJoint(rope)).toBe(true)
  })

  it('a rope holds a hanging box at its maximum length and carries exactly its weight', () => {
    const world = createWorld({ enableSleep: false })
    const b = world.createBody({ position: { x: 0, y: -1 }, shape: box(0.2, 0.2) })
    world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: 0, y: -0.8 },
      minLength: 0,
      maxLength: 1,
    })
    // The box falls 0.2 m until the rope is taut, bounces a little, settles.
    for (let i = 0; i < 180; i++) world.step()
    const top = world.getWorldPoint(b, { x: 0, y: 0.2 })
    expect(Math.hypot(top.x, top.y)).toBeCloseTo(1, 2)
    expect(world.joints()[0].force.y).toBeCloseTo(world.getMass(b) * G, 4)
  })
})

describe('distance joint: soft spring', () => {
  function hangingSpring(hertz: number, dampingRatio: number) {
    const world = createWorld({ enableSleep: false })
    const L = 1
    // Attached at the ball's centre: the ball does not rotate, so the effective mass is its mass.
    const ball = world.createBody({ position: { x: 0, y: -L }, shape: circle(0.1) })
    const joint = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: ball,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: 0, y: -L },
      hertz,
      dampingRatio,
    })
    const omega = 2 * PI * hertz
    return { world, ball, joint, rest: -L, deflection: G / (omega * omega) }
  }

  for (const hertz of [1, 3]) {
    it(`a ${hertz} Hz spring sags by g / omega^2 at rest`, () => {
      const s = hangingSpring(hertz, 1)
      for (let i = 0; i < 300; i++) s.world.step()
      const y = s.world.getPosition(s.ball).y
      expect(Math.abs((s.rest - y) / s.deflection - 1)).toBeLessThan(1e-6)
    })
  }

  for (const hertz of [1, 2, 5]) {
    it(`an undamped ${hertz} Hz spring oscillates at ${hertz} Hz within 2% about its sag`, () => {
      const s = hangingSpring(hertz, 0)
      const equilibrium = s.rest - s.deflection
      // Released at the rest length: it swings between 0 and 2 x the sag around the equilibrium.
      const crossings = zeroCrossings(s.world, 600, () => s.world.getPosition(s.ball).y - equilibrium)
      expect(crossings.length).toBeGreaterThanOrEqual(8)
      const measured = 1 / periodOf(crossings.slice(0, 9))
      expect(Math.abs(measured / hertz - 1)).toBeLessThan(0.02)
    })
  }

  it('stays stable at any stiffness a user can type (1e6 Hz, damping 0)', () => {
    const s = hangingSpring(1e6, 0)
    for (let i = 0; i < 120; i++) s.world.step()
    const y = s.world.getPosition(s.ball).y
    expect(Number.isFinite(y)).toBe(true)
    expect(Math.abs(y - s.rest)).toBeLessThan(1e-3)
  })
})

describe('revolute joint: limits and motor', () => {
  /** A 1 m arm pinned at its left end to the world, horizontal at creation. */
  function arm(opts: { lower: number; upper: number; motorSpeed: number; maxTorque: number }) {
    const world = createWorld({ enableSleep: false })
    const body = world.createBody({ position: { x: 0.5, y: 0 }, shape: box(0.5, 0.05) })
    const joint = world.createJoint({
      type: 'revolute',
      bodyA: null,
      bodyB: body,
      anchor: { x: 0, y: 0 },
      enableLimit: true,
      lowerAngle: opts.lower,
      upperAngle: opts.upper,
      enableMotor: true,
      motorSpeed: opts.motorSpeed,
      maxMotorTorque: opts.maxTorque,
    })
    return { world, body, joint }
  }

  /** Gravity's torque about the pivot on the arm at `angle` (N m): -m g (l/2) cos(angle). */
  function gravityTorque(world: World, body: number, angle: number): number {
    return -world.getMass(body) * G * 0.5 * Math.cos(angle)
  }

  it('the upper limit holds (within 0.02 rad) while a 500 N m motor drives past it', () => {
    const s = arm({ lower: -0.5, upper: 0.6, motorSpeed: 8, maxTorque: 500 })
    let maxAngle = Number.NEGATIVE_INFINITY
    for (let i = 0; i < 180; i++) {
      s.world.step()
      maxAngle = Math.max(maxAngle, s.world.getAngle(s.body))
    }
    expect(maxAngle).toBeGreaterThan(0.59)
    expect(maxAngle).toBeLessThan(0.6 + LIMIT_SLOP)
    // Statics at rest against the stop: the joint's torque balances gravity's about the pivot.
    const torque = s.world.joints()[0].torque
    expect(torque).toBeCloseTo(-gravityTorque(s.world, s.body, s.world.getAngle(s.body)), 4)
  })

  it('the lower limit stops a falling arm and holds it against gravity and a weak motor', () => {
    for (const motor of [0, 0.2]) {
      // Gravity's torque is 0.5 N m; a 0.2 N m motor pushing down leaves the rest to the stop.
      const s = arm({ lower: -0.4, upper: 0.5, motorSpeed: -8, maxTorque: motor })
      let minAngle = Number.POSITIVE_INFINITY
      for (let i = 0; i < 180; i++) {
        s.world.step()
        minAngle = Math.min(minAngle, s.world.getAngle(s.body))
      }
      expect(minAngle).toBeLessThan(-0.39)
      expect(minAngle).toBeGreaterThan(-0.4 - LIMIT_SLOP)
      expect(s.world.getAngle(s.body)).toBeCloseTo(-0.4, 3)
      const angle = s.world.getAngle(s.body)
      expect(s.world.joints()[0].torque).toBeCloseTo(-gravityTorque(s.world, s.body, angle), 4)
    }
  })

  it('a motor reaches its target speed in I w / T_max and never exceeds its torque cap', () => {
    const world = createWorld({ enableSleep: false })
    // A wheel pinned at its centre: gravity exerts no torque about the pivot.
    const wheel = world.createBody({ position: { x: 0, y: 0 }, shape: circle(0.5) })
    const maxTorque = 2
    const target = 6
    world.createJoint({
      type: 'revolute',
      bodyA: null,
      bodyB: wheel,
      anchor: { x: 0, y: 0 },
      enableMotor: true,
      motorSpeed: target,
      maxMotorTorque: maxTorque,
    })
    const inertia = world.getInertia(wheel)
    const spinUp = (inertia * target) / maxTorque
    let w0 = 0
    let reachedAt = -1
    for (let i = 1; i <= 120; i++) {
      world.step()
      const w = world.getAngularVelocity(wheel)
      // Torque from the body's own angular momentum change, independent of the joint's bookkeeping.
      const torque = (inertia * (w - w0)) / DT
      expect(torque).toBeLessThanOrEqual(maxTorque * (1 + 1e-9))
      const reported = world.joints()[0].torque
      expect(Math.abs(reported)).toBeLessThanOrEqual(maxTorque * (1 + 1e-9))
      if (reachedAt < 0 && Math.abs(w - target) < 1e-9) reachedAt = i * DT
      w0 = w
    }
    expect(world.getAngularVelocity(wheel)).toBeCloseTo(target, 9)
    expect(Math.abs(reachedAt - spinUp)).toBeLessThanOrEqual(DT)
  })
})

describe('mouse joint (the grab tool)', () => {
  it('sags by g / omega^2 when holding a box at its centre', () => {
    const world = createWorld({ enableSleep: false })
    const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.5, 0.5) })
    world.createJoint({ type: 'mouse', body: b, target: { x: 0, y: 3 }, hertz: 4, dampingRatio: 1 })
    for (let i = 0; i < 240; i++) world.step()
    const omega = 2 * PI * 4
    expect((3 - world.getPosition(b).y) / (G / (omega * omega))).toBeCloseTo(1, 6)
    expect(world.joints()[0].force.y).toBeCloseTo(world.getMass(b) * G, 6)
  })

  it('follows a target moving at constant speed, lagging by 2 zeta v / omega', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 }, enableSleep: false })
    const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const hertz = 3
    const zeta = 0.7
    const speed = 2
    const j = world.createJoint({ type: 'mouse', body: b, target: { x: 0, y: 0 }, hertz, dampingRatio: zeta })
    let x180 = 0
    for (let i = 1; i <= 240; i++) {
      world.setJointTarget(j, { x: speed * i * DT, y: 0 })
      world.step()
      if (i === 180) x180 = world.getPosition(b).x
    }
    // The target jumps once per step (a zero-order hold), which shortens the lag by about 3%.
    const lag = speed * 240 * DT - world.getPosition(b).x
    const expected = (2 * zeta * speed) / (2 * PI * hertz)
    expect(Math.abs(lag / expected - 1)).toBeLessThan(0.05)
    expect((world.getPosition(b).x - x180) / (60 * DT)).toBeCloseTo(speed, 6)
    expect(Math.abs(world.getPosition(b).y)).toBeLessThan(1e-9)
  })

  it('never applies more than its force cap (measured from the momentum change)', () => {
    const world = createWorld({ enableSleep: false })
    const b = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const mass = world.getMass(b)
    // Half the weight: it cannot even hold the box up, let alone reach a target 10 m away.
    const maxForce = 0.5 * mass * G
    const j = world.createJoint({ type: 'mouse', body: b, target: { x: 0, y: 0 }, maxForce, hertz: 5 })
    world.setJointTarget(j, { x: 10, y: 10 })
    let v0 = world.getLinearVelocity(b)
    let peak = 0
    for (let i = 0; i < 60; i++) {
      world.step()
      const v = world.getLinearVelocity(b)
      const fx = (mass * (v.x - v0.x)) / DT
      const fy = (mass * (v.y - v0.y)) / DT + mass * G
      peak = Math.max(peak, Math.hypot(fx, fy))
      v0 = v
    }
    expect(peak).toBeLessThanOrEqual(maxForce * (1 + 1e-9))
    expect(peak).toBeGreaterThan(maxForce * 0.99)
    const { force } = world.joints()[0]
    expect(Math.hypot(force.x, force.y)).toBeLessThanOrEqual(maxForce * (1 + 1e-9))
  })

  it('two players can hold one box: each carries half its weight and both can steer it', () => {
    const world = createWorld({ enableSleep: false })
    const b = world.createBody({ position: { x: 0, y: 2 }, shape: box(1, 0.1) })
    const left = world.createJoint({ type: 'mouse', body: b, target: { x: -0.9, y: 2 }, hertz: 5 })
    const right = world.createJoint({ type: 'mouse', body: b, target: { x: 0.9, y: 2 }, hertz: 5 })
    for (let i = 0; i < 180; i++) world.step()
    const weight = world.getMass(b) * G
    const [fl, fr] = world.joints().map((info) => info.force)
    expect(fl.y).toBeCloseTo(weight / 2, 6)
    expect(fr.y).toBeCloseTo(weight / 2, 6)
    expect(Math.abs(world.getAngle(b))).toBeLessThan(1e-9)
    // Player two lifts their end by 1 m: the box tilts (its anchors keep 1.8 m apart).
    world.setJointTarget(right, { x: -0.9 + Math.sqrt(1.8 * 1.8 - 1), y: 3 })
    for (let i = 0; i < 180; i++) world.step()
    const expectedAngle = Math.asin(1 / 1.8)
    expect(world.getAngle(b)).toBeCloseTo(expectedAngle, 2)
    expect(world.hasJoint(left) && world.hasJoint(right)).toBe(true)
  })
})

describe('joints, islands and sleep', () => {
  /** Two boxes resting on the ground 2 m apart, tied by a rod; returns once everything sleeps. */
  function tiedPair() {
    const world = createWorld()
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(20, 1) })
    const a = world.createBody({ position: { x: -1, y: 0.5 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 1, y: 0.5 }, shape: box(0.5, 0.5) })
    const rod = world.createJoint({
      type: 'distance',
      bodyA: a,
      bodyB: b,
      anchorA: { x: -1, y: 0.5 },
      anchorB: { x: 1, y: 0.5 },
    })
    for (let i = 0; i < 300 && world.awakeBodyCount() > 0; i++) world.step()
    expect(world.awakeBodyCount()).toBe(0)
    return { world, a, b, rod }
  }

  it('a jointed partner wakes when its partner is pushed, and follows it', () => {
    const { world, a, b } = tiedPair()
    world.applyLinearImpulse(a, { x: -3, y: 0 }, world.getWorldCenter(a))
    expect(world.isAwake(b)).toBe(true)
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getPosition(b).x).toBeLessThan(0.9)
  })

  it('a body hanging asleep on a rope falls when the rope is destroyed', () => {
    const world = createWorld()
    const b = world.createBody({ position: { x: 0, y: 5 }, shape: box(0.2, 0.2) })
    const rope = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 6 },
      anchorB: { x: 0, y: 5.2 },
      minLength: 0,
      maxLength: 0.8,
    })
    for (let i = 0; i < 300 && world.isAwake(b); i++) world.step()
    expect(world.isAwake(b)).toBe(false)
    const y0 = world.getPosition(b).y
    world.destroyJoint(rope)
    expect(world.isAwake(b)).toBe(true)
    for (let i = 0; i < 30; i++) world.step()
    // Free fall for 0.5 s: 1.25 m (semi-implicit Euler with 4 sub-steps falls a hair more).
    expect(y0 - world.getPosition(b).y).toBeCloseTo(0.5 * G * 0.25, 1)
  })

  it('destroying a body destroys its joints and wakes the partner', () => {
    const world = createWorld()
    const top = world.createBody({ position: { x: 0, y: 5 }, shape: box(0.2, 0.2) })
    const bottom = world.createBody({ position: { x: 0, y: 4 }, shape: box(0.2, 0.2) })
    world.createJoint({ type: 'revolute', bodyA: null, bodyB: top, anchor: { x: 0, y: 5 } })
    const link = world.createJoint({ type: 'revolute', bodyA: top, bodyB: bottom, anchor: { x: 0, y: 4.5 } })
    for (let i = 0; i < 300 && world.isAwake(bottom); i++) world.step()
    expect(world.isAwake(bottom)).toBe(false)
    world.destroyBody(top)
    expect(world.jointIds()).toEqual([])
    expect(world.hasJoint(link)).toBe(false)
    expect(world.isAwake(bottom)).toBe(true)
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getPosition(bottom).y).toBeLessThan(3)
  })
})

describe('joint read-back for drawing', () => {
  it('reports type, bodies (null for the world), world anchors and the mouse target', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const a = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5), angularVelocity: 1 })
    const b = world.createBody({ position: { x: 3, y: 0 }, shape: circle(0.5) })
    const pin = world.createJoint({ type: 'revolute', bodyA: null, bodyB: a, anchor: { x: 0.5, y: 0.5 } })
    const rod = world.createJoint({
      type: 'distance',
      bodyA: a,
      bodyB: b,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: 3, y: 0 },
    })
    const grab = world.createJoint({ type: 'mouse', body: b, target: { x: 3, y: 0.25 } })
    world.setJointTarget(grab, { x: 4, y: 1 })
    for (let i = 0; i < 30; i++) world.step()
    const [p, r, m] = world.joints()
    expect([p.id, p.type, p.bodyA, p.bodyB]).toEqual([pin, 'revolute', null, a])
    expect([r.id, r.type, r.bodyA, r.bodyB]).toEqual([rod, 'distance', a, b])
    expect([m.id, m.type, m.bodyA, m.bodyB]).toEqual([grab, 'mouse', null, b])
    // The pin's two anchors coincide (within the joint's softness); the rod's are 3 m apart.
    expect(Math.hypot(p.anchorA.x - p.anchorB.x, p.anchorA.y - p.anchorB.y)).toBeLessThan(0.005)
    expect(p.anchorA).toEqual({ x: 0.5, y: 0.5 })
    expect(Math.hypot(r.anchorB.x - r.anchorA.x, r.anchorB.y - r.anchorA.y)).toBeCloseTo(3, 2)
    expect(m.anchorA).toEqual({ x: 4, y: 1 })
    expect(() => world.setJointTarget(pin, { x: 0, y: 0 })).toThrow(RangeError)
  })
})
