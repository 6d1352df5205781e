/*
 * The World's query methods (engine/world/query-api.ts) against independent answers:
 *
 * - every shape kind on a turned, moved body: a ray and a shape cast whose answer is worked out by
 *   hand in the body's frame (fraction, point and normal), carried to the world by the body's
 *   rotation, to 1e-9;
 * - a random world of 1,000 shapes (mixed kinds, compound bodies, static, kinematic and dynamic
 *   bodies that have moved for 40 steps so their fat AABBs are not their shapes, random filters,
 *   sensors): castRayClosest, castRay, castShape, overlapAABB, overlapPoint and overlapShape against
 *   a loop over every shape with the per-shape functions (ray-cast.ts, shapeCast, shapeDistance) in
 *   the world frame, with the shapes moved there by the test;
 * - the query filter against Box2D's rule written out as a truth table (group index ignored);
 * - queries never change the state: save() bytes equal before and after, and a queried world steps
 *   bit-identically with an unqueried twin;
 * - bad arguments throw RangeErrors naming the value.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  capsule,
  circle,
  cos,
  createWorld,
  IdBuffer,
  MAX_QUERY_TRANSLATION,
  makeRayHit,
  Prng,
  polygon,
  type QueryFilterDef,
  RayHitList,
  type Shape,
  segment,
  sin,
  type World,
} from '../../engine/index.ts'
import type { Vec2 } from '../../engine/math.ts'
import {
  makeCastOutput,
  rayCastCapsule,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
} from '../../engine/queries/ray-cast.ts'
import { shapeCast } from '../../engine/queries/shape-cast.ts'
import {
  IDENTITY,
  makeDistanceOutput,
  makeShapeProxy,
  shapeDistance,
} from '../../engine/queries/shape-distance.ts'
import { proxyOf, type QueryGeometry } from '../../engine/queries/world-queries.ts'

interface Pose {
  x: number
  y: number
  c: number
  s: number
}

const apply = (t: Pose, p: Vec2): Vec2 => ({ x: t.x + t.c * p.x - t.s * p.y, y: t.y + t.s * p.x + t.c * p.y })
const rotate = (t: Pose, p: Vec2): Vec2 => ({ x: t.c * p.x - t.s * p.y, y: t.s * p.x + t.c * p.y })

/** A body's pose as the world holds it (exact rotation pair). */
function poseOf(world: World, body: number): Pose {
  const p = world.getPosition(body)
  const r = world.getRotation(body)
  return { x: p.x, y: p.y, c: r.c, s: r.s }
}

/** An engine shape moved into the world frame by the test, as plain geometry. */
function worldGeometry(shape: Shape, t: Pose): QueryGeometry {
  switch (shape.type) {
    case 'circle':
      return { type: 'circle', center: apply(t, shape.centroid), radius: shape.radius }
    case 'capsule':
      return {
        type: 'capsule',
        center1: apply(t, shape.vertices[0]),
        center2: apply(t, shape.vertices[1]),
        radius: shape.radius,
      }
    case 'polygon':
      return {
        type: 'polygon',
        vertices: shape.vertices.map((v) => apply(t, v)),
        normals: shape.normals.map((n) => rotate(t, n)),
        count: shape.count,
        radius: shape.radius,
      }
    default:
      return { type: 'segment', point1: apply(t, shape.vertices[0]), point2: apply(t, shape.vertices[1]) }
  }
}

const out = makeCastOutput()

/** The exact ray cast of a world-frame geometry (the per-shape functions), or null. */
function castWorld(
  g: QueryGeometry,
  origin: Vec2,
  translation: Vec2,
): { fraction: number; point: Vec2; normal: Vec2 } | null {
  const input = { origin, translation, maxFraction: 1 }
  let r: ReturnType<typeof rayCastCircle>
  if (g.type === 'circle') r = rayCastCircle(g, input, out)
  else if (g.type === 'capsule') r = rayCastCapsule(g, input, out)
  else if (g.type === 'polygon') r = rayCastPolygon(g, input, out)
  else if (g.type === 'segment') r = rayCastSegment(g, input, false, out)
  else throw new Error('no chain segments in this world')
  return r === null ? null : { fraction: r.fraction, point: { ...r.point }, normal: { ...r.normal } }
}

function expectVec(actual: Vec2, expected: Vec2, digits = 1e-9): void {
  expect(Math.abs(actual.x - expected.x), `x ${actual.x} vs ${expected.x}`).toBeLessThanOrEqual(digits)
  expect(Math.abs(actual.y - expected.y), `y ${actual.y} vs ${expected.y}`).toBeLessThanOrEqual(digits)
}

