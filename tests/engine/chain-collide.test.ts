/*
 * Chain segments in the narrowphase (engine/collision/chain-collide.ts). Oracles: hand-computed
 * manifolds on flat and bent chains, a two-sided segment() of the same geometry (what the ghost
 * vertices and the one-sided rule change), and a brute-force distance from a shape to the whole
 * chain polyline (every vertex against every edge), which the deepest point over all the chain's
 * segments must reproduce for shapes in front of the chain.
 */
import { describe, expect, it } from 'vitest'
import { collideShapes } from '../../engine/collision/collide.ts'
import { Manifold } from '../../engine/collision/manifold.ts'
import {
  box,
  type ChainSegmentShape,
  capsule,
  chain,
  circle,
  polygon,
  type Shape,
  segment,
} from '../../engine/collision/shapes.ts'
import { cos, sin, type Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { makeCastOutput, rayCastChainSegment } from '../../engine/queries/ray-cast.ts'

const SPEC = 0.02

interface Xf {
  x: number
  y: number
  c: number
  s: number
}
const xf = (x: number, y: number, angle = 0): Xf => ({ x, y, c: cos(angle), s: sin(angle) })
const ORIGIN = xf(0, 0)

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

/** Expects the normal and the points (in any order) within tol. */
function expectManifold(m: Manifold, normal: Vec2, expected: Pt[], tol = 1e-12): void {
  expect(m.pointCount, 'point count').toBe(expected.length)
  expect(Math.abs(m.normalX - normal.x) + Math.abs(m.normalY - normal.y), 'normal').toBeLessThanOrEqual(tol)
  const got = pts(m).sort((a, b) => a.x - b.x || a.y - b.y)
  const want = [...expected].sort((a, b) => a.x - b.x || a.y - b.y)
  for (let i = 0; i < got.length; i++) {
    expect(Math.abs(got[i].x - want[i].x), `point ${i} x`).toBeLessThanOrEqual(tol)
    expect(Math.abs(got[i].y - want[i].y), `point ${i} y`).toBeLessThanOrEqual(tol)
    expect(Math.abs(got[i].sep - want[i].sep), `point ${i} separation`).toBeLessThanOrEqual(tol)
  }
}

/** A flat floor at y = 0 from x = 3 to x = -3 (right to left: the normal is up), segments of 2 m. */
const floor = chain([
  { x: 5, y: 0 },
  { x: 3, y: 0 },
  { x: 1, y: 0 },
  { x: -1, y: 0 },
  { x: -3, y: 0 },
  { x: -5, y: 0 },
])
/** The floor's segment over x in [-1, 1]. */
const middle = floor.segments[1]

describe('chain() geometry', () => {
  it('an open chain of n points has n - 3 segments, ghosts from the neighbours; the normal is the right of travel', () => {
    expect(floor.segments.length).toBe(3)
    expect(middle.vertices).toEqual([
      { x: 1, y: 0 },
      { x: -1, y: 0 },
    ])
    expect(middle.ghost1).toEqual({ x: 3, y: 0 })
    expect(middle.ghost2).toEqual({ x: -3, y: 0 })
    // Travel is -x; its right is +y.
    expect(middle.normals[0].x).toBeCloseTo(0, 15)
    expect(middle.normals[0].y).toBe(1)
  })

  it('a loop of n points has n segments; each ghost is the point before or after', () => {
    const square = chain(
      [
        { x: 0, y: 0 },
        { x: 1, y: 0 },
        { x: 1, y: 1 },
        { x: 0, y: 1 },
      ],
      { loop: true },
    )
    expect(square.segments.length).toBe(4)
    const s0 = square.segments[0]
    expect(s0.ghost1).toEqual({ x: 0, y: 1 })
    expect(s0.vertices).toEqual([
      { x: 0, y: 0 },
      { x: 1, y: 0 },
    ])
    expect(s0.ghost2).toEqual({ x: 1, y: 1 })
    // Counter-clockwise: the bottom edge's normal points down, out of the square (solid inside).
    expect(s0.normals[0]).toEqual({ x: 0, y: -1 })
  })

  it('bad input throws a RangeError naming the problem', () => {
    const line = (n: number) => Array.from({ length: n }, (_, i) => ({ x: i, y: 0 }))
    expect(() => chain(line(3))).toThrow(/open chain needs 4 to 2048 points, got 3/)
    expect(() => chain(line(2), { loop: true })).toThrow(/chain loop needs 3 to 2048 points, got 2/)
    expect(() => chain(line(2049))).toThrow(/got 2049/)
    expect(() => chain([...line(3), { x: Number.NaN, y: 0 }])).toThrow(/chain point 3 must be a finite point/)
    expect(() => chain([...line(3), { x: 2.001, y: 0 }])).toThrow(
      /chain points 2 and 3 .* closer than 0.005 m: a zero-length or near-duplicate segment/,
    )
    expect(() => chain([...line(4), { x: 0, y: 0 }], { loop: true })).toThrow(
      /the last point and the first \(a loop closes itself\)/,
    )
    expect(() => chain([...line(3), { x: 2e5, y: 0 }])).toThrow(/more than 100000 m from the body origin/)
    expect(() => chain(line(4), { loop: 'yes' as unknown as boolean })).toThrow(
      /chain loop must be true or false/,
    )
    expect(() => chain('points' as unknown as Vec2[])).toThrow(/chain points must be an array/)
  })
})

describe('chain segment manifolds, by hand', () => {
  it('circle 1 cm into the floor: normal up, point halfway between the surfaces', () => {
    const m = collide(middle, ORIGIN, circle(0.5), xf(0.2, 0.49))
    expectManifold(m, { x: 0, y: 1 }, [{ x: 0.2, y: -0.005, sep: -0.01 }])
  })

  it('the same with the chain as shape B: normal from A to B is down', () => {
    const m = collide(circle(0.5), xf(0.2, 0.49), middle, ORIGIN)
    expectManifold(m, { x: 0, y: -1 }, [{ x: 0.2, y: -0.005, sep: -0.01 }])
  })

  it('one-sided: a circle below the floor gets no contact (a two-sided segment pushes it down)', () => {
    expect(collide(middle, ORIGIN, circle(0.5), xf(0.2, -0.49)).pointCount).toBe(0)
    const two = collide(segment({ x: 1, y: 0 }, { x: -1, y: 0 }), ORIGIN, circle(0.5), xf(0.2, -0.49))
    expectManifold(two, { x: 0, y: -1 }, [{ x: 0.2, y: 0.005, sep: -0.01 }])
  })

  it('a circle over the next segment belongs to that segment only', () => {
    // Centre at x = -1.3: past this segment's end p2 = (-1, 0), over the next segment.
    expect(collide(middle, ORIGIN, circle(0.5), xf(-1.3, 0.49)).pointCount).toBe(0)
    const next = collide(floor.segments[2], ORIGIN, circle(0.5), xf(-1.3, 0.49))
    expectManifold(next, { x: 0, y: 1 }, [{ x: -1.3, y: -0.005, sep: -0.01 }])
  })

  it('a circle at a convex corner (hilltop) touches the vertex, from both segments', () => {
    const roof = chain([
      { x: 4, y: -2 },
      { x: 2, y: -1 },
      { x: 0, y: 0 },
      { x: -2, y: -1 },
      { x: -4, y: -2 },
    ])
    // Straight above the apex: the vertex region of both segments; normal up, 1 cm deep.
    for (const s of roof.segments) {
      expectManifold(collide(s, ORIGIN, circle(0.5), xf(0, 0.49)), { x: 0, y: 1 }, [
        { x: 0, y: -0.005, sep: -0.01 },
      ])
    }
  })

  it('capsule lying on the floor: two points at its ends, separation = gap less radius', () => {
    const m = collide(middle, ORIGIN, capsule({ x: -0.5, y: 0 }, { x: 0.5, y: 0 }, 0.25), xf(0, 0.24))
    expectManifold(m, { x: 0, y: 1 }, [
      { x: -0.5, y: -0.005, sep: -0.01 },
      { x: 0.5, y: -0.005, sep: -0.01 },
    ])
  })

  it('rounded box on the floor: the rounding counts, points midway', () => {
    const rounded = polygon(
      [
        { x: -0.4, y: -0.4 },
        { x: 0.4, y: -0.4 },
        { x: 0.4, y: 0.4 },
        { x: -0.4, y: 0.4 },
      ],
      0.1,
    )
    const m = collide(middle, ORIGIN, rounded, xf(0.1, 0.49))
    expectManifold(m, { x: 0, y: 1 }, [
      { x: -0.3, y: -0.005, sep: -0.01 },
      { x: 0.5, y: -0.005, sep: -0.01 },
    ])
  })

  it('a box straddling a join: each segment clips the box to its own extent, both normals up', () => {
    const b = box(0.5, 0.5)
    // Box centred on the join x = 1, 1 cm deep.
    const left = collide(middle, ORIGIN, b, xf(1, 0.49))
    expectManifold(left, { x: 0, y: 1 }, [
      { x: 0.5, y: -0.005, sep: -0.01 },
      { x: 1, y: -0.005, sep: -0.01 },
    ])
    const right = collide(floor.segments[0], ORIGIN, b, xf(1, 0.49))
    expectManifold(right, { x: 0, y: 1 }, [
      { x: 1, y: -0.005, sep: -0.01 },
      { x: 1.5, y: -0.005, sep: -0.01 },
    ])
  })

  it('ghost vertices: a box corner 2 mm past a flat join gets the floor normal, where a lone segment catches it', () => {
    const b = box(0.5, 0.5)
    // The box's right side at x = 1.002, 1 cm deep: it overlaps the segment over x in [1, 3] by 2 mm.
    const at = xf(0.502, 0.49)
    const m = collide(floor.segments[0], ORIGIN, b, at)
    expectManifold(m, { x: 0, y: 1 }, [
      { x: 1, y: -0.005, sep: -0.01 },
      { x: 1.002, y: -0.005, sep: -0.01 },
    ])
    // A two-sided segment of the same geometry takes the box's side as the reference face: the
    // normal pushes the box back along the floor (the "ghost collision" chains exist to avoid).
    const lone = collide(segment({ x: 3, y: 0 }, { x: 1, y: 0 }), ORIGIN, b, at)
    expect(lone.normalX).toBeLessThan(-0.99)
  })

  it('a box 1 cm above a hilltop: one speculative point at the apex, normal up', () => {
    const roof = chain([
      { x: 4, y: -2 },
      { x: 2, y: -1 },
      { x: 0, y: 0 },
      { x: -2, y: -1 },
      { x: -4, y: -2 },
    ])
    for (const s of roof.segments) {
      expectManifold(collide(s, ORIGIN, box(0.5, 0.5), xf(0, 0.51)), { x: 0, y: 1 }, [
        { x: 0, y: 0.005, sep: 0.01 },
      ])
    }
  })

  it('a box corner 1 cm from a hilltop apex, diagonally: one point along the vertex-to-vertex line', () => {
    const roof = chain([
      { x: 4, y: -2 },
      { x: 2, y: -1 },
      { x: 0, y: 0 },
      { x: -2, y: -1 },
      { x: -4, y: -2 },
    ])
    // The box's bottom-left corner at (0.0028, 0.0096): distance 0.01 along (0.28, 0.96), which
    // lies between the two segments' normals (1, 2)/sqrt 5 and (-1, 2)/sqrt 5 (the apex's vertex
    // region): admitted by both.
    const at = xf(0.5028, 0.5096)
    for (const s of roof.segments) {
      expectManifold(
        collide(s, ORIGIN, box(0.5, 0.5), at),
        { x: 0.28, y: 0.96 },
        [{ x: 0.0014, y: 0.0048, sep: 0.01 }],
        1e-12,
      )
    }
  })

  it('one-sided for polygons: a box under the floor gets no contact', () => {
    expect(collide(middle, ORIGIN, box(0.5, 0.5), xf(0, -0.49)).pointCount).toBe(0)
    expect(
      collide(middle, ORIGIN, capsule({ x: -0.5, y: 0 }, { x: 0.5, y: 0 }, 0.25), xf(0, -0.2)).pointCount,
    ).toBe(0)
  })
})

/** The point of segment a-b nearest p. */
function nearestOnSegment(p: Vec2, a: Vec2, b: Vec2): Vec2 {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const t = Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey)))
  return { x: a.x + t * ex, y: a.y + t * ey }
}

