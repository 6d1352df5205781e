/*
 * Chain segments against every other shape kind: one-sided collision with ghost-vertex smoothing,
 * after Box2D v3's b2CollideChainSegmentAndCircle / b2CollideChainSegmentAndPolygon and Catto's
 * "Ghost collisions" (box2d.org, 2020). Our own code; the differences are below.
 *
 * Everything is worked out in the chain body's frame. A segment p1 -> p2 collides on its right (its
 * normal n1 = rightPerp(p2 - p1)); ghost1 (before p1) and ghost2 (after p2) are its neighbours'
 * far ends. A join is convex when the chain turns left there (cross(edge0, edge1) >= 0.01), which is
 * where a shape could catch on the next segment's end; there the neighbour's normal bounds the
 * normals this segment admits (the Gauss map of the join is split between the two segments).
 *
 * Circle: the centre must be on the right of the
 * line; behind p1 it collides with p1 only if it is not over the previous segment, ahead of p2 only
 * if it is not over the next one (the neighbour owns those regions), otherwise with the nearest
 * point of the segment.
 *
 * Polygon, capsule, rounded polygon (the core polygon, radius subtracted):
 * 1. One-sided: no contact if the polygon's centroid is behind the segment's line and behind the
 *    line of each convex neighbour.
 * 2. Separating axes: the segment normal; the normals of convex neighbours (if one separates best,
 *    the neighbour owns the contact: none here); the polygon's normals whose reverse the join admits
 *    (classify: admitted if within the convex neighbour's normal, snapped to n1 at a concave join,
 *    skipped beyond). Separated by more than the speculative distance on any axis: no contact.
 * 3. Apart by more than a tenth of the slop (and centroid in front): the closest features by brute
 *    force over the segment's two points and the polygon's edges (exact, at most 8 edges). Two
 *    vertices: one point along their direction if the join admits it; a segment end against a
 *    polygon edge: that edge is the reference face if admitted; otherwise the segment normal.
 *    (Box2D runs GJK with a cache here.)
 * 4. Otherwise the best admitted polygon face (if better than the segment's by more than
 *    REFERENCE_FACE_TOLERANCE; Box2D has no tolerance) or the segment normal is the reference face;
 *    the incident edge is clipped to it (two points at most), each point halfway between the
 *    surfaces. A polygon face is refused when the segment's neighbour would be the incident edge.
 *
 * Feature ids: (0 | 1 segment end, polygon vertex) for the segment face, 0x10 | (polygon edge end
 * 0 | 1) with the polygon edge for a polygon face, (segment end, polygon vertex) for vertex-vertex.
 *
 * Determinism and speed as collide.ts: + - * / sqrt only, scratch in module Float64Arrays, numbers
 * passed between helpers in arrays, never as double arguments.
 */
import { LINEAR_SLOP, MAX_POLYGON_VERTICES } from '../constants.ts'
import { type Manifold, makeFeatureId } from './manifold.ts'
import { NORMAL_X, NORMAL_Y, VERTEX_X, VERTEX_Y } from './polygon-geometry.ts'
import type { Shape } from './shapes.ts'

/** A body's pose (collide.ts's Pose): origin (m) and rotation as (cos, sin). */
interface Pose {
  readonly x: number
  readonly y: number
  readonly c: number
  readonly s: number
}

/** A join turns left (convex) when cross(edge0, edge1) is at least this (Box2D's convexTol). */
const CONVEX_TOLERANCE = 0.01
/** A normal beyond a convex neighbour's by more than this sine is skipped (Box2D's sinTol). */
const SIN_TOLERANCE = 0.01
/** How much better a polygon face must separate than the segment's to be the reference (m). */
const REFERENCE_FACE_TOLERANCE = 0.1 * LINEAR_SLOP
/** Distances below this are treated as zero when a direction is normalized (m). */
const TINY_DISTANCE = 1e-12

// Indices into `frame` (collide.ts's layout): pose A (x, y, cos, sin) at AX, pose B at BX, then the
// speculative distance.
const AX = 0
const BX = 4
const SPEC = 8

/** The other shape's core in the chain's frame: vertices x [i], y [M + i], normals [2M + i], [3M + i]. */
const M = MAX_POLYGON_VERTICES
const other = new Float64Array(4 * M)

