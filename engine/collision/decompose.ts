/*
 * Convex decomposition of a simple polygon outline, deterministic, for concave shapes that every
 * client must build identically (DESIGN.md: "Concave outlines are decomposed into convex pieces
 * inside the engine, deterministically").
 *
 * 1. Validate the outline as given: 3 to 64 finite points, no two closer than the hull's weld
 *    distance (0.02 m: a repeated point), no two edges that cross or touch except neighbours at
 *    their shared point, and no edge folding back onto the one before it.
 * 2. Make it counter-clockwise (shoelace sign) and drop every vertex within 0.01 m of the line
 *    through its neighbours, first in list order, until none is left (computeHull's collinear rule,
 *    so that no piece carries a vertex the hull would drop). The dropped vertices change the area
 *    by at most a sliver that thin; exactly collinear points change it by nothing.
 * 3. Triangulate by ear clipping. Of all ears (a convex vertex whose triangle holds no other
 *    vertex, not even on its boundary) the one with the best shape is cut first: the largest
 *    area / (sum of squared sides), which is largest for an equilateral triangle; a tie goes to
 *    the first in list order. Then flip diagonals (Lawson) to the constrained Delaunay
 *    triangulation, which has the largest smallest angle: a thin triangle is left only where the
 *    outline itself nearly touches a diagonal.
 * 4. Hertel-Mehlhorn: visit the diagonals longest first (a tie in creation order) and remove each
 *    one whose two pieces merge into a convex piece of at most 8 vertices in which both ends of
 *    the diagonal stay more than 0.01 m outside the line through their new neighbours (so the hull
 *    keeps them). Hertel and Mehlhorn (1983) show this leaves at most four times the fewest pieces.
 * 5. Check every piece: at least DECOMPOSE_MIN_WIDTH wide (the smallest, over its edges, of the
 *    largest distance of a vertex from the edge) and every vertex more than 0.01 m outside its
 *    neighbours' line. A piece that fails is a sliver and the outline is refused.
 *
 * Every decision uses + - * / and comparisons on the input coordinates in a fixed order, so the
 * same outline gives the same pieces, bit for bit, in every JavaScript engine. Errors name the
 * input's point and edge indices (edge i joins point i to point i + 1). Allocates (shape
 * creation, not the step).
 */
import { MAX_POLYGON_VERTICES } from '../constants.ts'
import type { Vec2 } from '../math.ts'
import { HULL_COLLINEAR_DISTANCE, HULL_WELD_DISTANCE } from './hull.ts'
import { convexPolygon, type PolygonShape } from './shapes.ts'

/** Most points an outline may have: 64. */
export const MAX_OUTLINE_POINTS = 64
/** Narrowest convex piece decompose accepts (m): 0.02, twice the hull's collinear tolerance. */
export const DECOMPOSE_MIN_WIDTH = 2 * HULL_COLLINEAR_DISTANCE

const cross = (o: Vec2, a: Vec2, b: Vec2): number => (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)

/** Distance of v outside (right of) the line prev -> next; positive when v is a convex corner of a CCW polygon. */
function outsideChord(prev: Vec2, v: Vec2, next: Vec2): number {
  const ex = next.x - prev.x
  const ey = next.y - prev.y
  return ((v.x - prev.x) * ey - (v.y - prev.y) * ex) / Math.sqrt(ex * ex + ey * ey)
}

/**
 * The issue-27 contract: a simple polygon outline (either winding, 3 to 64 points, m, body frame)
 * as convex polygon shapes whose union is the outline (decomposeOutline's pieces, each kept exactly
 * as convexPolygon). Give them to one body: `world.createBody({ shapes: decompose(outline).map((shape)
 * => ({ shape, density })) })`; its mass is the outline's area times the density. Throws what
 * decomposeOutline throws.
 */
export function decompose(points: readonly Vec2[]): PolygonShape[] {
  return decomposeOutline(points).map((piece) => convexPolygon(piece))
}

/**
 * Convex pieces (counter-clockwise, 3 to 8 vertices, fresh points) whose union is the simple
 * polygon `points` (either winding, 3 to 64 points, m). Throws a RangeError naming the problem and
 * the point or edge indices for: a wrong point count, a non-finite point, two points closer than
 * 0.02 m, crossing or touching edges, an edge folding back, an outline with no area, or a sliver
 * piece narrower than DECOMPOSE_MIN_WIDTH.
 */
