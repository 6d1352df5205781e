/*
 * Chains in a world: the API (static only, one shape id per segment, sensors and filters, events,
 * destroy, save and load), and the physics they exist for. Oracles: the sliding-friction closed form
 * v(t) = v0 - mu g t for a box crossing 72 joins of a 200-segment floor (no bounce, no spin); energy
 * conservation for a ball rolling down a chain curve (v = sqrt(4 g h / 3) for a disc); the
 * one-sided rule (a body from the back passes through, one from the front lands); and a car-shaped
 * compound at 50 m/s that never ends up under the terrain (the polyline's height at its x).
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  type ChainShape,
  chain,
  circle,
  createWorld,
  loadWorld,
  segment,
  type Vec2,
  type World,
  WorldLoadError,
} from '../../engine/index.ts'
import { SETTINGS_NUMBERS } from '../../engine/world/world-store.ts'

/** A flat floor at y = 0 from x = right to x = left, 1 m segments (right to left: normal up). */
function flatFloor(right: number, left: number): Vec2[] {
  const points: Vec2[] = []
  for (let x = right; x >= left; x--) points.push({ x, y: 0 })
  return points
}

/** The chain's height at x (its points run right to left), or -Infinity outside it. */
function heightAt(points: readonly Vec2[], x: number): number {
  for (let i = 0; i + 1 < points.length; i++) {
    const a = points[i]
    const b = points[i + 1]
    if (a.x >= x && x >= b.x) return a.y + ((b.y - a.y) * (x - a.x)) / (b.x - a.x)
  }
  return Number.NEGATIVE_INFINITY
}

