/*
 * decompose (engine/collision/decompose.ts) against independent checks: the pieces' areas sum to the
 * outline's shoelace area; each piece is convex, counter-clockwise, 3 to 8 vertices, made of
 * outline points, and unchanged by computeHull; no sample point lies strictly inside two pieces
 * (brute force over a grid and random points); every sample point strictly inside the outline
 * (crossing-number test) lies in some piece; the same outline gives the same pieces twice. Shapes:
 * L, U, star, comb, spiral, random star-shaped outlines of up to 64 points, both windings. Then
 * every error, with the indices it must name.
 */
import { describe, expect, it } from 'vitest'
import { DECOMPOSE_MIN_WIDTH, decomposeOutline as decompose } from '../../engine/collision/decompose.ts'
import { computeHull } from '../../engine/collision/hull.ts'
import type { Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'

const cross = (o: Vec2, a: Vec2, b: Vec2): number => (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)

function shoelace(ps: readonly Vec2[]): number {
  let a = 0
  for (let i = 0; i < ps.length; i++) {
    const p = ps[i]
    const q = ps[(i + 1) % ps.length]
    a += p.x * q.y - q.x * p.y
  }
  return 0.5 * a
}

/** Crossing-number point-in-polygon (any simple polygon). */
function insideOutline(ps: readonly Vec2[], p: Vec2): boolean {
  let inside = false
  for (let i = 0, j = ps.length - 1; i < ps.length; j = i++) {
    const a = ps[i]
    const b = ps[j]
    if (a.y > p.y !== b.y > p.y && p.x < ((b.x - a.x) * (p.y - a.y)) / (b.y - a.y) + a.x) inside = !inside
  }
  return inside
}

function distanceToSegment(p: Vec2, a: Vec2, b: Vec2): number {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const t = Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / (ex * ex + ey * ey)))
  return Math.hypot(p.x - a.x - t * ex, p.y - a.y - t * ey)
}

function distanceToBoundary(ps: readonly Vec2[], p: Vec2): number {
  let d = Number.POSITIVE_INFINITY
  for (let i = 0; i < ps.length; i++) d = Math.min(d, distanceToSegment(p, ps[i], ps[(i + 1) % ps.length]))
  return d
}

/** Signed depth of p inside convex CCW piece: the least distance left of its edges (negative outside). */
function depthInPiece(piece: readonly Vec2[], p: Vec2): number {
  let depth = Number.POSITIVE_INFINITY
  for (let i = 0; i < piece.length; i++) {
    const a = piece[i]
    const b = piece[(i + 1) % piece.length]
    depth = Math.min(depth, cross(a, b, p) / Math.hypot(b.x - a.x, b.y - a.y))
  }
  return depth
}

/** Every property the pieces must have; returns the pieces. */
function checkDecomposition(outline: readonly Vec2[], samples = 3000, seed = 1): Vec2[][] {
  const pieces = decompose(outline)
  // Same output twice, bit for bit.
  expect(decompose(outline)).toEqual(pieces)
  // Areas.
  const area = Math.abs(shoelace(outline))
  const sum = pieces.reduce((s, piece) => s + shoelace(piece), 0)
  expect(Math.abs(sum - area) / area).toBeLessThan(1e-9)
  for (const piece of pieces) {
    expect(piece.length).toBeGreaterThanOrEqual(3)
    expect(piece.length).toBeLessThanOrEqual(8)
    // Strictly convex, counter-clockwise: every other vertex strictly left of every edge.
    for (let i = 0; i < piece.length; i++) {
      const a = piece[i]
      const b = piece[(i + 1) % piece.length]
      for (const v of piece) if (v !== a && v !== b) expect(cross(a, b, v)).toBeGreaterThan(0)
    }
    // Made of outline points.
    for (const v of piece) expect(outline.some((p) => p.x === v.x && p.y === v.y)).toBe(true)
    // The hull keeps every vertex (the piece is a valid polygon as given).
    expect(computeHull(piece)).toHaveLength(piece.length)
  }
  // Sampling: no overlap, full coverage.
  let minX = Number.POSITIVE_INFINITY
  let minY = Number.POSITIVE_INFINITY
  let maxX = Number.NEGATIVE_INFINITY
  let maxY = Number.NEGATIVE_INFINITY
  for (const p of outline) {
    minX = Math.min(minX, p.x)
    minY = Math.min(minY, p.y)
    maxX = Math.max(maxX, p.x)
    maxY = Math.max(maxY, p.y)
  }
  const rng = new Prng(seed)
  const tol = 1e-9 * Math.max(maxX - minX, maxY - minY)
  let insideCount = 0
  for (let s = 0; s < samples; s++) {
    const p = { x: rng.range(minX, maxX), y: rng.range(minY, maxY) }
    const containing = pieces.filter((piece) => depthInPiece(piece, p) > tol).length
    expect(containing).toBeLessThanOrEqual(1)
    if (insideOutline(outline, p) && distanceToBoundary(outline, p) > tol) {
      insideCount++
      const covered = pieces.some((piece) => depthInPiece(piece, p) >= -tol)
      expect(covered).toBe(true)
    } else if (distanceToBoundary(outline, p) > tol) {
      // Outside the outline: in no piece.
      expect(pieces.some((piece) => depthInPiece(piece, p) > tol)).toBe(false)
    }
  }
  expect(insideCount).toBeGreaterThan(samples / 20)
  return pieces
}

