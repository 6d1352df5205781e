/*
 * Ray casts (engine/queries/ray-cast.ts) against answers worked out by hand for every shape kind (fraction,
 * point and normal to 1e-9), including grazing, parallel, too-short, zero-length and
 * starting-inside rays; then against brute force on random rays: the entry fraction found by
 * dense sampling and bisection on an independent point-in-shape test, and the normal as the
 * direction from the nearest core point (or the face the point lies on).
 */
import { describe, expect, it } from 'vitest'
import type { Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import {
  type CapsuleGeometry,
  type CastOutput,
  type CircleGeometry,
  makeCastOutput,
  type PolygonGeometry,
  type RayCastInput,
  rayCastCapsule,
  rayCastChainSegment,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
} from '../../engine/queries/ray-cast.ts'

const TOL = 1e-9
const ray = (ox: number, oy: number, tx: number, ty: number, maxFraction = 1): RayCastInput => ({
  origin: { x: ox, y: oy },
  translation: { x: tx, y: ty },
  maxFraction,
})

function expectHit(hit: CastOutput | null, fraction: number, point: Vec2, normal: Vec2): void {
  expect(hit).not.toBeNull()
  const h = hit as CastOutput
  expect(Math.abs(h.fraction - fraction)).toBeLessThan(TOL)
  expect(Math.abs(h.point.x - point.x)).toBeLessThan(TOL)
  expect(Math.abs(h.point.y - point.y)).toBeLessThan(TOL)
  expect(Math.abs(h.normal.x - normal.x)).toBeLessThan(TOL)
  expect(Math.abs(h.normal.y - normal.y)).toBeLessThan(TOL)
}

function expectInitialOverlap(hit: CastOutput | null, origin: Vec2): void {
  expect(hit).not.toBeNull()
  expect(hit?.fraction).toBe(0)
  expect(hit?.point).toEqual(origin)
  expect(hit?.normal).toEqual({ x: 0, y: 0 })
}

/** A convex polygon from CCW vertices, with its normals (test-side construction). */
function poly(vertices: Vec2[], radius = 0): PolygonGeometry {
  const normals = vertices.map((a, i) => {
    const b = vertices[(i + 1) % vertices.length]
    const l = Math.hypot(b.x - a.x, b.y - a.y)
    return { x: (b.y - a.y) / l, y: -(b.x - a.x) / l }
  })
  return { vertices, normals, count: vertices.length, radius }
}
const boxGeometry = (hx: number, hy: number, radius = 0): PolygonGeometry =>
  poly(
    [
      { x: -hx, y: -hy },
      { x: hx, y: -hy },
      { x: hx, y: hy },
      { x: -hx, y: hy },
    ],
    radius,
  )

describe('rayCastCircle (centre (2, 1), radius 0.5)', () => {
  const c: CircleGeometry = { center: { x: 2, y: 1 }, radius: 0.5 }
  const out = makeCastOutput()
  it('hits head on at x = 1.5: fraction 0.25 of a 10 m ray, normal (-1, 0)', () => {
    expectHit(rayCastCircle(c, ray(-1, 1, 10, 0), out), 0.25, { x: 1.5, y: 1 }, { x: -1, y: 0 })
  })
  it('hits off centre where the quadratic says', () => {
    // y = 1.3: x = 2 - sqrt(0.25 - 0.09) = 1.6, normal (-0.4, 0.3) / 0.5.
    expectHit(rayCastCircle(c, ray(0, 1.3, 4, 0), out), 0.4, { x: 1.6, y: 1.3 }, { x: -0.8, y: 0.6 })
  })
  it('hits a diagonal ray at the 45-degree point', () => {
    const s = Math.SQRT1_2 * 0.5
    const o = { x: 2 - s - 3, y: 1 - s - 3 }
    expectHit(
      rayCastCircle(c, ray(o.x, o.y, 6, 6), out),
      0.5,
      { x: 2 - s, y: 1 - s },
      { x: -Math.SQRT1_2, y: -Math.SQRT1_2 },
    )
  })
  it('grazes: 1e-9 m inside the tangent hits near the tangent point, 1e-9 m outside misses', () => {
    const inside = rayCastCircle(c, ray(0, 1.5 - 1e-9, 4, 0), out)
    expect(inside).not.toBeNull()
    expect(Math.abs((inside as CastOutput).point.x - 2)).toBeLessThan(1e-4)
    expect(rayCastCircle(c, ray(0, 1.5 + 1e-9, 4, 0), out)).toBeNull()
  })
  it('misses a ray pointing away, one too short (maxFraction), and a zero-length ray outside', () => {
    expect(rayCastCircle(c, ray(-1, 1, -10, 0), out)).toBeNull()
    expect(rayCastCircle(c, ray(-1, 1, 10, 0, 0.2499), out)).toBeNull()
    expect(rayCastCircle(c, ray(-1, 1, 0, 0), out)).toBeNull()
    // maxFraction beyond 1 reaches farther: a 1 m ray with maxFraction 3 reaches x = 2.
    expectHit(rayCastCircle(c, ray(-1, 1, 1, 0, 3), out), 2.5, { x: 1.5, y: 1 }, { x: -1, y: 0 })
  })
  it('starting inside is an initial overlap (fraction 0, point = origin, zero normal), whatever the direction or length', () => {
    expectInitialOverlap(rayCastCircle(c, ray(2.1, 1.1, 5, 0), out), { x: 2.1, y: 1.1 })
    expectInitialOverlap(rayCastCircle(c, ray(2.1, 1.1, -5, 3), out), { x: 2.1, y: 1.1 })
    expectInitialOverlap(rayCastCircle(c, ray(2.1, 1.1, 0, 0), out), { x: 2.1, y: 1.1 })
  })
  it('rejects a non-finite origin and a negative maxFraction by name', () => {
    expect(() => rayCastCircle(c, ray(Number.NaN, 0, 1, 0), out)).toThrow(/ray origin must be a finite point/)
    expect(() => rayCastCircle(c, ray(0, 0, 1, Number.POSITIVE_INFINITY), out)).toThrow(/ray translation/)
    expect(() => rayCastCircle(c, ray(0, 0, 1, 0, -1), out)).toThrow(
      /maxFraction must be a finite number >= 0, got -1/,
    )
  })
})

describe('rayCastCapsule ((0, 0)-(2, 0), radius 0.5)', () => {
  const cap: CapsuleGeometry = { center1: { x: 0, y: 0 }, center2: { x: 2, y: 0 }, radius: 0.5 }
  const out = makeCastOutput()
  it('hits the flat side from above and below', () => {
    expectHit(rayCastCapsule(cap, ray(1, 3, 0, -5), out), 0.5, { x: 1, y: 0.5 }, { x: 0, y: 1 })
    expectHit(rayCastCapsule(cap, ray(0.5, -2.5, 0, 4), out), 0.5, { x: 0.5, y: -0.5 }, { x: 0, y: -1 })
  })
  it('hits the end caps along the axis, from behind and from ahead', () => {
    expectHit(rayCastCapsule(cap, ray(-3, 0, 5, 0), out), 0.5, { x: -0.5, y: 0 }, { x: -1, y: 0 })
    expectHit(rayCastCapsule(cap, ray(6, 0, -7, 0), out), 0.5, { x: 2.5, y: 0 }, { x: 1, y: 0 })
  })
  it('hits a cap from outside the infinite capsule when the side hit lies past the segment end', () => {
    // Vertical ray at x = 2.3 hits the right cap at y = sqrt(0.25 - 0.09) = 0.4.
    expectHit(rayCastCapsule(cap, ray(2.3, 2, 0, -4), out), 0.4, { x: 2.3, y: 0.4 }, { x: 0.6, y: 0.8 })
  })
  it('misses a ray parallel to the axis outside it, and a ray starting behind the cap pointing away', () => {
    expect(rayCastCapsule(cap, ray(-5, 0.6, 10, 0), out)).toBeNull()
    expect(rayCastCapsule(cap, ray(-3, 0, -5, 0), out)).toBeNull()
    expect(rayCastCapsule(cap, ray(1, 3, 0, -2.4), out)).toBeNull() // stops 0.1 m short
  })
  it('starting inside the body is an initial overlap; inside a cap too', () => {
    expectInitialOverlap(rayCastCapsule(cap, ray(1, 0.2, 1, 1), out), { x: 1, y: 0.2 })
    expectInitialOverlap(rayCastCapsule(cap, ray(-0.3, 0.1, -1, 0), out), { x: -0.3, y: 0.1 })
    // Past the middle of the 2 m axis (Box2D v3.0 compared the projection with 1 m here, not the length).
    expectInitialOverlap(rayCastCapsule(cap, ray(1.5, 0.1, 1, 1), out), { x: 1.5, y: 0.1 })
    expectInitialOverlap(rayCastCapsule(cap, ray(2.3, 0.1, 1, 0), out), { x: 2.3, y: 0.1 })
  })
  it('a zero-length capsule is a circle', () => {
    const dot = { center1: { x: 1, y: 1 }, center2: { x: 1, y: 1 }, radius: 0.5 }
    expectHit(rayCastCapsule(dot, ray(-1, 1, 4, 0), out), 0.375, { x: 0.5, y: 1 }, { x: -1, y: 0 })
  })
})

describe('rayCastPolygon', () => {
  const box = boxGeometry(1, 0.5)
  const out = makeCastOutput()
  it('hits the faces of a 2 x 1 box from each side', () => {
    expectHit(rayCastPolygon(box, ray(-3, 0.2, 4, 0), out), 0.5, { x: -1, y: 0.2 }, { x: -1, y: 0 })
    expectHit(rayCastPolygon(box, ray(3, -0.1, -4, 0), out), 0.5, { x: 1, y: -0.1 }, { x: 1, y: 0 })
    expectHit(rayCastPolygon(box, ray(0.3, 2.5, 0, -4), out), 0.5, { x: 0.3, y: 0.5 }, { x: 0, y: 1 })
    expectHit(rayCastPolygon(box, ray(-0.7, -1.5, 0, 2), out), 0.5, { x: -0.7, y: -0.5 }, { x: 0, y: -1 })
  })
  it('hits a triangle on its slanted face', () => {
    const tri = poly([
      { x: 0, y: 0 },
      { x: 2, y: 0 },
      { x: 0, y: 2 },
    ])
    // Face x + y = 2, normal (1, 1)/sqrt 2; ray from (2, 2) towards the origin hits (1, 1) at fraction 0.5.
    expectHit(
      rayCastPolygon(tri, ray(2, 2, -2, -2), out),
      0.5,
      { x: 1, y: 1 },
      { x: Math.SQRT1_2, y: Math.SQRT1_2 },
    )
  })
  it('misses a ray parallel to a face outside it; a ray along a face line enters at the corner', () => {
    expect(rayCastPolygon(box, ray(-3, 0.6, 6, 0), out)).toBeNull()
    expectHit(rayCastPolygon(box, ray(-3, 0.5, 4, 0), out), 0.5, { x: -1, y: 0.5 }, { x: -1, y: 0 })
  })
  it('misses a ray that stops short or points away', () => {
    expect(rayCastPolygon(box, ray(-3, 0, 4, 0, 0.49), out)).toBeNull()
    expect(rayCastPolygon(box, ray(-3, 0, -4, 0), out)).toBeNull()
  })
  it('starting inside is an initial overlap', () => {
    expectInitialOverlap(rayCastPolygon(box, ray(0.2, 0.1, 5, 5), out), { x: 0.2, y: 0.1 })
  })
  it('rounded box (radius 0.25): faces at 1.25 / 0.75, corners on the quarter circles, inside the rounding is an overlap', () => {
    const rounded = boxGeometry(1, 0.5, 0.25)
    expectHit(rayCastPolygon(rounded, ray(-3, 0.2, 4, 0), out), 0.4375, { x: -1.25, y: 0.2 }, { x: -1, y: 0 })
    expectHit(rayCastPolygon(rounded, ray(0.3, 2.75, 0, -4), out), 0.5, { x: 0.3, y: 0.75 }, { x: 0, y: 1 })
    // Vertical ray at x = 1.15 meets the corner circle about (1, 0.5): y = 0.5 + sqrt(0.0625 - 0.0225) = 0.7.
    expectHit(
      rayCastPolygon(rounded, ray(1.15, 2.7, 0, -4), out),
      0.5,
      { x: 1.15, y: 0.7 },
      { x: 0.6, y: 0.8 },
    )
    // Diagonal at the corner: hits (1, 0.5) + 0.25 (1, 1)/sqrt 2.
    const s = 0.25 * Math.SQRT1_2
    expectHit(
      rayCastPolygon(rounded, ray(1 + s + 2, 0.5 + s + 2, -4, -4), out),
      0.5,
      { x: 1 + s, y: 0.5 + s },
      {
        x: Math.SQRT1_2,
        y: Math.SQRT1_2,
      },
    )
    expectInitialOverlap(rayCastPolygon(rounded, ray(1.1, 0.6, 1, 0), out), { x: 1.1, y: 0.6 })
    expect(rayCastPolygon(rounded, ray(1.2, 0.7, 1, 0), out)).toBeNull() // outside the corner circle, going away
  })
})

describe('rayCastSegment and rayCastChainSegment ((0, 0)-(2, 0))', () => {
  const seg = { point1: { x: 0, y: 0 }, point2: { x: 2, y: 0 } }
  const chain = { ghost1: { x: -1, y: 0 }, segment: seg, ghost2: { x: 3, y: 0 } }
  const out = makeCastOutput()
  it('two-sided: hits from either side with the normal facing the ray', () => {
    expectHit(rayCastSegment(seg, ray(1.5, 2, 0, -4), false, out), 0.5, { x: 1.5, y: 0 }, { x: 0, y: 1 })
    expectHit(rayCastSegment(seg, ray(0.5, -1, 0, 4), false, out), 0.25, { x: 0.5, y: 0 }, { x: 0, y: -1 })
  })
  it('hits exactly at an end point; misses past the ends, parallel, short or pointing away', () => {
    expectHit(rayCastSegment(seg, ray(2, 1, 0, -2), false, out), 0.5, { x: 2, y: 0 }, { x: 0, y: 1 })
    expect(rayCastSegment(seg, ray(2.01, 1, 0, -2), false, out)).toBeNull()
    expect(rayCastSegment(seg, ray(-1, 0, 5, 0), false, out)).toBeNull()
    expect(rayCastSegment(seg, ray(1, 1, 0, -2, 0.49), false, out)).toBeNull()
    expect(rayCastSegment(seg, ray(1, 1, 0, 2), false, out)).toBeNull()
  })
  it('one-sided chain segment: solid to the right of travel (below), passes rays from the left (above)', () => {
    expectHit(rayCastChainSegment(chain, ray(0.5, -1, 0, 4), out), 0.25, { x: 0.5, y: 0 }, { x: 0, y: -1 })
    expect(rayCastChainSegment(chain, ray(1.5, 2, 0, -4), out)).toBeNull()
    expect(rayCastSegment(seg, ray(1.5, 2, 0, -4), true, out)).toBeNull()
  })
})

// Brute force: entry fraction by sampling, then bisection on an independent inside test.
function segmentDistance(p: Vec2, a: Vec2, b: Vec2): { d: number; q: Vec2 } {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const l2 = ex * ex + ey * ey
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2)) : 0
  const q = { x: a.x + t * ex, y: a.y + t * ey }
  return { d: Math.hypot(p.x - q.x, p.y - q.y), q }
}
/** Distance from p to the convex polygon (0 inside) and the nearest polygon point. */
function polygonDistance(g: PolygonGeometry, p: Vec2): { d: number; q: Vec2 } {
  let inside = true
  for (let i = 0; i < g.count; i++) {
    if (g.normals[i].x * (p.x - g.vertices[i].x) + g.normals[i].y * (p.y - g.vertices[i].y) > 0)
      inside = false
  }
  if (inside) return { d: 0, q: p }
  let best = { d: Number.POSITIVE_INFINITY, q: p }
  for (let i = 0; i < g.count; i++) {
    const r = segmentDistance(p, g.vertices[i], g.vertices[(i + 1) % g.count])
    if (r.d < best.d) best = r
  }
  return best
}