describe('chains in the world API', () => {
  it('one shape per segment with consecutive ids; createShape returns the first', () => {
    const world = createWorld()
    const floor = chain(flatFloor(10, -10))
    const ground = world.createBody({
      type: 'static',
      shapes: [{ shape: box(1, 1) }, { shape: floor, friction: 0.3 }],
    })
    const ids = world.bodyShapes(ground)
    expect(ids).toEqual(Array.from({ length: 1 + 18 }, (_, i) => i + 1))
    expect(world.getShapeGeometry(ids[1]).type).toBe('chainSegment')
    const more = world.createShape(ground, { shape: chain(flatFloor(30, 20)) })
    expect(more).toBe(20)
    expect(world.bodyShapes(ground).length).toBe(19 + 8)
    // The shorthand `shape:` works too (typed for one shape; a chain is accepted at run time).
    const other = world.createBody({ type: 'static', shape: floor as unknown as ReturnType<typeof box> })
    expect(world.bodyShapes(other).length).toBe(18)
  })

  it('static bodies only, never a sensor: clear RangeErrors', () => {
    const world = createWorld()
    const floor = chain(flatFloor(5, -5))
    expect(() => world.createBody({ shapes: [{ shape: box(1, 1) }, { shape: floor }] })).toThrow(
      /chain shapes are for static bodies only: the body is dynamic/,
    )
    expect(() => world.createBody({ type: 'kinematic', shapes: [{ shape: floor }] })).toThrow(
      /static bodies only: the body is kinematic/,
    )
    const dyn = world.createBody({ shape: box(1, 1) })
    expect(() => world.createShape(dyn, { shape: floor })).toThrow(/static bodies only: body 1 is dynamic/)
    expect(world.bodyShapes(dyn).length).toBe(1)
    const ground = world.createBody({ type: 'static', shapes: [{ shape: floor }, { shape: box(1, 1) }] })
    expect(() => world.setBodyType(ground, 'dynamic')).toThrow(
      /static bodies only: body 2, which has a chain, is dynamic/,
    )
    expect(() => world.createBody({ type: 'static', shapes: [{ shape: floor, sensor: true }] })).toThrow(
      /a chain cannot be a sensor/,
    )
    expect(() => world.createShape(ground, { shape: { type: 'chain' } as unknown as ChainShape })).toThrow(
      /a chain shape must be made by chain\(\)/,
    )
  })

  it('a ball lands on the chain: contact begin events name the segment; destroying that segment drops it', () => {
    const world = createWorld({ enableSleep: false })
    const ground = world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(5, -5)) }] })
    const ball = world.createBody({ position: { x: 0.5, y: 1 }, shape: circle(0.25) })
    const ballShape = world.bodyShapes(ball)[0]
    const begun: number[] = []
    for (let i = 0; i < 60; i++) {
      world.step()
      for (const e of world.contactEvents().begin) begun.push(e.shapeA === ballShape ? e.shapeB : e.shapeA)
    }
    // Segment k runs from x = 4 - k to 3 - k: x = 0.5 lies on segment 3 (shape id 4).
    expect(begun).toEqual([4])
    expect(world.getPosition(ball).y).toBeCloseTo(0.25, 2)
    world.destroyShape(4)
    expect(world.bodyShapes(ground)).not.toContain(4)
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getPosition(ball).y).toBeLessThan(-1)
  })

  it('filters: a chain whose mask leaves out a category lets those bodies fall through', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({
      type: 'static',
      shapes: [{ shape: chain(flatFloor(5, -5)), filter: { categoryBits: 1, maskBits: 1, groupIndex: 0 } }],
    })
    const kept = world.createBody({ position: { x: -1, y: 1 }, shape: circle(0.25) })
    const passing = world.createBody({
      position: { x: 1, y: 1 },
      shapes: [{ shape: circle(0.25), filter: { categoryBits: 2, maskBits: 0xffffffff, groupIndex: 0 } }],
    })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.getPosition(kept).y).toBeCloseTo(0.25, 2)
    expect(world.getPosition(passing).y).toBeLessThan(-1)
  })

  it('a sensor sees the chain segments it overlaps as visitors', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(5, -5)) }] })
    const probe = world.createBody({
      type: 'kinematic',
      position: { x: 0.5, y: 0 },
      shapes: [{ shape: box(0.8, 0.2), sensor: true }],
    })
    world.step()
    const sensor = world.bodyShapes(probe)[0]
    // The box spans x in [-0.3, 1.3]: segments 2 (x in [1, 2]) and 3 ([0, 1]) and 4 ([-1, 0]).
    expect(world.sensorEvents().begin).toEqual([
      { sensor, visitor: 3 },
      { sensor, visitor: 4 },
      { sensor, visitor: 5 },
    ])
  })

  it('save and load keep the segments, ghosts included: the run continues bit-identically', () => {
    const world = createWorld()
    const points = [
      { x: 6, y: 2 },
      { x: 4, y: 1 },
      { x: 2, y: 0 },
      { x: 0, y: -0.2 },
      { x: -2, y: 0 },
      { x: -4, y: 1 },
      { x: -6, y: 2 },
    ]
    world.createBody({ type: 'static', shapes: [{ shape: chain(points), friction: 0.4 }] })
    world.createBody({ position: { x: 3, y: 2 }, shape: box(0.3, 0.2), angularVelocity: 2 })
    world.createBody({ position: { x: -3, y: 2 }, shape: circle(0.3) })
    for (let i = 0; i < 50; i++) world.step()
    const copy = loadWorld(world.save())
    expect(copy.hash()).toBe(world.hash())
    expect(copy.getShapeGeometry(3)).toEqual(world.getShapeGeometry(3))
    for (let i = 0; i < 200; i++) {
      world.step()
      copy.step()
      expect(copy.hash()).toBe(world.hash())
    }
  })
})

/** Steps until `done` or `steps` run out, calling `check` after each step. */
function run(world: World, steps: number, check: (step: number) => boolean | undefined): void {
  for (let i = 1; i <= steps; i++) {
    world.step()
    if (check(i) === true) return
  }
}

