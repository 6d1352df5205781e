/*
 * Narrowphase tests. Oracles: hand computations, a world-space box-box collider in the manner of
 * Box2D Lite (SAT over the four box axes, ClipSegmentToLine), a brute-force directional SAT over every
 * edge normal of two convex polygons, and a brute-force closest point on a polygon's boundary.
 */
import { describe, expect, it } from 'vitest'
import { collideShapes, REFERENCE_FACE_TOLERANCE } from '../../engine/collision/collide.ts'
import { Manifold } from '../../engine/collision/manifold.ts'
import { box, circle, type PolygonShape, polygon, type Shape } from '../../engine/collision/shapes.ts'
import { cos, PI, sin, type Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'

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

/** Why manifold `m` differs from the expected normal and points, or null if it matches within `tol`. */
function manifoldMismatch(m: Manifold, normal: Vec2, expected: Pt[], tol: number): string | null {
  if (m.pointCount !== expected.length) return `pointCount ${m.pointCount}, expected ${expected.length}`
  return (
    (m.pointCount > 0 ? normalMismatch(m, normal, tol) : null) ?? pointsMismatch(pts(m), expected, tol, tol)
  )
}

function normalMismatch(m: Manifold, normal: Vec2, tol: number): string | null {
  const dn = Math.abs(m.normalX - normal.x) + Math.abs(m.normalY - normal.y)
  return dn <= tol ? null : `normal (${m.normalX}, ${m.normalY}) off by ${dn}`
}

/** Each point of `a` must match a distinct point of `b` (greedy nearest, fine for 1-2 points). */
function pointsMismatch(a: Pt[], b: Pt[], posTol: number, sepTol: number): string | null {
  if (a.length !== b.length) return `${a.length} points, expected ${b.length}`
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
    if (!(bestD <= posTol)) return `point (${p.x}, ${p.y}) is ${bestD} from the nearest expected point`
    const ds = Math.abs(p.sep - b[best].sep)
    if (!(ds <= sepTol)) return `separation ${p.sep} differs by ${ds}`
  }
  return null
}

