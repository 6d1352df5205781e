/*
 * Ray casts against single shapes in their local frame, after Box2D v3.1's geometry.c
 * (b2RayCastCircle, b2RayCastCapsule, b2RayCastSegment, b2RayCastPolygon).
 *
 * A ray is an origin, a translation and a maxFraction: it covers origin + t * translation for t in
 * [0, maxFraction]. A hit gives the fraction t of the first point where the ray enters the shape,
 * that point, and the shape's outward unit normal there. The start-inside rule is Box2D v3.1's: a
 * ray that starts inside a circle, capsule or polygon (rounded or not) hits at fraction 0 with the
 * point at the origin and a zero normal ("initial overlap"); a segment has no inside. A chain
 * segment is one-sided: a ray starting on its left (the side its normal does not face) passes
 * through it.
 *
 * Differences from Box2D, for exact answers: numbers are doubles, not floats; a rounded polygon
 * is cast exactly, as the first entry into its offset edges and corner circles (Box2D runs a
 * shape cast there, which stops a linear slop short of the surface); the capsule's parallel-ray
 * test uses 1e-15 for float epsilon.
 *
 * Allocation: none. The caller passes the output object (makeCastOutput() once) and gets it back
 * on a hit, or null on a miss. Numbers cross internal calls through the module's scratch array,
 * never as arguments (V8 boxes a double argument of a call it does not inline).
 */
import type { Vec2 } from '../math.ts'

/** A ray: the points origin + t * translation for t in [0, maxFraction] (m). */
export interface RayCastInput {
  origin: Vec2
  translation: Vec2
  /** Largest fraction of the translation to look along, usually 1. */
  maxFraction: number
}

/** Where a ray or a moving shape first touches a shape. */
export interface CastOutput {
  /** Fraction of the translation at the hit (0 for an initial overlap). */
  fraction: number
  /** The hit point (m); the ray's origin for an initial overlap. */
  point: Vec2
  /** The shape's outward unit normal at the point; (0, 0) for an initial overlap. */
  normal: Vec2
}

/** A circle: centre (m) and radius (m). */
export interface CircleGeometry {
  readonly center: Vec2
  readonly radius: number
}

/** A capsule: the segment center1-center2 (m) thickened by radius (m). */
export interface CapsuleGeometry {
  readonly center1: Vec2
  readonly center2: Vec2
  readonly radius: number
}

/** A convex polygon, counter-clockwise, with outward unit edge normals, rounded by radius (m; 0 for sharp). */
export interface PolygonGeometry {
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  readonly count: number
  readonly radius: number
}

/** A two-sided segment point1-point2 (m). */
export interface SegmentGeometry {
  readonly point1: Vec2
  readonly point2: Vec2
}

/** A chain segment: its segment, one-sided (solid to the right of point1 -> point2), and ghost vertices. */
export interface ChainSegmentGeometry {
  readonly ghost1: Vec2
  readonly segment: SegmentGeometry
  readonly ghost2: Vec2
}

/** A fresh output object to reuse for casts. */
export function makeCastOutput(): CastOutput {
  return { fraction: 0, point: { x: 0, y: 0 }, normal: { x: 0, y: 0 } }
}

/** Throws a RangeError unless the ray has a finite origin and translation and 0 <= maxFraction < Infinity. */
export function checkRayInput(input: RayCastInput): void {
  const o = input.origin
  const d = input.translation
  if (!o || !Number.isFinite(o.x) || !Number.isFinite(o.y)) {
    throw new RangeError(`ray origin must be a finite point, got ${JSON.stringify(o)}`)
  }
  if (!d || !Number.isFinite(d.x) || !Number.isFinite(d.y)) {
    throw new RangeError(`ray translation must be a finite vector, got ${JSON.stringify(d)}`)
  }
  const f = input.maxFraction
  if (!(f >= 0 && f < Number.POSITIVE_INFINITY)) {
    throw new RangeError(`ray maxFraction must be a finite number >= 0, got ${f}`)
  }
}

