/*
 * GJK distance (engine/queries/shape-distance.ts) and the shape cast (engine/queries/shape-cast.ts) against
 * independent answers: a brute-force distance between convex point sets (edge intersections,
 * containment, then the least point-to-edge distance), closed forms for circle vs circle, box vs
 * box and circle vs segment casts, and for random pairs the first touching fraction found by
 * dense sampling and bisection on the brute-force distance.
 */
import { describe, expect, it } from 'vitest'
import { computeHull } from '../../engine/collision/hull.ts'
import type { Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { type CastOutput, makeCastOutput } from '../../engine/queries/ray-cast.ts'
import { CAST_TOLERANCE, type ShapeCastPairInput, shapeCast } from '../../engine/queries/shape-cast.ts'
import {
  capsuleProxy,
  circleProxy,
  IDENTITY,
  makeDistanceOutput,
  makeShapeProxy,
  type ShapeProxy,
  segmentProxy,
  shapeDistance,
  type Transform,
} from '../../engine/queries/shape-distance.ts'

// ---- brute force geometry on point sets (1 point, 2 points or a CCW convex polygon) ----
const cross = (o: Vec2, a: Vec2, b: Vec2): number => (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
const xfPoint = (t: Transform, p: Vec2): Vec2 => ({
  x: t.x + t.c * p.x - t.s * p.y,
  y: t.y + t.s * p.x + t.c * p.y,
})
const xfOf = (x: number, y: number, angle: number): Transform => ({
  x,
  y,
  c: Math.cos(angle),
  s: Math.sin(angle),
})

function proxyPoints(p: ShapeProxy, t: Transform): Vec2[] {
  const out: Vec2[] = []
  for (let i = 0; i < p.count; i++) out.push(xfPoint(t, { x: p.points[2 * i], y: p.points[2 * i + 1] }))
  return out
}

function pointSegment(p: Vec2, a: Vec2, b: Vec2): { d: number; q: Vec2 } {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const l2 = ex * ex + ey * ey
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2)) : 0
  const q = { x: a.x + t * ex, y: a.y + t * ey }
  return { d: Math.hypot(p.x - q.x, p.y - q.y), q }
}

function edgesOf(ps: Vec2[]): Array<[Vec2, Vec2]> {
  if (ps.length === 1) return [[ps[0], ps[0]]]
  if (ps.length === 2) return [[ps[0], ps[1]]]
  return ps.map((p, i) => [p, ps[(i + 1) % ps.length]] as [Vec2, Vec2])
}

function segmentsCross(a: Vec2, b: Vec2, c: Vec2, d: Vec2): boolean {
  const d1 = cross(c, d, a)
  const d2 = cross(c, d, b)
  const d3 = cross(a, b, c)
  const d4 = cross(a, b, d)
  return d1 * d2 < 0 && d3 * d4 < 0
}

function insidePolygon(ps: Vec2[], p: Vec2): boolean {
  if (ps.length < 3) return false
  for (let i = 0; i < ps.length; i++) if (cross(ps[i], ps[(i + 1) % ps.length], p) < 0) return false
  return true
}

/** Distance between the convex hulls of two point sets, and the closest pair (brute force). */
function bruteDistance(P: Vec2[], Q: Vec2[]): { d: number; a: Vec2; b: Vec2 } {
  for (const [a, b] of edgesOf(P))
    for (const [c, d] of edgesOf(Q)) if (segmentsCross(a, b, c, d)) return { d: 0, a, b: a }
  for (const p of P) if (insidePolygon(Q, p)) return { d: 0, a: p, b: p }
  for (const q of Q) if (insidePolygon(P, q)) return { d: 0, a: q, b: q }
  let best = { d: Number.POSITIVE_INFINITY, a: P[0], b: Q[0] }
  for (const p of P)
    for (const [c, d] of edgesOf(Q)) {
      const r = pointSegment(p, c, d)
      if (r.d < best.d) best = { d: r.d, a: p, b: r.q }
    }
  for (const q of Q)
    for (const [c, d] of edgesOf(P)) {
      const r = pointSegment(q, c, d)
      if (r.d < best.d) best = { d: r.d, a: r.q, b: q }
    }
  return best
}

function polygonProxyOf(points: Vec2[], radius: number): ShapeProxy {
  const hull = computeHull(points)
  const p = makeShapeProxy()
  hull.forEach((v, i) => {
    p.points[2 * i] = v.x
    p.points[2 * i + 1] = v.y
  })
  p.count = hull.length
  p.radius = radius
  return p
}