// The segment and its joins, in the chain's frame.
const P1X = 0
const P1Y = 1
const P2X = 2
const P2Y = 3
const E1X = 4 // unit edge p1 -> p2
const E1Y = 5
const N0X = 6 // right normal of the previous segment
const N0Y = 7
const N2X = 8 // right normal of the next segment
const N2Y = 9
const CONVEX1 = 10 // 1 when the join at p1 is convex
const CONVEX2 = 11
// The pose of the chain body and the other's transform relative to it.
const PX = 12
const PY = 13
const PC = 14
const PS = 15
const SIGN = 16 // +1 when the chain is A, -1 when it is B
const RADIUS = 17 // the other shape's radius
const CX = 18 // the other shape's centroid (circle centre) in the chain frame
const CY = 19
const SPECULATIVE = 20 // the speculative distance of the call
const QX = 21 // the normal classify() looks at
const QY = 22
const LEAST = 23 // leastProjection's result
const seg = new Float64Array(24)

/** What classify() decided about a normal. */
const SKIP = 0
const ADMIT = 1
const SNAP = 2

/**
 * Fills `out` for a pair where at least one shape is a chain segment, with the poses and the
 * speculative distance in `frame` (collide.ts's layout); given poses are copied into `frame` first.
 * The chain segment is A when `chainIsA`.
 */
export function collideChainSegmentInFrame(
  frame: Float64Array,
  chainIsA: boolean,
  shapeA: Shape,
  geometryA: Float64Array,
  poseA: Pose | null,
  shapeB: Shape,
  geometryB: Float64Array,
  poseB: Pose | null,
  out: Manifold,
): void {
  if (poseA !== null && poseB !== null) {
    // The bodies' poses, read here (this function is hot and optimized; see collideChainSegmentAt).
    frame[AX] = poseA.x
    frame[AX + 1] = poseA.y
    frame[AX + 2] = poseA.c
    frame[AX + 3] = poseA.s
    frame[BX] = poseB.x
    frame[BX + 1] = poseB.y
    frame[BX + 2] = poseB.c
    frame[BX + 3] = poseB.s
  }
  const chainGeometry = chainIsA ? geometryA : geometryB
  const otherShape = chainIsA ? shapeB : shapeA
  const otherGeometry = chainIsA ? geometryB : geometryA
  loadSegment(frame, chainIsA, chainGeometry)
  // The other shape's transform in the chain's frame: q = qP^T qO, t = qP^T (pO - pP).
  const oi = chainIsA ? BX : AX
  const pc = seg[PC]
  const ps = seg[PS]
  const oc = frame[oi + 2]
  const os = frame[oi + 3]
  const qc = pc * oc + ps * os
  const qs = pc * os - ps * oc
  const dx = frame[oi] - seg[PX]
  const dy = frame[oi + 1] - seg[PY]
  const tx = pc * dx + ps * dy
  const ty = pc * dy - ps * dx
  seg[RADIUS] = otherShape.radius
  const lc = otherShape.centroid
  seg[CX] = qc * lc.x - qs * lc.y + tx
  seg[CY] = qs * lc.x + qc * lc.y + ty
  seg[SPECULATIVE] = frame[SPEC]
  out.pointCount = 0
  if (otherShape.type === 'circle') {
    segmentAndCircle(out)
  } else {
    const count = otherShape.count
    for (let i = 0; i < count; i++) {
      const vx = otherGeometry[VERTEX_X + i]
      const vy = otherGeometry[VERTEX_Y + i]
      const nx = otherGeometry[NORMAL_X + i]
      const ny = otherGeometry[NORMAL_Y + i]
      other[i] = qc * vx - qs * vy + tx
      other[M + i] = qs * vx + qc * vy + ty
      other[2 * M + i] = qc * nx - qs * ny
      other[3 * M + i] = qs * nx + qc * ny
    }
    segmentAndPolygon(count, out)
  }
  if (out.pointCount === 0) {
    out.normalX = 0
    out.normalY = 0
    return
  }
  // Back to world space; the normal from A to B.
  const nx = out.normalX
  const ny = out.normalY
  const sign = seg[SIGN]
  out.normalX = sign * (pc * nx - ps * ny)
  out.normalY = sign * (ps * nx + pc * ny)
  for (let i = 0; i < out.pointCount; i++) {
    const p = out.points[i]
    const x = p.x
    const y = p.y
    p.x = seg[PX] + pc * x - ps * y
    p.y = seg[PY] + ps * x + pc * y
  }
}