// Numbers handed between the helpers below: the circle radius for castCircle.
const scratch = new Float64Array(1)
const RADIUS = 0

/** Ray against a circle (Box2D v3.1 b2RayCastCircle, Ray Tracing Gems ch. 7): `out` on a hit, else null. */
export function rayCastCircle(
  shape: CircleGeometry,
  input: RayCastInput,
  out: CastOutput,
): CastOutput | null {
  checkRayInput(input)
  scratch[RADIUS] = shape.radius
  return castCircle(shape.center, input, out)
}

/** Ray against the circle at `center` of radius scratch[RADIUS]. */
function castCircle(center: Vec2, input: RayCastInput, out: CastOutput): CastOutput | null {
  const r = scratch[RADIUS]
  const rr = r * r
  // Shift so the centre is the origin.
  const sx = input.origin.x - center.x
  const sy = input.origin.y - center.y
  const ss = sx * sx + sy * sy
  const tx = input.translation.x
  const ty = input.translation.y
  const length = Math.sqrt(tx * tx + ty * ty)
  if (length === 0) return ss < rr ? initialOverlap(input, out) : null
  const dx = tx / length
  const dy = ty / length
  // Closest point of the line to the centre, then Pythagoras (more precise than the quadratic).
  const t = -(sx * dx + sy * dy)
  const cx = sx + t * dx
  const cy = sy + t * dy
  const cc = cx * cx + cy * cy
  if (cc > rr) return null
  const h = Math.sqrt(rr - cc)
  const distance = t - h
  if (distance < 0 || input.maxFraction * length < distance)
    return ss < rr ? initialOverlap(input, out) : null
  const hx = sx + distance * dx
  const hy = sy + distance * dy
  const hl = Math.sqrt(hx * hx + hy * hy)
  out.fraction = distance / length
  out.normal.x = hx / hl
  out.normal.y = hy / hl
  out.point.x = center.x + r * out.normal.x
  out.point.y = center.y + r * out.normal.y
  return out
}

function initialOverlap(input: RayCastInput, out: CastOutput): CastOutput {
  out.fraction = 0
  out.point.x = input.origin.x
  out.point.y = input.origin.y
  out.normal.x = 0
  out.normal.y = 0
  return out
}

/** Ray against a capsule (Box2D v3.1 b2RayCastCapsule): `out` on a hit, else null. */
export function rayCastCapsule(
  shape: CapsuleGeometry,
  input: RayCastInput,
  out: CastOutput,
): CastOutput | null {
  checkRayInput(input)
  const v1 = shape.center1
  const v2 = shape.center2
  const radius = shape.radius
  scratch[RADIUS] = radius
  const ex = v2.x - v1.x
  const ey = v2.y - v1.y
  const capsuleLength = Math.sqrt(ex * ex + ey * ey)
  if (capsuleLength === 0) return castCircle(v1, input, out)
  const ax = ex / capsuleLength
  const ay = ey / capsuleLength
  // From the capsule's start to the ray's, along and across the axis.
  const qx = input.origin.x - v1.x
  const qy = input.origin.y - v1.y
  const qa = qx * ax + qy * ay
  const qpx = qx - qa * ax
  const qpy = qy - qa * ay
  if (qpx * qpx + qpy * qpy < radius * radius) {
    // Inside the infinite capsule: behind it, ahead of it, or inside.
    if (qa < 0) return castCircle(v1, input, out)
    if (qa > capsuleLength) return castCircle(v2, input, out)
    return initialOverlap(input, out)
  }
  const tx = input.translation.x
  const ty = input.translation.y
  const rayLength = Math.sqrt(tx * tx + ty * ty)
  if (rayLength === 0) return null
  const ux = tx / rayLength
  const uy = ty / rayLength
  // The ray against the two side lines v1 +- radius n + s1 a = p1 + s2 u, by Cramer's rule.
  let nx = ay
  let ny = -ax
  const den = -ax * uy + ux * ay
  if (-1e-15 < den && den < 1e-15) return null // parallel, outside the infinite capsule
  const b1x = qx - radius * nx
  const b1y = qy - radius * ny
  const b2x = qx + radius * nx
  const b2y = qy + radius * ny
  const invDen = 1 / den
  const s21 = (ax * b1y - b1x * ay) * invDen
  const s22 = (ax * b2y - b2x * ay) * invDen
  let s2: number
  let bx: number
  let by: number
  if (s21 < s22) {
    s2 = s21
    bx = b1x
    by = b1y
  } else {
    s2 = s22
    bx = b2x
    by = b2y
    nx = -nx
    ny = -ny
  }
  if (s2 < 0 || input.maxFraction * rayLength < s2) return null
  const s1 = (-bx * uy + ux * by) * invDen
  if (s1 < 0) return castCircle(v1, input, out) // passes behind the segment
  if (capsuleLength < s1) return castCircle(v2, input, out) // passes ahead of it
  const w = s1 / capsuleLength
  out.fraction = s2 / rayLength
  out.point.x = v1.x + w * ex + radius * nx
  out.point.y = v1.y + w * ey + radius * ny
  out.normal.x = nx
  out.normal.y = ny
  return out
}