function randomProxy(rng: Prng): ShapeProxy {
  const kind = rng.int(4)
  const radius = rng.next() < 0.5 ? 0 : rng.range(0.05, 0.6)
  if (kind === 0)
    return circleProxy(
      { center: { x: rng.range(-0.5, 0.5), y: rng.range(-0.5, 0.5) }, radius: Math.max(radius, 0.1) },
      makeShapeProxy(),
    )
  if (kind === 1) {
    const c1 = { x: rng.range(-1, 1), y: rng.range(-1, 1) }
    const c2 = { x: rng.range(-1, 1), y: rng.range(-1, 1) }
    return radius > 0
      ? capsuleProxy({ center1: c1, center2: c2, radius }, makeShapeProxy())
      : segmentProxy({ point1: c1, point2: c2 }, makeShapeProxy())
  }
  for (;;) {
    const pts = Array.from({ length: 3 + rng.int(6) }, () => ({ x: rng.range(-1, 1), y: rng.range(-1, 1) }))
    try {
      return polygonProxyOf(pts, radius)
    } catch {}
  }
}

describe('shapeDistance (GJK) against brute force', () => {
  it('distance, closest points and normal for 2,000 random pairs of circles, segments, capsules and polygons', () => {
    const rng = new Prng(11)
    const out = makeDistanceOutput()
    let separated = 0
    let overlapping = 0
    for (let trial = 0; trial < 2000; trial++) {
      const a = randomProxy(rng)
      const b = randomProxy(rng)
      const ta = xfOf(rng.range(-2, 2), rng.range(-2, 2), rng.range(-3, 3))
      const tb = xfOf(rng.range(-2, 2), rng.range(-2, 2), rng.range(-3, 3))
      const P = proxyPoints(a, ta)
      const Q = proxyPoints(b, tb)
      const brute = bruteDistance(P, Q)
      shapeDistance(a, ta, b, tb, false, out)
      expect(Math.abs(out.distance - brute.d)).toBeLessThan(1e-9)
      if (brute.d === 0) {
        overlapping++
        continue
      }
      separated++
      // The witness points lie on the cores, their distance is the distance, the normal joins them.
      expect(bruteDistance([out.pointA], P).d).toBeLessThan(1e-9)
      expect(bruteDistance([out.pointB], Q).d).toBeLessThan(1e-9)
      expect(
        Math.abs(Math.hypot(out.pointB.x - out.pointA.x, out.pointB.y - out.pointA.y) - brute.d),
      ).toBeLessThan(1e-9)
      expect(Math.abs(out.normal.x - (out.pointB.x - out.pointA.x) / out.distance)).toBeLessThan(1e-6)
      expect(Math.abs(out.normal.y - (out.pointB.y - out.pointA.y) / out.distance)).toBeLessThan(1e-6)
      // With radii: the surface distance.
      shapeDistance(a, ta, b, tb, true, out)
      const surface = Math.max(0, brute.d - a.radius - b.radius)
      if (brute.d > 0.1 * 0.005) expect(Math.abs(out.distance - surface)).toBeLessThan(1e-9)
    }
    expect(separated).toBeGreaterThan(800)
    expect(overlapping).toBeGreaterThan(100)
  })
})

// ---- shape casts ----
const out: CastOutput = makeCastOutput()
function cast(
  a: ShapeProxy,
  ta: Transform,
  b: ShapeProxy,
  tb: Transform,
  dx: number,
  dy: number,
  maxFraction = 1,
): CastOutput | null {
  const input: ShapeCastPairInput = {
    proxyA: a,
    transformA: ta,
    proxyB: b,
    transformB: tb,
    translationB: { x: dx, y: dy },
    maxFraction,
  }
  return shapeCast(input, out)
}
const boxProxy = (hx: number, hy: number, radius = 0): ShapeProxy =>
  polygonProxyOf(
    [
      { x: -hx, y: -hy },
      { x: hx, y: -hy },
      { x: hx, y: hy },
      { x: -hx, y: hy },
    ],
    radius,
  )
const at = (x: number, y: number): Transform => ({ x, y, c: 1, s: 0 })

