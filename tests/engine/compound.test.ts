/*
 * Compound bodies: a body owns any number of shapes. Oracles: the parallel-axis theorem worked by
 * hand, a brute-force narrowphase over every pair of shapes on different bodies (no broadphase),
 * and save/load against the uninterrupted run.
 */
import { describe, expect, it } from 'vitest'
import { collideShapes } from '../../engine/collision/collide.ts'
import { Manifold } from '../../engine/collision/manifold.ts'
import { box, capsule, circle, polygon, segment } from '../../engine/collision/shapes.ts'
import { PI } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { SAVE_FORMAT_VERSION, WorldLoadError } from '../../engine/world/save-format.ts'
import { createWorld, loadWorld, type World } from '../../engine/world/world.ts'

/** A dumbbell: two discs (r 0.3 at x = +-0.8) on a 1.6 x 0.2 bar. */
function dumbbell(world: World, x: number, y: number, angle = 0): number {
  return world.createBody({
    position: { x, y },
    angle,
    shapes: [
      { shape: circle(0.3, { x: -0.8, y: 0 }), density: 2 },
      { shape: box(0.8, 0.1), density: 1 },
      { shape: circle(0.3, { x: 0.8, y: 0 }), density: 2 },
    ],
  })
}

describe('compound bodies', () => {
  it('shape ids are handed out in creation order and never reused; bodyShapes lists them', () => {
    const world = createWorld()
    const ground = world.createBody({ type: 'static', shape: box(10, 0.5) })
    const a = dumbbell(world, 0, 2)
    expect(world.bodyShapes(ground)).toEqual([1])
    expect(world.bodyShapes(a)).toEqual([2, 3, 4])
    const extra = world.createShape(a, { shape: capsule({ x: 0, y: 0 }, { x: 0, y: 0.5 }, 0.1) })
    expect(extra).toBe(5)
    world.destroyShape(3)
    expect(world.bodyShapes(a)).toEqual([2, 4, 5])
    expect(world.createShape(a, { shape: circle(0.1) })).toBe(6)
    expect(world.getShapeBody(6)).toBe(a)
    expect(() => world.destroyShape(3)).toThrow(/no shape with id 3/)
  })

  it("mass, centre and inertia are the shapes' sums by the parallel-axis theorem (by hand)", () => {
    const world = createWorld()
    // A 2 x 1 box (density 1) at the origin and a disc r 0.5 (density 2) centred at (2, 0).
    const id = world.createBody({
      position: { x: 1, y: 3 },
      shapes: [{ shape: box(1, 0.5) }, { shape: circle(0.5, { x: 2, y: 0 }), density: 2 }],
    })
    const mBox = 2
    const mDisc = 2 * PI * 0.25
    const m = mBox + mDisc
    const cx = (2 * mDisc) / m
    const inertia = (mBox * (1 + 0.25)) / 3 + mBox * cx * cx + 0.5 * mDisc * 0.25 + mDisc * (2 - cx) ** 2
    expect(world.getMass(id)).toBeCloseTo(m, 12)
    expect(world.getInertia(id)).toBeCloseTo(inertia, 12)
    expect(world.getWorldCenter(id).x).toBeCloseTo(1 + cx, 12)
    expect(world.getWorldCenter(id).y).toBeCloseTo(3, 12)
  })

  it('createShape and destroyShape re-mass the body; its origin stays put', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const both = world.createBody({
      shapes: [{ shape: box(1, 0.5) }, { shape: circle(0.5, { x: 2, y: 0 }) }],
    })
    const grown = world.createBody({ position: { x: 10, y: 0 }, shape: box(1, 0.5) })
    const s = world.createShape(grown, { shape: circle(0.5, { x: 2, y: 0 }) })
    expect(world.getMass(grown)).toBeCloseTo(world.getMass(both), 12)
    expect(world.getInertia(grown)).toBeCloseTo(world.getInertia(both), 12)
    expect(world.getWorldCenter(grown).x - 10).toBeCloseTo(world.getWorldCenter(both).x, 12)
    expect(world.getPosition(grown)).toEqual({ x: 10, y: 0 })
    world.destroyShape(s)
    expect(world.getMass(grown)).toBeCloseTo(2, 12)
    expect(world.getWorldCenter(grown).x).toBeCloseTo(10, 12)
    // The last shape with mass of a dynamic body cannot go; a segment cannot carry it alone.
    const only = world.bodyShapes(grown)[0]
    expect(() => world.destroyShape(only)).toThrow(/last shape with mass/)
    world.createShape(grown, { shape: segment({ x: 0, y: 0 }, { x: 1, y: 1 }) })
    expect(() => world.destroyShape(only)).toThrow(/last shape with mass/)
  })

  it('shapes of one body never collide with each other (overlapping parts stay still)', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const id = world.createBody({ shapes: [{ shape: box(1, 1) }, { shape: circle(0.8, { x: 0.5, y: 0 }) }] })
    for (let i = 0; i < 60; i++) world.step()
    expect(world.getLinearVelocity(id)).toEqual({ x: 0, y: 0 })
    expect(world.contacts()).toEqual([])
  })

  it('a dumbbell lying on the ground rests on both discs: two contacts with the ground, one per disc', () => {
    const world = createWorld()
    const ground = world.createBody({ type: 'static', shape: box(10, 0.5), friction: 0.6 })
    const id = dumbbell(world, 0, 0.5 + 0.3 + 0.05)
    for (let i = 0; i < 120; i++) world.step()
    const touching = world.contacts().filter((c) => c.bodyA === ground || c.bodyB === ground)
    expect(touching.length).toBe(2)
    expect(touching.map((c) => c.shapeB).sort()).toEqual([2, 4])
    for (const c of touching) expect(c.shapeA).toBe(1)
    expect(world.getPosition(id).y).toBeGreaterThan(0.8 - 0.01)
    expect(world.getPosition(id).y).toBeLessThan(0.8 + 0.001)
    expect(Math.abs(world.getAngle(id))).toBeLessThan(1e-6)
  })

  it('touching shape pairs equal a brute-force narrowphase over all shape pairs, over 300 steps of a compound pile', () => {
    // The narrowphase runs at the start of a step, on the poses the last step left: the oracle
    // collides every pair of shapes on different bodies at those poses, then the step runs.
    const world = createWorld({ enableSleep: false })
    world.createBody({ type: 'static', shape: segment({ x: -6, y: 0 }, { x: 6, y: 0 }) })
    world.createBody({
      type: 'static',
      shapes: [{ shape: box(0.2, 3, { x: -6, y: 3 }) }, { shape: box(0.2, 3, { x: 6, y: 3 }) }],
    })
    const rng = new Prng(7)
    for (let i = 0; i < 40; i++) {
      const x = rng.range(-4.5, 4.5)
      const y = 1 + 0.9 * i
      const angle = rng.range(-3, 3)
      if (i % 3 === 0) dumbbell(world, x, y, angle)
      else if (i % 3 === 1)
        world.createBody({
          position: { x, y },
          angle,
          shapes: [
            { shape: capsule({ x: -0.4, y: 0 }, { x: 0.4, y: 0 }, 0.15) },
            { shape: box(0.1, 0.4, { x: 0.4, y: 0.2 }) },
          ],
        })
      else
        world.createBody({
          position: { x, y },
          angle,
          shapes: [
            {
              shape: polygon(
                [
                  { x: -0.3, y: -0.3 },
                  { x: 0.3, y: -0.3 },
                  { x: 0, y: 0.3 },
                ],
                0.05,
              ),
            },
            { shape: circle(0.2, { x: 0, y: 0.5 }) },
          ],
        })
    }
    const m = new Manifold()
    let checked = 0
    for (let step = 0; step < 300; step++) {
      if (step % 30 !== 29) {
        world.step()
        continue
      }
      const expected = new Set<string>()
      const ids = world.bodyIds()
      for (let i = 0; i < ids.length; i++) {
        for (let j = i + 1; j < ids.length; j++) {
          const a = ids[i]
          const b = ids[j]
          if (world.getBodyType(a) !== 'dynamic' && world.getBodyType(b) !== 'dynamic') continue
          const pa = world.getPosition(a)
          const pb = world.getPosition(b)
          const ra = world.getRotation(a)
          const rb = world.getRotation(b)
          for (const sa of world.bodyShapes(a)) {
            for (const sb of world.bodyShapes(b)) {
              collideShapes(
                world.getShapeGeometry(sa),
                pa.x,
                pa.y,
                ra.c,
                ra.s,
                world.getShapeGeometry(sb),
                pb.x,
                pb.y,
                rb.c,
                rb.s,
                0.02,
                m,
              )
              if (m.pointCount > 0) expected.add(sa < sb ? `${sa}-${sb}` : `${sb}-${sa}`)
            }
          }
        }
      }
      world.step()
      const reported = new Set(world.contacts().map((c) => `${c.shapeA}-${c.shapeB}`))
      expect([...reported].sort(), `step ${step}`).toEqual([...expected].sort())
      checked += expected.size
    }
    expect(checked).toBeGreaterThan(100)
  })

  it('saved mid-run, a compound pile continues bit for bit; shape ids continue after load', () => {
    const world = createWorld()
    world.createBody({
      type: 'static',
      shapes: [{ shape: segment({ x: -5, y: 0 }, { x: 5, y: 0 }) }, { shape: box(0.2, 2, { x: 5, y: 2 }) }],
    })
    for (let i = 0; i < 12; i++) dumbbell(world, -3 + 0.5 * i, 1 + 0.7 * i, 0.3 * i)
    for (let i = 0; i < 90; i++) world.step()
    const loaded = loadWorld(world.save())
    expect(loaded.hash()).toBe(world.hash())
    for (let i = 0; i < 120; i++) {
      world.step()
      loaded.step()
      expect(loaded.hash(), `step ${i}`).toBe(world.hash())
    }
    expect(loaded.createShape(loaded.bodyIds()[3], { shape: circle(0.1) })).toBe(
      world.createShape(world.bodyIds()[3], { shape: circle(0.1) }),
    )
  })

  it(`saves of format versions 1 to 3 are refused with one line naming them and ${SAVE_FORMAT_VERSION}`, () => {
    expect(SAVE_FORMAT_VERSION).toBe(4)
    for (const version of [1, 2, 3]) {
      const world = createWorld()
      world.createBody({ shape: box(1, 1) })
      const bytes = world.save()
      new DataView(bytes.buffer).setUint16(4, version, true)
      let message = ''
      try {
        loadWorld(bytes)
      } catch (e) {
        expect(e).toBeInstanceOf(WorldLoadError)
        message = (e as Error).message
      }
      expect(message).toBe(`saved world has format version ${version}; this engine reads version 4`)
    }
  })

  it('bad compound definitions throw a RangeError naming the problem', () => {
    const world = createWorld()
    expect(() => world.createBody({ shapes: [] })).toThrow(/1 to 1024/)
    expect(() => world.createBody({ shapes: [{ shape: segment({ x: 0, y: 0 }, { x: 1, y: 0 }) }] })).toThrow(
      /mass/,
    )
    expect(() => world.createBody({ shapes: [{ shape: box(1, 1), density: -1 }] })).toThrow(/density/)
    expect(() =>
      world.createBody({
        shapes: [{ shape: box(1, 1), filter: { categoryBits: 1.5, maskBits: 1, groupIndex: 0 } }],
      }),
    ).toThrow(/categoryBits/)
    expect(() => world.createShape(99, { shape: box(1, 1) })).toThrow(/no body with id 99/)
    expect(world.bodyCount).toBe(0)
  })
})