/** Reads the segment, its ghost vertices and the chain body's pose into `seg`. */
function loadSegment(frame: Float64Array, chainIsA: boolean, g: Float64Array): void {
  const at = chainIsA ? AX : BX
  seg[PX] = frame[at]
  seg[PY] = frame[at + 1]
  seg[PC] = frame[at + 2]
  seg[PS] = frame[at + 3]
  seg[SIGN] = chainIsA ? 1 : -1
  const p1x = g[VERTEX_X]
  const p1y = g[VERTEX_Y]
  const p2x = g[VERTEX_X + 1]
  const p2y = g[VERTEX_Y + 1]
  seg[P1X] = p1x
  seg[P1Y] = p1y
  seg[P2X] = p2x
  seg[P2Y] = p2y
  let ex = p2x - p1x
  let ey = p2y - p1y
  let len = Math.sqrt(ex * ex + ey * ey)
  const e1x = ex / len
  const e1y = ey / len
  seg[E1X] = e1x
  seg[E1Y] = e1y
  ex = p1x - g[VERTEX_X + 2]
  ey = p1y - g[VERTEX_Y + 2]
  len = Math.sqrt(ex * ex + ey * ey)
  const e0x = ex / len
  const e0y = ey / len
  seg[N0X] = e0y
  seg[N0Y] = -e0x
  seg[CONVEX1] = e0x * e1y - e0y * e1x >= CONVEX_TOLERANCE ? 1 : 0
  ex = g[VERTEX_X + 3] - p2x
  ey = g[VERTEX_Y + 3] - p2y
  len = Math.sqrt(ex * ex + ey * ey)
  const e2x = ex / len
  const e2y = ey / len
  seg[N2X] = e2y
  seg[N2Y] = -e2x
  seg[CONVEX2] = e1x * e2y - e1y * e2x >= CONVEX_TOLERANCE ? 1 : 0
}

/**
 * Circle at (seg[CX], seg[CY]) of radius seg[RADIUS] against the segment (Box2D v3
 * b2CollideChainSegmentAndCircle), in the chain frame.
 */
function segmentAndCircle(out: Manifold): void {
  const spec = seg[SPECULATIVE]
  const p1x = seg[P1X]
  const p1y = seg[P1Y]
  const p2x = seg[P2X]
  const p2y = seg[P2Y]
  const cx = seg[CX]
  const cy = seg[CY]
  const ex = p2x - p1x
  const ey = p2y - p1y
  // One-sided: the centre must be on the right of p1 -> p2.
  if (ey * (cx - p1x) - ex * (cy - p1y) < 0) return
  const u = ex * (p2x - cx) + ey * (p2y - cy)
  const v = ex * (cx - p1x) + ey * (cy - p1y)
  let qx: number
  let qy: number
  if (v <= 0) {
    // Behind p1: the previous segment owns the region over itself. edge0 = leftPerp(n0).
    if (-seg[N0Y] * (cx - p1x) + seg[N0X] * (cy - p1y) <= 0) return
    qx = p1x
    qy = p1y
  } else if (u <= 0) {
    // Ahead of p2: the next segment owns the region over itself. edge2 = (-n2y, n2x).
    if (-seg[N2Y] * (cx - p2x) + seg[N2X] * (cy - p2y) > 0) return
    qx = p2x
    qy = p2y
  } else {
    const ee = ex * ex + ey * ey
    qx = (u * p1x + v * p2x) / ee
    qy = (u * p1y + v * p2y) / ee
  }
  const gx = cx - qx
  const gy = cy - qy
  const distance = Math.sqrt(gx * gx + gy * gy)
  let nx = ey
  let ny = -ex
  if (distance > TINY_DISTANCE) {
    nx = gx / distance
    ny = gy / distance
  } else {
    const len = Math.sqrt(nx * nx + ny * ny)
    nx /= len
    ny /= len
  }
  const radius = seg[RADIUS]
  const separation = distance - radius
  if (!(separation < spec)) return
  out.normalX = nx
  out.normalY = ny
  out.pointCount = 1
  const p = out.points[0]
  // Midpoint of the segment's point q and the circle's deepest point c - r n.
  p.x = 0.5 * (qx + cx - radius * nx)
  p.y = 0.5 * (qy + cy - radius * ny)
  p.separation = separation
  p.id = 0
}

