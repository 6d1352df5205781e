/*
 * Filters, sensors and events. Oracles: Box2D's filter rule written out as a truth table by hand,
 * free fall (the time a ball reaches a sensor, sqrt(2 g h) at impact), a world without the sensor
 * (a sensor never pushes: bit-identical motion), and brute-force overlap scans over every pair of
 * shapes (begin and end events are exactly the changes of the brute-force touching set).
 */
import { describe, expect, it } from 'vitest'
import { collideShapes } from '../../engine/collision/collide.ts'
import { Manifold } from '../../engine/collision/manifold.ts'
import { box, capsule, circle, polygon, segment } from '../../engine/collision/shapes.ts'
import { Prng } from '../../engine/prng.ts'
import type { Filter } from '../../engine/types.ts'
import { createWorld, loadWorld, type World } from '../../engine/world/world.ts'

describe("filtering: Box2D's category / mask / group rule", () => {
  // [filter A, filter B, collide?] worked by hand from the rule: same non-zero group -> the group's
  // sign decides; otherwise (maskA & catB) != 0 and (catA & maskB) != 0.
  const f = (categoryBits: number, maskBits: number, groupIndex = 0): Filter => ({
    categoryBits,
    maskBits,
    groupIndex,
  })
  const table: [Filter, Filter, boolean][] = [
    [f(1, 0xffffffff), f(1, 0xffffffff), true],
    [f(1, 0xfffffffe), f(1, 0xffffffff), false],
    [f(2, 0xffffffff), f(1, 0xfffffffd), false],
    [f(2, 4), f(4, 2), true],
    [f(2, 4), f(4, 1), false],
    [f(0x80000000, 1), f(1, 0x80000000), true],
    [f(1, 0, 3), f(1, 0, 3), true],
    [f(1, 0xffffffff, -3), f(1, 0xffffffff, -3), false],
    [f(1, 0xffffffff, -3), f(1, 0xffffffff, -4), true],
    [f(1, 0, 3), f(1, 0, 4), false],
    [f(1, 0xffffffff, 2), f(1, 0xffffffff, 0), true],
    [f(0, 0xffffffff), f(1, 0xffffffff), false],
  ]
  it.each(table.map((row, i) => [i, ...row] as const))('row %i', (_i, fa, fb, expected) => {
    for (const [first, second] of [
      [fa, fb],
      [fb, fa],
    ]) {
      const world = createWorld({ gravity: { x: 0, y: 0 } })
      world.createBody({ shapes: [{ shape: box(0.5, 0.5), filter: first }] })
      world.createBody({ position: { x: 0.9, y: 0 }, shapes: [{ shape: box(0.5, 0.5), filter: second }] })
      world.step()
      expect(world.contacts().length).toBe(expected ? 1 : 0)
    }
  })

  it('setFilter ends a contact at the next step, and setting it back begins it again', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    world.createBody({ shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 0.99, y: 0 }, shape: box(0.5, 0.5) })
    world.step()
    expect(world.contactEvents().begin).toEqual([{ shapeA: 1, shapeB: 2 }])
    const [shape] = world.bodyShapes(b)
    world.setFilter(shape, { categoryBits: 2, maskBits: 0xfffffffe, groupIndex: 0 })
    expect(world.getFilter(shape)).toEqual({ categoryBits: 2, maskBits: 0xfffffffe, groupIndex: 0 })
    world.step()
    expect(world.contactEvents().end).toEqual([{ shapeA: 1, shapeB: 2 }])
    expect(world.contacts()).toEqual([])
    world.setFilter(shape, { categoryBits: 1, maskBits: 0xffffffff, groupIndex: 0 })
    world.step()
    expect(world.contactEvents().begin).toEqual([{ shapeA: 1, shapeB: 2 }])
    expect(world.contacts().length).toBe(1)
  })

  it('a bad filter throws a RangeError naming the field', () => {
    const world = createWorld()
    world.createBody({ shape: box(1, 1) })
    expect(() => world.setFilter(1, { categoryBits: 1, maskBits: 2 ** 32, groupIndex: 0 })).toThrow(
      /maskBits/,
    )
    expect(() => world.setFilter(1, { categoryBits: 1, maskBits: 1, groupIndex: 0.5 })).toThrow(/groupIndex/)
    expect(() => world.setFilter(9, { categoryBits: 1, maskBits: 1, groupIndex: 0 })).toThrow(
      /no shape with id 9/,
    )
  })
})