describe('world queries against hand-worked answers on a turned, moved body', () => {
  // Each case: a shape in the body frame, a ray in the body frame and its answer worked out by hand
  // there (fraction, point, normal); a circle of radius 0.25 cast along the same ray and its answer.
  const s = Math.sqrt(0.0525)
  const h = 0.1 / Math.SQRT2
  const segLength = Math.hypot(2, 0.5)
  const cases: Array<{
    name: string
    shape: Shape
    origin: Vec2
    translation: Vec2
    ray: { fraction: number; point: Vec2; normal: Vec2 }
    cast: { fraction: number; point: Vec2; normal: Vec2 }
  }> = [
    {
      // Circle at (0.3, 0.1), r 0.5; the ray y = 0.1 from x = -1.7 enters at x = 0.3 - 0.5.
      name: 'circle',
      shape: circle(0.5, { x: 0.3, y: 0.1 }),
      origin: { x: -1.7, y: 0.1 },
      translation: { x: 4, y: 0 },
      ray: { fraction: 1.5 / 4, point: { x: -0.2, y: 0.1 }, normal: { x: -1, y: 0 } },
      // The probe (r 0.25) touches when its centre is 0.75 from (0.3, 0.1): x = -0.45.
      cast: { fraction: 1.25 / 4, point: { x: -0.2, y: 0.1 }, normal: { x: -1, y: 0 } },
    },
    {
      // Circle, off-centre ray: y = 0.4 meets x = 0.3 - sqrt(0.25 - 0.09) = -0.1.
      name: 'circle (off-centre ray)',
      shape: circle(0.5, { x: 0.3, y: 0.1 }),
      origin: { x: -1.7, y: 0.4 },
      translation: { x: 4, y: 0 },
      ray: { fraction: 1.6 / 4, point: { x: -0.1, y: 0.4 }, normal: { x: -0.8, y: 0.6 } },
      // Centre-line distance 0.3 < 0.75: centre at x = 0.3 - sqrt(0.75^2 - 0.09); contact on the
      // line between the centres, 0.5 from (0.3, 0.1).
      cast: (() => {
        const cx = 0.3 - Math.sqrt(0.5625 - 0.09)
        const nx = (cx - 0.3) / 0.75
        const ny = 0.3 / 0.75
        return {
          fraction: (cx + 1.7) / 4,
          point: { x: 0.3 + 0.5 * nx, y: 0.1 + 0.5 * ny },
          normal: { x: nx, y: ny },
        }
      })(),
    },
    {
      // Box 2 x 1 centred on the origin: the ray y = 0.2 enters the left face x = -1.
      name: 'box',
      shape: box(1, 0.5),
      origin: { x: -3, y: 0.2 },
      translation: { x: 4, y: 0 },
      ray: { fraction: 0.5, point: { x: -1, y: 0.2 }, normal: { x: -1, y: 0 } },
      cast: { fraction: 1.75 / 4, point: { x: -1, y: 0.2 }, normal: { x: -1, y: 0 } },
    },
    {
      // A convex pentagon; the ray x = 0.5 going down enters the top edge y = 1 (from (-1, 1) to (1, 1)).
      name: 'polygon',
      shape: polygon([
        { x: -1, y: -1 },
        { x: 1, y: -1 },
        { x: 1.5, y: 0 },
        { x: 1, y: 1 },
        { x: -1, y: 1 },
      ]),
      origin: { x: 0.5, y: 3 },
      translation: { x: 0, y: -4 },
      ray: { fraction: 0.5, point: { x: 0.5, y: 1 }, normal: { x: 0, y: 1 } },
      cast: { fraction: 1.75 / 4, point: { x: 0.5, y: 1 }, normal: { x: 0, y: 1 } },
    },
    {
      // Box 2 x 1 rounded by 0.1: the top face is at y = 0.6.
      name: 'rounded polygon (face)',
      shape: polygon(
        [
          { x: -1, y: -0.5 },
          { x: 1, y: -0.5 },
          { x: 1, y: 0.5 },
          { x: -1, y: 0.5 },
        ],
        0.1,
      ),
      origin: { x: 0.2, y: 3 },
      translation: { x: 0, y: -4 },
      ray: { fraction: 2.4 / 4, point: { x: 0.2, y: 0.6 }, normal: { x: 0, y: 1 } },
      cast: { fraction: 2.15 / 4, point: { x: 0.2, y: 0.6 }, normal: { x: 0, y: 1 } },
    },
    {
      // The same rounded box hit on its corner circle at (1, 0.5) along the diagonal.
      name: 'rounded polygon (corner)',
      shape: polygon(
        [
          { x: -1, y: -0.5 },
          { x: 1, y: -0.5 },
          { x: 1, y: 0.5 },
          { x: -1, y: 0.5 },
        ],
        0.1,
      ),
      origin: { x: 3, y: 2.5 },
      translation: { x: -4, y: -4 },
      ray: {
        fraction: (2 * Math.SQRT2 - 0.1) / (4 * Math.SQRT2),
        point: { x: 1 + h, y: 0.5 + h },
        normal: { x: Math.SQRT1_2, y: Math.SQRT1_2 },
      },
      cast: {
        fraction: (2 * Math.SQRT2 - 0.35) / (4 * Math.SQRT2),
        point: { x: 1 + h, y: 0.5 + h },
        normal: { x: Math.SQRT1_2, y: Math.SQRT1_2 },
      },
    },
    {
      // Capsule (-1, 0)-(1, 0), r 0.25: the ray x = 0.3 down meets its flat side y = 0.25.
      name: 'capsule (side)',
      shape: capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.25),
      origin: { x: 0.3, y: 2 },
      translation: { x: 0, y: -4 },
      ray: { fraction: 1.75 / 4, point: { x: 0.3, y: 0.25 }, normal: { x: 0, y: 1 } },
      cast: { fraction: 1.5 / 4, point: { x: 0.3, y: 0.25 }, normal: { x: 0, y: 1 } },
    },
    {
      // The same capsule hit on its end cap at (1, 0) by the ray y = 0.1 going left.
      name: 'capsule (cap)',
      shape: capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.25),
      origin: { x: 3, y: 0.1 },
      translation: { x: -4, y: 0 },
      ray: { fraction: (2 - s) / 4, point: { x: 1 + s, y: 0.1 }, normal: { x: s / 0.25, y: 0.4 } },
      cast: (() => {
        // The probe's centre is 0.5 from (1, 0): x = 1 + sqrt(0.25 - 0.01).
        const d = Math.sqrt(0.24)
        return {
          fraction: (2 - d) / 4,
          point: { x: 1 + 0.25 * (d / 0.5), y: 0.25 * (0.1 / 0.5) },
          normal: { x: d / 0.5, y: 0.1 / 0.5 },
        }
      })(),
    },
    {
      // Segment (-1, 0)-(1, 0.5): the line y = 0.25 + 0.25 x; the ray x = 0 down meets it at
      // y = 0.25; the normal faces the ray's side (up).
      name: 'segment',
      shape: segment({ x: -1, y: 0 }, { x: 1, y: 0.5 }),
      origin: { x: 0, y: 2 },
      translation: { x: 0, y: -4 },
      ray: {
        fraction: 1.75 / 4,
        point: { x: 0, y: 0.25 },
        normal: { x: -0.5 / segLength, y: 2 / segLength },
      },
      // The probe touches when its centre is 0.25 from the line, along the normal.
      cast: (() => {
        const nx = -0.5 / segLength
        const ny = 2 / segLength
        // Centre (0, y) with (y - 0.25) * ny = 0.25 (distance to the line along its unit normal).
        const y = 0.25 + 0.25 / ny
        return {
          fraction: (2 - y) / 4,
          point: { x: 0 - 0.25 * nx, y: y - 0.25 * ny },
          normal: { x: nx, y: ny },
        }
      })(),
    },
  ]

  for (const c of cases) {
    it(`${c.name}: castRayClosest, castRay and castShape give the hand-worked fraction, point and normal`, () => {
      const world = createWorld()
      // A decoy at the origin that the ray never reaches, so that the shape ids are not 1.
      world.createBody({ type: 'static', position: { x: -30, y: -30 }, shape: box(0.5, 0.5) })
      const body = world.createBody({
        type: 'static',
        position: { x: 3.25, y: -2.5 },
        angle: 0.7,
        shape: c.shape,
      })
      const shapeId = world.bodyShapes(body)[0]
      const t = poseOf(world, body)
      const origin = apply(t, c.origin)
      const translation = rotate(t, c.translation)
      const before = world.save()

      const hit = world.castRayClosest(origin, translation)
      expect(hit).not.toBeNull()
      expect(hit!.shape).toBe(shapeId)
      expect(hit!.body).toBe(body)
      expect(Math.abs(hit!.fraction - c.ray.fraction)).toBeLessThanOrEqual(1e-9)
      expectVec(hit!.point, apply(t, c.ray.point))
      expectVec(hit!.normal, rotate(t, c.ray.normal))

      const all = world.castRay(origin, translation)
      expect(all.map((x) => x.shape)).toEqual([shapeId])
      expect(all[0]).toEqual(hit)

      const probe = circle(0.25)
      const cast = world.castShape(probe, { position: origin, angle: 0 }, translation)
      expect(cast).not.toBeNull()
      expect(cast!.shape).toBe(shapeId)
      expect(Math.abs(cast!.fraction - c.cast.fraction)).toBeLessThanOrEqual(1e-9)
      expectVec(cast!.point, apply(t, c.cast.point))
      expectVec(cast!.normal, rotate(t, c.cast.normal))

      // The reusing forms give the same answers.
      const into = makeRayHit()
      expect(world.castRayClosest(origin, translation, undefined, into)).toBe(into)
      expect(into).toEqual(hit)
      expect(world.castShape(probe, { position: origin, angle: 0 }, translation, undefined, into)).toBe(into)
      expect(into).toEqual(cast)
      expect(world.save()).toEqual(before)
    })
  }

  it('a shape placed by its exact rotation pair answers as by its angle; both at once, or a non-unit pair, is refused', () => {
    const world = createWorld()
    const body = world.createBody({
      type: 'static',
      position: { x: 1, y: 2 },
      angle: 0.3,
      shape: box(1, 0.5),
    })
    const rotation = world.getRotation(body)
    const probe = box(0.3, 0.2)
    const byAngle = world.castShape(probe, { position: { x: 1, y: 6 }, angle: 0.3 }, { x: 0, y: -8 })
    const byPair = world.castShape(probe, { position: { x: 1, y: 6 }, rotation }, { x: 0, y: -8 })
    expect(byPair).toEqual(byAngle)
    expect(world.overlapShape(probe, { position: { x: 1, y: 2 }, rotation })).toEqual([
      world.bodyShapes(body)[0],
    ])
    expect(() => world.overlapShape(probe, { position: { x: 0, y: 0 }, angle: 0, rotation })).toThrow(
      /both angle and rotation/,
    )
    expect(() => world.overlapShape(probe, { position: { x: 0, y: 0 }, rotation: { c: 1, s: 1 } })).toThrow(
      /rotation must be a unit/,
    )
  })

  it('a turned box cast corner-first onto a sharp box face: fraction from the corner distance, point at the corner', () => {
    const world = createWorld()
    const body = world.createBody({
      type: 'static',
      position: { x: -1.5, y: 4 },
      angle: -0.4,
      shape: box(1, 0.5),
    })
    const t = poseOf(world, body)
    // In the body frame: a square of half side 0.2 turned 45 degrees (a diamond), centre at
    // (0.3, 3), moving down by 4; its lowest corner is 0.2 sqrt 2 below the centre and meets the
    // top face y = 0.5 at x = 0.3.
    const corner = 0.2 * Math.SQRT2
    const origin = apply(t, { x: 0.3, y: 3 })
    const translation = rotate(t, { x: 0, y: -4 })
    const angle = -0.4 + Math.PI / 4
    const cast = world.castShape(box(0.2, 0.2), { position: origin, angle }, translation)
    expect(cast).not.toBeNull()
    expect(Math.abs(cast!.fraction - (2.5 - corner) / 4)).toBeLessThanOrEqual(1e-9)
    expectVec(cast!.point, apply(t, { x: 0.3, y: 0.5 }), 1e-8)
    expectVec(cast!.normal, rotate(t, { x: 0, y: 1 }))
  })
})

