/*
 * computeHull (engine/collision/hull.ts) against brute force: for points in general position (no two within
 * 0.1 m, none within 0.05 m of a line through two others, so welding and collinear removal do not
 * apply) a point is a hull vertex exactly when it lies in no triangle of three other points, and a
 * counter-clockwise hull has every other point strictly left of each of its edges. Then the slop
 * rules (welding, collinear removal) on hand-made cases, and every error.
 */
import { describe, expect, it } from 'vitest'
import { computeHull, HULL_COLLINEAR_DISTANCE, HULL_WELD_DISTANCE } from '../../engine/collision/hull.ts'
import { LINEAR_SLOP } from '../../engine/constants.ts'
import type { Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'

const cross = (o: Vec2, a: Vec2, b: Vec2): number => (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)

/** Is p strictly inside triangle abc (either winding)? */
function inTriangle(p: Vec2, a: Vec2, b: Vec2, c: Vec2): boolean {
  const d1 = cross(a, b, p)
  const d2 = cross(b, c, p)
  const d3 = cross(c, a, p)
  return (d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0)
}

/** Indices of the points that lie in no triangle of three others (the hull vertices, brute force). */
function bruteHullIndices(ps: readonly Vec2[]): number[] {
  const out: number[] = []
  const n = ps.length
  for (let i = 0; i < n; i++) {
    let inside = false
    for (let a = 0; a < n && !inside; a++) {
      for (let b = a + 1; b < n && !inside; b++) {
        for (let c = b + 1; c < n && !inside; c++) {
          if (a === i || b === i || c === i) continue
          inside = inTriangle(ps[i], ps[a], ps[b], ps[c])
        }
      }
    }
    if (!inside) out.push(i)
  }
  return out
}

function distanceToLine(p: Vec2, a: Vec2, b: Vec2): number {
  const ex = b.x - a.x
  const ey = b.y - a.y
  return Math.abs(cross(a, b, p)) / Math.sqrt(ex * ex + ey * ey)
}

/** n random points in a 10 m square, in general position (rejection sampling). */
function generalPosition(rng: Prng, n: number): Vec2[] {
  for (;;) {
    const ps: Vec2[] = []
    for (let i = 0; i < n; i++) ps.push({ x: rng.range(-5, 5), y: rng.range(-5, 5) })
    let ok = true
    for (let i = 0; i < n && ok; i++) {
      for (let j = i + 1; j < n && ok; j++) {
        if (Math.hypot(ps[i].x - ps[j].x, ps[i].y - ps[j].y) < 0.1) ok = false
        for (let k = 0; k < n && ok; k++) {
          if (k !== i && k !== j && distanceToLine(ps[k], ps[i], ps[j]) < 0.05) ok = false
        }
      }
    }
    if (ok) return ps
  }
}

describe('computeHull against brute force', () => {
  it('finds exactly the points in no triangle of three others, counter-clockwise, for 600 random sets', () => {
    const rng = new Prng(27)
    let tooMany = 0
    let checked = 0
    for (let trial = 0; trial < 600; trial++) {
      const n = 3 + (trial % 10)
      const ps = generalPosition(rng, n)
      const expected = bruteHullIndices(ps)
      if (expected.length > 8) {
        expect(() => computeHull(ps)).toThrow(/more than 8/)
        tooMany++
        continue
      }
      const hull = computeHull(ps)
      checked++
      // Same vertex set (each hull vertex is an input point, by value).
      const got = hull.map((h) => ps.findIndex((p) => p.x === h.x && p.y === h.y)).sort((a, b) => a - b)
      expect(got).toEqual(expected)
      // Every input point that is not an edge's end is strictly left of every edge: CCW and convex.
      for (let i = 0; i < hull.length; i++) {
        const a = hull[i]
        const b = hull[(i + 1) % hull.length]
        for (const p of ps) {
          if ((p.x === a.x && p.y === a.y) || (p.x === b.x && p.y === b.y)) continue
          expect(cross(a, b, p)).toBeGreaterThan(0)
        }
      }
    }
    expect(checked).toBeGreaterThan(400)
    expect(tooMany).toBeGreaterThan(0)
  })

  it('gives the same hull, bit for bit, twice, and the same vertex set for a permuted input', () => {
    const rng = new Prng(5)
    for (let trial = 0; trial < 100; trial++) {
      const ps = generalPosition(rng, 7)
      const a = computeHull(ps)
      expect(computeHull(ps)).toEqual(a)
      const reversed = computeHull([...ps].reverse())
      const key = (v: Vec2) => `${v.x},${v.y}`
      expect(reversed.map(key).sort()).toEqual(a.map(key).sort())
    }
  })

  it('keeps every input point inside the hull or within the slop rules of it, even for near-degenerate sets', () => {
    // Clusters and near-lines: points may be welded (<= 0.02 m away) or dropped as collinear (<= 0.01 m).
    const rng = new Prng(99)
    let built = 0
    for (let trial = 0; trial < 500; trial++) {
      const n = 3 + (trial % 8)
      const ps: Vec2[] = []
      for (let i = 0; i < n; i++) {
        const base = rng.int(3)
        const jitter = rng.next() < 0.3 ? 0.03 : 2
        ps.push({ x: base + rng.range(-jitter, jitter), y: base * 0.5 + rng.range(-jitter, jitter) })
      }
      let hull: Vec2[]
      try {
        hull = computeHull(ps)
      } catch (e) {
        expect(e).toBeInstanceOf(RangeError)
        continue
      }
      built++
      expect(hull.length).toBeGreaterThanOrEqual(3)
      expect(hull.length).toBeLessThanOrEqual(8)
      for (let i = 0; i < hull.length; i++) {
        const a = hull[i]
        const b = hull[(i + 1) % hull.length]
        const c = hull[(i + 2) % hull.length]
        // Strictly convex with Box2D's margin: the middle vertex is more than 2 slop left of a -> c.
        expect(cross(a, c, b) / Math.hypot(c.x - a.x, c.y - a.y)).toBeLessThan(-HULL_COLLINEAR_DISTANCE)
        for (const p of ps) {
          const outside = -cross(a, b, p) / Math.hypot(b.x - a.x, b.y - a.y)
          expect(outside).toBeLessThanOrEqual(HULL_WELD_DISTANCE + HULL_COLLINEAR_DISTANCE + 1e-12)
        }
      }
    }
    expect(built).toBeGreaterThan(200)
  })
})

describe('computeHull slop rules (Box2D v3 hull.c)', () => {
  const square = [
    { x: 0, y: 0 },
    { x: 1, y: 0 },
    { x: 1, y: 1 },
    { x: 0, y: 1 },
  ]

  it('returns a square counter-clockwise from either winding', () => {
    const ccw = computeHull(square)
    const cw = computeHull([...square].reverse())
    for (const h of [ccw, cw]) {
      expect(h).toHaveLength(4)
      let area2 = 0
      for (let i = 0; i < 4; i++) area2 += h[i].x * h[(i + 1) % 4].y - h[(i + 1) % 4].x * h[i].y
      expect(area2).toBe(2)
    }
  })

  it('welds a point closer than 4 slop to an earlier one, keeping the earlier point', () => {
    const near = { x: 1 + 0.7 * HULL_WELD_DISTANCE, y: 1 }
    const hull = computeHull([...square, near])
    expect(hull).toHaveLength(4)
    expect(hull).toContainEqual({ x: 1, y: 1 })
    expect(hull).not.toContainEqual(near)
    // Just outside the weld distance (and far from collinear) it is a vertex.
    const apart = { x: 1 + 1.5 * HULL_WELD_DISTANCE, y: 1 + 1.5 * HULL_WELD_DISTANCE }
    expect(computeHull([...square, apart])).toContainEqual(apart)
  })

  it('drops a vertex within 2 slop of its neighbours line, keeps one farther out', () => {
    const bump = (d: number) => computeHull([...square.slice(0, 2), { x: 1 + d, y: 0.5 }, ...square.slice(2)])
    expect(bump(0.9 * HULL_COLLINEAR_DISTANCE)).toHaveLength(4)
    expect(bump(1.1 * HULL_COLLINEAR_DISTANCE)).toHaveLength(5)
    expect(bump(1.1 * HULL_COLLINEAR_DISTANCE)).toContainEqual({
      x: 1 + 1.1 * HULL_COLLINEAR_DISTANCE,
      y: 0.5,
    })
  })

  it('keeps the first of two equally distant extreme points (deterministic ties)', () => {
    const hull = computeHull([
      { x: -1, y: -1 },
      { x: 1, y: -1 },
      { x: 1, y: 1 },
      { x: -1, y: 1 },
    ])
    expect(hull[0]).toEqual({ x: -1, y: -1 })
  })
})

describe('computeHull errors name the problem', () => {
  it('rejects fewer than 3 and more than 64 points', () => {
    expect(() => computeHull(square2())).toThrow(/3 to 64 points, got 2/)
    const many = Array.from({ length: 65 }, (_, i) => ({ x: i, y: (i * i) % 7 }))
    expect(() => computeHull(many)).toThrow(/got 65/)
  })
  it('rejects a non-finite coordinate, naming its index', () => {
    expect(() =>
      computeHull([
        { x: 0, y: 0 },
        { x: 1, y: 0 },
        { x: Number.NaN, y: 1 },
      ]),
    ).toThrow(/point 2 is not a finite point/)
  })
  it('rejects points that weld to fewer than 3', () => {
    expect(() =>
      computeHull([
        { x: 0, y: 0 },
        { x: 0.01, y: 0 },
        { x: 0, y: 0.01 },
        { x: 3, y: 3 },
      ]),
    ).toThrow(/weld to 2 distinct points/)
  })
  it('rejects collinear points, also with noise below 2 slop', () => {
    const line = Array.from({ length: 6 }, (_, i) => ({
      x: i,
      y: 2 * i + (i % 2 ? LINEAR_SLOP : -LINEAR_SLOP) * 0.9,
    }))
    expect(() => computeHull(line)).toThrow(/lie within 0.01 m of one line/)
  })
  it('rejects a hull of 9 vertices', () => {
    // A regular 9-gon, vertices from the engine-independent reference Math (test code only).
    const nine = Array.from({ length: 9 }, (_, i) => ({
      x: Math.cos((2 * Math.PI * i) / 9),
      y: Math.sin((2 * Math.PI * i) / 9),
    }))
    expect(() => computeHull(nine)).toThrow(/hull has 9 vertices, more than 8/)
  })
})

function square2(): Vec2[] {
  return [
    { x: 0, y: 0 },
    { x: 1, y: 0 },
  ]
}
