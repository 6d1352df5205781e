/*
 * The distance between two convex shapes by GJK (Box2D v3's b2ShapeDistance, distance.c; Catto,
 * "Computing Distance", GDC 2010). Each shape is a proxy: up to 8 points and a radius (a circle is
 * one point, a capsule or segment two, a polygon its vertices), so one routine serves every pair.
 *
 * GJK works on the Minkowski difference A - B in A's frame: a simplex of one to three support
 * points (a point of A minus a point of B) is reduced to the sub-simplex nearest the origin
 * (barycentric regions, Ericson 9.5), the search direction is from that nearest point to the
 * origin, and a new support point is added until it repeats one already in the simplex (the main
 * exit) or 20 iterations pass. Three points mean the origin is inside: the cores overlap (distance
 * 0, no normal). Only + - * / and Math.sqrt; the same proxies give the same bits everywhere.
 *
 * engine/collision/swept-distance.ts measures distances for continuous collision, but on Body objects and
 * without the closest points or the normal, which a cast needs; so this is a separate routine.
 *
 * Allocation: none per call. Proxies and outputs are the caller's (makeShapeProxy(),
 * makeDistanceOutput()); scratch lives in module Float64Arrays and no double crosses a call.
 */
import { LINEAR_SLOP, MAX_POLYGON_VERTICES } from '../constants.ts'
import type { Vec2 } from '../math.ts'
import type { CapsuleGeometry, CircleGeometry, PolygonGeometry, SegmentGeometry } from './ray-cast.ts'

/** A rigid transform: position (m) and rotation as its cosine and sine. */
export interface Transform {
  x: number
  y: number
  c: number
  s: number
}

/** Box2D's b2ShapeProxy: `count` points (x, y pairs in `points`, m) and a radius (m). */
export interface ShapeProxy {
  readonly points: Float64Array
  count: number
  radius: number
}

/** Result of shapeDistance. */
export interface DistanceOutput {
  /** Closest point on A (m, world). */
  pointA: Vec2
  /** Closest point on B (m, world). */
  pointB: Vec2
  /** Unit normal from A to B (world); (0, 0) when the cores overlap. */
  normal: Vec2
  /** Distance (m): between the cores, or between the surfaces when radii are used; 0 when overlapping. */
  distance: number
  /** Support-point iterations taken. */
  iterations: number
  /** Points of A and of B in the final simplex that are distinct (1 or 2 each; 3 and 3 on overlap). */
  featureA: number
  featureB: number
}

/** The identity transform. */
export const IDENTITY: Readonly<Transform> = Object.freeze({ x: 0, y: 0, c: 1, s: 0 })

/** A proxy with room for 8 points. */
export function makeShapeProxy(): ShapeProxy {
  return { points: new Float64Array(2 * MAX_POLYGON_VERTICES), count: 0, radius: 0 }
}

/** A fresh distance output to reuse. */
export function makeDistanceOutput(): DistanceOutput {
  return {
    pointA: { x: 0, y: 0 },
    pointB: { x: 0, y: 0 },
    normal: { x: 0, y: 0 },
    distance: 0,
    iterations: 0,
    featureA: 0,
    featureB: 0,
  }
}

/** Fills `out` with a circle's proxy (its centre, its radius). */
export function circleProxy(shape: CircleGeometry, out: ShapeProxy): ShapeProxy {
  out.points[0] = shape.center.x
  out.points[1] = shape.center.y
  out.count = 1
  out.radius = shape.radius
  return out
}

/** Fills `out` with a capsule's proxy (its two centres, its radius). */
export function capsuleProxy(shape: CapsuleGeometry, out: ShapeProxy): ShapeProxy {
  out.points[0] = shape.center1.x
  out.points[1] = shape.center1.y
  out.points[2] = shape.center2.x
  out.points[3] = shape.center2.y
  out.count = 2
  out.radius = shape.radius
  return out
}

/** Fills `out` with a polygon's proxy (its vertices, its rounding radius). */
export function polygonProxy(shape: PolygonGeometry, out: ShapeProxy): ShapeProxy {
  for (let i = 0; i < shape.count; i++) {
    out.points[2 * i] = shape.vertices[i].x
    out.points[2 * i + 1] = shape.vertices[i].y
  }
  out.count = shape.count
  out.radius = shape.radius
  return out
}