describe('sensors', () => {
  function dropThroughSensor(withSensor: boolean): { world: World; ball: number; log: string[] } {
    const world = createWorld()
    if (withSensor)
      world.createBody({
        type: 'static',
        position: { x: 0, y: 5 },
        shapes: [{ shape: box(2, 0.5), sensor: true }],
      })
    const ball = world.createBody({ position: { x: 0, y: 10 }, shape: circle(0.25) })
    const log: string[] = []
    for (let i = 0; i < 120; i++) {
      world.step()
      const e = world.sensorEvents()
      for (const b of e.begin) log.push(`begin ${b.sensor} ${b.visitor} @${world.tick}`)
      for (const b of e.end) log.push(`end ${b.sensor} ${b.visitor} @${world.tick}`)
    }
    return { world, ball, log }
  }

  it('a ball falling through a sensor gets exactly one begin and one end, when free fall says, and is never pushed', () => {
    const { world, ball, log } = dropThroughSensor(true)
    const free = dropThroughSensor(false)
    expect(world.getPosition(ball)).toEqual(free.world.getPosition(free.ball))
    expect(log.length).toBe(2)
    // The ball's bottom (10 - 0.25) reaches the sensor top (5.5) after falling 4.25 m, and its top
    // (10 + 0.25) leaves the sensor bottom (4.5) after 5.75 m: t = sqrt(2 d / g). The step ends
    // integrate semi-implicitly (a fall of g h^2 n (n + 1) / 2 after n steps), so allow one step.
    const stepOf = (d: number) => Math.sqrt((2 * d) / 10) * 60
    const beginTick = Number(log[0].split('@')[1])
    const endTick = Number(log[1].split('@')[1])
    expect(log[0].startsWith('begin 1 2')).toBe(true)
    expect(log[1].startsWith('end 1 2')).toBe(true)
    expect(Math.abs(beginTick - stepOf(4.25))).toBeLessThan(1.5)
    expect(Math.abs(endTick - stepOf(5.75))).toBeLessThan(1.5)
  })

  it('shapes without enableSensorEvents, other sensors and filtered shapes are not seen', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    world.createBody({
      type: 'static',
      shapes: [
        { shape: box(3, 3), sensor: true, filter: { categoryBits: 1, maskBits: 0xfffffffd, groupIndex: 0 } },
      ],
    })
    world.createBody({ shapes: [{ shape: circle(0.2), enableSensorEvents: false }] })
    world.createBody({ position: { x: 1, y: 0 }, shapes: [{ shape: circle(0.2), sensor: true }] })
    world.createBody({
      position: { x: -1, y: 0 },
      shapes: [{ shape: circle(0.2), filter: { categoryBits: 2, maskBits: 0xffffffff, groupIndex: 0 } }],
    })
    world.createBody({
      position: { x: 0, y: 1 },
      shapes: [{ shape: capsule({ x: 0, y: 0 }, { x: 0.5, y: 0 }, 0.1) }],
    })
    world.step()
    expect(world.sensorEvents().begin).toEqual([{ sensor: 1, visitor: 5 }])
  })
})

