/*
 * Per-shape setters, body type changes, forces, torques and explosions. Oracles: Newton's second
 * law (a = F / m, alpha = T / I) and the inclined plane (a = g (sin t - mu cos t)) by hand, and the
 * explosion's definition (impulse per length x width x falloff) worked by hand.
 */
import { describe, expect, it } from 'vitest'
import { box, circle } from '../../engine/collision/shapes.ts'
import { cos, PI, sin } from '../../engine/math.ts'
import { createWorld, loadWorld } from '../../engine/world/world.ts'

describe('forces and torques', () => {
  it('a force at the centre for 60 steps: v = F t / m; off the centre it also spins at T t / I', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const a = world.createBody({ shape: box(0.5, 0.25), density: 2 })
    const b = world.createBody({ position: { x: 5, y: 0 }, shape: box(0.5, 0.25), density: 2 })
    const m = world.getMass(a)
    const inertia = world.getInertia(b)
    for (let i = 0; i < 60; i++) {
      world.applyForce(a, { x: 3, y: -1 }, world.getWorldCenter(a))
      world.applyForce(
        b,
        { x: 0, y: 2 },
        { x: world.getWorldCenter(b).x + 0.5, y: world.getWorldCenter(b).y },
      )
      world.step()
    }
    expect(world.getLinearVelocity(a).x).toBeCloseTo(3 / m, 12)
    expect(world.getLinearVelocity(a).y).toBeCloseTo(-1 / m, 12)
    expect(world.getLinearVelocity(b).y).toBeCloseTo(2 / m, 12)
    // Torque 0.5 x 2 = 1 N m; the angle turns, so the lever arm is re-measured each step: first step exact.
    expect(world.getAngularVelocity(b)).toBeGreaterThan(0)
    const c = world.createBody({ position: { x: 10, y: 0 }, shape: circle(0.5) })
    world.applyTorque(c, 2)
    world.step()
    expect(world.getAngularVelocity(c)).toBeCloseTo((2 / world.getInertia(c)) * (1 / 60), 12)
    expect(inertia).toBeGreaterThan(0)
  })

  it('forces act once: the step after, none is left; a pending force survives save and load', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const a = world.createBody({ shape: circle(0.5) })
    world.applyForce(a, { x: 10, y: 0 }, world.getWorldCenter(a))
    const copy = loadWorld(world.save())
    world.step()
    copy.step()
    const v = world.getLinearVelocity(a).x
    expect(copy.getLinearVelocity(a).x).toBe(v)
    expect(v).toBeCloseTo(10 / world.getMass(a) / 60, 12)
    world.step()
    expect(world.getLinearVelocity(a).x).toBe(v)
  })

  it('an angular impulse gives w = J / I at once', () => {
    const world = createWorld()
    const a = world.createBody({ shape: box(1, 0.5) })
    world.applyAngularImpulse(a, 0.5)
    expect(world.getAngularVelocity(a)).toBeCloseTo(0.5 / world.getInertia(a), 12)
  })
})