/** Box2D's query rule (b2ShouldQueryShape), written out for the test. */
function box2dQueryRule(
  shape: { categoryBits: number; maskBits: number },
  q: { categoryBits: number; maskBits: number },
): boolean {
  return (shape.categoryBits & q.maskBits) !== 0 && (shape.maskBits & q.categoryBits) !== 0
}

interface Record {
  id: number
  body: number
  shape: Shape
  sensor: boolean
  filter: { categoryBits: number; maskBits: number; groupIndex: number }
}

function randomConvex(rng: Prng): Vec2[] {
  const n = 3 + rng.int(6)
  const a = rng.range(0.3, 1.2)
  const b = rng.range(0.3, 1.2)
  const cx = rng.range(-0.5, 0.5)
  const cy = rng.range(-0.5, 0.5)
  return Array.from({ length: n }, (_, i) => {
    const angle = ((i + rng.range(0.2, 0.8)) * 2 * Math.PI) / n
    return { x: cx + a * Math.cos(angle), y: cy + b * Math.sin(angle) }
  })
}

function randomShape(rng: Prng, allowSegment: boolean): Shape {
  const p = () => ({ x: rng.range(-1.5, 1.5), y: rng.range(-1.5, 1.5) })
  const kind = rng.int(allowSegment ? 6 : 5)
  if (kind === 0) return circle(rng.range(0.1, 0.8), p())
  if (kind === 1) return box(rng.range(0.1, 1), rng.range(0.1, 1), p(), rng.range(-3, 3))
  if (kind === 2) return polygon(randomConvex(rng))
  if (kind === 3) return polygon(randomConvex(rng), rng.range(0.05, 0.3))
  if (kind === 4) {
    const a = p()
    return capsule(a, { x: a.x + rng.range(0.2, 1.5), y: a.y + rng.range(-1, 1) }, rng.range(0.05, 0.5))
  }
  const a = p()
  return segment(a, { x: a.x + rng.range(0.3, 2), y: a.y + rng.range(-2, 2) })
}

