/*
 * Joints and collision (Box2D's collideConnected), and the joint reaction read-back.
 * - A rope, rod or spring lets its bodies collide by default: two boxes tied by a rope and dropped
 *   onto each other end stacked, one box height apart (geometry), not interpenetrating.
 * - A pin does not: two boxes pinned at a point inside both may overlap and get no contact; asked
 *   for, they do collide.
 * - The flag survives save and load and is reported by joints().
 * - getJointReaction: the free-body diagram of a body held at rest by two joints closes (the joint
 *   forces and moments balance gravity: Newton's first law), with A and B signs as documented.
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld, loadWorld, type World } from '../../engine/index.ts'

const G = 10

/** A static ground whose top is at y = 0. */
function ground(world: World): void {
  world.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5) })
}

function hasContact(world: World, a: number, b: number): boolean {
  return world.contacts().some((c) => (c.bodyA === a && c.bodyB === b) || (c.bodyA === b && c.bodyB === a))
}

describe('collideConnected', () => {
  it('two boxes tied by a rope and dropped onto each other end stacked, 1 m apart', () => {
    const world = createWorld()
    ground(world)
    const lower = world.createBody({ position: { x: 0, y: 0.5 }, shape: box(0.5, 0.5) })
    const upper = world.createBody({ position: { x: 0.1, y: 4 }, shape: box(0.5, 0.5) })
    const rope = world.createJoint({
      type: 'distance',
      bodyA: lower,
      bodyB: upper,
      anchorA: { x: 0, y: 0.5 },
      anchorB: { x: 0.1, y: 4 },
      minLength: 0,
      maxLength: 4,
    })
    expect(world.joints()[0].collideConnected).toBe(true)
    for (let i = 0; i < 240; i++) world.step()
    // Geometry: the upper box rests on the lower one, centres one box height (1 m) apart.
    const pl = world.getPosition(lower)
    const pu = world.getPosition(upper)
    expect(pl.y).toBeCloseTo(0.5, 1)
    expect(Math.abs(pu.y - pl.y - 1)).toBeLessThan(0.02)
    expect(hasContact(world, lower, upper)).toBe(true)
    expect(world.hasJoint(rope)).toBe(true)
  })

  it('a rope created between two touching boxes keeps their contact', () => {
    const world = createWorld()
    ground(world)
    const lower = world.createBody({ position: { x: 0, y: 0.5 }, shape: box(0.5, 0.5) })
    const upper = world.createBody({ position: { x: 0, y: 1.5 }, shape: box(0.5, 0.5) })
    for (let i = 0; i < 30; i++) world.step()
    expect(hasContact(world, lower, upper)).toBe(true)
    world.createJoint({
      type: 'distance',
      bodyA: lower,
      bodyB: upper,
      anchorA: { x: 0, y: 0.5 },
      anchorB: { x: 0, y: 1.5 },
    })
    world.step()
    expect(hasContact(world, lower, upper)).toBe(true)
    expect(world.getPosition(upper).y).toBeCloseTo(1.5, 2)
  })

  it('two boxes pinned at a point inside both overlap freely and get no contact', () => {
    const world = createWorld({ enableSleep: false })
    const a = world.createBody({ type: 'static', position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 0.5, y: 0 }, shape: box(0.5, 0.5) })
    world.createJoint({ type: 'revolute', bodyA: a, bodyB: b, anchor: { x: 0.25, y: 0 } })
    expect(world.joints()[0].collideConnected).toBe(false)
    for (let i = 0; i < 60; i++) {
      world.step()
      expect(hasContact(world, a, b)).toBe(false)
    }
    // The box swings down about the pin, through the static box: its centre ends below the pin.
    const p = world.getPosition(b)
    expect(Math.hypot(p.x - 0.25, p.y)).toBeCloseTo(0.25, 2)
  })

  it('a pin asked to collide its bodies pushes overlapping boxes apart (and one not asked does not)', () => {
    const spread = (collideConnected: boolean): { contact: boolean; angle: number } => {
      const world = createWorld({ gravity: { x: 0, y: 0 }, enableSleep: false })
      const a = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
      const b = world.createBody({ position: { x: 0.9, y: 0 }, shape: box(0.5, 0.5) })
      world.createJoint({
        type: 'revolute',
        bodyA: a,
        bodyB: b,
        anchor: { x: 0.45, y: 0.6 },
        collideConnected,
      })
      world.step()
      const contact = hasContact(world, a, b)
      for (let i = 0; i < 5; i++) world.step()
      return { contact, angle: world.getAngle(b) - world.getAngle(a) }
    }
    // The overlap pushes them apart; the pin above the contact turns them into a V.
    const colliding = spread(true)
    expect(colliding.contact).toBe(true)
    expect(colliding.angle).toBeGreaterThan(0.3)
    expect(spread(false)).toEqual({ contact: false, angle: 0 })
  })

  it('rejects a non-boolean flag, naming it', () => {
    const world = createWorld()
    const a = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const def = { type: 'revolute', bodyA: null, bodyB: a, anchor: { x: 0, y: 0 }, collideConnected: 1 }
    expect(() => world.createJoint(def as never)).toThrow(/collideConnected must be a boolean, got 1/)
  })

  it('survives save and load, and the loaded world steps identically', () => {
    const world = createWorld()
    ground(world)
    const lower = world.createBody({ position: { x: 0, y: 0.5 }, shape: box(0.5, 0.5) })
    const upper = world.createBody({ position: { x: 0.2, y: 3 }, shape: box(0.5, 0.5) })
    const anchor = { anchorA: { x: 0, y: 0.5 }, anchorB: { x: 0.2, y: 3 } }
    world.createJoint({ type: 'distance', bodyA: lower, bodyB: upper, ...anchor, collideConnected: true })
    world.createJoint({ type: 'distance', bodyA: lower, bodyB: upper, ...anchor, collideConnected: false })
    world.createJoint({ type: 'distance', bodyA: lower, bodyB: upper, ...anchor })
    const copy = loadWorld(world.save())
    expect(copy.joints().map((j) => j.collideConnected)).toEqual([true, false, true])
    for (let i = 0; i < 120; i++) {
      world.step()
      copy.step()
    }
    expect(copy.hash()).toBe(world.hash())
    // One joint that forbids collision is enough: the boxes pass through each other.
    expect(world.getPosition(upper).y).toBeLessThan(1)
  })
})