/** Fills `out` with a segment's proxy (its two points, radius 0). */
export function segmentProxy(shape: SegmentGeometry, out: ShapeProxy): ShapeProxy {
  out.points[0] = shape.point1.x
  out.points[1] = shape.point1.y
  out.points[2] = shape.point2.x
  out.points[3] = shape.point2.y
  out.count = 2
  out.radius = 0
  return out
}

// B's points in A's frame.
const localB = new Float64Array(2 * MAX_POLYGON_VERTICES)
// Simplex: three vertices of STRIDE numbers (wA, wB, w = wA - wB, barycentric a, indexA, indexB).
const WAX = 0
const WAY = 1
const WBX = 2
const WBY = 3
const WX = 4
const WY = 5
const A = 6
const IA = 7
const IB = 8
const STRIDE = 9
const simplex = new Float64Array(3 * STRIDE)
// Search direction (d) written by the solvers, and witness points.
const work = new Float64Array(6)
const DX = 0
const DY = 1
const PAX = 2
const PAY = 3
const PBX = 4
const PBY = 5
let simplexCount = 0

/**
 * Distance between proxyA at transformA and proxyB at transformB (Box2D b2ShapeDistance with an
 * empty cache). With `useRadii`, the radii are subtracted (floored at 0) and the points moved onto
 * the surfaces, as Box2D does when the cores are more than a tenth of a slop apart. Fills `out`.
 */
export function shapeDistance(
  proxyA: ShapeProxy,
  transformA: Transform,
  proxyB: ShapeProxy,
  transformB: Transform,
  useRadii: boolean,
  out: DistanceOutput,
): DistanceOutput {
  // B in A's frame: q = qA^T qB, p = qA^T (pB - pA).
  const ac = transformA.c
  const as = transformA.s
  const qc = ac * transformB.c + as * transformB.s
  const qs = ac * transformB.s - as * transformB.c
  const dx = transformB.x - transformA.x
  const dy = transformB.y - transformA.y
  const px = ac * dx + as * dy
  const py = ac * dy - as * dx
  const countB = proxyB.count
  for (let i = 0; i < countB; i++) {
    const x = proxyB.points[2 * i]
    const y = proxyB.points[2 * i + 1]
    localB[2 * i] = qc * x - qs * y + px
    localB[2 * i + 1] = qs * x + qc * y + py
  }
  const pa = proxyA.points
  // Start from the first points of each.
  setVertex(0, pa, 0, 0)
  simplex[A] = 1
  simplexCount = 1
  let nonUnitX = 0
  let nonUnitY = 0
  let iteration = 0
  let overlap = false
  while (iteration < 20) {
    // The simplex's indices before solving, to detect a repeated support point.
    const saveCount = simplexCount
    const sa0 = simplex[IA]
    const sb0 = simplex[IB]
    const sa1 = simplex[STRIDE + IA]
    const sb1 = simplex[STRIDE + IB]
    const sa2 = simplex[2 * STRIDE + IA]
    const sb2 = simplex[2 * STRIDE + IB]
    if (simplexCount === 1) {
      work[DX] = -simplex[WX]
      work[DY] = -simplex[WY]
    } else if (simplexCount === 2) {
      solve2()
    } else {
      solve3()
    }
    if (simplexCount === 3) {
      overlap = true
      break
    }
    const ddx = work[DX]
    const ddy = work[DY]
    // A direction too short to trust: the origin is on the simplex, the cores touch or overlap.
    if (ddx * ddx + ddy * ddy < 1e-30) {
      overlap = true
      break
    }
    nonUnitX = ddx
    nonUnitY = ddy
    // New support point: support(A, d) - support(B, -d).
    const ia = support(pa, proxyA.count, 1)
    const ib = support(localB, countB, -1)
    iteration++
    let duplicate = false
    if (ia === sa0 && ib === sb0) duplicate = true
    if (saveCount > 1 && ia === sa1 && ib === sb1) duplicate = true
    if (saveCount > 2 && ia === sa2 && ib === sb2) duplicate = true
    if (duplicate) break
    setVertex(simplexCount, pa, ia, ib)
    simplexCount++
  }
  out.iterations = iteration
  witnessPoints()
  countFeatures(out)
  const pAx = work[PAX]
  const pAy = work[PAY]
  const pBx = work[PBX]
  const pBy = work[PBY]
  out.pointA.x = transformA.x + ac * pAx - as * pAy
  out.pointA.y = transformA.y + as * pAx + ac * pAy
  out.pointB.x = transformA.x + ac * pBx - as * pBy
  out.pointB.y = transformA.y + as * pBx + ac * pBy
  if (overlap) {
    out.distance = 0
    out.normal.x = 0
    out.normal.y = 0
    return out
  }
  const length = Math.sqrt(nonUnitX * nonUnitX + nonUnitY * nonUnitY)
  const nx = nonUnitX / length
  const ny = nonUnitY / length
  out.normal.x = ac * nx - as * ny
  out.normal.y = as * nx + ac * ny
  const ex = pBx - pAx
  const ey = pBy - pAy
  out.distance = Math.sqrt(ex * ex + ey * ey)
  if (useRadii && out.distance > 0.1 * LINEAR_SLOP) {
    const ra = proxyA.radius
    const rb = proxyB.radius
    out.distance = Math.max(0, out.distance - ra - rb)
    out.pointA.x += ra * out.normal.x
    out.pointA.y += ra * out.normal.y
    out.pointB.x -= rb * out.normal.x
    out.pointB.y -= rb * out.normal.y
  }
  return out
}