const L: Vec2[] = [
  { x: 0, y: 0 },
  { x: 3, y: 0 },
  { x: 3, y: 1 },
  { x: 1, y: 1 },
  { x: 1, y: 3 },
  { x: 0, y: 3 },
]
const U: Vec2[] = [
  { x: 0, y: 0 },
  { x: 3, y: 0 },
  { x: 3, y: 3 },
  { x: 2, y: 3 },
  { x: 2, y: 1 },
  { x: 1, y: 1 },
  { x: 1, y: 3 },
  { x: 0, y: 3 },
]

/** A star of `points` tips (outer radius 2, inner 0.8); reference Math is fine in test code. */
function star(points: number): Vec2[] {
  return Array.from({ length: 2 * points }, (_, i) => {
    const r = i % 2 ? 0.8 : 2
    const a = (Math.PI * i) / points
    return { x: r * Math.cos(a), y: r * Math.sin(a) }
  })
}

/** A comb: a 11 x 1 m back with six 1 m teeth 3 m long, 24 points. */
function comb(): Vec2[] {
  const ps: Vec2[] = [
    { x: 0, y: 0 },
    { x: 11, y: 0 },
  ]
  for (let t = 5; t >= 0; t--) {
    ps.push({ x: 2 * t + 1, y: 4 }, { x: 2 * t, y: 4 })
    if (t > 0) ps.push({ x: 2 * t, y: 1 }, { x: 2 * t - 1, y: 1 })
  }
  return ps
}

/** A spiral band 0.4 m wide over 1.5 turns, 28 points per side (56 points). */
function spiral(): Vec2[] {
  const outer: Vec2[] = []
  const inner: Vec2[] = []
  const k = 28
  for (let i = 0; i < k; i++) {
    const a = (3 * Math.PI * i) / (k - 1)
    const r = 1.5 + 0.35 * a
    outer.push({ x: r * Math.cos(a), y: r * Math.sin(a) })
    inner.push({ x: (r - 0.4) * Math.cos(a), y: (r - 0.4) * Math.sin(a) })
  }
  return [...outer, ...inner.reverse()]
}

describe('decompose: named outlines', () => {
  it('splits an L into two convex pieces covering it exactly', () => {
    expect(checkDecomposition(L)).toHaveLength(2)
  })
  it('splits a U into three pieces', () => {
    expect(checkDecomposition(U)).toHaveLength(3)
  })
  it('decomposes a five-pointed star (10 points)', () => {
    const pieces = checkDecomposition(star(5))
    // Each tip is a reflex-free triangle; at least 5 + 1 pieces are impossible to beat by much.
    expect(pieces.length).toBeLessThanOrEqual(6)
  })
  it('decomposes an eight-pointed star and a comb of six teeth', () => {
    checkDecomposition(star(8))
    const pieces = checkDecomposition(comb())
    expect(pieces.length).toBeLessThanOrEqual(4 * 7) // Hertel-Mehlhorn: at most 4x the optimum (7)
  })
  it('decomposes a 56-point spiral band', () => {
    checkDecomposition(spiral(), 6000)
  })
  it('gives valid pieces for the clockwise outline too', () => {
    for (const outline of [L, U, star(5), comb(), spiral()]) checkDecomposition([...outline].reverse())
  })
  it('returns a convex outline of at most 8 points as one piece', () => {
    const hexagon = Array.from({ length: 6 }, (_, i) => ({
      x: Math.cos((Math.PI * i) / 3),
      y: Math.sin((Math.PI * i) / 3),
    }))
    expect(checkDecomposition(hexagon)).toHaveLength(1)
  })
  it('drops exactly collinear points without changing the area', () => {
    const withMidpoints = [L[0], { x: 1.5, y: 0 }, L[1], L[2], { x: 2, y: 1 }, L[3], L[4], L[5]]
    const pieces = checkDecomposition(withMidpoints)
    for (const piece of pieces) expect(piece).not.toContainEqual({ x: 1.5, y: 0 })
  })
})

