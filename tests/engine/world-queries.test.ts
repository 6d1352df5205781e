/*
 * The world queries (engine/queries/world-queries.ts) against brute force over a random world of 1,000
 * shapes on 300 bodies (circles, capsules, polygons, rounded polygons, segments, chain segments;
 * random filters; some sensors): every shape is moved into the world frame by the test (so the
 * queries' own frame changes are checked), and each query is answered by a loop over all shapes
 * with independent tests (point-in-shape by distance formulas, tight boxes, casts in the world
 * frame). The tree is a DynamicTree with one fat leaf per shape, as Box2D's broadphase keeps it.
 */
import { describe, expect, it } from 'vitest'
import { IdBuffer } from '../../engine/collision/broad-phase.ts'
import { DynamicTree } from '../../engine/collision/dynamic-tree.ts'
import type { Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { makeCastOutput, type RayCastInput } from '../../engine/queries/ray-cast.ts'
import { shapeCast } from '../../engine/queries/shape-cast.ts'
import {
  circleProxy,
  IDENTITY,
  makeDistanceOutput,
  makeShapeProxy,
  type ShapeProxy,
  shapeDistance,
  type Transform,
} from '../../engine/queries/shape-distance.ts'
import {
  castGeometry,
  DEFAULT_QUERY_FILTER,
  makeRayHit,
  proxyOf,
  type QueryFilter,
  type QueryGeometry,
  type QueryWorld,
  RayHitList,
  shouldQueryShape,
  WorldQueries,
} from '../../engine/queries/world-queries.ts'

interface TestShape {
  id: number
  body: number
  local: QueryGeometry
  world: QueryGeometry
  filter: QueryFilter
  sensor: boolean
}

const apply = (t: Transform, p: Vec2): Vec2 => ({
  x: t.x + t.c * p.x - t.s * p.y,
  y: t.y + t.s * p.x + t.c * p.y,
})
const rotate = (t: Transform, p: Vec2): Vec2 => ({ x: t.c * p.x - t.s * p.y, y: t.s * p.x + t.c * p.y })

function toWorld(g: QueryGeometry, t: Transform): QueryGeometry {
  switch (g.type) {
    case 'circle':
      return { type: 'circle', center: apply(t, g.center), radius: g.radius }
    case 'capsule':
      return { type: 'capsule', center1: apply(t, g.center1), center2: apply(t, g.center2), radius: g.radius }
    case 'polygon':
      return {
        type: 'polygon',
        vertices: g.vertices.map((v) => apply(t, v)),
        normals: g.normals.map((n) => rotate(t, n)),
        count: g.count,
        radius: g.radius,
      }
    case 'segment':
      return { type: 'segment', point1: apply(t, g.point1), point2: apply(t, g.point2) }
    default:
      return {
        type: 'chainSegment',
        ghost1: apply(t, g.ghost1),
        segment: { point1: apply(t, g.segment.point1), point2: apply(t, g.segment.point2) },
        ghost2: apply(t, g.ghost2),
      }
  }
}

function randomPolygon(rng: Prng, radius: number): QueryGeometry {
  // A random convex polygon: points on an ellipse at sorted random angles (3..8).
  const n = 3 + rng.int(6)
  const a = rng.range(0.3, 1.2)
  const b = rng.range(0.3, 1.2)
  const cx = rng.range(-0.5, 0.5)
  const cy = rng.range(-0.5, 0.5)
  const angles = Array.from({ length: n }, (_, i) => ((i + rng.range(0.2, 0.8)) * 2 * Math.PI) / n)
  const vertices = angles.map((t) => ({ x: cx + a * Math.cos(t), y: cy + b * Math.sin(t) }))
  const normals = vertices.map((v, i) => {
    const w = vertices[(i + 1) % n]
    const l = Math.hypot(w.x - v.x, w.y - v.y)
    return { x: (w.y - v.y) / l, y: -(w.x - v.x) / l }
  })
  return { type: 'polygon', vertices, normals, count: n, radius }
}

function randomGeometry(rng: Prng): QueryGeometry {
  const p = () => ({ x: rng.range(-1, 1), y: rng.range(-1, 1) })
  switch (rng.int(6)) {
    case 0:
      return { type: 'circle', center: p(), radius: rng.range(0.1, 0.8) }
    case 1:
      return { type: 'capsule', center1: p(), center2: p(), radius: rng.range(0.05, 0.5) }
    case 2:
      return randomPolygon(rng, 0)
    case 3:
      return randomPolygon(rng, rng.range(0.05, 0.3))
    case 4:
      return { type: 'segment', point1: p(), point2: p() }
    default: {
      const s = { point1: p(), point2: p() }
      return { type: 'chainSegment', ghost1: { x: -5, y: 0 }, segment: s, ghost2: { x: 5, y: 0 } }
    }
  }
}

/** Tight world box of a world-frame geometry (by hand, per kind). */
function tightBox(g: QueryGeometry): [number, number, number, number] {
  let pts: Vec2[]
  let r = 0
  switch (g.type) {
    case 'circle':
      pts = [g.center]
      r = g.radius
      break
    case 'capsule':
      pts = [g.center1, g.center2]
      r = g.radius
      break
    case 'polygon':
      pts = [...g.vertices]
      r = g.radius
      break
    case 'segment':
      pts = [g.point1, g.point2]
      break
    default:
      pts = [g.segment.point1, g.segment.point2]
  }
  return [
    Math.min(...pts.map((q) => q.x)) - r,
    Math.min(...pts.map((q) => q.y)) - r,
    Math.max(...pts.map((q) => q.x)) + r,
    Math.max(...pts.map((q) => q.y)) + r,
  ]
}

function segmentDistance(p: Vec2, a: Vec2, b: Vec2): number {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const l2 = ex * ex + ey * ey
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2)) : 0
  return Math.hypot(p.x - a.x - t * ex, p.y - a.y - t * ey)
}