/**
 * Whether the join admits the normal (seg[QX], seg[QY]) (chain frame, from the chain outward): SKIP,
 * ADMIT or SNAP. (The normal is passed in `seg`: V8 boxes a double argument of a call it does not
 * inline, and these run for every chain contact every step.)
 */
function classify(): number {
  const nx = seg[QX]
  const ny = seg[QY]
  if (nx * seg[E1X] + ny * seg[E1Y] <= 0) {
    // Towards p1.
    if (seg[CONVEX1] === 0) return SNAP
    return nx * seg[N0Y] - ny * seg[N0X] > SIN_TOLERANCE ? SKIP : ADMIT
  }
  if (seg[CONVEX2] === 0) return SNAP
  return seg[N2X] * ny - seg[N2Y] * nx > SIN_TOLERANCE ? SKIP : ADMIT
}

/** The axes leastProjection measures along: the segment's normal, and its neighbours'. */
const AXIS_SEGMENT = 0
const AXIS_PREVIOUS = 1
const AXIS_NEXT = 2

/**
 * Smallest projection of the other polygon's vertices onto an axis (AXIS_SEGMENT: n1 from p1,
 * AXIS_PREVIOUS: n0 from p1, AXIS_NEXT: n2 from p2), into seg[LEAST].
 */
function leastProjection(count: number, axis: number): void {
  const nx = axis === AXIS_SEGMENT ? seg[E1Y] : axis === AXIS_PREVIOUS ? seg[N0X] : seg[N2X]
  const ny = axis === AXIS_SEGMENT ? -seg[E1X] : axis === AXIS_PREVIOUS ? seg[N0Y] : seg[N2Y]
  const ox = axis === AXIS_NEXT ? seg[P2X] : seg[P1X]
  const oy = axis === AXIS_NEXT ? seg[P2Y] : seg[P1Y]
  let least = Number.POSITIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const s = nx * (other[i] - ox) + ny * (other[M + i] - oy)
    if (s < least) least = s
  }
  seg[LEAST] = least
}

/** Index of the other polygon's vertex of least projection on the segment normal. */
function deepestVertex(count: number): number {
  const n1x = seg[E1Y]
  const n1y = -seg[E1X]
  let best = 0
  let least = Number.POSITIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const s = n1x * (other[i] - seg[P1X]) + n1y * (other[M + i] - seg[P1Y])
    if (s < least) {
      least = s
      best = i
    }
  }
  return best
}

/** The other polygon (in `other`, core of radius seg[RADIUS]) against the segment, in the chain frame. */
function segmentAndPolygon(count: number, out: Manifold): void {
  const spec = seg[SPECULATIVE]
  const p1x = seg[P1X]
  const p1y = seg[P1Y]
  const p2x = seg[P2X]
  const p2y = seg[P2Y]
  const n1x = seg[E1Y]
  const n1y = -seg[E1X]
  const convex1 = seg[CONVEX1] === 1
  const convex2 = seg[CONVEX2] === 1
  const cx = seg[CX]
  const cy = seg[CY]
  // 1. One-sided: behind the segment and behind each convex neighbour.
  const behind1 = n1x * (cx - p1x) + n1y * (cy - p1y) < 0
  const behind0 = !convex1 || seg[N0X] * (cx - p1x) + seg[N0Y] * (cy - p1y) < 0
  const behind2 = !convex2 || seg[N2X] * (cx - p2x) + seg[N2Y] * (cy - p2y) < 0
  if (behind1 && behind0 && behind2) return
  const reach = spec + seg[RADIUS]
  // 2. Separating axes.
  leastProjection(count, AXIS_SEGMENT)
  let edgeSeparation = seg[LEAST]
  let neighbourOwns = false
  if (convex1) {
    leastProjection(count, AXIS_PREVIOUS)
    const s0 = seg[LEAST]
    if (s0 > edgeSeparation) {
      edgeSeparation = s0
      neighbourOwns = true
    }
  }
  if (convex2) {
    leastProjection(count, AXIS_NEXT)
    const s2 = seg[LEAST]
    if (s2 > edgeSeparation) {
      edgeSeparation = s2
      neighbourOwns = true
    }
  }
  if (!(edgeSeparation < reach)) return
  let polygonSeparation = Number.NEGATIVE_INFINITY
  let reference = -1
  for (let i = 0; i < count; i++) {
    const nx = other[2 * M + i]
    const ny = other[3 * M + i]
    const vx = other[i]
    const vy = other[M + i]
    const s = Math.min(nx * (p1x - vx) + ny * (p1y - vy), nx * (p2x - vx) + ny * (p2y - vy))
    if (!(s < reach)) return // this axis separates them
    if (!(s > polygonSeparation)) continue
    seg[QX] = -nx
    seg[QY] = -ny
    if (classify() === ADMIT) {
      polygonSeparation = s
      reference = i
    }
  }
  // 3. Apart: the closest features decide the normal.
  const apart = Math.max(edgeSeparation, polygonSeparation) > 0.1 * LINEAR_SLOP
  if (!behind1 && apart) {
    closestFeatures(count, out)
    return
  }
  // 4. Touching or overlapping: the best reference face.
  if (reference >= 0 && polygonSeparation > edgeSeparation + REFERENCE_FACE_TOLERANCE) {
    clipToPolygonFace(count, reference, out)
    return
  }
  if (neighbourOwns) return
  clipToSegmentFace(count, incidentEdgeAt(count, deepestVertex(count)), out)
}