describe('shapeCast against closed forms', () => {
  it('circle (r 0.3) moving past a circle (r 0.5): the root of |c + t d| = 0.8', () => {
    const a = circleProxy({ center: { x: 0, y: 0 }, radius: 0.5 }, makeShapeProxy())
    const b = circleProxy({ center: { x: 0, y: 0 }, radius: 0.3 }, makeShapeProxy())
    const hit = cast(a, IDENTITY, b, at(-3, 0.4), 6, 0) as CastOutput
    const t = (3 - Math.sqrt(0.48)) / 6
    expect(hit).not.toBeNull()
    expect(Math.abs(hit.fraction - t)).toBeLessThan(1e-6)
    const n = { x: (-3 + 6 * t) / 0.8, y: 0.4 / 0.8 }
    expect(Math.abs(hit.normal.x - n.x)).toBeLessThan(1e-6)
    expect(Math.abs(hit.normal.y - n.y)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.x - 0.5 * n.x)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.y - 0.5 * n.y)).toBeLessThan(1e-6)
  })
  it('box sliding into a box, axis-aligned: face meets face at t = 0.5625, normal (-1, 0), point on the shared face', () => {
    const a = boxProxy(0.5, 0.5)
    const b = boxProxy(0.25, 0.25)
    const hit = cast(a, IDENTITY, b, at(-3, 0.1), 4, 0) as CastOutput
    expect(hit).not.toBeNull()
    expect(Math.abs(hit.fraction - 0.5625)).toBeLessThan(1e-6)
    expect(Math.abs(hit.normal.x + 1)).toBeLessThan(1e-6)
    expect(Math.abs(hit.normal.y)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.x + 0.5)).toBeLessThan(1e-6)
    expect(hit.point.y).toBeGreaterThanOrEqual(-0.15 - 1e-6)
    expect(hit.point.y).toBeLessThanOrEqual(0.35 + 1e-6)
  })
  it('box falling diagonally onto a box: B lands on A top face at t = 0.4', () => {
    const a = boxProxy(2, 0.5)
    const b = boxProxy(0.5, 0.5)
    // B's bottom y = 3 - 0.5 - 5 t reaches 0.5 at t = 0.4; x moves 1 m meanwhile (still over A).
    const hit = cast(a, IDENTITY, b, at(-1, 3), 2.5, -5) as CastOutput
    expect(Math.abs(hit.fraction - 0.4)).toBeLessThan(1e-6)
    expect(Math.abs(hit.normal.y - 1)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.y - 0.5)).toBeLessThan(1e-6)
    expect(hit.point.x).toBeGreaterThanOrEqual(-1.5 - 1e-6) // on B's bottom face at contact: x in [-0.5, 0.5]
    expect(hit.point.x).toBeLessThanOrEqual(0.5 + 1e-6)
  })
  it('rounded boxes (radius 0.1 each) touch 0.2 m earlier than sharp ones', () => {
    const a = boxProxy(0.5, 0.5, 0.1)
    const b = boxProxy(0.25, 0.25, 0.1)
    const hit = cast(a, IDENTITY, b, at(-3, 0.1), 4, 0) as CastOutput
    expect(Math.abs(hit.fraction - (0.5625 - 0.2 / 4))).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.x + 0.6)).toBeLessThan(1e-6)
  })
  it('circle (r 0.2) dropping onto a segment: t = 0.45, normal up; past the end it meets the end point', () => {
    const seg = segmentProxy({ point1: { x: -1, y: 0 }, point2: { x: 1, y: 0 } }, makeShapeProxy())
    const ball = circleProxy({ center: { x: 0, y: 0 }, radius: 0.2 }, makeShapeProxy())
    let hit = cast(seg, IDENTITY, ball, at(0.3, 2), 0, -4) as CastOutput
    expect(Math.abs(hit.fraction - 0.45)).toBeLessThan(1e-6)
    expect(Math.abs(hit.normal.y - 1)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.x - 0.3)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.y)).toBeLessThan(1e-6)
    // Centre at x = 1.1 passes the end (1, 0) at distance 0.2 when y = sqrt(0.04 - 0.01).
    hit = cast(seg, IDENTITY, ball, at(1.1, 2), 0, -4) as CastOutput
    expect(Math.abs(hit.fraction - (2 - Math.sqrt(0.03)) / 4)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.x - 1)).toBeLessThan(1e-6)
    expect(Math.abs(hit.point.y)).toBeLessThan(1e-6)
  })
  it('misses: moving away, passing by, stopping short', () => {
    const a = boxProxy(0.5, 0.5)
    const b = boxProxy(0.25, 0.25)
    expect(cast(a, IDENTITY, b, at(-3, 0.1), -4, 0)).toBeNull()
    expect(cast(a, IDENTITY, b, at(-3, 0.8), 6, 0)).toBeNull()
    expect(cast(a, IDENTITY, b, at(-3, 0.1), 4, 0, 0.56)).toBeNull()
  })
  it('starting in contact or overlapping is a hit at fraction 0 with a zero normal', () => {
    const a = boxProxy(0.5, 0.5)
    const b = boxProxy(0.25, 0.25)
    const hit = cast(a, IDENTITY, b, at(0.6, 0), 1, 0) as CastOutput
    expect(hit.fraction).toBe(0)
    expect(hit.normal).toEqual({ x: 0, y: 0 })
    const c = circleProxy({ center: { x: 0, y: 0 }, radius: 0.5 }, makeShapeProxy())
    const touching = cast(c, IDENTITY, c, at(1, 0), 1, 0) as CastOutput
    expect(touching.fraction).toBe(0)
    expect(Math.abs(touching.point.x - 0.5)).toBeLessThan(1e-9)
  })
  it('rejects bad input by name', () => {
    const a = boxProxy(0.5, 0.5)
    expect(() => cast(a, IDENTITY, a, at(Number.NaN, 0), 1, 0)).toThrow(/transformB must be finite/)
    expect(() => cast(a, IDENTITY, a, at(3, 0), 1, Number.NaN)).toThrow(
      /translationB must be a finite vector/,
    )
    expect(() => cast(a, IDENTITY, a, at(3, 0), 1, 0, -0.5)).toThrow(
      /maxFraction must be a finite number >= 0, got -0.5/,
    )
    const empty = makeShapeProxy()
    expect(() => cast(a, IDENTITY, empty, at(3, 0), 1, 0)).toThrow(/proxyB must have 1 to 8 points, got 0/)
  })
})

