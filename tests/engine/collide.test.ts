/*
 * Narrowphase tests. Oracles: hand computations, a world-space box-box collider in the manner of
 * Box2D Lite (SAT over the four box axes, ClipSegmentToLine), a brute-force directional SAT over every
 * edge normal of two convex polygons, and a brute-force closest point on a polygon's boundary.
 */
import { describe, expect, it } from 'vitest'
import { collideShapes, REFERENCE_FACE_TOLERANCE } from '../../engine/collide.ts'
import { Manifold } from '../../engine/manifold.ts'
import { cos, PI, sin, type Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { box, circle, type PolygonShape, polygon, type Shape } from '../../engine/shapes.ts'

const SPEC = 0.02
const SLOP = 0.005

interface Xf {
  x: number
  y: number
  c: number
  s: number
}
const xf = (x: number, y: number, angle = 0): Xf => ({ x, y, c: cos(angle), s: sin(angle) })

function collide(a: Shape, ta: Xf, b: Shape, tb: Xf, spec = SPEC): Manifold {
  const m = new Manifold()
  collideShapes(a, ta.x, ta.y, ta.c, ta.s, b, tb.x, tb.y, tb.c, tb.s, spec, m)
  return m
}

interface Pt {
  x: number
  y: number
  sep: number
}
const pts = (m: Manifold): Pt[] =>
  m.points.slice(0, m.pointCount).map((p) => ({ x: p.x, y: p.y, sep: p.separation }))
const toWorld = (t: Xf, p: Vec2): Vec2 => ({ x: t.x + t.c * p.x - t.s * p.y, y: t.y + t.s * p.x + t.c * p.y })
const rotate = (t: Xf, p: Vec2): Vec2 => ({ x: t.c * p.x - t.s * p.y, y: t.s * p.x + t.c * p.y })
const dot = (a: Vec2, b: Vec2) => a.x * b.x + a.y * b.y
const sub = (a: Vec2, b: Vec2): Vec2 => ({ x: a.x - b.x, y: a.y - b.y })

function expectManifold(m: Manifold, normal: Vec2, expected: Pt[], tol = 1e-12): void {
  expect(m.pointCount).toBe(expected.length)
  expect(Math.abs(m.normalX - normal.x)).toBeLessThan(tol)
  expect(Math.abs(m.normalY - normal.y)).toBeLessThan(tol)
  expectSamePoints(pts(m), expected, tol, tol)
}

/** Each point of `a` matches a distinct point of `b` (greedy nearest, fine for 1-2 points). */
function expectSamePoints(a: Pt[], b: Pt[], posTol: number, sepTol: number): void {
  expect(a.length).toBe(b.length)
  const used = new Set<number>()
  for (const p of a) {
    let best = -1
    let bestD = Number.POSITIVE_INFINITY
    b.forEach((q, k) => {
      const d = Math.hypot(p.x - q.x, p.y - q.y)
      if (!used.has(k) && d < bestD) {
        bestD = d
        best = k
      }
    })
    used.add(best)
    expect(bestD).toBeLessThan(posTol)
    expect(Math.abs(p.sep - b[best].sep)).toBeLessThan(sepTol)
  }
}

describe('hand-computed manifolds', () => {
  const unit = box(0.5, 0.5)

  it('two unit boxes overlapping by 0.1 along x: normal +x, two points at depth 0.1 halfway in', () => {
    const m = collide(unit, xf(0, 0), unit, xf(0.9, 0))
    expectManifold(m, { x: 1, y: 0 }, [
      { x: 0.45, y: -0.5, sep: -0.1 },
      { x: 0.45, y: 0.5, sep: -0.1 },
    ])
    expect(m.points[0].id).not.toBe(m.points[1].id)
  })

  it('a box resting 0.01 deep on a wide box: normal up, the two bottom corners', () => {
    const m = collide(box(10, 1), xf(0, -1), unit, xf(2, 0.49))
    expectManifold(m, { x: 0, y: 1 }, [
      { x: 1.5, y: -0.005, sep: -0.01 },
      { x: 2.5, y: -0.005, sep: -0.01 },
    ])
  })

  it('a box rotated 45 degrees pushes one corner 0.05 into a face: one point', () => {
    const m = collide(box(5, 0.5), xf(0, 0), unit, xf(0, 0.5 + Math.sqrt(0.5) - 0.05, PI / 4))
    expectManifold(m, { x: 0, y: 1 }, [{ x: 0, y: 0.475, sep: -0.05 }], 1e-12)
  })

  it('the same contact with A and B swapped: normal down, same point', () => {
    const m = collide(unit, xf(0, 0.5 + Math.sqrt(0.5) - 0.05, PI / 4), box(5, 0.5), xf(0, 0))
    expectManifold(m, { x: 0, y: -1 }, [{ x: 0, y: 0.475, sep: -0.05 }], 1e-12)
  })

  it('a small box deep inside a big one is pushed out through the nearest face', () => {
    const m = collide(box(1, 1), xf(0, 0), box(0.1, 0.1), xf(0.25, 0.1))
    expectManifold(m, { x: 1, y: 0 }, [
      { x: 0.575, y: 0, sep: -0.85 },
      { x: 0.575, y: 0.2, sep: -0.85 },
    ])
  })

  it('circle against circle: centre-to-centre normal, midpoint between surfaces', () => {
    const m = collide(circle(0.5), xf(0, 0), circle(0.3), xf(0.45, 0.6))
    expectManifold(m, { x: 0.6, y: 0.8 }, [{ x: 0.285, y: 0.38, sep: -0.05 }])
  })

  it('coincident circles get the documented fixed normal (1, 0)', () => {
    const m = collide(circle(0.5), xf(1, 2), circle(0.25), xf(1, 2))
    expectManifold(m, { x: 1, y: 0 }, [{ x: 1.125, y: 2, sep: -0.75 }])
  })

  it('circle against a box face, also with the box turned 90 degrees', () => {
    const m = collide(box(1, 0.5), xf(0, 0), circle(0.25), xf(0.3, 0.7))
    expectManifold(m, { x: 0, y: 1 }, [{ x: 0.3, y: 0.475, sep: -0.05 }])
    const turned = collide(box(1, 0.5), xf(1, 2, PI / 2), circle(0.25), xf(1.7, 2.3))
    expectManifold(turned, { x: 1, y: 0 }, [{ x: 1.475, y: 2.3, sep: -0.05 }], 1e-12)
  })

  it('circle in a box corner region: normal from the corner, either order', () => {
    const m = collide(unit, xf(0, 0), circle(0.2), xf(0.59, 0.62))
    expectManifold(m, { x: 0.6, y: 0.8 }, [{ x: 0.485, y: 0.48, sep: -0.05 }])
    const swapped = collide(circle(0.2), xf(0.59, 0.62), unit, xf(0, 0))
    expectManifold(swapped, { x: -0.6, y: -0.8 }, [{ x: 0.485, y: 0.48, sep: -0.05 }])
  })

  it('shapes apart by less than the speculative distance report a positive separation', () => {
    const boxes = collide(unit, xf(0, 0), unit, xf(1.01, 0))
    expectManifold(boxes, { x: 1, y: 0 }, [
      { x: 0.505, y: -0.5, sep: 0.01 },
      { x: 0.505, y: 0.5, sep: 0.01 },
    ])
    const circles = collide(circle(0.5), xf(0, 0), circle(0.5), xf(0, 1.015))
    expectManifold(circles, { x: 0, y: 1 }, [{ x: 0, y: 0.5075, sep: 0.015 }])
    const boxCircle = collide(unit, xf(0, 0), circle(0.5), xf(0, 1.015))
    expectManifold(boxCircle, { x: 0, y: 1 }, [{ x: 0, y: 0.5075, sep: 0.015 }])
  })

  it('corner to corner apart: one point along the vertex-to-vertex direction', () => {
    const m = collide(unit, xf(0, 0), unit, xf(1.006, 1.008))
    expectManifold(m, { x: 0.6, y: 0.8 }, [{ x: 0.503, y: 0.504, sep: 0.01 }])
  })

  it('shapes farther apart than the speculative distance give no points', () => {
    expect(collide(unit, xf(0, 0), unit, xf(1.03, 0)).pointCount).toBe(0)
    expect(collide(unit, xf(0, 0), unit, xf(1.016, 1.016)).pointCount).toBe(0)
    expect(collide(circle(0.5), xf(0, 0), circle(0.5), xf(1.021, 0)).pointCount).toBe(0)
    expect(collide(unit, xf(0, 0), circle(0.5), xf(0, 1.021)).pointCount).toBe(0)
    expect(collide(circle(0.5), xf(0, 50), unit, xf(0, 0)).pointCount).toBe(0)
  })
})