/** Simplex vertex k = A's point ia minus B's (local) point ib. */
function setVertex(k: number, pa: Float64Array, ia: number, ib: number): void {
  const o = k * STRIDE
  simplex[o + WAX] = pa[2 * ia]
  simplex[o + WAY] = pa[2 * ia + 1]
  simplex[o + WBX] = localB[2 * ib]
  simplex[o + WBY] = localB[2 * ib + 1]
  simplex[o + WX] = simplex[o + WAX] - simplex[o + WBX]
  simplex[o + WY] = simplex[o + WAY] - simplex[o + WBY]
  simplex[o + IA] = ia
  simplex[o + IB] = ib
}

/** Index of the point of `points` farthest along sign * work[D] (the first on a tie). */
function support(points: Float64Array, count: number, sign: number): number {
  const dx = sign * work[DX]
  const dy = sign * work[DY]
  let best = 0
  let bestValue = points[0] * dx + points[1] * dy
  for (let i = 1; i < count; i++) {
    const value = points[2 * i] * dx + points[2 * i + 1] * dy
    if (value > bestValue) {
      best = i
      bestValue = value
    }
  }
  return best
}

/** Copies simplex vertex `from` into slot `to`. */
function moveVertex(from: number, to: number): void {
  for (let i = 0; i < STRIDE; i++) simplex[to * STRIDE + i] = simplex[from * STRIDE + i]
}

/** Nearest point of the segment w1 w2 to the origin (Box2D b2SolveSimplex2); direction into work[D]. */
function solve2(): void {
  const w1x = simplex[WX]
  const w1y = simplex[WY]
  const w2x = simplex[STRIDE + WX]
  const w2y = simplex[STRIDE + WY]
  const ex = w2x - w1x
  const ey = w2y - w1y
  // w1 region
  const d12n2 = -(w1x * ex + w1y * ey)
  if (d12n2 <= 0) {
    simplex[A] = 1
    simplexCount = 1
    work[DX] = -w1x
    work[DY] = -w1y
    return
  }
  // w2 region
  const d12n1 = w2x * ex + w2y * ey
  if (d12n1 <= 0) {
    moveVertex(1, 0)
    simplex[A] = 1
    simplexCount = 1
    work[DX] = -w2x
    work[DY] = -w2y
    return
  }
  // Edge region: the perpendicular towards the origin, cross(cross(w1 + w2, e), e).
  const inv = 1 / (d12n1 + d12n2)
  simplex[A] = d12n1 * inv
  simplex[STRIDE + A] = d12n2 * inv
  simplexCount = 2
  const c = (w1x + w2x) * ey - (w1y + w2y) * ex
  work[DX] = -c * ey
  work[DY] = c * ex
}