const orient = (a: Vec2, b: Vec2, c: Vec2) => (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)

/** Distance between segments a1-a2 and b1-b2: 0 if they cross, else every end against the other segment. */
function segmentDistance(a1: Vec2, a2: Vec2, b1: Vec2, b2: Vec2): number {
  const d = (p: Vec2, q: Vec2) => Math.hypot(p.x - q.x, p.y - q.y)
  if (orient(a1, a2, b1) * orient(a1, a2, b2) < 0 && orient(b1, b2, a1) * orient(b1, b2, a2) < 0) return 0
  return Math.min(
    d(a1, nearestOnSegment(a1, b1, b2)),
    d(a2, nearestOnSegment(a2, b1, b2)),
    d(b1, nearestOnSegment(b1, a1, a2)),
    d(b2, nearestOnSegment(b2, a1, a2)),
  )
}

/** A random terrain: points right to left, heights within +-0.6 m, 1 to 2 m apart. */
function terrain(rng: Prng, n: number): Vec2[] {
  const points: Vec2[] = []
  let x = 0
  for (let i = 0; i < n; i++) {
    points.push({ x, y: 0.6 * (2 * rng.next() - 1) })
    x -= 1 + rng.next()
  }
  return points
}

/** Deepest separation and its normal over all segments of a chain. */
function deepest(
  segments: readonly ChainSegmentShape[],
  shape: Shape,
  at: Xf,
): { sep: number; normal: Vec2 } | null {
  let best: { sep: number; normal: Vec2 } | null = null
  for (const s of segments) {
    const m = collide(s, ORIGIN, shape, at)
    for (let i = 0; i < m.pointCount; i++) {
      if (best === null || m.points[i].separation < best.sep)
        best = { sep: m.points[i].separation, normal: { x: m.normalX, y: m.normalY } }
    }
  }
  return best
}