function expectManifold(m: Manifold, normal: Vec2, expected: Pt[], tol = 1e-12, label = ''): void {
  const why = manifoldMismatch(m, normal, expected, tol)
  // Only reach expect() on a mismatch: thousands of random cases stay fast.
  if (why !== null) expect(why, label).toBeNull()
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

// ---------------------------------------------------------------------------------------------
// Oracle 1: a world-space box-box collider in the manner of Box2D Lite (SAT over the four box axes,
// incident face by the most anti-parallel normal, ClipSegmentToLine), written without the engine.

interface OBox {
  x: number
  y: number
  c: number
  s: number
  hx: number
  hy: number
}
const axesOf = (b: OBox): Vec2[] => [
  { x: b.c, y: b.s },
  { x: -b.s, y: b.c },
]
const halvesOf = (b: OBox) => [b.hx, b.hy]
const extentAlong = (b: OBox, n: Vec2) =>
  b.hx * Math.abs(dot(n, axesOf(b)[0])) + b.hy * Math.abs(dot(n, axesOf(b)[1]))

interface Face {
  n: Vec2
  sep: number
  center: Vec2
  halfT: number
  ambiguous: boolean
}

/** The face of X (of its four) that separates it most from Y. */
function bestFace(X: OBox, Y: OBox): Face {
  const d = { x: Y.x - X.x, y: Y.y - X.y }
  const faces = axesOf(X).map((axis, k) => {
    const p = dot(axis, d)
    const n = p >= 0 ? axis : { x: -axis.x, y: -axis.y }
    const h = halvesOf(X)
    return { n, p, sep: Math.abs(p) - h[k] - extentAlong(Y, n), h: h[k], t: h[1 - k] }
  })
  const [f, g] = faces[0].sep >= faces[1].sep ? faces : [faces[1], faces[0]]
  return {
    n: f.n,
    sep: f.sep,
    center: { x: X.x + f.n.x * f.h, y: X.y + f.n.y * f.h },
    halfT: f.t,
    ambiguous: f.sep - g.sep < 1e-9 || Math.abs(f.p) < 1e-9,
  }
}

/** Box2D Lite's ClipSegmentToLine: keeps the part of the segment with dot(n, p) <= offset. */
function clipSegmentToLine(seg: Vec2[], n: Vec2, offset: number): Vec2[] {
  const out: Vec2[] = []
  const d0 = dot(n, seg[0]) - offset
  const d1 = dot(n, seg[1]) - offset
  if (d0 <= 0) out.push(seg[0])
  if (d1 <= 0) out.push(seg[1])
  if (d0 * d1 < 0) {
    const t = d0 / (d0 - d1)
    out.push({ x: seg[0].x + t * (seg[1].x - seg[0].x), y: seg[0].y + t * (seg[1].y - seg[0].y) })
  }
  return out
}

/** Closest endpoints of two segments if the closest pair is vertex-vertex, else null; 'skip' if borderline. */
function closestVertices(s1: Vec2[], s2: Vec2[]): Vec2[] | null | 'skip' {
  const cands: { d: number; vv: boolean; pair: Vec2[]; border: boolean }[] = []
  const project = (p: Vec2, seg: Vec2[], pFirst: boolean) => {
    const e = sub(seg[1], seg[0])
    const u = dot(sub(p, seg[0]), e) / dot(e, e)
    const uc = Math.max(0, Math.min(1, u))
    const q = { x: seg[0].x + uc * e.x, y: seg[0].y + uc * e.y }
    const border = Math.abs(u) < 1e-9 || Math.abs(u - 1) < 1e-9
    cands.push({
      d: Math.hypot(p.x - q.x, p.y - q.y),
      vv: u <= 0 || u >= 1,
      pair: pFirst ? [p, q] : [q, p],
      border,
    })
  }
  for (const p of s1) project(p, s2, true)
  for (const p of s2) project(p, s1, false)
  cands.sort((a, b) => a.d - b.d)
  if (cands[0].border || (cands[1].d - cands[0].d < 1e-12 && cands[1].vv !== cands[0].vv)) return 'skip'
  return cands[0].vv ? cands[0].pair : null
}

type Expected = { normal: Vec2; points: Pt[]; vertexVertex?: boolean } | 'skip'

/** The expected manifold of boxes A and B (normal from A to B, points kept below `spec`). */
function oracleBoxes(A: OBox, B: OBox, spec: number): Expected {
  const fa = bestFace(A, B)
  const fb = bestFace(B, A)
  const none = { normal: { x: 0, y: 0 }, points: [] }
  if (Math.abs(fa.sep - spec) < 1e-9 || Math.abs(fb.sep - spec) < 1e-9) return 'skip'
  if (fa.sep >= spec || fb.sep >= spec) return none
  if (Math.abs(fb.sep - fa.sep - REFERENCE_FACE_TOLERANCE) < 1e-9) return 'skip'
  const flip = fb.sep > fa.sep + REFERENCE_FACE_TOLERANCE
  const ref = flip ? fb : fa
  if (ref.ambiguous) return 'skip'
  const inc = flip ? A : B
  // Incident face: the face of the other box whose normal is most anti-parallel to the reference normal.
  const faces = axesOf(inc).flatMap((axis, k) =>
    [1, -1].map((sg) => ({ m: { x: sg * axis.x, y: sg * axis.y }, k })),
  )
  faces.sort((f, g) => dot(f.m, ref.n) - dot(g.m, ref.n))
  if (dot(faces[1].m, ref.n) - dot(faces[0].m, ref.n) < 1e-9) return 'skip'
  const { m, k } = faces[0]
  const h = halvesOf(inc)
  const mid = { x: inc.x + m.x * h[k], y: inc.y + m.y * h[k] }
  const mt = { x: -m.y * h[1 - k], y: m.x * h[1 - k] }
  const incSeg = [sub(mid, mt), { x: mid.x + mt.x, y: mid.y + mt.y }]
  const t = { x: -ref.n.y, y: ref.n.x }
  const refSeg = [
    { x: ref.center.x - t.x * ref.halfT, y: ref.center.y - t.y * ref.halfT },
    { x: ref.center.x + t.x * ref.halfT, y: ref.center.y + t.y * ref.halfT },
  ]
  const normalAB = (n: Vec2) => (flip ? { x: -n.x, y: -n.y } : n)
  if (Math.max(fa.sep, fb.sep) > 0.1 * SLOP) {
    const vv = closestVertices(refSeg, incSeg)
    if (vv === 'skip') return 'skip'
    if (vv !== null) {
      const [pa, pb] = flip ? [vv[1], vv[0]] : vv
      const dist = Math.hypot(pb.x - pa.x, pb.y - pa.y)
      if (Math.abs(dist - spec) < 1e-9) return 'skip'
      if (dist >= spec) return none
      const n = { x: (pb.x - pa.x) / dist, y: (pb.y - pa.y) / dist }
      const points = [{ x: 0.5 * (pa.x + pb.x), y: 0.5 * (pa.y + pb.y), sep: dist }]
      return { normal: n, points, vertexVertex: true }
    }
  }
  let clipped = clipSegmentToLine(incSeg, t, dot(t, ref.center) + ref.halfT)
  if (clipped.length < 2) return 'skip'
  clipped = clipSegmentToLine(clipped, { x: -t.x, y: -t.y }, -dot(t, ref.center) + ref.halfT)
  if (clipped.length < 2) return 'skip'
  const points: Pt[] = []
  for (const p of clipped) {
    const sep = dot(ref.n, sub(p, ref.center))
    if (Math.abs(sep - spec) < 1e-9) return 'skip'
    if (sep < spec) points.push({ x: p.x - 0.5 * sep * ref.n.x, y: p.y - 0.5 * sep * ref.n.y, sep })
  }
  return points.length === 0 ? none : { normal: normalAB(ref.n), points }
}

/** A random box size: mostly 0.05-2 m, some tiny (0.001-0.05 m) and some huge (5-100 m). */
function randomHalf(rng: Prng): number {
  const r = rng.next()
  if (r < 0.1) return rng.range(0.001, 0.05)
  if (r < 0.2) return rng.range(5, 100)
  return rng.range(0.05, 2)
}

/**
 * Moves B from A's centre along a random direction until the largest SAT separation (`sepAt`)
 * reaches a random target: a deep overlap, a shallow one, or a gap within the speculative distance.
 * The SAT separation is convex along the ray, so bisection finds the one crossing.
 */
function placeNear(rng: Prng, sepAt: (x: number, y: number) => number, ax: number, ay: number): Vec2 {
  const theta = rng.range(-PI, PI)
  const dir = { x: cos(theta), y: sin(theta) }
  const deepest = sepAt(ax, ay)
  const r = rng.next()
  const target = r < 0.25 ? deepest * rng.next() : r < 0.75 ? rng.range(-0.1, 0) : rng.range(0, 0.03)
  let lo = 0
  let hi = 1
  while (sepAt(ax + dir.x * hi, ay + dir.y * hi) < target) hi *= 2
  for (let k = 0; k < 44; k++) {
    const mid = 0.5 * (lo + hi)
    if (sepAt(ax + dir.x * mid, ay + dir.y * mid) < target) lo = mid
    else hi = mid
  }
  return { x: ax + dir.x * hi, y: ay + dir.y * hi }
}

function randomBoxPair(rng: Prng): [OBox, OBox] {
  const a = rng.range(-PI, PI)
  const A = {
    x: rng.range(-5, 5),
    y: rng.range(-5, 5),
    c: cos(a),
    s: sin(a),
    hx: randomHalf(rng),
    hy: randomHalf(rng),
  }
  const b = rng.range(-PI, PI)
  const B = { x: 0, y: 0, c: cos(b), s: sin(b), hx: randomHalf(rng), hy: randomHalf(rng) }
  const sepAt = (x: number, y: number) => {
    const moved = { ...B, x, y }
    return Math.max(bestFace(A, moved).sep, bestFace(moved, A).sep)
  }
  const p = placeNear(rng, sepAt, A.x, A.y)
  B.x = p.x
  B.y = p.y
  return [A, B]
}

const boxXf = (b: OBox): Xf => ({ x: b.x, y: b.y, c: b.c, s: b.s })

/** Corner k (0..3, counter-clockwise from bottom-left) of a box and its outward half-angle bisector. */
function corner(b: OBox, k: number): { p: Vec2; u: Vec2; v: Vec2 } {
  const [u, v] = axesOf(b)
  const sx = k === 1 || k === 2 ? 1 : -1
  const sy = k >= 2 ? 1 : -1
  return {
    p: { x: b.x + sx * b.hx * u.x + sy * b.hy * v.x, y: b.y + sx * b.hx * u.y + sy * b.hy * v.y },
    u: { x: sx * u.x, y: sx * u.y },
    v: { x: sy * v.x, y: sy * v.y },
  }
}

/**
 * Two boxes whose closest features are a corner of each, `gap` apart: the gap direction lies in the
 * normal cone of A's corner and its opposite in the cone of B's corner (retries until it does).
 */
function cornerToCornerPair(rng: Prng, gap: number): [OBox, OBox, Vec2, Vec2] {
  for (;;) {
    const [A, B] = randomBoxPair(rng)
    const ca = corner(A, rng.int(4))
    const w = rng.range(0.05, 0.95)
    const dir = { x: w * ca.u.x + (1 - w) * ca.v.x, y: w * ca.u.y + (1 - w) * ca.v.y }
    const len = Math.hypot(dir.x, dir.y)
    const n = { x: dir.x / len, y: dir.y / len }
    const cb = corner(B, rng.int(4))
    // -n in B's corner cone: positive components along both of B's outward corner axes, with margin.
    if (-dot(n, cb.u) < 0.05 || -dot(n, cb.v) < 0.05) continue
    B.x += ca.p.x + gap * n.x - cb.p.x
    B.y += ca.p.y + gap * n.y - cb.p.y
    return [A, B, n, ca.p]
  }
}

describe('polygon-polygon against a Box2D Lite style box-box oracle', () => {
  it('agrees on normal, separations and points for 3000 random box pairs', () => {
    const rng = new Prng(20261122)
    const counts = { compared: 0, skipped: 0, none: 0, one: 0, two: 0, vertexVertex: 0 }
    for (let i = 0; i < 3000; i++) {
      const [A, B] = i % 4 === 0 ? cornerToCornerPair(rng, rng.range(0, 0.025)) : randomBoxPair(rng)
      const expected = oracleBoxes(A, B, SPEC)
      if (expected === 'skip') {
        counts.skipped++
        continue
      }
      const m = collide(box(A.hx, A.hy), boxXf(A), box(B.hx, B.hy), boxXf(B))
      const scale = 1 + Math.max(A.hx, A.hy, B.hx, B.hy)
      counts.compared++
      if (m.pointCount === 0) counts.none++
      else if (m.pointCount === 1) counts.one++
      else counts.two++
      if (expected.vertexVertex) counts.vertexVertex++
      // Normal within 1e-9, points within 1e-6 m, separations (so the minimum too) within 1e-9 m.
      const why =
        m.pointCount !== expected.points.length
          ? `pointCount ${m.pointCount}, expected ${expected.points.length}`
          : ((m.pointCount > 0 ? normalMismatch(m, expected.normal, 1e-9) : null) ??
            pointsMismatch(pts(m), expected.points, 1e-6 * scale, 1e-9 * scale))
      if (why !== null) expect(why, `pair ${i}`).toBeNull()
    }
    console.log('box-box oracle', counts)
    expect(counts.compared).toBeGreaterThan(2700)
    expect(Math.min(counts.none, counts.one, counts.two)).toBeGreaterThan(150)
    expect(counts.vertexVertex).toBeGreaterThan(20)
  })

  it('boxes whose closest features are two corners report the true gap along the corner-to-corner line', () => {
    const rng = new Prng(7)
    for (let i = 0; i < 500; i++) {
      const gap = rng.range(0.001, 0.0199)
      const [A, B, n, pa] = cornerToCornerPair(rng, gap)
      const m = collide(box(A.hx, A.hy), boxXf(A), box(B.hx, B.hy), boxXf(B))
      const midway = { x: pa.x + 0.5 * gap * n.x, y: pa.y + 0.5 * gap * n.y, sep: gap }
      expectManifold(m, n, [midway], 1e-9 * (1 + Math.abs(pa.x) + Math.abs(pa.y)), `pair ${i}`)
    }
  })
})

// ---------------------------------------------------------------------------------------------
// Oracle 2: brute-force SAT over every edge normal of two convex polygons in world space.

interface WPoly {
  v: Vec2[]
  n: Vec2[]
}
const worldPoly = (p: PolygonShape, t: Xf): WPoly => ({
  v: p.vertices.map((v) => toWorld(t, v)),
  n: p.normals.map((n) => rotate(t, n)),
})

/** Largest over P's edge normals of how far Q's vertices stay outside that edge; with the runner-up. */
function satSeparation(P: WPoly, Q: WPoly): { sep: number; edge: number; runnerUp: number } {
  const seps = P.n.map((n, i) => Math.min(...Q.v.map((w) => dot(n, sub(w, P.v[i])))))
  const order = seps.map((_, i) => i).sort((i, j) => seps[j] - seps[i])
  return { sep: seps[order[0]], edge: order[0], runnerUp: seps[order[1]] }
}

/** satSeparation(P, Q moved by (dx, dy)).sep without allocating: the bisection in placeNear calls it often. */
function maxSeparation(P: WPoly, Q: WPoly, dx: number, dy: number): number {
  let best = Number.NEGATIVE_INFINITY
  for (let i = 0; i < P.n.length; i++) {
    let least = Number.POSITIVE_INFINITY
    for (const w of Q.v)
      least = Math.min(least, P.n[i].x * (w.x + dx - P.v[i].x) + P.n[i].y * (w.y + dy - P.v[i].y))
    best = Math.max(best, least)
  }
  return best
}

/** A random convex polygon of 3-8 vertices: jittered points on an ellipse, off-centre, any size. */
function randomPolygon(rng: Prng): PolygonShape {
  for (;;) {
    const count = 3 + rng.int(6)
    const a = Math.max(0.01, randomHalf(rng))
    const b = a * rng.range(0.3, 1)
    const phase = rng.range(-PI, PI)
    const cx = rng.range(-0.5, 0.5) * a
    const cy = rng.range(-0.5, 0.5) * a
    const points: Vec2[] = []
    for (let i = 0; i < count; i++) {
      const t = phase + ((i + rng.range(-0.35, 0.35)) * 2 * PI) / count
      points.push({ x: cx + a * cos(t), y: cy + b * sin(t) })
    }
    try {
      return polygon(points)
    } catch {
      // too thin or nearly collinear for polygon(): draw again
    }
  }
}

function randomXf(rng: Prng): Xf {
  return xf(rng.range(-5, 5), rng.range(-5, 5), rng.range(-PI, PI))
}

/** Random polygon pair placed by placeNear, with the world polygons and both SAT separations. */
function randomPolygonPair(rng: Prng) {
  const a = randomPolygon(rng)
  const b = randomPolygon(rng)
  const ta = randomXf(rng)
  const tb = randomXf(rng)
  const wa = worldPoly(a, ta)
  const wb0 = worldPoly(b, { ...tb, x: 0, y: 0 })
  const sepAt = (x: number, y: number) =>
    Math.max(maxSeparation(wa, wb0, x, y), maxSeparation(wb0, wa, -x, -y))
  const p = placeNear(rng, sepAt, ta.x, ta.y)
  tb.x = p.x
  tb.y = p.y
  const wb = worldPoly(b, tb)
  return { a, b, ta, tb, wa, wb, satA: satSeparation(wa, wb), satB: satSeparation(wb, wa) }
}

describe('polygon-polygon against a brute-force SAT', () => {
  it('penetration depth of overlapping random convex polygons is the minimum SAT overlap', () => {
    const rng = new Prng(99)
    let overlapping = 0
    for (let i = 0; i < 2000; i++) {
      const { a, b, ta, tb, wa, wb, satA, satB } = randomPolygonPair(rng)
      if (Math.max(satA.sep, satB.sep) >= 0) continue
      overlapping++
      const m = collide(a, ta, b, tb)
      const scale = 1 + Math.max(...wa.v.concat(wb.v).map((v) => Math.abs(v.x) + Math.abs(v.y)))
      const tol = 1e-9 * scale
      const minSep = m.pointCount > 0 ? Math.min(...pts(m).map((p) => p.sep)) : Number.NaN
      // Depth: the smallest push along any edge normal that separates the two (brute force).
      const depth = -Math.max(satA.sep, satB.sep)
      const flip = satB.sep > satA.sep + REFERENCE_FACE_TOLERANCE
      const chosen = flip ? satB : satA
      // Unambiguous reference face: the deepest point is exactly the SAT depth. Inside the band,
      // A's face is kept although B's is up to the tolerance better: the depth is A's face's or
      // shallower (its deepest vertex may be clipped away), but never shallower than B's.
      const depthOk =
        Math.abs(satA.sep - satB.sep) > REFERENCE_FACE_TOLERANCE
          ? Math.abs(minSep + depth) < tol
          : minSep > chosen.sep - tol && minSep < -depth + tol
      if (!depthOk) expect({ minSep, satA: satA.sep, satB: satB.sep }, `pair ${i}`).toBeNull()
      const clearFace = chosen.sep - chosen.runnerUp > 1e-9
      if (clearFace && Math.abs(satB.sep - satA.sep - REFERENCE_FACE_TOLERANCE) > 1e-9) {
        const n = flip ? wb.n[chosen.edge] : wa.n[chosen.edge]
        const sign = flip ? -1 : 1
        const why = normalMismatch(m, { x: sign * n.x, y: sign * n.y }, 1e-9)
        if (why !== null) expect(why, `pair ${i}`).toBeNull()
      }
    }
    expect(overlapping).toBeGreaterThan(1000)
  })
})

// ---------------------------------------------------------------------------------------------
// Oracle 3: brute-force closest point on a polygon's boundary (every edge segment).

/** Expected polygon(A)-circle(B) contact from the closest boundary point, or the SAT face if inside. */
function oraclePolygonCircle(P: WPoly, c: Vec2, r: number): { normal: Vec2; point: Pt; ambiguous: boolean } {
  const faceSeps = P.n.map((n, i) => dot(n, sub(c, P.v[i])))
  const inside = faceSeps.every((s) => s <= 0)
  if (inside) {
    const order = faceSeps.map((_, i) => i).sort((i, j) => faceSeps[j] - faceSeps[i])
    const f = order[0]
    const n = P.n[f]
    const s = faceSeps[f]
    const point = { x: c.x - 0.5 * (s + r) * n.x, y: c.y - 0.5 * (s + r) * n.y, sep: s - r }
    return { normal: n, point, ambiguous: s - faceSeps[order[1]] < 1e-9 }
  }
  let best = { d: Number.POSITIVE_INFINITY, q: c }
  P.v.forEach((a, i) => {
    const b = P.v[(i + 1) % P.v.length]
    const e = sub(b, a)
    const u = Math.max(0, Math.min(1, dot(sub(c, a), e) / dot(e, e)))
    const q = { x: a.x + u * e.x, y: a.y + u * e.y }
    const d = Math.hypot(c.x - q.x, c.y - q.y)
    if (d < best.d) best = { d, q }
  })
  const n = { x: (c.x - best.q.x) / best.d, y: (c.y - best.q.y) / best.d }
  const point = { x: 0.5 * (best.q.x + c.x - r * n.x), y: 0.5 * (best.q.y + c.y - r * n.y), sep: best.d - r }
  return { normal: n, point, ambiguous: best.d < 1e-6 }
}

/** A random circle radius: mostly 0.05-2 m, some tiny, some huge. */
const randomRadius = (rng: Prng) => Math.max(0.001, randomHalf(rng))

describe('polygon-circle against a brute-force closest point', () => {
  it('agrees on separation, normal and point for 2500 random pairs, in either order', () => {
    const rng = new Prng(4242)
    const counts = { inside: 0, outside: 0, none: 0 }
    for (let i = 0; i < 2500; i++) {
      const poly = randomPolygon(rng)
      const r = randomRadius(rng)
      const ta = randomXf(rng)
      const P = worldPoly(poly, ta)
      const sepAt = (x: number, y: number) => oraclePolygonCircle(P, { x, y }, r).point.sep
      const c = placeNear(rng, sepAt, ta.x, ta.y)
      const expected = oraclePolygonCircle(P, c, r)
      const tc = xf(c.x, c.y, rng.range(-PI, PI))
      const scale = 1 + Math.abs(c.x) + Math.abs(c.y) + r
      if (expected.ambiguous || Math.abs(expected.point.sep - SPEC) < 1e-9) continue
      const m = collide(poly, ta, circle(r), tc)
      const swapped = collide(circle(r), tc, poly, ta)
      if (expected.point.sep >= SPEC) {
        counts.none++
        expect(m.pointCount).toBe(0)
        expect(swapped.pointCount).toBe(0)
        continue
      }
      if (expected.point.sep < -r) counts.inside++
      else counts.outside++
      const flipped = { x: -expected.normal.x, y: -expected.normal.y }
      expectManifold(m, expected.normal, [expected.point], 1e-9 * scale, `pair ${i}`)
      expectManifold(swapped, flipped, [expected.point], 1e-9 * scale, `swapped pair ${i}`)
    }
    expect(Math.min(counts.inside, counts.outside, counts.none)).toBeGreaterThan(150)
  })
})

describe('circle-circle against the distance between centres', () => {
  it('separation is the centre distance minus both radii for 1000 random pairs', () => {
    const rng = new Prng(5)
    for (let i = 0; i < 1000; i++) {
      const ra = randomRadius(rng)
      const rb = randomRadius(rng)
      const ta = randomXf(rng)
      const theta = rng.range(-PI, PI)
      const d = Math.max(0, ra + rb + rng.range(-(ra + rb), 0.03))
      const tb = xf(ta.x + d * cos(theta), ta.y + d * sin(theta), rng.range(-PI, PI))
      const dist = Math.hypot(tb.x - ta.x, tb.y - ta.y)
      const m = collide(circle(ra), ta, circle(rb), tb)
      if (Math.abs(dist - ra - rb - SPEC) < 1e-9) continue
      if (dist - ra - rb >= SPEC) {
        expect(m.pointCount).toBe(0)
        continue
      }
      const n = { x: (tb.x - ta.x) / dist, y: (tb.y - ta.y) / dist }
      const surfaceA = { x: ta.x + ra * n.x, y: ta.y + ra * n.y }
      const surfaceB = { x: tb.x - rb * n.x, y: tb.y - rb * n.y }
      const point = {
        x: 0.5 * (surfaceA.x + surfaceB.x),
        y: 0.5 * (surfaceA.y + surfaceB.y),
        sep: dist - ra - rb,
      }
      expectManifold(m, n, [point], 1e-9, `pair ${i}`)
    }
  })
})

describe('swapping A and B', () => {
  /** Checks m2 (B, A) is m1 (A, B) with the normal flipped and the same points. */
  function expectMirrored(m1: Manifold, m2: Manifold, tol: number, label: string): void {
    expect(m2.pointCount, label).toBe(m1.pointCount)
    if (m1.pointCount === 0) return
    expect(Math.abs(m1.normalX + m2.normalX) + Math.abs(m1.normalY + m2.normalY), label).toBeLessThan(1e-12)
    const why = pointsMismatch(pts(m2), pts(m1), tol, tol)
    if (why !== null) expect(why, label).toBeNull()
  }

  it('flips the normal and keeps the points for random pairs of every kind', () => {
    const rng = new Prng(77)
    let polygonPairs = 0
    for (let i = 0; i < 1000; i++) {
      const { a, b, ta, tb, satA, satB } = randomPolygonPair(rng)
      const scale = 1 + Math.max(Math.abs(ta.x), Math.abs(ta.y), Math.abs(tb.x), Math.abs(tb.y))
      // Inside the tolerance band each order prefers its own A: a different, equally valid face.
      if (Math.abs(satA.sep - satB.sep) <= REFERENCE_FACE_TOLERANCE + 1e-9) continue
      polygonPairs++
      expectMirrored(collide(a, ta, b, tb), collide(b, tb, a, ta), 1e-12 * scale, `polygons ${i}`)
      const r = randomRadius(rng)
      expectMirrored(
        collide(a, ta, circle(r), tb),
        collide(circle(r), tb, a, ta),
        1e-12 * scale,
        `poly-circle ${i}`,
      )
      const rb = randomRadius(rng)
      const near = xf(ta.x + rng.range(-1, 1) * r, ta.y + rng.range(-1, 1) * r)
      expectMirrored(
        collide(circle(r), ta, circle(rb), near),
        collide(circle(rb), near, circle(r), ta),
        0,
        `circles ${i}`,
      )
    }
    expect(polygonPairs).toBeGreaterThan(800)
  })
})

describe('feature ids', () => {
  /** Ids of a two-point manifold ordered by the points' x (left corner first). */
  const idsLeftToRight = (m: Manifold) =>
    m.points[0].x < m.points[1].x ? [m.points[0].id, m.points[1].id] : [m.points[1].id, m.points[0].id]

  it('a box resting on the ground keeps the id of each corner while it jiggles, in either order', () => {
    const ground = box(10, 1)
    const tg = xf(0, -1)
    const body = box(0.5, 0.5)
    const rng = new Prng(3)
    for (const groundFirst of [true, false]) {
      const at = (t: Xf) => (groundFirst ? collide(ground, tg, body, t) : collide(body, t, ground, tg))
      const base = at(xf(0.3, 0.49))
      expect(base.pointCount).toBe(2)
      const baseIds = idsLeftToRight(base)
      expect(baseIds[0]).not.toBe(baseIds[1])
      for (let i = 0; i < 200; i++) {
        const t = xf(0.3 + rng.range(-0.05, 0.05), 0.5 + rng.range(-0.015, 0.004), rng.range(-0.005, 0.005))
        const m = at(t)
        if (m.pointCount !== 2) expect(m.pointCount, `step ${i}`).toBe(2)
        const ids = idsLeftToRight(m)
        if (ids[0] !== baseIds[0] || ids[1] !== baseIds[1]) expect(ids, `step ${i}`).toEqual(baseIds)
      }
    }
  })

  it('the two points of every two-point manifold have different ids', () => {
    const rng = new Prng(11)
    let twoPoint = 0
    for (let i = 0; i < 1000; i++) {
      const { a, b, ta, tb } = randomPolygonPair(rng)
      const m = collide(a, ta, b, tb)
      if (m.pointCount < 2) continue
      twoPoint++
      if (m.points[0].id === m.points[1].id) expect(m.points[1].id, `pair ${i}`).not.toBe(m.points[0].id)
    }
    expect(twoPoint).toBeGreaterThan(100)
  })
})

describe('robustness', () => {
  const finiteUnit = (m: Manifold) =>
    pts(m).every((p) => Number.isFinite(p.x) && Number.isFinite(p.y) && Number.isFinite(p.sep)) &&
    (m.pointCount === 0 || Math.abs(Math.hypot(m.normalX, m.normalY) - 1) < 1e-12)

  it('identical transforms: full overlap gives finite points at the full depth', () => {
    const m = collide(box(0.5, 0.5), xf(2, 3, 0.3), box(0.5, 0.5), xf(2, 3, 0.3))
    expect(m.pointCount).toBe(2)
    expect(finiteUnit(m)).toBe(true)
    for (const p of pts(m)) expect(p.sep).toBeCloseTo(-1, 12)
    const rng = new Prng(8)
    for (let i = 0; i < 100; i++) {
      const poly = randomPolygon(rng)
      const t = randomXf(rng)
      const same = collide(poly, t, poly, t)
      expect(same.pointCount).toBeGreaterThan(0)
      expect(finiteUnit(same)).toBe(true)
      const r = randomRadius(rng)
      const c = collide(circle(r), t, circle(r), t)
      expect(finiteUnit(c) && c.pointCount === 1 && c.points[0].separation === -2 * r).toBe(true)
    }
  })

  it('a 0.05 m box on a 100 m box, in either order', () => {
    const big = box(50, 50)
    const small = box(0.025, 0.025)
    const expected = [
      { x: 9.975, y: -0.0005, sep: -0.001 },
      { x: 10.025, y: -0.0005, sep: -0.001 },
    ]
    expectManifold(collide(big, xf(0, -50), small, xf(10, 0.024)), { x: 0, y: 1 }, expected, 1e-12)
    expectManifold(collide(small, xf(10, 0.024), big, xf(0, -50)), { x: 0, y: -1 }, expected, 1e-12)
  })

  it('a 2 mm box resting 0.1 mm deep, and tilted 30 degrees corner down', () => {
    const tiny = box(0.001, 0.001)
    const ground = box(5, 0.5)
    expectManifold(collide(ground, xf(0, -0.5), tiny, xf(1, 0.0009)), { x: 0, y: 1 }, [
      { x: 0.999, y: -0.00005, sep: -0.0001 },
      { x: 1.001, y: -0.00005, sep: -0.0001 },
    ])
    // Tilted by 30 degrees the lowest corner is 0.001 (cos 30 + sin 30) below the centre and the
    // other end of the bottom edge 2 * 0.001 sin 30 = 0.001 higher: still within the speculative distance.
    const drop = 0.001 * (cos(PI / 6) + sin(PI / 6))
    const m = collide(ground, xf(0, -0.5), tiny, xf(1, drop - 0.0001, PI / 6))
    expect(m.pointCount).toBe(2)
    expect(m.normalY).toBe(1)
    const seps = pts(m).map((p) => p.sep)
    expect(Math.min(...seps)).toBeCloseTo(-0.0001, 12)
    expect(Math.max(...seps)).toBeCloseTo(0.0009, 12)
  })

  it('a small polygon deep inside a large one is pushed out through the nearest face', () => {
    const big = polygon([
      { x: -3, y: -2 },
      { x: 3, y: -2 },
      { x: 4, y: 1 },
      { x: 0, y: 3 },
      { x: -4, y: 1 },
    ])
    const m = collide(big, xf(0, 0), box(0.1, 0.1), xf(0, -1.5))
    // The bottom face y = -2 is nearest: pushing the box out through it takes 0.6 m (its top edge,
    // y = -1.4, is the incident edge), against more than 3 m through any other face.
    expect(m.normalX).toBe(0)
    expect(m.normalY).toBe(-1)
    expectManifold(m, { x: 0, y: -1 }, [
      { x: -0.1, y: -1.7, sep: -0.6 },
      { x: 0.1, y: -1.7, sep: -0.6 },
    ])
  })

  it('a circle centred on a polygon vertex or deep inside gets a face normal and a finite point', () => {
    const square = box(1, 1)
    const onVertex = collide(square, xf(0, 0), circle(0.3), xf(1, 1))
    expect(finiteUnit(onVertex) && onVertex.pointCount === 1).toBe(true)
    expect(onVertex.points[0].separation).toBeCloseTo(-0.3, 12)
    const centred = collide(square, xf(0, 0), circle(0.3), xf(0, 0))
    expect(finiteUnit(centred) && centred.pointCount === 1).toBe(true)
    expect(centred.points[0].separation).toBeCloseTo(-1.3, 12)
  })
})