/** Nearest feature of the triangle w1 w2 w3 to the origin (Box2D b2SolveSimplex3). */
function solve3(): void {
  const w1x = simplex[WX]
  const w1y = simplex[WY]
  const w2x = simplex[STRIDE + WX]
  const w2y = simplex[STRIDE + WY]
  const w3x = simplex[2 * STRIDE + WX]
  const w3y = simplex[2 * STRIDE + WY]
  const e12x = w2x - w1x
  const e12y = w2y - w1y
  const d12n1 = w2x * e12x + w2y * e12y
  const d12n2 = -(w1x * e12x + w1y * e12y)
  const e13x = w3x - w1x
  const e13y = w3y - w1y
  const d13n1 = w3x * e13x + w3y * e13y
  const d13n2 = -(w1x * e13x + w1y * e13y)
  const e23x = w3x - w2x
  const e23y = w3y - w2y
  const d23n1 = w3x * e23x + w3y * e23y
  const d23n2 = -(w2x * e23x + w2y * e23y)
  const n123 = e12x * e13y - e12y * e13x
  const d123n1 = n123 * (w2x * w3y - w2y * w3x)
  const d123n2 = n123 * (w3x * w1y - w3y * w1x)
  const d123n3 = n123 * (w1x * w2y - w1y * w2x)
  // w1 region
  if (d12n2 <= 0 && d13n2 <= 0) {
    simplex[A] = 1
    simplexCount = 1
    work[DX] = -w1x
    work[DY] = -w1y
    return
  }
  // e12
  if (d12n1 > 0 && d12n2 > 0 && d123n3 <= 0) {
    const inv = 1 / (d12n1 + d12n2)
    simplex[A] = d12n1 * inv
    simplex[STRIDE + A] = d12n2 * inv
    simplexCount = 2
    const c = (w1x + w2x) * e12y - (w1y + w2y) * e12x
    work[DX] = -c * e12y
    work[DY] = c * e12x
    return
  }
  // e13
  if (d13n1 > 0 && d13n2 > 0 && d123n2 <= 0) {
    const inv = 1 / (d13n1 + d13n2)
    simplex[A] = d13n1 * inv
    moveVertex(2, 1)
    simplex[STRIDE + A] = d13n2 * inv
    simplexCount = 2
    const c = (w1x + w3x) * e13y - (w1y + w3y) * e13x
    work[DX] = -c * e13y
    work[DY] = c * e13x
    return
  }
  // w2 region
  if (d12n1 <= 0 && d23n2 <= 0) {
    moveVertex(1, 0)
    simplex[A] = 1
    simplexCount = 1
    work[DX] = -w2x
    work[DY] = -w2y
    return
  }
  // w3 region
  if (d13n1 <= 0 && d23n1 <= 0) {
    moveVertex(2, 0)
    simplex[A] = 1
    simplexCount = 1
    work[DX] = -w3x
    work[DY] = -w3y
    return
  }
  // e23
  if (d23n1 > 0 && d23n2 > 0 && d123n1 <= 0) {
    const inv = 1 / (d23n1 + d23n2)
    moveVertex(2, 0)
    simplex[A] = d23n2 * inv
    simplex[STRIDE + A] = d23n1 * inv
    simplexCount = 2
    const c = (w2x + w3x) * e23y - (w2y + w3y) * e23x
    work[DX] = -c * e23y
    work[DY] = c * e23x
    return
  }
  // Inside the triangle.
  const inv = 1 / (d123n1 + d123n2 + d123n3)
  simplex[A] = d123n1 * inv
  simplex[STRIDE + A] = d123n2 * inv
  simplex[2 * STRIDE + A] = d123n3 * inv
  simplexCount = 3
  work[DX] = 0
  work[DY] = 0
}

/** Witness points of the simplex (in A's frame) into work[PA], work[PB]. */
function witnessPoints(): void {
  let ax = 0
  let ay = 0
  let bx = 0
  let by = 0
  for (let k = 0; k < simplexCount; k++) {
    const o = k * STRIDE
    const a = simplex[o + A]
    ax += a * simplex[o + WAX]
    ay += a * simplex[o + WAY]
    bx += a * simplex[o + WBX]
    by += a * simplex[o + WBY]
  }
  if (simplexCount === 3) {
    // Box2D: on overlap both witnesses are A's point.
    bx = ax
    by = ay
  }
  work[PAX] = ax
  work[PAY] = ay
  work[PBX] = bx
  work[PBY] = by
}

/** How many distinct points of A and of B the final simplex uses. */
function countFeatures(out: DistanceOutput): void {
  let fa = 1
  let fb = 1
  if (simplexCount >= 2) {
    if (simplex[IA] !== simplex[STRIDE + IA]) fa++
    if (simplex[IB] !== simplex[STRIDE + IB]) fb++
  }
  if (simplexCount === 3) {
    fa = 3
    fb = 3
  }
  out.featureA = fa
  out.featureB = fb
}
