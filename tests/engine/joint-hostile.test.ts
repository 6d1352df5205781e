/*
 * Joints asked for the impossible (issue 11: pin and rope anchors hundreds of metres from their
 * bodies produced NaN and kilometre positions). Whatever the joints ask, every body stays finite
 * and moves no faster than the speed limits allow, and every joint read-back is finite. The oracle
 * is the contract itself: finite numbers, and per step a centre moves at most MAX_LINEAR_SPEED / 60
 * and turns at most 4 x MAX_ROTATION (the limits the integrator enforces in every sub-step). The
 * velocity read back after the step is not checked against the limit: the last relax pass and
 * restitution run after the last clamp (as in Box2D), and it came back up to 12% over.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  circle,
  createWorld,
  MAX_LINEAR_SPEED,
  MAX_ROTATION,
  STEP_SECONDS,
  type World,
} from '../../engine/index.ts'

const STEPS = 600

/** Every body is finite, moved and turned within the speed limits since `before`, and joints read back finite. */
function expectSane(
  world: World,
  before: Map<number, { x: number; y: number; angle: number }>,
  label: string,
): void {
  for (const id of world.bodyIds()) {
    const p = world.getWorldCenter(id)
    const angle = world.getAngle(id)
    const v = world.getLinearVelocity(id)
    const values = [p.x, p.y, angle, v.x, v.y, world.getAngularVelocity(id)]
    if (!values.every(Number.isFinite))
      throw new Error(`${label}: body ${id} is not finite: ${values.join(', ')}`)
    const last = before.get(id)
    if (last !== undefined) {
      const moved = Math.hypot(p.x - last.x, p.y - last.y)
      expect(moved, `${label}: body ${id} moved`).toBeLessThanOrEqual(
        MAX_LINEAR_SPEED * STEP_SECONDS * (1 + 1e-9),
      )
      const turned = Math.abs(Math.atan2(Math.sin(angle - last.angle), Math.cos(angle - last.angle)))
      if (turned > 4 * MAX_ROTATION + 1e-9) throw new Error(`${label}: body ${id} turned ${turned} rad`)
    }
    before.set(id, { x: p.x, y: p.y, angle })
  }
  for (const j of world.joints()) {
    const values = [j.anchorA.x, j.anchorA.y, j.anchorB.x, j.anchorB.y, j.force.x, j.force.y, j.torque]
    if (!values.every(Number.isFinite))
      throw new Error(`${label}: joint ${j.id} read-back is not finite: ${values.join(', ')}`)
  }
}

function run(world: World, label: string): void {
  const before = new Map<number, { x: number; y: number; angle: number }>()
  expectSane(world, before, `${label}, start`)
  for (let i = 0; i < STEPS; i++) {
    world.step()
    expectSane(world, before, `${label}, step ${world.tick}`)
  }
}