export function decomposeOutline(points: readonly Vec2[]): Vec2[][] {
  validateOutline(points)
  const n = points.length
  // 2. Counter-clockwise index list, collinear vertices dropped.
  let area2 = 0
  for (let i = 0; i < n; i++) {
    const a = points[i]
    const b = points[(i + 1) % n]
    area2 += a.x * b.y - a.y * b.x
  }
  const order: number[] = []
  for (let i = 0; i < n; i++) order.push(area2 >= 0 ? i : n - 1 - i)
  let searching = true
  while (searching && order.length >= 3) {
    searching = false
    const m = order.length
    for (let k = 0; k < m; k++) {
      const prev = points[order[(k + m - 1) % m]]
      const next = points[order[(k + 1) % m]]
      if (Math.abs(outsideChord(prev, points[order[k]], next)) <= HULL_COLLINEAR_DISTANCE) {
        order.splice(k, 1)
        searching = true
        break
      }
    }
  }
  if (order.length < 3) {
    throw new RangeError(
      `outline is degenerate: all ${n} points lie within ${HULL_COLLINEAR_DISTANCE} m of one line`,
    )
  }
  const triangles = triangulate(points, order)
  flipToDelaunay(points, triangles.pieces, triangles.diagonals)
  const pieces = mergeTriangles(points, triangles.pieces, triangles.diagonals)
  for (let k = 0; k < pieces.length; k++) checkPiece(points, pieces[k], k)
  return pieces.map((piece) => piece.map((i) => ({ x: points[i].x, y: points[i].y })))
}

/** Step 1: point count, finite coordinates, repeated points, crossing and folding edges. */
function validateOutline(points: readonly Vec2[]): void {
  const n = points.length
  if (n < 3 || n > MAX_OUTLINE_POINTS) {
    throw new RangeError(`outline needs 3 to ${MAX_OUTLINE_POINTS} points, got ${n}`)
  }
  for (let i = 0; i < n; i++) {
    const p = points[i]
    if (!p || !Number.isFinite(p.x) || !Number.isFinite(p.y)) {
      throw new RangeError(`outline point ${i} is not a finite point: ${JSON.stringify(p)}`)
    }
  }
  const weldSquared = HULL_WELD_DISTANCE * HULL_WELD_DISTANCE
  for (let i = 0; i < n; i++) {
    for (let j = i + 1; j < n; j++) {
      const dx = points[j].x - points[i].x
      const dy = points[j].y - points[i].y
      if (dx * dx + dy * dy < weldSquared) {
        throw new RangeError(
          `outline has a repeated point: points ${i} and ${j} are ${Math.sqrt(dx * dx + dy * dy)} m apart (closer than ${HULL_WELD_DISTANCE} m)`,
        )
      }
    }
  }
  for (let i = 0; i < n; i++) {
    // Neighbouring edges i - 1 and i meet at point i; they overlap only if they fold back.
    const prev = points[(i + n - 1) % n]
    const cur = points[i]
    const next = points[(i + 1) % n]
    const dot = (cur.x - prev.x) * (next.x - cur.x) + (cur.y - prev.y) * (next.y - cur.y)
    if (cross(prev, cur, next) === 0 && dot < 0) {
      throw new RangeError(
        `outline is self-intersecting: edges ${(i + n - 1) % n} and ${i} fold back onto each other at point ${i}`,
      )
    }
  }
  for (let i = 0; i < n; i++) {
    const cur = points[i]
    const next = points[(i + 1) % n]
    for (let j = i + 2; j < n; j++) {
      if (i === 0 && j === n - 1) continue // neighbours through point 0
      if (segmentsTouch(cur, next, points[j], points[(j + 1) % n])) {
        throw new RangeError(
          `outline is self-intersecting: edge ${i} (points ${i}-${(i + 1) % n}) and edge ${j} (points ${j}-${(j + 1) % n}) cross or touch`,
        )
      }
    }
  }
}

/** Do segments ab and cd share any point (crossing, touching or overlapping)? */
function segmentsTouch(a: Vec2, b: Vec2, c: Vec2, d: Vec2): boolean {
  const d1 = cross(c, d, a)
  const d2 = cross(c, d, b)
  const d3 = cross(a, b, c)
  const d4 = cross(a, b, d)
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true
  return (
    (d1 === 0 && onSegment(c, d, a)) ||
    (d2 === 0 && onSegment(c, d, b)) ||
    (d3 === 0 && onSegment(a, b, c)) ||
    (d4 === 0 && onSegment(a, b, d))
  )
}

/** For p collinear with ab: is p within the segment's bounding box? */
function onSegment(a: Vec2, b: Vec2, p: Vec2): boolean {
  return (
    Math.min(a.x, b.x) <= p.x &&
    p.x <= Math.max(a.x, b.x) &&
    Math.min(a.y, b.y) <= p.y &&
    p.y <= Math.max(a.y, b.y)
  )
}

