/*
 * Shapes, mass properties, body types and island sleep, against hand computations:
 * - polygon(): hull and winding validated, bad input rejected with a message naming it;
 * - mass, centroid and inertia against the closed forms for a rectangle, a circle and a triangle;
 * - kinematic bodies move by their velocity only and push dynamic bodies;
 * - sleep is per island, a touch wakes a sleeping island, destroying a body wakes what it touched.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  circle,
  computeMass,
  convexPolygon,
  cos,
  createWorld,
  MAX_LINEAR_SPEED,
  MAX_POSITION,
  MAX_SHAPE_EXTENT,
  POSE_STRIDE,
  polygon,
  sin,
  TRIG_LIMIT,
  towerScene,
} from '../../engine/index.ts'

describe('shapes', () => {
  it('polygon() stores either winding counter-clockwise with outward unit normals', () => {
    const cw = polygon([
      { x: 0, y: 0 },
      { x: 0, y: 1 },
      { x: 2, y: 1 },
      { x: 2, y: 0 },
    ])
    let area2 = 0
    for (let i = 0; i < cw.count; i++) {
      const a = cw.vertices[i]
      const b = cw.vertices[(i + 1) % cw.count]
      area2 += a.x * b.y - a.y * b.x
      const n = cw.normals[i]
      expect(Math.hypot(n.x, n.y)).toBeCloseTo(1, 15)
      // outward: the centroid is behind every edge
      expect(n.x * (cw.centroid.x - a.x) + n.y * (cw.centroid.y - a.y)).toBeLessThan(0)
    }
    expect(area2).toBeCloseTo(4, 12) // twice the area, positive: counter-clockwise
  })

  it.each([
    [
      'a concave vertex',
      [
        { x: 0, y: 0 },
        { x: 2, y: 0 },
        { x: 1, y: 0.5 },
        { x: 2, y: 2 },
        { x: 0, y: 2 },
      ],
      /convex/,
    ],
    [
      'collinear vertices',
      [
        { x: 0, y: 0 },
        { x: 1, y: 0 },
        { x: 2, y: 0 },
        { x: 1, y: 1 },
      ],
      /convex|collinear/,
    ],
    [
      'a repeated point',
      [
        { x: 0, y: 0 },
        { x: 0, y: 0 },
        { x: 1, y: 1 },
      ],
      /degenerate/,
    ],
    [
      'two vertices',
      [
        { x: 0, y: 0 },
        { x: 1, y: 0 },
      ],
      /3 to 8 vertices, got 2/,
    ],
    ['nine vertices', Array.from({ length: 9 }, (_, i) => ({ x: Math.cos(i), y: Math.sin(i) })), /got 9/],
    [
      'a NaN vertex',
      [
        { x: 0, y: 0 },
        { x: Number.NaN, y: 0 },
        { x: 1, y: 1 },
      ],
      /vertex 1/,
    ],
    [
      'a self-intersecting star',
      [0, 2, 4, 1, 3].map((k) => ({
        x: Math.cos((2 * Math.PI * k) / 5),
        y: Math.sin((2 * Math.PI * k) / 5),
      })),
      /convex/,
    ],
  ])('convexPolygon() rejects %s with a message naming it', (_name, points, message) => {
    expect(() => convexPolygon(points)).toThrow(message)
  })

  it('circle() and box() reject zero, negative and non-finite sizes, naming the value', () => {
    expect(() => circle(0)).toThrow(/radius.*0/)
    expect(() => circle(Number.POSITIVE_INFINITY)).toThrow(/radius/)
    expect(() => box(-1, 1)).toThrow(/halfWidth.*-1/)
  })

  it('circle(), box() and polygon() refuse sizes beyond MAX_SHAPE_EXTENT (100 km), naming the value', () => {
    // Found by tests/engine/api-fuzz.test.ts: box(1e308, 0.02) was accepted, its inertia was
    // Infinity and its body's centre NaN after one step; circle(1e154) had an infinite mass.
    expect(MAX_SHAPE_EXTENT).toBe(1e5)
    expect(() => circle(1e154)).toThrow(/radius.*1e\+154/)
    expect(() => box(1e308, 0.02)).toThrow(/halfWidth.*1e\+308/)
    expect(() => box(1, 100001)).toThrow(/halfHeight.*100001/)
    expect(() =>
      polygon([
        { x: 0, y: 0 },
        { x: 2e5, y: 0 },
        { x: 0, y: 1 },
      ]),
    ).toThrow(/vertex 1 \(200000, 0\)/)
    // At the bound everything stays finite: a 200 km box of the densest material falls as four
    // semi-implicit Euler sub-steps of h = 1/240 s say, g h^2 (1 + 2 + 3 + 4).
    const world = createWorld()
    const id = world.createBody({ shape: box(MAX_SHAPE_EXTENT, MAX_SHAPE_EXTENT), density: 1e6 })
    const mass = computeMass(box(MAX_SHAPE_EXTENT, MAX_SHAPE_EXTENT), 1e6)
    expect([mass.mass, mass.inertia].every(Number.isFinite)).toBe(true)
    world.step()
    const c = world.getWorldCenter(id)
    expect(c.x).toBe(0)
    expect(c.y).toBeCloseTo(-10 * 10 * (1 / 240) ** 2, 12)
  })

  it('sin and cos take |x| < TRIG_LIMIT (2^20 rad) and give NaN beyond; bodies refuse such angles', () => {
    // Found by tests/engine/api-fuzz.test.ts: createBody({ angle: 1e308 }) made a NaN body, and
    // sin(1e20) was 2.7e27. Math.sin and Math.cos are the oracle inside the domain (within 1e-12).
    expect(TRIG_LIMIT).toBe(2 ** 20)
    for (const x of [TRIG_LIMIT - 1, -(TRIG_LIMIT - 0.5), 123456.789]) {
      expect(Math.abs(sin(x) - Math.sin(x))).toBeLessThan(1e-12)
      expect(Math.abs(cos(x) - Math.cos(x))).toBeLessThan(1e-12)
    }
    for (const x of [TRIG_LIMIT, -TRIG_LIMIT, 1e20, -1e308, Number.NaN, Number.POSITIVE_INFINITY]) {
      expect(sin(x)).toBeNaN()
      expect(cos(x)).toBeNaN()
    }
    const world = createWorld()
    expect(() => world.createBody({ shape: circle(1), angle: 1e308 })).toThrow(/angle.*1e\+308/)
    const id = world.createBody({ shape: circle(1), angle: TRIG_LIMIT - 1 })
    expect(() => world.setTransform(id, { x: 0, y: 0 }, -TRIG_LIMIT)).toThrow(/angle.*-1048576/)
    const q = world.getRotation(id)
    expect(Math.abs(q.c - Math.cos(TRIG_LIMIT - 1))).toBeLessThan(1e-12)
    expect(Math.abs(q.s - Math.sin(TRIG_LIMIT - 1))).toBeLessThan(1e-12)
  })

  it('positions set through the API lie within MAX_POSITION (1000 km); speeds a definition gives are clamped', () => {
    // Found by tests/engine/api-fuzz.test.ts: a body created at y = 2^53 m, where doubles are 2 m
    // apart, moved 7.4 m in one step at 29 m/s; createBody took a linear velocity of -1e308 m/s
    // (and a kinematic angular velocity of 1e308 rad/s) unclamped, where setLinearVelocity clamps.
    expect(MAX_POSITION).toBe(1e6)
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    expect(() => world.createBody({ shape: circle(1), position: { x: 0, y: 2 ** 53 } })).toThrow(
      /position.*9007199254740992/,
    )
    const id = world.createBody({ shape: circle(1), position: { x: -MAX_POSITION, y: MAX_POSITION } })
    expect(() => world.setTransform(id, { x: MAX_POSITION + 1, y: 0 }, 0)).toThrow(/position.*1000001/)
    const fast = world.createBody({ shape: circle(1), linearVelocity: { x: -1e308, y: 0 } })
    expect(world.getLinearVelocity(fast)).toEqual({ x: -MAX_LINEAR_SPEED, y: 0 })
    const spinner = world.createBody({ type: 'kinematic', shape: circle(1), angularVelocity: 1e308 })
    expect(world.getAngularVelocity(spinner)).toBe(world.maxAngularSpeed)
  })

  it('mass properties match the closed forms (rectangle, circle, right triangle)', () => {
    // Rectangle w x h at density 2: m = 2 w h, I = m (w^2 + h^2) / 12 about the centre.
    const rect = computeMass(box(1.5, 0.25), 2)
    expect(rect.mass).toBeCloseTo(2 * 3 * 0.5, 12)
    expect(rect.inertia).toBeCloseTo((rect.mass * (9 + 0.25)) / 12, 12)
    // Circle r at density 3: m = 3 pi r^2, I = m r^2 / 2.
    const disc = computeMass(circle(0.4), 3)
    expect(disc.mass).toBeCloseTo(3 * Math.PI * 0.16, 12)
    expect(disc.inertia).toBeCloseTo((disc.mass * 0.16) / 2, 12)
    // Right triangle with legs a (x) and b (y) at the origin: centroid (a/3, b/3),
    // I about the centroid = m (a^2 + b^2) / 18.
    const a = 3
    const b = 2
    const tri = computeMass(
      polygon([
        { x: 0, y: 0 },
        { x: a, y: 0 },
        { x: 0, y: b },
      ]),
      1,
    )
    expect(tri.mass).toBeCloseTo((a * b) / 2, 12)
    expect(tri.center.x).toBeCloseTo(a / 3, 12)
    expect(tri.center.y).toBeCloseTo(b / 3, 12)
    expect(tri.inertia).toBeCloseTo((tri.mass * (a * a + b * b)) / 18, 12)
  })

  it('an off-centre polygon rotates about its centroid, not its origin', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const shape = polygon([
      { x: 2, y: 0 },
      { x: 4, y: 0 },
      { x: 4, y: 2 },
      { x: 2, y: 2 },
    ])
    const id = world.createBody({ position: { x: 0, y: 0 }, shape, angularVelocity: 1 })
    for (let i = 0; i < 60; i++) world.step()
    const c = world.getWorldCenter(id)
    expect(c.x).toBeCloseTo(3, 9)
    expect(c.y).toBeCloseTo(1, 9)
  })
})

describe('body types', () => {
  it('a kinematic body moves exactly by its velocity, ignores gravity, and pushes a dynamic box', () => {
    const world = createWorld()
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(50, 1) })
    const pusher = world.createBody({
      type: 'kinematic',
      position: { x: -3, y: 0.5 },
      shape: box(0.5, 0.5),
      linearVelocity: { x: 1, y: 0 },
    })
    const crate = world.createBody({ position: { x: 0, y: 0.5 }, shape: box(0.5, 0.5) })
    for (let i = 0; i < 240; i++) world.step()
    const p = world.getPosition(pusher)
    expect(p.x).toBeCloseTo(-3 + 4, 9) // 4 s at 1 m/s, untouched by the crate it pushes
    expect(p.y).toBe(0.5)
    expect(world.getLinearVelocity(pusher)).toEqual({ x: 1, y: 0 })
    expect(world.getMass(pusher)).toBe(0)
    // The crate is pushed ahead of the kinematic box, face to face.
    const q = world.getPosition(crate)
    expect(q.x).toBeGreaterThan(p.x + 0.98)
    expect(q.x).toBeLessThan(p.x + 1.05)
  })

  it('a static body never moves and is never awake', () => {
    const world = createWorld()
    const ground = world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(5, 1) })
    world.createBody({ position: { x: 0, y: 3 }, shape: circle(0.5) })
    for (let i = 0; i < 120; i++) world.step()
    expect(world.getPosition(ground)).toEqual({ x: 0, y: -1 })
    expect(world.isAwake(ground)).toBe(false)
  })
})

describe('writePoses', () => {
  it('writes what bodyIds, getBodyType, getPosition, getAngle and isAwake read, for every body', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shape: box(20, 0.5) })
    world.createBody({ type: 'kinematic', shape: circle(0.5), position: { x: -3, y: 4 }, angularVelocity: 2 })
    const tilted = world.createBody({ shape: box(0.5, 0.25), position: { x: 1, y: 3 }, angle: 2.5 })
    world.createBody({ shape: circle(0.3), position: { x: 5, y: 0.8 } })
    world.destroyBody(tilted) // ids stay ascending with a gap
    for (let id = 0; id < 6; id++)
      world.createBody({ shape: box(0.4, 0.4), position: { x: id - 3, y: 2 + id }, angle: -id })
    for (let i = 0; i < 90; i++) world.step()
    const out = new Float64Array(world.bodyCount * POSE_STRIDE)
    expect(world.writePoses(out)).toBe(world.bodyCount)
    const types = ['static', 'kinematic', 'dynamic']
    world.bodyIds().forEach((id, i) => {
      const o = i * POSE_STRIDE
      const p = world.getPosition(id)
      expect([out[o], types[out[o + 1]], out[o + 2], out[o + 3], out[o + 4], out[o + 5] === 1]).toEqual([
        id,
        world.getBodyType(id),
        p.x,
        p.y,
        world.getAngle(id),
        world.isAwake(id),
      ])
    })
    expect(new Set(Array.from({ length: world.bodyCount }, (_, i) => out[i * POSE_STRIDE + 5])).size).toBe(2) // some asleep, some awake
    expect(() => world.writePoses(new Float64Array(out.length - 1))).toThrow(
      /writePoses needs room for 54 numbers, got 53/,
    )
  })
})

describe('islands and sleep', () => {
  it('sleep is per island: a resting box sleeps while a separate box keeps falling', () => {
    const world = createWorld()
    world.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: box(50, 1) })
    const resting = world.createBody({ position: { x: -10, y: 0.5 }, shape: box(0.5, 0.5) })
    const falling = world.createBody({ position: { x: 10, y: 30 }, shape: box(0.5, 0.5) })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.isAwake(resting)).toBe(false)
    expect(world.isAwake(falling)).toBe(true)
  })

  it('a body dropped on a sleeping tower wakes the whole tower (its island), not other islands', () => {
    const world = createWorld()
    const ids = buildScene(world, towerScene(5, false))
    const loner = world.createBody({ position: { x: 20, y: 0.5 }, shape: box(0.5, 0.5) })
    for (let i = 0; i < 120; i++) world.step()
    for (const id of [...ids.slice(1), loner]) expect(world.isAwake(id)).toBe(false)
    world.createBody({ position: { x: 0, y: 8 }, shape: box(0.5, 0.5), linearVelocity: { x: 0, y: -5 } })
    let woke = false
    for (let i = 0; i < 60 && !woke; i++) {
      world.step()
      woke = ids.slice(1).every((id) => world.isAwake(id))
    }
    expect(woke).toBe(true)
    expect(world.isAwake(loner)).toBe(false)
  })

  it('destroying the bottom box of a sleeping stack wakes the boxes above, which then fall', () => {
    const world = createWorld()
    const ids = buildScene(world, towerScene(3, false))
    for (let i = 0; i < 120; i++) world.step()
    expect(world.isAwake(ids[3])).toBe(false)
    world.destroyBody(ids[1])
    expect(world.isAwake(ids[2])).toBe(true)
    expect(world.isAwake(ids[3])).toBe(true)
    for (let i = 0; i < 120; i++) world.step()
    expect(world.getPosition(ids[2]).y).toBeCloseTo(0.5, 2)
    expect(world.getPosition(ids[3]).y).toBeCloseTo(1.5, 2)
    expect(world.hasBody(ids[1])).toBe(false)
  })

  it('an impulse on a sleeping body wakes it and its island', () => {
    const world = createWorld()
    const ids = buildScene(world, towerScene(2, false))
    for (let i = 0; i < 120; i++) world.step()
    expect(world.isAwake(ids[1])).toBe(false)
    world.applyLinearImpulse(ids[2], { x: 0.1, y: 0 }, world.getPosition(ids[2]))
    expect(world.isAwake(ids[1])).toBe(true)
    expect(world.isAwake(ids[2])).toBe(true)
  })
})