// The closest features: distance squared, segment feature (0, 1 its ends, 2 its interior), polygon
// feature (vertex index, or edge index + M for an edge interior), closest points.
const near = new Float64Array(7)
const NEAR_D2 = 0
const NEAR_A = 1
const NEAR_B = 2
const NEAR_AX = 3
const NEAR_AY = 4
const NEAR_BX = 5
const NEAR_BY = 6

/** Step 3 of segmentAndPolygon: the shapes are apart; find their closest features (brute force). */
function closestFeatures(count: number, out: Manifold): void {
  const spec = seg[SPECULATIVE]
  const p1x = seg[P1X]
  const p1y = seg[P1Y]
  const ex = seg[P2X] - p1x
  const ey = seg[P2Y] - p1y
  const ee = ex * ex + ey * ey
  near[NEAR_D2] = Number.POSITIVE_INFINITY
  // Each polygon vertex against the segment.
  for (let i = 0; i < count; i++) {
    const vx = other[i]
    const vy = other[M + i]
    const t = Math.max(0, Math.min(1, ((vx - p1x) * ex + (vy - p1y) * ey) / ee))
    const qx = t === 1 ? seg[P2X] : p1x + t * ex
    const qy = t === 1 ? seg[P2Y] : p1y + t * ey
    const d2 = (vx - qx) * (vx - qx) + (vy - qy) * (vy - qy)
    if (d2 < near[NEAR_D2]) {
      near[NEAR_D2] = d2
      near[NEAR_A] = t === 0 ? 0 : t === 1 ? 1 : 2
      near[NEAR_B] = i
      near[NEAR_AX] = qx
      near[NEAR_AY] = qy
      near[NEAR_BX] = vx
      near[NEAR_BY] = vy
    }
  }
  // Each segment end against each polygon edge (a capsule's one edge once).
  const edges = count === 2 ? 1 : count
  for (let k = 0; k < 2; k++) {
    const ax = k === 0 ? p1x : seg[P2X]
    const ay = k === 0 ? p1y : seg[P2Y]
    for (let j = 0; j < edges; j++) {
      const j2 = j + 1 < count ? j + 1 : 0
      const bx = other[j]
      const by = other[M + j]
      const fx = other[j2] - bx
      const fy = other[M + j2] - by
      const t = Math.max(0, Math.min(1, ((ax - bx) * fx + (ay - by) * fy) / (fx * fx + fy * fy)))
      const qx = t === 1 ? other[j2] : bx + t * fx
      const qy = t === 1 ? other[M + j2] : by + t * fy
      const d2 = (ax - qx) * (ax - qx) + (ay - qy) * (ay - qy)
      if (d2 < near[NEAR_D2]) {
        near[NEAR_D2] = d2
        near[NEAR_A] = k
        near[NEAR_B] = t === 0 ? j : t === 1 ? j2 : j + M
        near[NEAR_AX] = ax
        near[NEAR_AY] = ay
        near[NEAR_BX] = qx
        near[NEAR_BY] = qy
      }
    }
  }
  const a = near[NEAR_A]
  const b = near[NEAR_B]
  if (a === 2) {
    // A polygon vertex over the segment's interior: the segment face.
    clipToSegmentFace(count, incidentEdgeAt(count, b), out)
    return
  }
  if (b >= M) {
    // A segment end against a polygon edge's interior: that edge, if the join admits it. (A
    // capsule's one edge was tried once: its face is the one whose normal points to the end.)
    let edge = b - M
    const gx = near[NEAR_AX] - near[NEAR_BX]
    const gy = near[NEAR_AY] - near[NEAR_BY]
    if (count === 2 && other[2 * M + edge] * gx + other[3 * M + edge] * gy < 0) edge = 1 - edge
    seg[QX] = -other[2 * M + edge]
    seg[QY] = -other[3 * M + edge]
    const type = classify()
    if (type === SKIP) return
    if (type === ADMIT) clipToPolygonFace(count, edge, out)
    else clipToSegmentFace(count, edge, out)
    return
  }
  // Two vertices: one point along their direction, if the join admits it.
  const distance = Math.sqrt(near[NEAR_D2])
  const nx = (near[NEAR_BX] - near[NEAR_AX]) / distance
  const ny = (near[NEAR_BY] - near[NEAR_AY]) / distance
  seg[QX] = nx
  seg[QY] = ny
  const type = classify()
  if (type === SKIP) return
  if (type === SNAP) {
    clipToSegmentFace(count, incidentEdgeAt(count, b), out)
    return
  }
  const radius = seg[RADIUS]
  const separation = distance - radius
  if (!(separation < spec)) return
  out.normalX = nx
  out.normalY = ny
  out.pointCount = 1
  const p = out.points[0]
  p.x = near[NEAR_AX] + 0.5 * (distance - radius) * nx
  p.y = near[NEAR_AY] + 0.5 * (distance - radius) * ny
  p.separation = separation
  p.id = makeFeatureId(a, b)
}

