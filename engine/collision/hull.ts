/*
 * The convex hull of a point set, as Box2D v3 builds polygons (hull.c, after Erin Catto): quickhull
 * with the slop-based clean-up that keeps a polygon usable by the narrowphase.
 *
 * 1. Weld: a point closer than 4 x slop (0.02 m) to a point already kept is dropped; the first of a
 *    cluster stays (input order decides, so the result is deterministic).
 * 2. Extreme points: p1 is the kept point farthest from the centre of the points' bounding box (the
 *    first such on a tie), p2 the point farthest from p1. They are on the hull.
 * 3. Split the rest into the points right of p1 -> p2 and left of it, skipping those within
 *    2 x slop of the line; recurse on each side: the point farthest right of an edge joins the hull
 *    unless it is within 2 x slop of the edge, and the two new edges are recursed on with the points
 *    right of the old one. The stitched list (p1, right side, p2, left side) is counter-clockwise.
 * 4. Merge collinear: while some vertex lies within 2 x slop of the line through its two
 *    neighbours, remove the first such vertex (in list order) and look again.
 *
 * Box2D returns an empty hull for bad input; here bad input throws a RangeError that names the
 * problem, because a polygon built from it would be silently wrong. Box2D accepts at most 8 input
 * points; this accepts up to MAX_HULL_INPUT and rejects a hull of more than 8 vertices.
 *
 * Only + - * / Math.sqrt and comparisons: the same input gives the same bits everywhere.
 */
import { LINEAR_SLOP, MAX_POLYGON_VERTICES } from '../constants.ts'
import type { Vec2 } from '../math.ts'

/** Points closer than this to an earlier kept point are welded to it (m): 4 x slop = 0.02. */
export const HULL_WELD_DISTANCE = 4 * LINEAR_SLOP
/** A vertex within this distance of the line through its neighbours is dropped as collinear (m): 2 x slop = 0.01. */
export const HULL_COLLINEAR_DISTANCE = 2 * LINEAR_SLOP
/** Most input points computeHull accepts: 64. */
export const MAX_HULL_INPUT = 64

/**
 * The convex hull of `points` (m), counter-clockwise, 3 to 8 vertices, each an input point (fresh
 * objects). Near-duplicates (within 0.02 m) are welded and near-collinear vertices (within 0.01 m
 * of their neighbours' line) removed, as in Box2D v3. Throws a RangeError for fewer than 3 or more
 * than MAX_HULL_INPUT points, a non-finite coordinate, points that weld to fewer than 3, points
 * that all lie on a line, or a hull of more than 8 vertices. Allocates (it is for shape creation).
 */