/**
 * Ray against a segment (Box2D v3 b2RayCastSegment). Two-sided: the normal faces the ray's origin.
 * With `oneSided`, a ray starting on the segment's left (cross(origin - point1, point2 - point1) < 0)
 * misses. `out` on a hit, else null.
 */
export function rayCastSegment(
  shape: SegmentGeometry,
  input: RayCastInput,
  oneSided: boolean,
  out: CastOutput,
): CastOutput | null {
  checkRayInput(input)
  const v1 = shape.point1
  const v2 = shape.point2
  const px = input.origin.x
  const py = input.origin.y
  const ex = v2.x - v1.x
  const ey = v2.y - v1.y
  if (oneSided && (px - v1.x) * ey - (py - v1.y) * ex < 0) return null
  const length = Math.sqrt(ex * ex + ey * ey)
  if (length === 0) return null
  const eux = ex / length
  const euy = ey / length
  // The normal points to the right of point1 -> point2.
  let nx = euy
  let ny = -eux
  // The ray against the segment's line: dot(n, p1 + t d - v1) = 0.
  const dx = input.translation.x
  const dy = input.translation.y
  const numerator = nx * (v1.x - px) + ny * (v1.y - py)
  const denominator = nx * dx + ny * dy
  if (denominator === 0) return null // parallel
  const t = numerator / denominator
  if (t < 0 || input.maxFraction < t) return null
  const hx = px + t * dx
  const hy = py + t * dy
  const s = (hx - v1.x) * eux + (hy - v1.y) * euy
  if (s < 0 || length < s) return null
  if (numerator > 0) {
    nx = -nx
    ny = -ny
  }
  out.fraction = t
  out.point.x = hx
  out.point.y = hy
  out.normal.x = nx
  out.normal.y = ny
  return out
}

/** Ray against a chain segment: its segment, one-sided (Box2D v3 b2RayCastShape for chain segments). */
export function rayCastChainSegment(
  shape: ChainSegmentGeometry,
  input: RayCastInput,
  out: CastOutput,
): CastOutput | null {
  return rayCastSegment(shape.segment, input, true, out)
}

/**
 * Ray against a convex polygon (Box2D v3.1 b2RayCastPolygon for radius 0: clip the ray by each
 * edge's half plane, in a frame shifted to vertex 0). A rounded polygon (radius > 0) is cast
 * exactly: the first entry among its edges pushed out by the radius and the circles at its
 * vertices. `out` on a hit, else null.
 */