/** Of the two polygon edges at vertex i, the one most anti-parallel to the segment normal. */
function incidentEdgeAt(count: number, i: number): number {
  const prev = i > 0 ? i - 1 : count - 1
  const n1x = seg[E1Y]
  const n1y = -seg[E1X]
  const dPrev = n1x * other[2 * M + prev] + n1y * other[3 * M + prev]
  const dThis = n1x * other[2 * M + i] + n1y * other[3 * M + i]
  return dPrev < dThis ? prev : i
}

/**
 * The segment is the reference face (normal n1): clips polygon edge `edge` (its vertices b1 -> b2
 * run against the segment's direction) to the segment's ends and keeps the points closer than the
 * speculative distance, halfway between the surfaces.
 */
function clipToSegmentFace(count: number, edge: number, out: Manifold): void {
  const spec = seg[SPECULATIVE]
  const p1x = seg[P1X]
  const p1y = seg[P1Y]
  const tx = seg[E1X]
  const ty = seg[E1Y]
  const nx = ty
  const ny = -tx
  const i1 = edge
  const i2 = edge + 1 < count ? edge + 1 : 0
  const b1x = other[i1]
  const b1y = other[M + i1]
  const b2x = other[i2]
  const b2y = other[M + i2]
  const upper1 = tx * (seg[P2X] - p1x) + ty * (seg[P2Y] - p1y)
  const upper2 = tx * (b1x - p1x) + ty * (b1y - p1y)
  const lower2 = tx * (b2x - p1x) + ty * (b2y - p1y)
  if (upper2 < 0 || upper1 < lower2) return
  const span = upper2 - lower2
  let lowerX = b2x
  let lowerY = b2y
  let upperX = b1x
  let upperY = b1y
  if (lower2 < 0 && span > TINY_DISTANCE) {
    const t = -lower2 / span
    lowerX = b2x + t * (b1x - b2x)
    lowerY = b2y + t * (b1y - b2y)
  }
  if (upper2 > upper1 && span > TINY_DISTANCE) {
    const t = (upper1 - lower2) / span
    upperX = b2x + t * (b1x - b2x)
    upperY = b2y + t * (b1y - b2y)
  }
  const radius = seg[RADIUS]
  const sLower = nx * (lowerX - p1x) + ny * (lowerY - p1y)
  const sUpper = nx * (upperX - p1x) + ny * (upperY - p1y)
  out.normalX = nx
  out.normalY = ny
  let n = 0
  if (sLower - radius < spec) {
    const p = out.points[n++]
    // Halfway between the segment (s = 0) and the rounded incident surface (s - radius).
    p.x = lowerX - 0.5 * (sLower + radius) * nx
    p.y = lowerY - 0.5 * (sLower + radius) * ny
    p.separation = sLower - radius
    p.id = makeFeatureId(0, i2)
  }
  if (sUpper - radius < spec) {
    const p = out.points[n++]
    p.x = upperX - 0.5 * (sUpper + radius) * nx
    p.y = upperY - 0.5 * (sUpper + radius) * ny
    p.separation = sUpper - radius
    p.id = makeFeatureId(1, i1)
  }
  out.pointCount = n
}