describe('per-shape setters and body types', () => {
  function ramp(mu: number): { world: ReturnType<typeof createWorld>; block: number; shape: number } {
    const t = (30 * PI) / 180
    const world = createWorld()
    world.createBody({ type: 'static', angle: t, shape: box(20, 0.5), friction: mu })
    const n = { x: -sin(t), y: cos(t) }
    const block = world.createBody({
      angle: t,
      position: { x: n.x * 0.75, y: n.y * 0.75 },
      shape: box(0.25, 0.25),
      friction: mu,
    })
    return { world, block, shape: world.bodyShapes(block)[0] }
  }

  it('setFriction: a block held at mu 0.6 on a 30 degree ramp slides at g (sin t - mu cos t) after mu becomes 0.2', () => {
    const { world, block, shape } = ramp(0.6)
    for (let i = 0; i < 60; i++) world.step()
    const v = world.getLinearVelocity(block)
    expect(Math.hypot(v.x, v.y)).toBeLessThan(0.01)
    world.setFriction(shape, 0.2)
    world.setFriction(1, 0.2)
    const start = world.getLinearVelocity(block)
    for (let i = 0; i < 60; i++) world.step()
    const end = world.getLinearVelocity(block)
    const t = (30 * PI) / 180
    const expected = 10 * (Math.sin(t) - 0.2 * Math.cos(t))
    const measured = Math.hypot(end.x - start.x, end.y - start.y)
    expect(Math.abs(measured - expected) / expected).toBeLessThan(0.02)
  })

  it('setDensity re-masses the body; setRestitution makes a ball bounce', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shape: box(5, 0.5) })
    const ball = world.createBody({ position: { x: 0, y: 3 }, shape: circle(0.25) })
    const [s] = world.bodyShapes(ball)
    const m = world.getMass(ball)
    world.setDensity(s, 3)
    expect(world.getMass(ball)).toBeCloseTo(3 * m, 12)
    world.setRestitution(s, 0.8)
    let up = 0
    for (let i = 0; i < 90; i++) {
      world.step()
      up = Math.max(up, world.getLinearVelocity(ball).y)
    }
    expect(up).toBeGreaterThan(3)
  })

  it('setBodyType: a falling body made static stops and holds others; made dynamic again it falls at g', () => {
    const world = createWorld()
    const a = world.createBody({ position: { x: 0, y: 5 }, shape: box(1, 0.25) })
    for (let i = 0; i < 30; i++) world.step()
    world.setBodyType(a, 'static')
    expect(world.getLinearVelocity(a)).toEqual({ x: 0, y: 0 })
    const y = world.getPosition(a).y
    const top = world.createBody({ position: { x: 0, y: y + 0.75 }, shape: box(0.5, 0.5) })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.getPosition(a).y).toBe(y)
    expect(world.getPosition(top).y).toBeGreaterThan(y + 0.74)
    world.setBodyType(a, 'dynamic')
    expect(world.getMass(a)).toBeCloseTo(1, 12)
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getLinearVelocity(a).y).toBeCloseTo(-5, 4)
    expect(() => world.setBodyType(a, 'floating' as 'static')).toThrow(/body type/)
  })
})

describe('explode', () => {
  it('impulse = impulsePerLength x width x falloff factor, away from the centre, only for masked categories', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    // A ball inside the radius, one in the falloff band, one out of reach, one masked out.
    const near = world.createBody({ position: { x: 2, y: 0 }, shape: circle(0.5) })
    const band = world.createBody({ position: { x: 0, y: -4.5 }, shape: circle(0.5) })
    const far = world.createBody({ position: { x: -9, y: 0 }, shape: circle(0.5) })
    const masked = world.createBody({
      position: { x: 0, y: 2 },
      shapes: [{ shape: circle(0.5), filter: { categoryBits: 4, maskBits: 0xffffffff, groupIndex: 0 } }],
    })
    world.explode({
      position: { x: 0, y: 0 },
      radius: 3,
      falloff: 2,
      impulsePerLength: 1.5,
      maskBits: 0xfffffffb,
    })
    const m = world.getMass(near)
    // Near: surface 1.5 m away (inside 3): full 1.5 x 1 m width along +x.
    expect(world.getLinearVelocity(near).x).toBeCloseTo(1.5 / m, 12)
    expect(world.getLinearVelocity(near).y).toBeCloseTo(0, 12)
    // Band: surface 4 m away: (3 + 2 - 4) / 2 = 0.5 of it, along -y.
    expect(world.getLinearVelocity(band).y).toBeCloseTo((-1.5 * 0.5) / m, 12)
    expect(world.getLinearVelocity(far)).toEqual({ x: 0, y: 0 })
    expect(world.getLinearVelocity(masked)).toEqual({ x: 0, y: 0 })
    // A box side-on: width across the blast is its full side.
    const world2 = createWorld({ gravity: { x: 0, y: 0 } })
    const b = world2.createBody({ position: { x: 2, y: 0 }, shape: box(0.5, 1) })
    world2.explode({ position: { x: 0, y: 0 }, radius: 3, impulsePerLength: 1 })
    expect(world2.getLinearVelocity(b).x).toBeCloseTo(2 / world2.getMass(b), 12)
  })
})