/** A random world of exactly `total` shapes, stepped 40 times so the fat AABBs have moved away from the shapes. */
function buildWorld(seed: number, total = 1000): { world: World; records: Record[] } {
  const rng = new Prng(seed)
  const world = createWorld()
  const records: Record[] = []
  while (records.length < total) {
    const roll = rng.next()
    const type = roll < 0.35 ? 'static' : roll < 0.45 ? 'kinematic' : 'dynamic'
    const count = Math.min(1 + rng.int(5), total - records.length)
    const shapes: Array<{ shape: Shape; sensor: boolean; filter: Record['filter'] }> = []
    for (let k = 0; k < count; k++) {
      // A dynamic body's first shape has mass; segments go on static and kinematic bodies or later.
      const shape = randomShape(rng, type !== 'dynamic' || k > 0)
      const filter = {
        categoryBits: rng.next() < 0.1 ? 0x80000000 : 1 << rng.int(4),
        maskBits:
          rng.next() < 0.7 ? 0xffffffff : ((1 + rng.int(15)) | (rng.next() < 0.3 ? 0x80000000 : 0)) >>> 0,
        groupIndex: rng.next() < 0.1 ? -1 - rng.int(3) : 0,
      }
      shapes.push({ shape, sensor: rng.next() < 0.06, filter })
    }
    const body = world.createBody({
      type,
      position: { x: rng.range(-45, 45), y: rng.range(-45, 45) },
      angle: rng.range(-3, 3),
      linearVelocity: { x: rng.range(-6, 6), y: rng.range(-6, 6) },
      angularVelocity: rng.range(-3, 3),
      shapes: shapes.map((s) => ({ shape: s.shape, sensor: s.sensor, filter: s.filter })),
    })
    const ids = world.bodyShapes(body)
    shapes.forEach((s, k) => {
      records.push({ id: ids[k], body, shape: s.shape, sensor: s.sensor, filter: s.filter })
    })
  }
  for (let i = 0; i < 40; i++) world.step()
  return { world, records }
}