describe('hostile joints never make a body non-finite or too fast', () => {
  it('pins and ropes with anchors 500 m from their bodies', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(50, 1) })
    const ids: number[] = []
    for (let i = 0; i < 8; i++) {
      ids.push(
        world.createBody({
          position: { x: i - 4, y: 1 + (i % 3) },
          shape: i % 2 ? circle(0.3) : box(0.3, 0.2),
        }),
      )
    }
    const far = [
      { x: 500, y: 500 },
      { x: -500, y: 480 },
      { x: 499, y: -500 },
      { x: -500, y: -500 },
    ]
    for (let i = 0; i < ids.length; i++) {
      const p = far[i % far.length]
      world.createJoint({ type: 'revolute', bodyA: i === 0 ? null : ids[i - 1], bodyB: ids[i], anchor: p })
      world.createJoint({ type: 'revolute', bodyA: null, bodyB: ids[i], anchor: far[(i + 1) % far.length] })
      const q = far[(i + 2) % far.length]
      // A rope from a far point of the world to a far point of the body, much shorter than the gap.
      world.createJoint({
        type: 'distance',
        bodyA: null,
        bodyB: ids[i],
        anchorA: { x: -q.x, y: -q.y },
        anchorB: q,
        length: 0.001,
        minLength: 0,
        maxLength: 0.001,
      })
    }
    run(world, 'far anchors')
  })

  it('zero-length ropes and rods, coincident anchors, stiff springs', () => {
    const world = createWorld({ enableSleep: false })
    const a = world.createBody({ position: { x: 0, y: 5 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 3, y: 5 }, shape: circle(0.2), density: 0.001 })
    const c = world.createBody({ position: { x: -3, y: 5 }, shape: box(0.01, 0.01), density: 1000 })
    const at = { x: 0, y: 5 }
    for (const [p, q] of [
      [a, b],
      [b, c],
      [c, a],
    ] as const) {
      world.createJoint({ type: 'distance', bodyA: p, bodyB: q, anchorA: at, anchorB: at, length: 0.001 })
      world.createJoint({
        type: 'distance',
        bodyA: p,
        bodyB: q,
        anchorA: at,
        anchorB: at,
        length: 0.001,
        minLength: 0,
        maxLength: 0.001,
      })
      world.createJoint({
        type: 'distance',
        bodyA: p,
        bodyB: q,
        anchorA: at,
        anchorB: at,
        length: 0.001,
        hertz: 1e6,
        dampingRatio: 0,
      })
      world.createJoint({
        type: 'distance',
        bodyA: p,
        bodyB: q,
        anchorA: at,
        anchorB: { x: 500, y: 500 },
        length: 1e6,
        minLength: 1e6,
        maxLength: 1e6,
      })
    }
    run(world, 'zero lengths')
  })

  it('the same pair joined many times, fighting motors, and grabs pulling far away', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(50, 1) })
    const a = world.createBody({ position: { x: 0, y: 2 }, shape: box(1, 0.1), density: 0.01 })
    const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.1, 1), density: 100 })
    for (let i = 0; i < 12; i++) {
      const anchor = { x: (i % 4) * 130 - 200, y: Math.floor(i / 4) * 190 - 200 }
      world.createJoint({
        type: 'revolute',
        bodyA: a,
        bodyB: b,
        anchor,
        enableMotor: true,
        motorSpeed: i % 2 ? 1e6 : -1e6,
        maxMotorTorque: 1e12,
        enableLimit: i % 3 === 0,
        lowerAngle: -0.01,
        upperAngle: 0.01,
      })
      world.createJoint({
        type: 'distance',
        bodyA: a,
        bodyB: b,
        anchorA: anchor,
        anchorB: { x: -anchor.x, y: anchor.y },
      })
    }
    world.createJoint({
      type: 'mouse',
      body: a,
      target: { x: 500, y: 500 },
      localAnchor: { x: 400, y: -400 },
      maxForce: 1e12,
      hertz: 1000,
      dampingRatio: 0,
    })
    world.createJoint({ type: 'mouse', body: b, target: { x: -500, y: -500 }, maxForce: 1e12, hertz: 1000 })
    run(world, 'same pair')
  })

  it('anchors 1e6 m away (the farthest a definition accepts) and grabs toward 1e300 m', () => {
    const world = createWorld({ enableSleep: false })
    const a = world.createBody({ position: { x: 0, y: 2 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 2, y: 2 }, shape: circle(0.5) })
    const far = { x: 1e6, y: -1e6 + 2 }
    world.createJoint({ type: 'revolute', bodyA: a, bodyB: b, anchor: far })
    world.createJoint({ type: 'revolute', bodyA: null, bodyB: a, anchor: { x: -1e6, y: 1e6 } })
    world.createJoint({
      type: 'distance',
      bodyA: a,
      bodyB: b,
      anchorA: far,
      anchorB: { x: 1e6, y: 1e6 },
      length: 1e6,
    })
    const grab = world.createJoint({ type: 'mouse', body: b, target: { x: 0, y: 0 }, maxForce: 1e12 })
    world.setJointTarget(grab, { x: 1e300, y: -1e300 })
    run(world, 'huge anchors')
  })

  it('refuses anchors farther than 1e6 m from their body, naming the value', () => {
    const world = createWorld()
    const a = world.createBody({ position: { x: 0, y: 2 }, shape: box(0.5, 0.5) })
    expect(() =>
      world.createJoint({ type: 'revolute', bodyA: null, bodyB: a, anchor: { x: 1e300, y: 0 } }),
    ).toThrow(/anchor must lie within 1000000 m of the world origin, got \(1e\+300, 0\)/)
    expect(() =>
      world.createJoint({
        type: 'distance',
        bodyA: null,
        bodyB: a,
        anchorA: { x: 0, y: 0 },
        anchorB: { x: 0, y: -2e6 },
      }),
    ).toThrow(/anchorB must lie within 1000000 m of body 1, got \(0, -2000002\) from it/)
    expect(() =>
      world.createJoint({ type: 'mouse', body: a, target: { x: 0, y: 0 }, localAnchor: { x: 0, y: 1e7 } }),
    ).toThrow(/localAnchor must lie within 1000000 m of body 1/)
  })

  it('coincident anchors with no length make the shortest rod (1 mm), not an error', () => {
    const world = createWorld()
    const a = world.createBody({ position: { x: 0, y: 2 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 0, y: 2 }, shape: box(0.5, 0.5) })
    const at = { x: 0.3, y: 2 }
    world.createJoint({ type: 'distance', bodyA: a, bodyB: b, anchorA: at, anchorB: at })
    expect(() =>
      world.createJoint({ type: 'distance', bodyA: a, bodyB: b, anchorA: at, anchorB: at, length: 0 }),
    ).toThrow(/length must be in \[0.001, 1000000\], got 0/)
  })
})