describe('chain segments against a brute-force distance to the whole chain', () => {
  it('circles in front of a random terrain: deepest separation = distance to the polyline less r, normal along it', () => {
    const rng = new Prng(7)
    let checked = 0
    for (let trial = 0; trial < 40; trial++) {
      const points = terrain(rng, 12)
      const c = chain(points)
      // Interior points only (the open chain's first and last are ghosts).
      const inner = points.slice(1, -1)
      for (let k = 0; k < 50; k++) {
        const r = 0.1 + 0.4 * rng.next()
        const x = inner[2].x + (inner[inner.length - 3].x - inner[2].x) * rng.next()
        // Place the centre at a random height and keep cases near the surface.
        const y = -1 + 3 * rng.next()
        let bestD = Number.POSITIVE_INFINITY
        let bestQ = { x: 0, y: 0 }
        for (let i = 0; i + 1 < inner.length; i++) {
          const q = nearestOnSegment({ x, y }, inner[i], inner[i + 1])
          const d = Math.hypot(x - q.x, y - q.y)
          if (d < bestD) {
            bestD = d
            bestQ = q
          }
        }
        const gap = bestD - r
        // In front: above the terrain (the polyline's y at x, by interpolation).
        const j = inner.findIndex((p, i) => i + 1 < inner.length && p.x >= x && inner[i + 1].x <= x)
        const a = inner[j]
        const b = inner[j + 1]
        const surface = a.y + ((b.y - a.y) * (x - a.x)) / (b.x - a.x)
        if (!(y > surface) || gap > 0.015 || gap < -0.1) continue
        const got = deepest(c.segments, circle(r), xf(x, y))
        expect(got, `circle at (${x}, ${y})`).not.toBeNull()
        if (got === null) continue
        expect(Math.abs(got.sep - gap)).toBeLessThan(1e-12)
        expect(Math.abs(got.normal.x - (x - bestQ.x) / bestD)).toBeLessThan(1e-9)
        expect(Math.abs(got.normal.y - (y - bestQ.y) / bestD)).toBeLessThan(1e-9)
        checked++
      }
    }
    expect(checked).toBeGreaterThan(40)
  })

  it('boxes, capsules, rounded boxes and triangles just apart in front of a random terrain: deepest separation = brute-force distance', () => {
    const rng = new Prng(11)
    let checked = 0
    const perKind = [0, 0, 0, 0]
    for (let trial = 0; trial < 60; trial++) {
      const points = terrain(rng, 10)
      const c = chain(points)
      const inner = points.slice(1, -1)
      for (let k = 0; k < 2000 && checked < 600; k++) {
        const angle = 6.2 * rng.next()
        const shape: Shape =
          k % 4 === 0
            ? box(0.2 + 0.3 * rng.next(), 0.1 + 0.3 * rng.next())
            : k % 4 === 1
              ? capsule({ x: -0.3, y: 0 }, { x: 0.3, y: 0 }, 0.05 + 0.2 * rng.next())
              : k % 4 === 2
                ? polygon(
                    [
                      { x: -0.3, y: -0.2 },
                      { x: 0.3, y: -0.2 },
                      { x: 0.3, y: 0.2 },
                      { x: -0.3, y: 0.2 },
                    ],
                    0.02 + 0.15 * rng.next(),
                  )
                : polygon([
                    { x: -0.4, y: -0.2 },
                    { x: 0.4 * rng.next(), y: -0.25 },
                    { x: 0.1, y: 0.35 },
                  ])
        const x = inner[2].x + (inner[inner.length - 3].x - inner[2].x) * rng.next()
        const y = -0.6 + 2.4 * rng.next()
        const t = xf(x, y, angle)
        const world = shape.vertices.slice(0, shape.count).map((v) => ({
          x: t.x + t.c * v.x - t.s * v.y,
          y: t.y + t.s * v.x + t.c * v.y,
        }))
        // The core's distance to the polyline: every core edge against every chain edge.
        let bestD = Number.POSITIVE_INFINITY
        const edges = shape.count === 2 ? 1 : shape.count
        for (let i = 0; i + 1 < inner.length; i++) {
          for (let e = 0; e < edges; e++) {
            const d = segmentDistance(inner[i], inner[i + 1], world[e], world[(e + 1) % shape.count])
            bestD = Math.min(bestD, d)
          }
        }
        const gap = bestD - shape.radius
        // Just apart (so the brute force, which cannot see overlap, is exact), and wholly above
        // the terrain: every core vertex over the polyline.
        if (!(gap > 0.001 && gap < 0.015)) continue
        const above = world.every((p) => {
          const j = inner.findIndex((q, i) => i + 1 < inner.length && q.x >= p.x && inner[i + 1].x <= p.x)
          if (j < 0) return false
          const a = inner[j]
          const b = inner[j + 1]
          return p.y > a.y + ((b.y - a.y) * (p.x - a.x)) / (b.x - a.x)
        })
        // ... and no chain point inside the core (a whole segment inside crosses no edge).
        const inside = (p: Vec2) =>
          shape.count > 2 && world.every((v, e) => orient(v, world[(e + 1) % shape.count], p) > 0)
        if (!above || inner.some(inside)) continue
        const got = deepest(c.segments, shape, t)
        expect(got, `${shape.type} at (${x}, ${y}, ${angle})`).not.toBeNull()
        if (got !== null)
          expect(Math.abs(got.sep - gap), `${shape.type} at (${x}, ${y}, ${angle})`).toBeLessThan(1e-9)
        checked++
        perKind[k % 4]++
      }
    }
    expect(checked).toBeGreaterThan(300)
    for (const n of perKind) expect(n).toBeGreaterThan(40)
  })
})

describe('ray casts against chain segments (queries/ray-cast.ts)', () => {
  it('a ray from the collision side hits the floor at its point; one from behind passes through', () => {
    const geometry = {
      ghost1: middle.ghost1,
      segment: { point1: middle.vertices[0], point2: middle.vertices[1] },
      ghost2: middle.ghost2,
    }
    const out = makeCastOutput()
    const down = rayCastChainSegment(
      geometry,
      { origin: { x: 0.25, y: 2 }, translation: { x: 0, y: -4 }, maxFraction: 1 },
      out,
    )
    expect(down).not.toBeNull()
    expect(out.fraction).toBe(0.5)
    expect(out.point).toEqual({ x: 0.25, y: 0 })
    expect(out.normal.y).toBe(1)
    expect(
      rayCastChainSegment(
        geometry,
        { origin: { x: 0.25, y: -2 }, translation: { x: 0, y: 4 }, maxFraction: 1 },
        out,
      ),
    ).toBeNull()
  })
})