/** Does the world-frame geometry contain p (boundary counts)? Independent formulas. */
function contains(g: QueryGeometry, p: Vec2): boolean {
  switch (g.type) {
    case 'circle':
      return Math.hypot(p.x - g.center.x, p.y - g.center.y) <= g.radius
    case 'capsule':
      return segmentDistance(p, g.center1, g.center2) <= g.radius
    case 'polygon': {
      let inside = true
      for (let i = 0; i < g.count; i++) {
        const v = g.vertices[i]
        if (g.normals[i].x * (p.x - v.x) + g.normals[i].y * (p.y - v.y) > 0) inside = false
      }
      if (inside) return true
      let d = Number.POSITIVE_INFINITY
      for (let i = 0; i < g.count; i++)
        d = Math.min(d, segmentDistance(p, g.vertices[i], g.vertices[(i + 1) % g.count]))
      return d <= g.radius
    }
    default:
      return false // zero thickness: a random point is never on it
  }
}

function buildWorld(seed: number): { world: QueryWorld; shapes: TestShape[] } {
  const rng = new Prng(seed)
  const bodies: Transform[] = [IDENTITY]
  const shapes: TestShape[] = []
  const tree = new DynamicTree()
  const leafShape = new Map<number, number>()
  let id = 0
  while (shapes.length < 1000) {
    const angle = rng.range(-3, 3)
    const t = { x: rng.range(-40, 40), y: rng.range(-40, 40), c: Math.cos(angle), s: Math.sin(angle) }
    bodies.push(t)
    const body = bodies.length - 1
    const count = 1 + rng.int(4)
    for (let k = 0; k < count && shapes.length < 1000; k++) {
      const local = randomGeometry(rng)
      const world = toWorld(local, t)
      const filter = {
        categoryBits: 1 << rng.int(4),
        maskBits: rng.next() < 0.8 ? 0xffffffff : 1 + rng.int(15),
      }
      const shape = { id: ++id, body, local, world, filter, sensor: rng.next() < 0.05 }
      shapes.push(shape)
      const [x0, y0, x1, y1] = tightBox(world)
      const leaf = tree.createLeaf(x0 - 0.1, y0 - 0.1, x1 + 0.1, y1 + 0.1, shape.id, 0)
      leafShape.set(leaf, shape.id)
    }
  }
  const byId = new Map(shapes.map((s) => [s.id, s]))
  const get = (shape: number) => byId.get(shape) as TestShape
  const world: QueryWorld = {
    tree,
    leafShapeCount: () => 1,
    leafShape: (leaf) => leafShape.get(leaf) as number,
    shapeGeometry: (shape) => get(shape).local,
    shapeBody: (shape) => get(shape).body,
    shapeFilter: (shape) => get(shape).filter,
    isSensor: (shape) => get(shape).sensor,
    bodyTransform: (body, out) => {
      const t = bodies[body]
      out.x = t.x
      out.y = t.y
      out.c = t.c
      out.s = t.s
    },
  }
  return { world, shapes }
}

function randomFilter(rng: Prng): QueryFilter {
  return rng.next() < 0.5
    ? DEFAULT_QUERY_FILTER
    : { categoryBits: 1 << rng.int(4), maskBits: 1 + rng.int(15) }
}

const queried = (s: TestShape, f: QueryFilter) => !s.sensor && shouldQueryShape(s.filter, f)