/**
 * Polygon face `face` (normal n) is the reference: refused when the segment's neighbour would be the
 * incident edge; otherwise the segment is clipped to the face's ends (the segment runs against the
 * face's direction) and the points are kept as in clipToSegmentFace. The manifold normal is -n.
 */
function clipToPolygonFace(count: number, face: number, out: Manifold): void {
  const spec = seg[SPECULATIVE]
  const p1x = seg[P1X]
  const p1y = seg[P1Y]
  const p2x = seg[P2X]
  const p2y = seg[P2Y]
  const nx = other[2 * M + face]
  const ny = other[3 * M + face]
  const i2 = face + 1 < count ? face + 1 : 0
  const a1x = other[face]
  const a1y = other[M + face]
  const a2x = other[i2]
  const a2y = other[M + i2]
  const n1x = seg[E1Y]
  const n1y = -seg[E1X]
  // The deeper end of the segment decides which neighbour could be incident instead.
  const dot1 = nx * (p1x - a1x) + ny * (p1y - a1y)
  const dot2 = nx * (p2x - a1x) + ny * (p2y - a1y)
  const along1 = n1x * nx + n1y * ny
  if (dot1 < dot2) {
    const n0x = seg[CONVEX1] === 1 ? seg[N0X] : n1x
    const n0y = seg[CONVEX1] === 1 ? seg[N0Y] : n1y
    if (n0x * nx + n0y * ny < along1) return
  } else {
    const n2x = seg[CONVEX2] === 1 ? seg[N2X] : n1x
    const n2y = seg[CONVEX2] === 1 ? seg[N2Y] : n1y
    if (n2x * nx + n2y * ny < along1) return
  }
  // Tangent of the face a1 -> a2; the segment runs against it, so p1 is the upper end.
  const tx = -ny
  const ty = nx
  const upper1 = tx * (a2x - a1x) + ty * (a2y - a1y)
  const upper2 = tx * (p1x - a1x) + ty * (p1y - a1y)
  const lower2 = tx * (p2x - a1x) + ty * (p2y - a1y)
  if (upper2 < 0 || upper1 < lower2) return
  const span = upper2 - lower2
  let lowerX = p2x
  let lowerY = p2y
  let upperX = p1x
  let upperY = p1y
  if (lower2 < 0 && span > TINY_DISTANCE) {
    const t = -lower2 / span
    lowerX = p2x + t * (p1x - p2x)
    lowerY = p2y + t * (p1y - p2y)
  }
  if (upper2 > upper1 && span > TINY_DISTANCE) {
    const t = (upper1 - lower2) / span
    upperX = p2x + t * (p1x - p2x)
    upperY = p2y + t * (p1y - p2y)
  }
  const radius = seg[RADIUS]
  const sLower = nx * (lowerX - a1x) + ny * (lowerY - a1y)
  const sUpper = nx * (upperX - a1x) + ny * (upperY - a1y)
  out.normalX = -nx
  out.normalY = -ny
  let n = 0
  if (sLower - radius < spec) {
    const p = out.points[n++]
    // Halfway between the rounded face (radius) and the segment point (s): v + (radius - s) / 2 n.
    p.x = lowerX + 0.5 * (radius - sLower) * nx
    p.y = lowerY + 0.5 * (radius - sLower) * ny
    p.separation = sLower - radius
    p.id = makeFeatureId(0x10 | 1, face)
  }
  if (sUpper - radius < spec) {
    const p = out.points[n++]
    p.x = upperX + 0.5 * (radius - sUpper) * nx
    p.y = upperY + 0.5 * (radius - sUpper) * ny
    p.separation = sUpper - radius
    p.id = makeFeatureId(0x10, face)
  }
  out.pointCount = n
}