describe('getJointReaction', () => {
  it('a plank held level by a pin and a rope: joint forces and moments balance gravity', () => {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    // A 2 m plank; a pin at its left end (to the world) and a rope from its right end up to a hook.
    const plank = world.createBody({ position: { x: 1, y: 0 }, shape: box(1, 0.05) })
    const hook = world.createBody({ type: 'static', position: { x: 3, y: 1 }, shape: box(0.1, 0.1) })
    const pin = world.createJoint({ type: 'revolute', bodyA: null, bodyB: plank, anchor: { x: 0, y: 0 } })
    // The plank is body A of the rope, so its reaction on the plank is minus the reported force.
    const rope = world.createJoint({
      type: 'distance',
      bodyA: plank,
      bodyB: hook,
      anchorA: { x: 2, y: 0 },
      anchorB: { x: 3, y: 1 },
    })
    for (let i = 0; i < 300; i++) world.step()
    expect(Math.abs(world.getAngularVelocity(plank))).toBeLessThan(1e-3)
    const m = world.getMass(plank)
    const c = world.getWorldCenter(plank)
    const pinR = world.getJointReaction(pin)
    const ropeR = world.getJointReaction(rope)
    const [pinInfo, ropeInfo] = world.joints()
    expect(pinR).toEqual({ force: pinInfo.force, torque: pinInfo.torque })
    expect(ropeR).toEqual({ force: ropeInfo.force, torque: ropeInfo.torque })
    // Forces on the plank: the pin's (+, it is B), the rope's (-, it is A), gravity.
    const fx = pinR.force.x - ropeR.force.x
    const fy = pinR.force.y - ropeR.force.y - m * G
    expect(Math.abs(fx)).toBeLessThan(1e-3 * m * G)
    expect(Math.abs(fy)).toBeLessThan(1e-3 * m * G)
    // Moments about the centre of mass: each force at its own anchor, plus the pure torques.
    const armPin = { x: pinInfo.anchorB.x - c.x, y: pinInfo.anchorB.y - c.y }
    const armRope = { x: ropeInfo.anchorA.x - c.x, y: ropeInfo.anchorA.y - c.y }
    const moment =
      armPin.x * pinR.force.y -
      armPin.y * pinR.force.x +
      pinR.torque -
      (armRope.x * ropeR.force.y - armRope.y * ropeR.force.x) -
      ropeR.torque
    expect(Math.abs(moment)).toBeLessThan(1e-3 * m * G)
    // Statics by hand: the rope at 45 degrees carries half the weight vertically (moments about the pin).
    expect(-ropeR.force.y).toBeCloseTo((m * G) / 2, 2)
    expect(-ropeR.force.x).toBeCloseTo((m * G) / 2, 2)
  })

  it('names a missing joint', () => {
    expect(() => createWorld().getJointReaction(7)).toThrow(/no joint with id 7/)
  })
})