describe('world queries against brute force over a random 1,000-shape world', () => {
  const { world, shapes } = buildWorld(2026)
  const queries = new WorldQueries()

  it('shouldQueryShape is Box2D rule (truth table)', () => {
    const f = (categoryBits: number, maskBits: number) => ({ categoryBits, maskBits })
    expect(shouldQueryShape(f(1, 0xffffffff), f(1, 0xffffffff))).toBe(true)
    expect(shouldQueryShape(f(2, 0xffffffff), f(1, 1))).toBe(false) // shape not in query mask
    expect(shouldQueryShape(f(2, 1), f(4, 2))).toBe(false) // query not in shape mask
    expect(shouldQueryShape(f(2, 4), f(4, 2))).toBe(true)
    expect(shouldQueryShape(f(0x80000000, 0xffffffff), f(1, 0x80000000))).toBe(true) // bit 31
  })

  it('castRayClosest and castRay: closest shape, fraction, point, normal; every hit sorted (400 rays)', () => {
    const rng = new Prng(1)
    const out = makeRayHit()
    const list = new RayHitList()
    const scratch = makeCastOutput()
    let closest = 0
    let total = 0
    for (let k = 0; k < 400; k++) {
      const o = { x: rng.range(-45, 45), y: rng.range(-45, 45) }
      const input: RayCastInput = {
        origin: o,
        translation: { x: rng.range(-40, 40), y: rng.range(-40, 40) },
        maxFraction: 1,
      }
      const filter = randomFilter(rng)
      const brute: Array<{ shape: number; fraction: number; point: Vec2; normal: Vec2 }> = []
      for (const s of shapes) {
        if (!queried(s, filter)) continue
        const h = castGeometry(s.world, input, scratch)
        if (h)
          brute.push({ shape: s.id, fraction: h.fraction, point: { ...h.point }, normal: { ...h.normal } })
      }
      brute.sort((a, b) => a.fraction - b.fraction || a.shape - b.shape)
      const got = queries.castRayClosest(world, input, filter, out)
      if (brute.length === 0) {
        expect(got).toBeNull()
      } else {
        closest++
        expect(got).not.toBeNull()
        expect(Math.abs(out.fraction - brute[0].fraction)).toBeLessThan(1e-9)
        const same = brute.find((b) => b.shape === out.shape)
        expect(same, `ray ${k}`).toBeDefined()
        expect(Math.abs((same?.fraction ?? 0) - brute[0].fraction)).toBeLessThan(1e-9) // a tie at most
        expect(out.body).toBe(shapes[out.shape - 1].body)
        expect(Math.abs(out.point.x - (same?.point.x ?? 0))).toBeLessThan(1e-9)
        expect(Math.abs(out.point.y - (same?.point.y ?? 0))).toBeLessThan(1e-9)
        expect(Math.abs(out.normal.x - (same?.normal.x ?? 0))).toBeLessThan(1e-9)
        expect(Math.abs(out.normal.y - (same?.normal.y ?? 0))).toBeLessThan(1e-9)
      }
      const n = queries.castRay(world, input, filter, list)
      expect(n).toBe(brute.length)
      expect(new Set(list.hits.slice(0, n).map((h) => h.shape))).toEqual(new Set(brute.map((b) => b.shape)))
      for (let i = 0; i < n; i++) {
        const h = list.hits[i]
        const b = brute.find((x) => x.shape === h.shape)
        expect(Math.abs(h.fraction - (b?.fraction ?? -1))).toBeLessThan(1e-9)
        if (i > 0) expect(h.fraction).toBeGreaterThanOrEqual(list.hits[i - 1].fraction)
      }
      total += n
    }
    console.log(`world ray casts: ${closest} rays hit, ${total} hits in all`)
    expect(closest).toBeGreaterThan(150)
  })

  it('castShape: the closest touching shape and fraction of a moving circle, box or capsule (150 casts)', () => {
    const rng = new Prng(2)
    const out = makeRayHit()
    const worldProxy = makeShapeProxy()
    const castOut = makeCastOutput()
    let hits = 0
    for (let k = 0; k < 150; k++) {
      const moving = proxyOf(randomGeometry(rng), makeShapeProxy())
      if (moving.count === 2 && moving.radius === 0)
        circleProxy({ center: { x: 0, y: 0 }, radius: 0.3 }, moving)
      const angle = rng.range(-3, 3)
      const xf = { x: rng.range(-45, 45), y: rng.range(-45, 45), c: Math.cos(angle), s: Math.sin(angle) }
      const translation = { x: rng.range(-30, 30), y: rng.range(-30, 30) }
      const filter = randomFilter(rng)
      let best = Number.POSITIVE_INFINITY
      let bestShapes: number[] = []
      for (const s of shapes) {
        if (!queried(s, filter)) continue
        const h = shapeCast(
          {
            proxyA: proxyOf(s.world, worldProxy),
            transformA: IDENTITY,
            proxyB: moving,
            transformB: xf,
            translationB: translation,
            maxFraction: 1,
          },
          castOut,
        )
        if (!h) continue
        if (h.fraction < best - 1e-7) {
          best = h.fraction
          bestShapes = [s.id]
        } else if (h.fraction <= best + 1e-7) bestShapes.push(s.id)
      }
      const got = queries.castShape(world, moving, xf, translation, filter, out)
      if (best === Number.POSITIVE_INFINITY) {
        expect(got).toBeNull()
        continue
      }
      hits++
      expect(got, `cast ${k}`).not.toBeNull()
      expect(Math.abs(out.fraction - best) * Math.hypot(translation.x, translation.y)).toBeLessThan(1e-6)
      expect(bestShapes).toContain(out.shape)
    }
    expect(hits).toBeGreaterThan(50)
  })

  it('overlapAABB, overlapPoint and overlapShape: exactly the brute-force id lists, sorted (300 each)', () => {
    const rng = new Prng(3)
    const ids = new IdBuffer()
    const distance = makeDistanceOutput()
    const worldProxy = makeShapeProxy()
    let found = 0
    for (let k = 0; k < 300; k++) {
      const filter = randomFilter(rng)
      const x = rng.range(-45, 45)
      const y = rng.range(-45, 45)
      const aabb = { minX: x, minY: y, maxX: x + rng.range(0, 15), maxY: y + rng.range(0, 15) }
      const expectedBox = shapes
        .filter((s) => {
          if (!queried(s, filter)) return false
          const [x0, y0, x1, y1] = tightBox(s.world)
          return !(x0 > aabb.maxX || y0 > aabb.maxY || aabb.minX > x1 || aabb.minY > y1)
        })
        .map((s) => s.id)
      queries.overlapAABB(world, aabb, filter, ids)
      expect([...ids.ids.subarray(0, ids.count)]).toEqual(expectedBox)
      found += ids.count
      // Points and probes near a random shape, so that many overlap something.
      const [bx0, by0, bx1, by1] = tightBox(shapes[rng.int(shapes.length)].world)
      const p = { x: rng.range(bx0 - 0.2, bx1 + 0.2), y: rng.range(by0 - 0.2, by1 + 0.2) }
      const expectedPoint = shapes.filter((s) => queried(s, filter) && contains(s.world, p)).map((s) => s.id)
      queries.overlapPoint(world, p, filter, ids)
      expect([...ids.ids.subarray(0, ids.count)]).toEqual(expectedPoint)
      found += ids.count
      const probe = proxyOf(randomGeometry(rng), makeShapeProxy())
      const angle = rng.range(-3, 3)
      const xf = {
        x: p.x + rng.range(-1, 1),
        y: p.y + rng.range(-1, 1),
        c: Math.cos(angle),
        s: Math.sin(angle),
      }
      const expectedShape = shapes
        .filter((s) => {
          if (!queried(s, filter)) return false
          const a = proxyOf(s.world, worldProxy)
          shapeDistance(a, IDENTITY, probe, xf, false, distance)
          return distance.distance <= a.radius + probe.radius
        })
        .map((s) => s.id)
      queries.overlapShape(world, probe, xf, filter, ids)
      expect([...ids.ids.subarray(0, ids.count)]).toEqual(expectedShape)
      found += ids.count
    }
    console.log(`world overlap queries: ${found} shapes found in all`)
    expect(found).toBeGreaterThan(1000)
  })

  it('skips sensors and refuses bad input by name', () => {
    const sensor = shapes.find((s) => s.sensor) as TestShape
    const ids = new IdBuffer()
    const [x0, y0, x1, y1] = tightBox(sensor.world)
    queries.overlapAABB(world, { minX: x0, minY: y0, maxX: x1, maxY: y1 }, DEFAULT_QUERY_FILTER, ids)
    expect([...ids.ids.subarray(0, ids.count)]).not.toContain(sensor.id)
    expect(() =>
      queries.overlapAABB(world, { minX: 1, minY: 0, maxX: 0, maxY: 1 }, DEFAULT_QUERY_FILTER, ids),
    ).toThrow(/minX <= maxX/)
    expect(() => queries.overlapPoint(world, { x: Number.NaN, y: 0 }, DEFAULT_QUERY_FILTER, ids)).toThrow(
      /finite point/,
    )
    const empty: ShapeProxy = makeShapeProxy()
    expect(() => queries.overlapShape(world, empty, IDENTITY, DEFAULT_QUERY_FILTER, ids)).toThrow(
      /must have 1 to 8 points/,
    )
    expect(() =>
      queries.castRayClosest(
        world,
        { origin: { x: 0, y: 0 }, translation: { x: 1, y: 0 }, maxFraction: -1 },
        DEFAULT_QUERY_FILTER,
        makeRayHit(),
      ),
    ).toThrow(/maxFraction/)
  })
})