describe('decompose: random star-shaped outlines of 5 to 64 points', () => {
  it('meets every property on 150 outlines and refuses none of them as a sliver', () => {
    const rng = new Prng(2027)
    let built = 0
    let refused = 0
    for (let trial = 0; trial < 150; trial++) {
      const n = 5 + (trial % 60)
      // One point per equal sector (gaps below pi), radii random: always simple. Outlines with a
      // vertex within 0.02 m of its neighbours' line (it would be dropped) or two points within
      // 0.05 m are drawn again.
      let ps: Vec2[] = []
      for (let ok = false; !ok; ) {
        ps = Array.from({ length: n }, (_, i) => {
          const a = ((i + rng.range(0.1, 0.9)) * 2 * Math.PI) / n
          const r = rng.range(2, 6)
          return { x: r * Math.cos(a), y: r * Math.sin(a) }
        })
        ok = true
        for (let i = 0; i < n && ok; i++) {
          const a = ps[(i + n - 1) % n]
          const b = ps[(i + 1) % n]
          if (Math.abs(cross(a, b, ps[i])) / Math.hypot(b.x - a.x, b.y - a.y) < 0.02) ok = false
          for (let j = i + 1; j < n && ok; j++)
            if (Math.hypot(ps[i].x - ps[j].x, ps[i].y - ps[j].y) < 0.05) ok = false
        }
      }
      try {
        decompose(ps)
      } catch (e) {
        expect(e).toBeInstanceOf(RangeError)
        expect(String(e)).toMatch(/sliver/)
        refused++
        continue
      }
      checkDecomposition(ps, 600, trial)
      built++
    }
    console.log(`random outlines: ${built} decomposed, ${refused} refused as slivers`)
    // Ear clipping alone (no Delaunay flips) refused 3 of these as slivers.
    expect(refused).toBe(0)
    expect(built).toBeGreaterThan(120)
  })
})

describe('decompose errors name the problem and the indices', () => {
  it('rejects fewer than 3 and more than 64 points, and a non-finite point', () => {
    expect(() => decompose(L.slice(0, 2))).toThrow(/3 to 64 points, got 2/)
    const many = Array.from({ length: 65 }, (_, i) => ({
      x: Math.cos((2 * Math.PI * i) / 65),
      y: Math.sin((2 * Math.PI * i) / 65),
    }))
    expect(() => decompose(many)).toThrow(/got 65/)
    expect(() => decompose([...L.slice(0, 3), { x: Number.POSITIVE_INFINITY, y: 0 }])).toThrow(
      /point 3 is not a finite point/,
    )
  })
  it('rejects a repeated point, next to its twin or not', () => {
    expect(() => decompose([L[0], L[1], { x: 3.01, y: 0 }, ...L.slice(2)])).toThrow(
      /repeated point: points 1 and 2 are .* apart/,
    )
    expect(() => decompose([...L, { x: 1.005, y: 1.005 }])).toThrow(/repeated point: points 3 and 6/)
  })
  it('rejects a bow tie (crossing edges), naming both edges', () => {
    const bowtie = [
      { x: 0, y: 0 },
      { x: 1, y: 1 },
      { x: 1, y: 0 },
      { x: 0, y: 1 },
    ]
    expect(() => decompose(bowtie)).toThrow(
      /self-intersecting: edge 0 \(points 0-1\) and edge 2 \(points 2-3\)/,
    )
  })
  it('rejects a point touching another edge', () => {
    const touching = [
      { x: 0, y: 0 },
      { x: 2, y: 0 },
      { x: 2, y: 2 },
      { x: 1, y: 0 },
      { x: 0, y: 2 },
    ]
    expect(() => decompose(touching)).toThrow(
      /edge 0 \(points 0-1\) and edge 2 \(points 2-3\) cross or touch/,
    )
  })
  it('rejects an edge folding back onto the one before it', () => {
    const fold = [
      { x: 0, y: 0 },
      { x: 2, y: 0 },
      { x: 1, y: 0 },
      { x: 1, y: 1 },
    ]
    expect(() => decompose(fold)).toThrow(/edges 0 and 1 fold back onto each other at point 1/)
  })
  it('rejects an outline with no area', () => {
    const flat = [
      { x: 0, y: 0 },
      { x: 1, y: 0.004 },
      { x: 2, y: 0 },
      { x: 1.5, y: -0.004 },
    ]
    expect(() => decompose(flat)).toThrow(/degenerate: all 4 points lie within 0.01 m of one line/)
  })
  it('rejects a thin triangle and a thin spike as slivers, naming the piece points and the width', () => {
    const thin = [
      { x: 0, y: 0 },
      { x: 5, y: 0 },
      { x: 2.5, y: 0.015 },
    ]
    expect(() => decompose(thin)).toThrow(
      /sliver: the piece with points .* is 0\.015\d* m wide across points 0-1/,
    )
    const spike = [
      { x: 0, y: 0 },
      { x: 2, y: 0 },
      { x: 2, y: 1 },
      { x: 1.01, y: 1 },
      { x: 1, y: 3 },
      { x: 0.99, y: 1 },
      { x: 0, y: 1 },
    ]
    expect(() => decompose(spike)).toThrow(
      new RegExp(`sliver: .*points (3, 4, 5|4, 5, 3|5, 3, 4).* less than ${DECOMPOSE_MIN_WIDTH} m`),
    )
  })
})