export function rayCastPolygon(
  shape: PolygonGeometry,
  input: RayCastInput,
  out: CastOutput,
): CastOutput | null {
  checkRayInput(input)
  if (shape.radius > 0) return castRoundedPolygon(shape, input, out)
  const vs = shape.vertices
  const ns = shape.normals
  const baseX = vs[0].x
  const baseY = vs[0].y
  const p1x = input.origin.x - baseX
  const p1y = input.origin.y - baseY
  const dx = input.translation.x
  const dy = input.translation.y
  let lower = 0
  let upper = input.maxFraction
  let index = -1
  for (let i = 0; i < shape.count; i++) {
    // dot(normal, p1 + a d - v) = 0 where the ray crosses edge i's line.
    const nx = ns[i].x
    const ny = ns[i].y
    const numerator = nx * (vs[i].x - baseX - p1x) + ny * (vs[i].y - baseY - p1y)
    const denominator = nx * dx + ny * dy
    if (denominator === 0) {
      if (numerator < 0) return null // parallel and outside this edge
    } else if (denominator < 0 && numerator < lower * denominator) {
      // Enters this half plane later than any before.
      lower = numerator / denominator
      index = i
    } else if (denominator > 0 && numerator < upper * denominator) {
      // Leaves this half plane earlier.
      upper = numerator / denominator
    }
    if (upper < lower) return null
  }
  if (index < 0) return initialOverlap(input, out)
  out.fraction = lower
  out.normal.x = ns[index].x
  out.normal.y = ns[index].y
  out.point.x = input.origin.x + lower * dx
  out.point.y = input.origin.y + lower * dy
  return out
}

/** Exact ray cast against a rounded polygon: inside test, then the first of its offset edges and corner circles. */
function castRoundedPolygon(shape: PolygonGeometry, input: RayCastInput, out: CastOutput): CastOutput | null {
  const vs = shape.vertices
  const ns = shape.normals
  const count = shape.count
  const radius = shape.radius
  const px = input.origin.x
  const py = input.origin.y
  // Start inside: within radius of the core polygon (or inside it).
  let separation = Number.NEGATIVE_INFINITY
  for (let i = 0; i < count; i++) {
    separation = Math.max(separation, ns[i].x * (px - vs[i].x) + ns[i].y * (py - vs[i].y))
  }
  if (separation <= 0) return initialOverlap(input, out)
  let closest = Number.POSITIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const a = vs[i]
    const b = vs[i + 1 < count ? i + 1 : 0]
    const ex = b.x - a.x
    const ey = b.y - a.y
    const e2 = ex * ex + ey * ey
    const w = Math.max(0, Math.min(1, ((px - a.x) * ex + (py - a.y) * ey) / e2))
    const qx = px - a.x - w * ex
    const qy = py - a.y - w * ey
    closest = Math.min(closest, qx * qx + qy * qy)
  }
  if (closest < radius * radius) return initialOverlap(input, out)
  const dx = input.translation.x
  const dy = input.translation.y
  let best = Number.POSITIVE_INFINITY
  let bestNx = 0
  let bestNy = 0
  // Edges pushed out by the radius: entered where the ray crosses them going inwards.
  for (let i = 0; i < count; i++) {
    const nx = ns[i].x
    const ny = ns[i].y
    const denominator = nx * dx + ny * dy
    if (!(denominator < 0)) continue
    const a = vs[i]
    const b = vs[i + 1 < count ? i + 1 : 0]
    const t = (nx * (a.x + radius * nx - px) + ny * (a.y + radius * ny - py)) / denominator
    if (t < 0 || t > input.maxFraction || !(t < best)) continue
    const hx = px + t * dx - radius * nx
    const hy = py + t * dy - radius * ny
    const ex = b.x - a.x
    const ey = b.y - a.y
    const s = (hx - a.x) * ex + (hy - a.y) * ey
    if (s < 0 || s > ex * ex + ey * ey) continue
    best = t
    bestNx = nx
    bestNy = ny
  }
  // Corner circles.
  scratch[RADIUS] = radius
  for (let i = 0; i < count; i++) {
    if (castCircle(vs[i], input, out) !== null && out.fraction < best) {
      best = out.fraction
      bestNx = out.normal.x
      bestNy = out.normal.y
    }
  }
  if (best === Number.POSITIVE_INFINITY) return null
  out.fraction = best
  out.point.x = px + best * dx
  out.point.y = py + best * dy
  out.normal.x = bestNx
  out.normal.y = bestNy
  return out
}