/** Every shape the query may see, in the world frame (the test's own frame change). */
function worldShapes(world: World, records: Record[]): Array<Record & { g: QueryGeometry }> {
  return records.map((r) => ({ ...r, g: worldGeometry(r.shape, poseOf(world, r.body)) }))
}

function randomFilter(rng: Prng): QueryFilterDef | undefined {
  if (rng.next() < 0.4) return undefined
  return { categoryBits: 1 << rng.int(5), maskBits: rng.next() < 0.5 ? 0xffffffff : 1 + rng.int(31) }
}

const DEFAULT = { categoryBits: 1, maskBits: 0xffffffff }

function visible(r: Record, f: QueryFilterDef | undefined): boolean {
  const q = { categoryBits: f?.categoryBits ?? 1, maskBits: f?.maskBits ?? 0xffffffff }
  return !r.sensor && box2dQueryRule(r.filter, f === undefined ? DEFAULT : q)
}

function tightBox(g: QueryGeometry): [number, number, number, number] {
  let pts: Vec2[]
  let r = 0
  if (g.type === 'circle') {
    pts = [g.center]
    r = g.radius
  } else if (g.type === 'capsule') {
    pts = [g.center1, g.center2]
    r = g.radius
  } else if (g.type === 'polygon') {
    pts = [...g.vertices]
    r = g.radius
  } else if (g.type === 'segment') pts = [g.point1, g.point2]
  else throw new Error('no chains')
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
  const t = Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey)))
  return Math.hypot(p.x - a.x - t * ex, p.y - a.y - t * ey)
}