export function computeHull(points: readonly Vec2[]): Vec2[] {
  const count = points.length
  if (count < 3 || count > MAX_HULL_INPUT) {
    throw new RangeError(`hull needs 3 to ${MAX_HULL_INPUT} points, got ${count}`)
  }
  let minX = Number.POSITIVE_INFINITY
  let minY = Number.POSITIVE_INFINITY
  let maxX = Number.NEGATIVE_INFINITY
  let maxY = Number.NEGATIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const p = points[i]
    if (!p || !Number.isFinite(p.x) || !Number.isFinite(p.y)) {
      throw new RangeError(`hull point ${i} is not a finite point: ${JSON.stringify(p)}`)
    }
    minX = Math.min(minX, p.x)
    minY = Math.min(minY, p.y)
    maxX = Math.max(maxX, p.x)
    maxY = Math.max(maxY, p.y)
  }

  // 1. Weld near-duplicates into the first point of each cluster.
  const weldSquared = HULL_WELD_DISTANCE * HULL_WELD_DISTANCE
  const ps: Vec2[] = []
  for (let i = 0; i < count; i++) {
    const p = points[i]
    let unique = true
    for (let j = 0; j < ps.length; j++) {
      const dx = p.x - ps[j].x
      const dy = p.y - ps[j].y
      if (dx * dx + dy * dy < weldSquared) {
        unique = false
        break
      }
    }
    if (unique) ps.push({ x: p.x, y: p.y })
  }
  if (ps.length < 3) {
    throw new RangeError(
      `hull is degenerate: the ${count} points weld to ${ps.length} distinct points (closer than ${HULL_WELD_DISTANCE} m)`,
    )
  }

  // 2. Two extreme points: farthest from the box centre, then farthest from that one.
  const cx = 0.5 * (minX + maxX)
  const cy = 0.5 * (minY + maxY)
  const f1 = farthest(ps, cx, cy)
  const p1 = ps[f1]
  ps[f1] = ps[ps.length - 1]
  ps.pop()
  const f2 = farthest(ps, p1.x, p1.y)
  const p2 = ps[f2]
  ps[f2] = ps[ps.length - 1]
  ps.pop()

  // 3. Points clearly right and left of p1 -> p2, then quickhull on each side.
  const ex = p2.x - p1.x
  const ey = p2.y - p1.y
  const length = Math.sqrt(ex * ex + ey * ey)
  const ux = ex / length
  const uy = ey / length
  const right: Vec2[] = []
  const left: Vec2[] = []
  for (const p of ps) {
    const d = (p.x - p1.x) * uy - (p.y - p1.y) * ux
    if (d >= HULL_COLLINEAR_DISTANCE) right.push(p)
    else if (d <= -HULL_COLLINEAR_DISTANCE) left.push(p)
  }
  const hull1 = recurseHull(p1, p2, right)
  const hull2 = recurseHull(p2, p1, left)
  if (hull1.length === 0 && hull2.length === 0) {
    throw new RangeError(
      `hull is degenerate: all ${count} points lie within ${HULL_COLLINEAR_DISTANCE} m of one line`,
    )
  }
  const hull: Vec2[] = [p1, ...hull1, p2, ...hull2]

  // 4. Merge collinear vertices, first in list order, until none is left.
  let searching = true
  while (searching && hull.length > 2) {
    searching = false
    const n = hull.length
    for (let i = 0; i < n; i++) {
      const s1 = hull[i]
      const s2 = hull[(i + 1) % n]
      const s3 = hull[(i + 2) % n]
      if (distanceFromLine(s2, s1, s3) <= HULL_COLLINEAR_DISTANCE) {
        hull.splice((i + 1) % n, 1)
        searching = true
        break
      }
    }
  }
  if (hull.length < 3) {
    throw new RangeError(
      `hull is degenerate: all ${count} points lie within ${HULL_COLLINEAR_DISTANCE} m of one line`,
    )
  }
  if (hull.length > MAX_POLYGON_VERTICES) {
    throw new RangeError(`hull has ${hull.length} vertices, more than ${MAX_POLYGON_VERTICES}`)
  }
  return hull
}

/** Index of the point farthest from (x, y); the first on a tie. */
function farthest(ps: readonly Vec2[], x: number, y: number): number {
  let best = 0
  let bestSquared = -1
  for (let i = 0; i < ps.length; i++) {
    const dx = ps[i].x - x
    const dy = ps[i].y - y
    const d = dx * dx + dy * dy
    if (d > bestSquared) {
      best = i
      bestSquared = d
    }
  }
  return best
}

/** Signed distance of p to the right of the line a -> b (line through a and b, unit direction). */
function distanceFromLine(p: Vec2, a: Vec2, b: Vec2): number {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const length = Math.sqrt(ex * ex + ey * ey)
  return ((p.x - a.x) * ey - (p.y - a.y) * ex) / length
}

/** The hull vertices strictly right of p1 -> p2 (not p1 or p2), in order from p1 to p2 (quickhull). */
function recurseHull(p1: Vec2, p2: Vec2, ps: readonly Vec2[]): Vec2[] {
  if (ps.length === 0) return []
  const ex = p2.x - p1.x
  const ey = p2.y - p1.y
  const length = Math.sqrt(ex * ex + ey * ey)
  const ux = ex / length
  const uy = ey / length
  const right: Vec2[] = []
  let bestIndex = 0
  let bestDistance = Number.NEGATIVE_INFINITY
  for (let i = 0; i < ps.length; i++) {
    const d = (ps[i].x - p1.x) * uy - (ps[i].y - p1.y) * ux
    if (d > bestDistance) {
      bestIndex = i
      bestDistance = d
    }
    if (d > 0) right.push(ps[i])
  }
  if (bestDistance < HULL_COLLINEAR_DISTANCE) return []
  const best = ps[bestIndex]
  return [...recurseHull(p1, best, right), best, ...recurseHull(best, p2, right)]
}