describe('contact events', () => {
  it('a ball dropped from 2 m hits the ground once at sqrt(2 g h) within 1 %', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shapes: [{ shape: segment({ x: -5, y: 0 }, { x: 5, y: 0 }) }] })
    world.createBody({
      position: { x: 0, y: 2.25 },
      shapes: [{ shape: circle(0.25), enableHitEvents: true }],
    })
    const hits: { speed: number; nx: number; ny: number; y: number }[] = []
    let begins = 0
    for (let i = 0; i < 120; i++) {
      world.step()
      const e = world.contactEvents()
      begins += e.begin.length
      for (const h of e.hit)
        hits.push({ speed: h.approachSpeed, nx: h.normal.x, ny: h.normal.y, y: h.point.y })
    }
    expect(begins).toBe(1)
    expect(hits.length).toBe(1)
    const expected = Math.sqrt(2 * 10 * 2)
    expect(Math.abs(hits[0].speed - expected) / expected).toBeLessThan(0.01)
    expect(hits[0].ny).toBeCloseTo(1, 12)
    expect(Math.abs(hits[0].y)).toBeLessThan(0.03)
  })

  it('begin and end events are exactly the changes of a brute-force touching scan, and sensor events of a brute-force overlap scan, over 600 steps of a pile (saved and reloaded midway)', () => {
    let world = createWorld({ enableSleep: false })
    world.createBody({
      type: 'static',
      shapes: [
        { shape: segment({ x: -6, y: 0 }, { x: 6, y: 0 }) },
        { shape: box(0.2, 4, { x: -6, y: 4 }) },
        { shape: box(0.2, 4, { x: 6, y: 4 }) },
        { shape: box(1.5, 0.75, { x: 2, y: 1 }), sensor: true },
      ],
    })
    world.createBody({
      type: 'kinematic',
      angularVelocity: 1,
      position: { x: -2, y: 2 },
      shapes: [{ shape: capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.3), sensor: true }],
    })
    const rng = new Prng(11)
    for (let i = 0; i < 36; i++) {
      const kind = i % 4
      const shape =
        kind === 0
          ? circle(rng.range(0.15, 0.35))
          : kind === 1
            ? box(rng.range(0.15, 0.35), rng.range(0.15, 0.35))
            : kind === 2
              ? capsule({ x: -0.25, y: 0 }, { x: 0.25, y: 0 }, 0.15)
              : polygon(
                  [
                    { x: -0.3, y: -0.25 },
                    { x: 0.3, y: -0.25 },
                    { x: 0, y: 0.3 },
                  ],
                  0.05,
                )
      world.createBody({
        position: { x: rng.range(-5, 5), y: 1 + 0.5 * i },
        angle: rng.range(-3, 3),
        shapes: [{ shape }],
      })
    }
    const m = new Manifold()
    const scan = (spec: number, sensors: boolean): Set<string> => {
      const out = new Set<string>()
      const ids = world.bodyIds()
      for (let i = 0; i < ids.length; i++) {
        for (let j = 0; j < ids.length; j++) {
          if (i === j || (!sensors && j < i)) continue
          const a = ids[i]
          const b = ids[j]
          if (!sensors && world.getBodyType(a) !== 'dynamic' && world.getBodyType(b) !== 'dynamic') continue
          const pa = world.getPosition(a)
          const pb = world.getPosition(b)
          const ra = world.getRotation(a)
          const rb = world.getRotation(b)
          for (const sa of world.bodyShapes(a)) {
            for (const sb of world.bodyShapes(b)) {
              const aSensor = sa === 4 || sa === 5
              const bSensor = sb === 4 || sb === 5
              if (sensors ? !aSensor || bSensor : aSensor || bSensor) continue
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
                spec,
                m,
              )
              if (m.pointCount > 0) out.add(sensors ? `${sa}-${sb}` : sa < sb ? `${sa}-${sb}` : `${sb}-${sa}`)
            }
          }
        }
      }
      return out
    }
    let touching = new Set<string>()
    let seen = new Set<string>()
    let begins = 0
    let sensorBegins = 0
    for (let step = 0; step < 600; step++) {
      if (step === 300) world = loadWorld(world.save())
      const now = scan(0.02, false)
      world.step()
      const e = world.contactEvents()
      const began = e.begin.map((p) => `${p.shapeA}-${p.shapeB}`)
      const ended = e.end.map((p) => `${p.shapeA}-${p.shapeB}`)
      expect(began, `begin at step ${step}`).toEqual([...now].filter((k) => !touching.has(k)).sort(byPair))
      expect(ended, `end at step ${step}`).toEqual([...touching].filter((k) => !now.has(k)).sort(byPair))
      begins += began.length
      touching = now
      const inside = scan(0, true)
      const s = world.sensorEvents()
      expect(
        s.begin.map((p) => `${p.sensor}-${p.visitor}`),
        `sensor begin at ${step}`,
      ).toEqual([...inside].filter((k) => !seen.has(k)).sort(byPair))
      expect(
        s.end.map((p) => `${p.sensor}-${p.visitor}`),
        `sensor end at ${step}`,
      ).toEqual([...seen].filter((k) => !inside.has(k)).sort(byPair))
      sensorBegins += s.begin.length
      seen = inside
    }
    expect(begins).toBeGreaterThan(50)
    expect(sensorBegins).toBeGreaterThan(10)
  })
})

function byPair(p: string, q: string): number {
  const [a, b] = p.split('-').map(Number)
  const [c, d] = q.split('-').map(Number)
  return a - c || b - d
}