describe('shapeCast against bisection on the brute-force distance', () => {
  it('first touching fraction within 1e-6 m of travel for 400 random pairs; point on both surfaces; misses agree', () => {
    const rng = new Prng(3)
    let hits = 0
    let misses = 0
    for (let trial = 0; trial < 400; trial++) {
      const a = randomProxy(rng)
      const b = randomProxy(rng)
      const ta = xfOf(0, 0, rng.range(-3, 3))
      const start = { x: rng.range(-5, 5), y: rng.range(-5, 5) }
      const tb0 = xfOf(start.x, start.y, rng.range(-3, 3))
      const aim = { x: rng.range(-1.5, 1.5), y: rng.range(-1.5, 1.5) }
      const d = { x: 1.5 * (aim.x - start.x), y: 1.5 * (aim.y - start.y) }
      const total = a.radius + b.radius
      const P = proxyPoints(a, ta)
      const gap = (t: number) =>
        bruteDistance(P, proxyPoints(b, { ...tb0, x: start.x + t * d.x, y: start.y + t * d.y })).d - total
      if (gap(0) <= 1e-6) continue
      // Dense sampling for the first touching step, then bisection.
      let expected: number | null = null
      const steps = 4000
      for (let k = 1; k <= steps; k++) {
        if (gap(k / steps) <= 0) {
          let lo = (k - 1) / steps
          let hi = k / steps
          for (let i = 0; i < 60; i++) {
            const mid = 0.5 * (lo + hi)
            if (gap(mid) <= 0) hi = mid
            else lo = mid
          }
          expected = hi
          break
        }
      }
      const hit = cast(a, ta, b, tb0, d.x, d.y)
      const length = Math.hypot(d.x, d.y)
      if (expected === null) {
        expect(hit).toBeNull()
        misses++
        continue
      }
      expect(hit, `trial ${trial}`).not.toBeNull()
      const h = hit as CastOutput
      hits++
      expect(Math.abs(h.fraction - expected) * length, `trial ${trial}`).toBeLessThan(1e-6)
      // The point is on A's surface and on B's surface at the contact pose.
      const tbHit = { ...tb0, x: start.x + h.fraction * d.x, y: start.y + h.fraction * d.y }
      expect(Math.abs(bruteDistance([h.point], P).d - a.radius), `trial ${trial}`).toBeLessThan(1e-6)
      expect(
        Math.abs(bruteDistance([h.point], proxyPoints(b, tbHit)).d - b.radius),
        `trial ${trial}`,
      ).toBeLessThan(1e-6)
      // The normal is unit and opposes the motion.
      expect(Math.abs(Math.hypot(h.normal.x, h.normal.y) - 1)).toBeLessThan(1e-9)
      expect(h.normal.x * d.x + h.normal.y * d.y).toBeLessThan(0)
    }
    console.log(`shape casts: ${hits} hits, ${misses} misses checked`)
    expect(hits).toBeGreaterThan(100)
    expect(misses).toBeGreaterThan(20)
    expect(CAST_TOLERANCE).toBe(1e-9)
  })
})