/** Step 3: ear clipping, best-shaped ear first. Triangles and diagonals as point indices. */
function triangulate(
  points: readonly Vec2[],
  order: readonly number[],
): { pieces: number[][]; diagonals: number[][] } {
  const ring = [...order]
  const pieces: number[][] = []
  const diagonals: number[][] = []
  while (ring.length > 3) {
    const m = ring.length
    let best = -1
    let bestQuality = 0
    for (let k = 0; k < m; k++) {
      const p = points[ring[(k + m - 1) % m]]
      const c = points[ring[k]]
      const q = points[ring[(k + 1) % m]]
      const twiceArea = cross(p, c, q)
      if (!(twiceArea > 0)) continue
      let empty = true
      for (let j = 0; j < m && empty; j++) {
        if (j === k || j === (k + m - 1) % m || j === (k + 1) % m) continue
        const v = points[ring[j]]
        if (cross(p, c, v) >= 0 && cross(c, q, v) >= 0 && cross(q, p, v) >= 0) empty = false
      }
      if (!empty) continue
      const sides =
        (c.x - p.x) * (c.x - p.x) +
        (c.y - p.y) * (c.y - p.y) +
        (q.x - c.x) * (q.x - c.x) +
        (q.y - c.y) * (q.y - c.y) +
        (p.x - q.x) * (p.x - q.x) +
        (p.y - q.y) * (p.y - q.y)
      const quality = twiceArea / sides
      if (quality > bestQuality) {
        best = k
        bestQuality = quality
      }
    }
    if (best < 0) {
      throw new RangeError(
        `outline could not be triangulated: no ear among points ${ring.join(', ')} (nearly self-touching)`,
      )
    }
    const prev = ring[(best + m - 1) % m]
    const next = ring[(best + 1) % m]
    pieces.push([prev, ring[best], next])
    diagonals.push([prev, next])
    ring.splice(best, 1)
  }
  pieces.push([ring[0], ring[1], ring[2]])
  return { pieces, diagonals }
}

/**
 * Step 3b: Lawson's edge flips to the constrained Delaunay triangulation (de Berg et al.,
 * "Computational Geometry" 9.2): a diagonal whose opposite vertex lies inside the circumcircle of
 * the other triangle is flipped, in diagonal order, until a whole pass flips nothing. This
 * maximizes the smallest angle, so a thin triangle is left only where the outline forces one. A
 * relative tolerance keeps round-off on (nearly) cocircular points from flipping back and forth,
 * and the passes are capped.
 */
function flipToDelaunay(points: readonly Vec2[], triangles: number[][], diagonals: number[][]): void {
  const n = MAX_OUTLINE_POINTS
  const owner = new Int32Array(n * n).fill(-1)
  for (let k = 0; k < triangles.length; k++) setOwner(owner, triangles[k], k)
  const maxPasses = 4 * diagonals.length + 4
  for (let pass = 0, flipped = true; flipped && pass < maxPasses; pass++) {
    flipped = false
    for (const diagonal of diagonals) {
      const a = diagonal[0]
      const b = diagonal[1]
      const t1 = owner[a * n + b]
      const t2 = owner[b * n + a]
      const c = thirdVertex(triangles[t1], a, b)
      const d = thirdVertex(triangles[t2], b, a)
      const pa = points[a]
      const pb = points[b]
      const pc = points[c]
      const pd = points[d]
      if (!(cross(pc, pa, pd) > 0 && cross(pd, pb, pc) > 0)) continue // quad not convex: no flip
      if (!inCircumcircle(pa, pb, pc, pd)) continue
      owner[a * n + b] = -1
      owner[b * n + a] = -1
      triangles[t1] = [a, d, c]
      triangles[t2] = [d, b, c]
      setOwner(owner, triangles[t1], t1)
      setOwner(owner, triangles[t2], t2)
      diagonal[0] = c
      diagonal[1] = d
      flipped = true
    }
  }
}

/** The vertex of triangle t that follows the directed edge a -> b. */
function thirdVertex(t: readonly number[], a: number, b: number): number {
  const i = t.indexOf(a)
  if (t[(i + 1) % 3] !== b) throw new Error(`decompose: triangle ${t.join(',')} has no edge ${a}->${b}`)
  return t[(i + 2) % 3]
}