describe('chains in motion', () => {
  it('a box slides over 72 joins of a 200-segment floor: no bounce, no spin, speed = v0 - mu g t', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(101, -101)), friction: 0.1 }] })
    const v0 = 12
    const mu = 0.1
    const b = world.createBody({
      position: { x: -90.3, y: 0.5 },
      shape: box(0.5, 0.5),
      friction: 0.1,
      linearVelocity: { x: v0, y: 0 },
    })
    let worstVy = 0
    let worstW = 0
    let worstY = 0
    let worstSpeed = 0
    run(world, 11 * 60, (i) => {
      const v = world.getLinearVelocity(b)
      worstVy = Math.max(worstVy, Math.abs(v.y))
      worstW = Math.max(worstW, Math.abs(world.getAngularVelocity(b)))
      worstY = Math.max(worstY, Math.abs(world.getPosition(b).y - 0.5))
      // The closed form from the second step on (the first step lands the box's contact).
      if (i > 1) worstSpeed = Math.max(worstSpeed, Math.abs(v.x - (v0 - mu * 10 * (i / 60))))
      return undefined
    })
    const travelled = world.getPosition(b).x + 90.3
    expect(travelled).toBeGreaterThan(71)
    expect(worstVy).toBeLessThan(0.01)
    expect(worstW).toBeLessThan(0.01)
    expect(worstY).toBeLessThan(0.005)
    expect(worstSpeed).toBeLessThan(0.02)
  })

  it('a ball rolls down a chain curve: speed at the bottom = sqrt(4 g h / 3) within 1 %', () => {
    const world = createWorld({ enableSleep: false })
    // A quarter-cosine drop of 5 m over 12 m (steepest 33 degrees), then flat; right to left.
    const h = 5
    const points: Vec2[] = []
    for (let i = 0; i <= 120; i++) {
      const x = 12 - 0.1 * i
      points.push({ x, y: h * 0.5 * (1 - Math.cos((Math.PI * x) / 12)) })
    }
    for (let x = -1; x >= -40; x--) points.push({ x, y: 0 })
    world.createBody({ type: 'static', shapes: [{ shape: chain(points), friction: 0.8 }] })
    const r = 0.3
    const ball = world.createBody({
      position: { x: 11.9, y: h + r - 0.0002 },
      shape: circle(r),
      friction: 0.8,
    })
    // Nudge it over the crest.
    world.setLinearVelocity(ball, { x: -0.05, y: 0 })
    let speed = 0
    run(world, 20 * 60, () => {
      if (world.getPosition(ball).x > -5) return undefined
      const v = world.getLinearVelocity(ball)
      speed = Math.hypot(v.x, v.y)
      return true
    })
    const expected = Math.sqrt((4 * 10 * h) / 3 + 0.05 * 0.05)
    expect(speed).toBeGreaterThan(0)
    expect(Math.abs(speed - expected) / expected).toBeLessThan(0.01)
  })

  it('one-sided: a ball thrown up through the floor from below passes, then lands on it from above', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(5, -5)) }] })
    const ball = world.createBody({
      position: { x: 0.3, y: -2 },
      shape: circle(0.25),
      linearVelocity: { x: 0, y: 9 },
    })
    let highest = Number.NEGATIVE_INFINITY
    run(world, 240, () => {
      highest = Math.max(highest, world.getPosition(ball).y)
      return undefined
    })
    // 9 m/s from -2 m rises 4.05 m to about 2.05 m, through the floor untouched.
    expect(highest).toBeGreaterThan(2)
    expect(world.getPosition(ball).y).toBeCloseTo(0.25, 2)
    // A two-sided segment of the same line stops it from below (the contrast).
    const other = createWorld({ enableSleep: false })
    other.createBody({ type: 'static', shape: segment({ x: 5, y: 0 }, { x: -5, y: 0 }) })
    const stopped = other.createBody({
      position: { x: 0.3, y: -2 },
      shape: circle(0.25),
      linearVelocity: { x: 0, y: 9 },
    })
    let top = Number.NEGATIVE_INFINITY
    run(other, 60, () => {
      top = Math.max(top, other.getPosition(stopped).y)
      return undefined
    })
    expect(top).toBeLessThan(0)
  })

  it('one-sided for a bullet box too: from behind at 40 m/s it passes (continuous collision skips the back side)', () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(5, -5)) }] })
    const b = world.createBody({
      position: { x: 0.3, y: -3 },
      shape: box(0.2, 0.2),
      bullet: true,
      linearVelocity: { x: 0, y: 40 },
    })
    run(world, 30, () => undefined)
    expect(world.getPosition(b).y).toBeGreaterThan(10)
    // From the front it is stopped at the floor.
    const c = world.createBody({
      position: { x: -0.3, y: 3 },
      shape: box(0.2, 0.2),
      bullet: true,
      linearVelocity: { x: 0, y: -40 },
    })
    run(world, 30, () => undefined)
    expect(world.getPosition(c).y).toBeGreaterThan(0.15)
  })

  it('a car (box chassis and two wheels, one compound, bullet) at 50 m/s on a chain terrain never ends up under it', () => {
    const world = createWorld({ enableSleep: false })
    // Rolling hills right to left: 300 segments of 1 m, heights 0..3 m.
    const points: Vec2[] = []
    for (let i = 0; i <= 302; i++) {
      const x = 150 - i
      points.push({ x, y: 1.5 + 1.5 * Math.sin(x * 0.21) * Math.cos(x * 0.053) })
    }
    world.createBody({ type: 'static', shapes: [{ shape: chain(points), friction: 0.7 }] })
    const car = world.createBody({
      position: { x: -140, y: 6 },
      bullet: true,
      linearVelocity: { x: 30, y: -40 },
      shapes: [
        { shape: box(1.0, 0.25, { x: 0, y: 0.4 }), density: 2 },
        { shape: circle(0.35, { x: -0.75, y: 0 }) },
        { shape: circle(0.35, { x: 0.75, y: 0 }) },
      ],
    })
    let worst = Number.POSITIVE_INFINITY
    let touching = 0
    run(world, 4 * 60, () => {
      const p = world.getPosition(car)
      // Driven at 50 m/s, 30 degrees down into the terrain, every step (what a contact took away
      // is given back): every shape's centre must stay above the polyline.
      world.setLinearVelocity(car, { x: 50 * Math.cos(Math.PI / 6), y: -50 * Math.sin(Math.PI / 6) })
      if (world.contacts().length > 0) touching++
      const angle = world.getAngle(car)
      for (const local of [
        { x: 0, y: 0.4 },
        { x: -0.75, y: 0 },
        { x: 0.75, y: 0 },
      ]) {
        const x = p.x + Math.cos(angle) * local.x - Math.sin(angle) * local.y
        const y = p.y + Math.sin(angle) * local.x + Math.cos(angle) * local.y
        worst = Math.min(worst, y - heightAt(points, x))
      }
      return undefined
    })
    // It was on the terrain nearly all the time and made its way along it.
    expect(touching).toBeGreaterThan(200)
    expect(world.getPosition(car).x).toBeGreaterThan(-100)
    expect(worst).toBeGreaterThan(0)
  })
})

describe('a saved world with a chain, damaged', () => {
  it('a chain on a body saved as kinematic is refused with a WorldLoadError naming it', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shapes: [{ shape: chain(flatFloor(3, -3)) }] })
    const damaged = world.save().slice()
    // The first body's type byte (world-state.ts writeWorld): header 16, gravity 2 f64, sub-steps
    // u32, flags u8, the settings' f64s, tick and three id counters, the body count u32, its f64 id.
    const at = 16 + 16 + 4 + 1 + 8 * SETTINGS_NUMBERS.length + 32 + 4 + 8
    expect(damaged[at]).toBe(0)
    damaged[at] = 1
    // Re-seal the checksum (FNV-1a over the payload) so that only the content is wrong.
    let h = 0x811c9dc5
    for (let i = 16; i < damaged.length; i++) {
      h ^= damaged[i]
      h = Math.imul(h, 0x01000193)
    }
    new DataView(damaged.buffer).setUint32(12, h >>> 0, true)
    expect(() => loadWorld(damaged)).toThrow(WorldLoadError)
    expect(() => loadWorld(damaged)).toThrow('saved world has a chain on body 1, which is not static')
  })
})