function bruteEntry(inside: (p: Vec2) => boolean, input: RayCastInput): number | null {
  const at = (t: number) => ({
    x: input.origin.x + t * input.translation.x,
    y: input.origin.y + t * input.translation.y,
  })
  const steps = 20000
  let prev = 0
  for (let k = 1; k <= steps; k++) {
    const t = (input.maxFraction * k) / steps
    if (inside(at(t))) {
      let lo = prev
      let hi = t
      for (let i = 0; i < 80; i++) {
        const mid = 0.5 * (lo + hi)
        if (inside(at(mid))) hi = mid
        else lo = mid
      }
      return hi
    }
    prev = t
  }
  return null
}

describe('ray casts against brute force on random rays', () => {
  const rng = new Prng(7)
  const randomRay = (): RayCastInput => {
    const o = { x: rng.range(-6, 6), y: rng.range(-6, 6) }
    const target = { x: rng.range(-2, 2), y: rng.range(-2, 2) }
    const scale = rng.range(0.6, 2)
    return {
      origin: o,
      translation: { x: scale * (target.x - o.x), y: scale * (target.y - o.y) },
      maxFraction: 1,
    }
  }
  type Kind = {
    name: string
    inside: (p: Vec2) => boolean
    cast: (r: RayCastInput) => CastOutput | null
    normal: (p: Vec2) => Vec2
  }
  const out = makeCastOutput()
  const circleG = { center: { x: 0.3, y: -0.2 }, radius: 1.1 }
  const capsuleG = { center1: { x: -1, y: -0.5 }, center2: { x: 1.2, y: 0.8 }, radius: 0.4 }
  const hexagon = poly(
    Array.from({ length: 6 }, (_, i) => ({
      x: 1.5 * Math.cos((Math.PI * i) / 3 + 0.2),
      y: 1.2 * Math.sin((Math.PI * i) / 3 + 0.2),
    })),
  )
  const roundedHex = { ...hexagon, radius: 0.3 }
  const away = (p: Vec2, q: Vec2) => {
    const l = Math.hypot(p.x - q.x, p.y - q.y)
    return { x: (p.x - q.x) / l, y: (p.y - q.y) / l }
  }
  const kinds: Kind[] = [
    {
      name: 'circle',
      inside: (p) => Math.hypot(p.x - circleG.center.x, p.y - circleG.center.y) <= circleG.radius,
      cast: (r) => rayCastCircle(circleG, r, out),
      normal: (p) => away(p, circleG.center),
    },
    {
      name: 'capsule',
      inside: (p) => segmentDistance(p, capsuleG.center1, capsuleG.center2).d <= capsuleG.radius,
      cast: (r) => rayCastCapsule(capsuleG, r, out),
      normal: (p) => away(p, segmentDistance(p, capsuleG.center1, capsuleG.center2).q),
    },
    {
      name: 'polygon',
      inside: (p) => polygonDistance(hexagon, p).d === 0,
      cast: (r) => rayCastPolygon(hexagon, r, out),
      normal: (p) => {
        let best = 0
        let bestS = Number.NEGATIVE_INFINITY
        for (let i = 0; i < 6; i++) {
          const s =
            hexagon.normals[i].x * (p.x - hexagon.vertices[i].x) +
            hexagon.normals[i].y * (p.y - hexagon.vertices[i].y)
          if (s > bestS) {
            bestS = s
            best = i
          }
        }
        return hexagon.normals[best]
      },
    },
    {
      name: 'rounded polygon',
      inside: (p) => polygonDistance(roundedHex, p).d <= roundedHex.radius,
      cast: (r) => rayCastPolygon(roundedHex, r, out),
      normal: (p) => away(p, polygonDistance(roundedHex, p).q),
    },
  ]
  for (const kind of kinds) {
    it(`${kind.name}: fraction, point and normal within 1e-9 of brute force on 300 rays (hits and misses)`, () => {
      let hits = 0
      let misses = 0
      for (let trial = 0; trial < 300; trial++) {
        const r = randomRay()
        if (kind.inside(r.origin)) continue
        const expected = bruteEntry(kind.inside, r)
        const got = kind.cast(r)
        if (expected === null) {
          expect(got).toBeNull()
          misses++
          continue
        }
        hits++
        expect(got).not.toBeNull()
        const h = got as CastOutput
        const length = Math.hypot(r.translation.x, r.translation.y)
        expect(Math.abs(h.fraction - expected) * length).toBeLessThan(TOL)
        expect(Math.abs(h.point.x - (r.origin.x + h.fraction * r.translation.x))).toBeLessThan(TOL)
        expect(Math.abs(h.point.y - (r.origin.y + h.fraction * r.translation.y))).toBeLessThan(TOL)
        const n = kind.normal(h.point)
        expect(Math.abs(h.normal.x - n.x)).toBeLessThan(1e-7)
        expect(Math.abs(h.normal.y - n.y)).toBeLessThan(1e-7)
      }
      expect(hits).toBeGreaterThan(50)
      expect(misses).toBeGreaterThan(5)
    })
  }
})