/** Is d clearly inside the circumcircle of the counter-clockwise triangle abc? */
function inCircumcircle(a: Vec2, b: Vec2, c: Vec2, d: Vec2): boolean {
  const ax = a.x - d.x
  const ay = a.y - d.y
  const bx = b.x - d.x
  const by = b.y - d.y
  const cx = c.x - d.x
  const cy = c.y - d.y
  const a2 = ax * ax + ay * ay
  const b2 = bx * bx + by * by
  const c2 = cx * cx + cy * cy
  const det = ax * (by * c2 - b2 * cy) - ay * (bx * c2 - b2 * cx) + a2 * (bx * cy - by * cx)
  const scale = Math.max(a2, b2, c2)
  return det > 1e-10 * scale * scale
}

/** Step 4: Hertel-Mehlhorn merging of the triangles across their diagonals, longest first. */
function mergeTriangles(points: readonly Vec2[], triangles: number[][], diagonals: number[][]): number[][] {
  const n = MAX_OUTLINE_POINTS
  const pieces: Array<number[] | null> = triangles.map((t) => [...t])
  // Owner piece of each directed edge a -> b, at a * n + b.
  const owner = new Int32Array(n * n).fill(-1)
  for (let k = 0; k < pieces.length; k++) setOwner(owner, pieces[k] as number[], k)
  const byLength = diagonals.map((d, index) => {
    const a = points[d[0]]
    const b = points[d[1]]
    return { d, index, length2: (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) }
  })
  byLength.sort((u, v) => (u.length2 !== v.length2 ? v.length2 - u.length2 : u.index - v.index))
  for (const { d } of byLength) {
    const a = d[0]
    const b = d[1]
    const pi = owner[a * n + b]
    const qi = owner[b * n + a]
    const p = pieces[pi] as number[]
    const q = pieces[qi] as number[]
    if (p.length + q.length - 2 > MAX_POLYGON_VERTICES) continue
    // p runs ... a, b ...; q runs ... b, a ...: merged = p from b round to a, then q after a up to before b.
    const merged: number[] = []
    const pb = p.indexOf(b)
    for (let k = 0; k < p.length; k++) merged.push(p[(pb + k) % p.length])
    const qa = q.indexOf(a)
    for (let k = 1; k < q.length - 1; k++) merged.push(q[(qa + k) % q.length])
    const m = merged.length
    const ia = p.length - 1 // a's place in merged
    const keepsA =
      outsideChord(points[merged[ia - 1]], points[a], points[merged[ia + 1]]) > HULL_COLLINEAR_DISTANCE
    const keepsB = outsideChord(points[merged[m - 1]], points[b], points[merged[1]]) > HULL_COLLINEAR_DISTANCE
    if (!keepsA || !keepsB) continue
    owner[a * n + b] = -1
    owner[b * n + a] = -1
    pieces[pi] = merged
    pieces[qi] = null
    setOwner(owner, merged, pi)
  }
  return pieces.filter((piece): piece is number[] => piece !== null)
}

function setOwner(owner: Int32Array, piece: readonly number[], k: number): void {
  for (let i = 0; i < piece.length; i++) {
    owner[piece[i] * MAX_OUTLINE_POINTS + piece[(i + 1) % piece.length]] = k
  }
}

/** Step 5: width and hull stability of piece k. */
function checkPiece(points: readonly Vec2[], piece: readonly number[], k: number): void {
  const m = piece.length
  let width = Number.POSITIVE_INFINITY
  let edge = 0
  for (let i = 0; i < m; i++) {
    const a = points[piece[i]]
    const b = points[piece[(i + 1) % m]]
    const length = Math.sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y))
    let deepest = 0
    for (let j = 0; j < m; j++) deepest = Math.max(deepest, cross(a, b, points[piece[j]]) / length)
    if (deepest < width) {
      width = deepest
      edge = i
    }
  }
  if (width < DECOMPOSE_MIN_WIDTH) {
    throw new RangeError(
      `outline has a sliver: the piece with points ${piece.join(', ')} is ${width} m wide across points ${piece[edge]}-${piece[(edge + 1) % m]}, less than ${DECOMPOSE_MIN_WIDTH} m (piece ${k})`,
    )
  }
  for (let i = 0; i < m; i++) {
    const prev = points[piece[(i + m - 1) % m]]
    const next = points[piece[(i + 1) % m]]
    if (!(outsideChord(prev, points[piece[i]], next) > HULL_COLLINEAR_DISTANCE)) {
      throw new RangeError(
        `outline has a sliver: in the piece with points ${piece.join(', ')}, point ${piece[i]} is within ${HULL_COLLINEAR_DISTANCE} m of the line through its neighbours (piece ${k})`,
      )
    }
  }
}