/** Does the world-frame geometry contain p (the boundary counts)? Distance formulas, no GJK. */
function contains(g: QueryGeometry, p: Vec2): boolean {
  if (g.type === 'circle') return Math.hypot(p.x - g.center.x, p.y - g.center.y) <= g.radius
  if (g.type === 'capsule') return segmentDistance(p, g.center1, g.center2) <= g.radius
  if (g.type === 'polygon') {
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
  return false // zero thickness: a random point is never on it
}

const proxyA = makeShapeProxy()
const distance = makeDistanceOutput()

describe('world queries against brute force over a random world of 1,000 shapes', () => {
  const { world, records } = buildWorld(27)
  const shapes = worldShapes(world, records)
  const rng = new Prng(2027)
  // The query shape's rotation as the world makes it: the engine's own cosine and sine.
  const rotationOf = (angle: number) => ({ c: cos(angle), s: sin(angle) })

  it('the world has every kind, compound bodies, sensors, filters, and moved fat AABBs', () => {
    const kinds = new Set(
      records.map((r) => (r.shape.type === 'polygon' && r.shape.radius > 0 ? 'rounded' : r.shape.type)),
    )
    expect([...kinds].sort()).toEqual(['capsule', 'circle', 'polygon', 'rounded', 'segment'])
    expect(records.length).toBe(1000)
    expect(records.filter((r) => r.sensor).length).toBeGreaterThan(20)
    const perBody = new Map<number, number>()
    for (const r of records) perBody.set(r.body, (perBody.get(r.body) ?? 0) + 1)
    expect([...perBody.values()].filter((n) => n > 1).length).toBeGreaterThan(100)
    expect(world.awakeBodyCount()).toBeGreaterThan(50)
  })

  it('castRayClosest and castRay equal the per-shape ray casts over every shape (400 rays)', () => {
    const list = new RayHitList()
    let hits = 0
    let multi = 0
    for (let q = 0; q < 400; q++) {
      const origin = { x: rng.range(-55, 55), y: rng.range(-55, 55) }
      const angle = rng.range(0, 2 * Math.PI)
      const length = rng.range(1, 80)
      const translation = { x: length * Math.cos(angle), y: length * Math.sin(angle) }
      const filter = randomFilter(rng)
      const expected: Array<{ id: number; body: number; fraction: number; point: Vec2; normal: Vec2 }> = []
      for (const s of shapes) {
        if (!visible(s, filter)) continue
        const r = castWorld(s.g, origin, translation)
        if (r !== null) expected.push({ id: s.id, body: s.body, ...r })
      }
      expected.sort((a, b) => a.fraction - b.fraction || a.id - b.id)
      const all = world.castRay(origin, translation, filter)
      expect(all.map((h) => h.shape)).toEqual(expected.map((e) => e.id))
      all.forEach((h, i) => {
        expect(h.body).toBe(expected[i].body)
        expect(Math.abs(h.fraction - expected[i].fraction)).toBeLessThanOrEqual(1e-9)
        expectVec(h.point, expected[i].point)
        expectVec(h.normal, expected[i].normal)
      })
      expect(world.castRayInto(origin, translation, filter, list)).toBe(all.length)
      expect(list.hits.slice(0, list.count)).toEqual(all)
      const closest = world.castRayClosest(origin, translation, filter)
      if (expected.length === 0) expect(closest).toBeNull()
      else expect(closest).toEqual(all[0])
      hits += expected.length > 0 ? 1 : 0
      multi += expected.length > 1 ? 1 : 0
    }
    expect(hits).toBeGreaterThan(150)
    expect(multi).toBeGreaterThan(80)
  })

  it('castShape equals shapeCast against every shape (250 casts of circles, boxes, capsules and polygons)', () => {
    let hits = 0
    const cast = makeCastOutput()
    for (let q = 0; q < 250; q++) {
      const shape = randomShape(rng, false)
      const position = { x: rng.range(-50, 50), y: rng.range(-50, 50) }
      const angle = rng.range(-3, 3)
      const a = rng.range(0, 2 * Math.PI)
      const length = rng.range(1, 40)
      const translation = { x: length * Math.cos(a), y: length * Math.sin(a) }
      const filter = randomFilter(rng)
      const r = rotationOf(angle)
      const probe = proxyOf(
        worldGeometry(shape, { x: position.x, y: position.y, c: r.c, s: r.s }),
        makeShapeProxy(),
      )
      let best: { id: number; fraction: number; point: Vec2; normal: Vec2 } | null = null
      for (const s of shapes) {
        if (!visible(s, filter)) continue
        const hit = shapeCast(
          {
            proxyA: proxyOf(s.g, proxyA),
            transformA: IDENTITY,
            proxyB: probe,
            transformB: IDENTITY,
            translationB: translation,
            maxFraction: 1,
          },
          cast,
        )
        if (hit === null) continue
        if (
          best === null ||
          hit.fraction < best.fraction ||
          (hit.fraction === best.fraction && s.id < best.id)
        )
          best = { id: s.id, fraction: hit.fraction, point: { ...hit.point }, normal: { ...hit.normal } }
      }
      const got = world.castShape(shape, { position, angle }, translation, filter)
      if (best === null) {
        expect(got).toBeNull()
        continue
      }
      hits++
      expect(got).not.toBeNull()
      expect(got!.shape).toBe(best.id)
      expect(Math.abs(got!.fraction - best.fraction)).toBeLessThanOrEqual(1e-9)
      expectVec(got!.point, best.point, 1e-7)
      expectVec(got!.normal, best.normal, 1e-7)
    }
    expect(hits).toBeGreaterThan(100)
  })

  it('overlapAABB equals a tight-box test over every shape (300 boxes), not the fat AABBs', () => {
    const ids = new IdBuffer()
    let found = 0
    for (let q = 0; q < 300; q++) {
      const x = rng.range(-50, 50)
      const y = rng.range(-50, 50)
      const aabb = { minX: x, minY: y, maxX: x + rng.range(0, 8), maxY: y + rng.range(0, 8) }
      const filter = randomFilter(rng)
      const expected = shapes
        .filter((s) => visible(s, filter))
        .filter((s) => {
          const b = tightBox(s.g)
          return !(b[0] > aabb.maxX || b[1] > aabb.maxY || aabb.minX > b[2] || aabb.minY > b[3])
        })
        .map((s) => s.id)
        .sort((a, b) => a - b)
      expect(world.overlapAABB(aabb, filter)).toEqual(expected)
      expect(world.overlapAABBInto(aabb, filter, ids)).toBe(expected.length)
      expect(Array.from(ids.ids.subarray(0, ids.count))).toEqual(expected)
      found += expected.length
    }
    expect(found).toBeGreaterThan(500)
  })

  it('overlapPoint equals point-in-shape by distance formulas over every shape (400 points)', () => {
    let found = 0
    for (let q = 0; q < 400; q++) {
      // Half the points near a shape's centre, so that many hit.
      const near = shapes[rng.int(shapes.length)]
      const b = tightBox(near.g)
      const point =
        q % 2 === 0
          ? { x: rng.range(b[0], b[2]), y: rng.range(b[1], b[3]) }
          : { x: rng.range(-50, 50), y: rng.range(-50, 50) }
      const filter = randomFilter(rng)
      const expected = shapes
        .filter((s) => visible(s, filter) && contains(s.g, point))
        .map((s) => s.id)
        .sort((a, c) => a - c)
      expect(world.overlapPoint(point, filter)).toEqual(expected)
      found += expected.length
    }
    expect(found).toBeGreaterThan(100)
  })

  it('overlapShape equals the GJK distance test over every shape (250 shapes)', () => {
    let found = 0
    for (let q = 0; q < 250; q++) {
      const shape = randomShape(rng, true)
      const position = { x: rng.range(-50, 50), y: rng.range(-50, 50) }
      const angle = rng.range(-3, 3)
      const filter = randomFilter(rng)
      const r = rotationOf(angle)
      const probe = proxyOf(
        worldGeometry(shape, { x: position.x, y: position.y, c: r.c, s: r.s }),
        makeShapeProxy(),
      )
      const expected = shapes
        .filter((s) => {
          if (!visible(s, filter)) return false
          const a = proxyOf(s.g, proxyA)
          shapeDistance(a, IDENTITY, probe, IDENTITY, false, distance)
          return distance.distance <= a.radius + probe.radius
        })
        .map((s) => s.id)
        .sort((a, b) => a - b)
      expect(world.overlapShape(shape, { position, angle }, filter)).toEqual(expected)
      found += expected.length
    }
    expect(found).toBeGreaterThan(50)
  })
})

describe('query filters follow Box2D rule', () => {
  it('overlapPoint and castRayClosest report a shape exactly when (shape.category & query.mask) and (shape.mask & query.category); sensors never', () => {
    const bits = [0, 1, 2, 3, 0x80000000, 0xffffffff, 0x7fffffff, 0x80000001]
    const world = createWorld()
    const table: Array<{ id: number; categoryBits: number; maskBits: number; sensor: boolean }> = []
    for (const categoryBits of bits) {
      for (const maskBits of bits) {
        for (const sensor of [false, true]) {
          // Every shape covers the origin; groups must not matter to queries.
          const body = world.createBody({
            type: 'static',
            shapes: [{ shape: circle(1), filter: { categoryBits, maskBits, groupIndex: -3 }, sensor }],
          })
          table.push({ id: world.bodyShapes(body)[0], categoryBits, maskBits, sensor })
        }
      }
    }
    let reported = 0
    for (const categoryBits of bits) {
      for (const maskBits of bits) {
        const q = { categoryBits, maskBits }
        const expected = table.filter((s) => !s.sensor && box2dQueryRule(s, q)).map((s) => s.id)
        expect(world.overlapPoint({ x: 0, y: 0 }, q)).toEqual(expected)
        const hit = world.castRayClosest({ x: 0, y: 5 }, { x: 0, y: -10 }, q)
        expect(hit?.shape ?? null).toBe(expected.length > 0 ? expected[0] : null)
        reported += expected.length
      }
    }
    // 0 and the sensors are never reported; many others are.
    expect(reported).toBeGreaterThan(300)
    // The default filter is Box2D's: category 1, every mask bit.
    expect(world.overlapPoint({ x: 0, y: 0 })).toEqual(
      table.filter((s) => !s.sensor && box2dQueryRule(s, DEFAULT)).map((s) => s.id),
    )
  })
})

describe('queries never change the state', () => {
  it('save() is byte-identical before and after 600 queries, and the queried world steps bit-identically with an unqueried twin', () => {
    const a = buildWorld(5, 300).world
    const b = buildWorld(5, 300).world
    const rng = new Prng(8)
    for (let step = 0; step < 60; step++) {
      const before = a.save()
      for (let q = 0; q < 10; q++) {
        const origin = { x: rng.range(-50, 50), y: rng.range(-50, 50) }
        const translation = { x: rng.range(-40, 40), y: rng.range(-40, 40) }
        a.castRayClosest(origin, translation)
        a.castRay(origin, translation)
        a.castShape(box(0.5, 0.3), { position: origin, angle: 0.3 }, translation)
        a.overlapAABB({ minX: origin.x, minY: origin.y, maxX: origin.x + 5, maxY: origin.y + 5 })
        a.overlapPoint(origin)
        a.overlapShape(circle(2), { position: origin, angle: 0 })
      }
      // Byte comparison (toEqual walks a 100 KB array element by element).
      expect(Buffer.compare(a.save(), before)).toBe(0)
      a.step()
      b.step()
      expect(a.hash()).toBe(b.hash())
    }
  })
})

describe('bad query arguments throw RangeErrors naming the value', () => {
  const world = createWorld()
  world.createBody({ type: 'static', shape: box(1, 1) })
  const at = { position: { x: 0, y: 0 }, angle: 0 }
  it.each([
    [
      'a NaN ray origin',
      () => world.castRayClosest({ x: Number.NaN, y: 0 }, { x: 1, y: 0 }),
      /ray origin\.x.*NaN/,
    ],
    [
      'a ray origin beyond MAX_POSITION',
      () => world.castRay({ x: 2e6, y: 0 }, { x: 1, y: 0 }),
      /ray origin.*1000000/,
    ],
    [
      'an infinite translation',
      () => world.castRay({ x: 0, y: 0 }, { x: 0, y: Number.POSITIVE_INFINITY }),
      /ray translation\.y/,
    ],
    [
      'too long a ray',
      () => world.castRayClosest({ x: 0, y: 0 }, { x: MAX_QUERY_TRANSLATION * 1.5, y: 0 }),
      /ray translation must be within 2000000 m/,
    ],
    [
      'a filter mask out of range',
      () => world.overlapPoint({ x: 0, y: 0 }, { maskBits: 2 ** 32 }),
      /maskBits.*4294967296/,
    ],
    [
      'a fractional category',
      () => world.castRay({ x: 0, y: 0 }, { x: 1, y: 0 }, { categoryBits: 1.5 }),
      /categoryBits.*1\.5/,
    ],
    ['an inverted AABB', () => world.overlapAABB({ minX: 1, minY: 0, maxX: 0, maxY: 1 }), /minX <= maxX/],
    ['an infinite AABB', () => world.overlapAABB({ minX: -Infinity, minY: 0, maxX: 0, maxY: 1 }), /finite/],
    ['a NaN point', () => world.overlapPoint({ x: 0, y: Number.NaN }), /overlapPoint point\.y/],
    [
      'a shape that is not one',
      () => world.overlapShape({ type: 'blob' } as unknown as Shape, at),
      /made by circle/,
    ],
    [
      'a NaN shape angle',
      () => world.overlapShape(circle(1), { position: { x: 0, y: 0 }, angle: Number.NaN }),
      /overlapShape angle/,
    ],
    [
      'a shape cast position beyond MAX_POSITION',
      () => world.castShape(circle(1), { position: { x: 0, y: -3e6 }, angle: 0 }, { x: 1, y: 0 }),
      /castShape position/,
    ],
    [
      'a NaN shape cast translation',
      () => world.castShape(circle(1), at, { x: Number.NaN, y: 0 }),
      /castShape translation\.x/,
    ],
  ])('%s', (_name, call, message) => {
    expect(call).toThrow(RangeError)
    expect(call).toThrow(message)
  })
})
