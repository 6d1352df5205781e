/*
 * Shapes and their mass properties: Box2D v3's set, in the body's local frame (metres).
 *
 * - circle(radius, center?): a disc.
 * - box(halfWidth, halfHeight, center?, angle?): a polygon of four vertices.
 * - polygon(points, radius?): the convex hull of 3 to 64 points, 3 to 8 vertices, counter-clockwise;
 *   points that already form a strictly convex polygon are kept exactly as given, any other list is
 *   replaced by its hull (hull.ts). convexPolygon(points, radius?) takes exactly the vertices given
 *   and refuses a list that is not a strictly convex polygon (the wire uses it). A radius > 0 rounds
 *   it: the shape is the polygon grown by that radius (a Minkowski sum with a disc).
 * - capsule(center1, center2, radius): a segment grown by a radius (a stadium).
 * - segment(point1, point2): a two-sided line of zero thickness and zero mass.
 *
 * Capsules and segments are laid out as two-vertex polygons (normals n and -n), which is how the
 * narrowphase treats them (Box2D v3's b2MakeCapsule): one polygon routine with a radius collides
 * every pair of them.
 *
 * Mass, centroid and rotational inertia come from density by closed forms: the polygon triangle fan
 * (Box2D's b2ComputePolygonMass; Ericson, "Real-Time Collision Detection" 2.6); for a rounded
 * polygon, exactly, the polygon plus a rectangle on each edge plus a circular sector at each vertex
 * (Box2D approximates it by pushing the vertices out); a capsule as a rectangle and two half discs
 * (b2ComputeCapsuleMass). A body of several shapes adds them by the parallel-axis theorem
 * (`combineMass`).
 */

import {
  LINEAR_SLOP,
  MAX_CHAIN_POINTS,
  MAX_POLYGON_VERTICES,
  MAX_SHAPE_EXTENT,
  MIN_SHAPE_EXTENT,
  SLENDER_RATIO,
} from '../constants.ts'
import { atan2, cos, PI, sin, TRIG_LIMIT, type Vec2 } from '../math.ts'
import { computeHull, MAX_HULL_INPUT } from './hull.ts'

/*
 * Every shape object has every field, in the same order (type, radius, count, vertices, normals,
 * centroid, box), so all shapes share one hidden class in V8 and the engine's shape reads stay
 * monomorphic: a polymorphic load of `radius` was measured to allocate in the step.
 */

/** A circle (disc) in the body frame. */
export interface CircleShape {
  readonly type: 'circle'
  /** Radius (m). */
  readonly radius: number
  /** Always 0, [] and [] for circles (uniform layout). */
  readonly count: 0
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  /** The circle's centre in the body frame (m); the origin unless given. */
  readonly centroid: Vec2
  readonly box: null
  /** Always null: only chain segments have ghost vertices (uniform layout). */
  readonly ghost1: null
  readonly ghost2: null
}

/** A convex polygon in the body frame, counter-clockwise, with outward unit edge normals. */
export interface PolygonShape {
  readonly type: 'polygon'
  /** Rounding radius (m): 0 for a sharp polygon, > 0 grows it by that much all round. */
  readonly radius: number
  /** Number of vertices, 3..8. */
  readonly count: number
  /** Vertices in the body frame (m), counter-clockwise. */
  readonly vertices: readonly Vec2[]
  /** normals[i] is the outward unit normal of edge vertices[i] -> vertices[i + 1]. */
  readonly normals: readonly Vec2[]
  /** Area centroid in the body frame (m). */
  readonly centroid: Vec2
  /**
   * Set for shapes made by box() centred on the origin and not turned: half extents (m), for
   * compact encoding and drawing; null for every other polygon.
   */
  readonly box: { readonly halfWidth: number; readonly halfHeight: number } | null
  /** Always null (uniform layout). */
  readonly ghost1: null
  readonly ghost2: null
}

/**
 * A capsule in the body frame, laid out as a two-vertex polygon with a radius: vertices [center1,
 * center2], normals [n, -n] with n the right-hand normal of center1 -> center2.
 */
export interface CapsuleShape {
  readonly type: 'capsule'
  /** Radius (m). */
  readonly radius: number
  /** Always 2. */
  readonly count: 2
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  /** Midpoint of the two centres (m). */
  readonly centroid: Vec2
  readonly box: null
  /** Always null (uniform layout). */
  readonly ghost1: null
  readonly ghost2: null
}

/** A two-sided segment of zero thickness and zero mass, laid out as a capsule of radius 0. */
export interface SegmentShape {
  readonly type: 'segment'
  /** Always 0. */
  readonly radius: number
  /** Always 2. */
  readonly count: 2
  /** [point1, point2]; normals [n, -n] with n the right-hand normal of point1 -> point2. */
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  /** Midpoint (m). */
  readonly centroid: Vec2
  readonly box: null
  /** Always null (uniform layout). */
  readonly ghost1: null
  readonly ghost2: null
}

/**
 * One segment of a chain (Box2D v3's b2ChainSegment): one-sided, zero thickness, zero mass, laid
 * out as a segment. vertices [point1, point2]; normals [n, -n] with n the right-hand normal of
 * point1 -> point2, the side that collides; ghost1 and ghost2 are the chain's points before point1
 * and after point2, which smooth the joins (chain-collide.ts). Made by chain(), never alone.
 */
export interface ChainSegmentShape {
  readonly type: 'chainSegment'
  /** Always 0. */
  readonly radius: number
  /** Always 2. */
  readonly count: 2
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  /** Midpoint (m). */
  readonly centroid: Vec2
  readonly box: null
  /** The chain's point before point1 (m, body frame). */
  readonly ghost1: Vec2
  /** The chain's point after point2 (m, body frame). */
  readonly ghost2: Vec2
}

/** Every shape kind a body can have. */
export type Shape = CircleShape | PolygonShape | CapsuleShape | SegmentShape | ChainSegmentShape

/** The shapes the narrowphase treats as polygons (capsules and segments have two vertices). */
export type PolygonalShape = PolygonShape | CapsuleShape | SegmentShape | ChainSegmentShape

/**
 * A chain (Box2D v3's b2ChainDef): made by chain(), attached to a static body as one
 * ChainSegmentShape per segment (each its own ShapeId, in order along the chain).
 */
export interface ChainShape {
  readonly type: 'chain'
  /** Whether the last point joins the first. */
  readonly loop: boolean
  /** The points as given (m, body frame). */
  readonly points: readonly Vec2[]
  /** The segments in order: points.length of them for a loop, points.length - 3 for an open chain. */
  readonly segments: readonly ChainSegmentShape[]
}

/** Mass properties of a shape at a density. */
export interface MassData {
  /** Mass (kg). */
  mass: number
  /** Centre of mass in the body frame (m). */
  center: Vec2
  /** Rotational inertia about the centre of mass (kg m^2). */
  inertia: number
}

function checkSize(what: string, value: number): void {
  if (!Number.isFinite(value) || value < MIN_SHAPE_EXTENT || value > MAX_SHAPE_EXTENT) {
    throw new RangeError(
      `${what} must be a finite number in [${MIN_SHAPE_EXTENT}, ${MAX_SHAPE_EXTENT}] m, got ${value}`,
    )
  }
}

function checkPoint(what: string, p: Vec2 | undefined): Vec2 {
  if (p === null || typeof p !== 'object' || !Number.isFinite(p.x) || !Number.isFinite(p.y)) {
    throw new RangeError(`${what} must be a finite point {x, y}, got ${JSON.stringify(p)}`)
  }
  if (Math.abs(p.x) > MAX_SHAPE_EXTENT || Math.abs(p.y) > MAX_SHAPE_EXTENT) {
    throw new RangeError(`${what} (${p.x}, ${p.y}) is more than ${MAX_SHAPE_EXTENT} m from the body origin`)
  }
  return { x: p.x, y: p.y }
}

/** A circle of the given radius (m), centred on `center` in the body frame (default: the origin). */
export function circle(radius: number, center?: Vec2): CircleShape {
  checkSize('circle radius', radius)
  const c = center === undefined ? { x: 0, y: 0 } : checkPoint('circle center', center)
  if (Math.abs(c.x) + radius > MAX_SHAPE_EXTENT || Math.abs(c.y) + radius > MAX_SHAPE_EXTENT) {
    throw new RangeError(`circle reaches more than ${MAX_SHAPE_EXTENT} m from the body origin`)
  }
  return {
    type: 'circle',
    radius,
    count: 0,
    vertices: [],
    normals: [],
    centroid: c,
    box: null,
    ghost1: null,
    ghost2: null,
  }
}

/**
 * A box of the given half extents (m), centred on `center` (default: the origin) and turned by
 * `angle` (rad, default 0) in the body frame. Vertices start at the (-halfWidth, -halfHeight) corner.
 */
export function box(halfWidth: number, halfHeight: number, center?: Vec2, angle?: number): PolygonShape {
  checkSize('box halfWidth', halfWidth)
  checkSize('box halfHeight', halfHeight)
  if (center !== undefined || (angle !== undefined && angle !== 0)) {
    return turnedBox(halfWidth, halfHeight, center ?? { x: 0, y: 0 }, angle ?? 0)
  }
  const vertices = [
    { x: -halfWidth, y: -halfHeight },
    { x: halfWidth, y: -halfHeight },
    { x: halfWidth, y: halfHeight },
    { x: -halfWidth, y: halfHeight },
  ]
  const normals = [
    { x: 0, y: -1 },
    { x: 1, y: 0 },
    { x: 0, y: 1 },
    { x: -1, y: 0 },
  ]
  return {
    type: 'polygon',
    radius: 0,
    count: 4,
    vertices,
    normals,
    centroid: { x: 0, y: 0 },
    box: { halfWidth, halfHeight },
    ghost1: null,
    ghost2: null,
  }
}

/** A box that is offset or turned: its four vertices as a polygon (box: null). */
function turnedBox(halfWidth: number, halfHeight: number, center: Vec2, angle: number): PolygonShape {
  const c0 = checkPoint('box center', center)
  if (!Number.isFinite(angle) || Math.abs(angle) >= TRIG_LIMIT) {
    throw new RangeError(`box angle must be a finite number below ${TRIG_LIMIT} rad in size, got ${angle}`)
  }
  const c = cos(angle)
  const s = sin(angle)
  const corners = [
    [-halfWidth, -halfHeight],
    [halfWidth, -halfHeight],
    [halfWidth, halfHeight],
    [-halfWidth, halfHeight],
  ]
  const points = corners.map(([x, y]) => ({ x: c0.x + c * x - s * y, y: c0.y + s * x + c * y }))
  return polygon(points)
}

function cross3(o: Vec2, a: Vec2, b: Vec2): number {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

/**
 * A convex polygon: the convex hull of `points` (3 to 64 points in the body frame, m; 3 to 8
 * vertices after the hull), rounded by `radius` (m, default 0). Points that already form a strictly
 * convex polygon of at most 8 vertices (either winding, any starting vertex) are kept exactly as
 * given, stored counter-clockwise (as convexPolygon); any other list is replaced by its hull
 * (computeHull, Box2D's quickhull: points within 0.02 m welded, vertices within 0.01 m of their
 * neighbours' line dropped). Throws a RangeError naming the problem: not an array, a non-finite or
 * too distant point, fewer than 3 or more than 64 points, points that weld to fewer than 3 or lie
 * along one line, or a hull of more than 8 vertices.
 */
export function polygon(points: readonly Vec2[], radius = 0): PolygonShape {
  if (!Array.isArray(points))
    throw new RangeError(`polygon points must be an array, got ${JSON.stringify(points)}`)
  if (radius !== 0) checkSize('polygon radius', radius)
  const n = points.length
  if (n < 3 || n > MAX_HULL_INPUT) {
    throw new RangeError(`polygon needs 3 to ${MAX_HULL_INPUT} points, got ${n}`)
  }
  checkPolygonPoints(points)
  if (n <= MAX_POLYGON_VERTICES && convexityProblem(counterClockwise(points)) === null) {
    return convexPolygon(points, radius)
  }
  let hull: Vec2[]
  try {
    hull = computeHull(points)
  } catch (e) {
    throw e instanceof RangeError ? new RangeError(`polygon: ${e.message}`) : e
  }
  return convexPolygon(hull, radius)
}

/**
 * A convex polygon from exactly the vertices given: 3..8 vertices in the body frame (m), rounded by
 * `radius` (m, default 0), in either winding and from any starting vertex, stored counter-clockwise.
 * Throws if the list is not a strictly convex polygon: repeated points, collinear vertices, a
 * concave vertex, a self-intersecting order, or too small. The wire uses this (a peer's vertex
 * list is taken as sent or refused); polygon() takes the hull instead.
 */
export function convexPolygon(points: readonly Vec2[], radius = 0): PolygonShape {
  if (!Array.isArray(points))
    throw new RangeError(`polygon points must be an array, got ${JSON.stringify(points)}`)
  if (radius !== 0) checkSize('polygon radius', radius)
  const n = points.length
  if (n < 3 || n > MAX_POLYGON_VERTICES) {
    throw new RangeError(`polygon needs 3 to ${MAX_POLYGON_VERTICES} vertices, got ${n}`)
  }
  checkPolygonPoints(points)
  const ccw = counterClockwise(points)
  const problem = convexityProblem(ccw)
  if (problem !== null) throw new RangeError(problem)
  const normals: Vec2[] = []
  for (let i = 0; i < n; i++) {
    const a = ccw[i]
    const b = ccw[(i + 1) % n]
    const ex = b.x - a.x
    const ey = b.y - a.y
    const len = Math.sqrt(ex * ex + ey * ey)
    normals.push({ x: ey / len, y: -ex / len })
  }
  const mass = polygonMass(ccw, 1)
  for (const v of ccw) {
    if (Math.abs(v.x) + radius > MAX_SHAPE_EXTENT || Math.abs(v.y) + radius > MAX_SHAPE_EXTENT) {
      throw new RangeError(`rounded polygon reaches more than ${MAX_SHAPE_EXTENT} m from the body origin`)
    }
  }
  return {
    type: 'polygon',
    radius,
    count: n,
    vertices: ccw,
    normals,
    centroid: mass.center,
    box: null,
    ghost1: null,
    ghost2: null,
  }
}

/** Throws a RangeError naming the first point that is not finite or lies too far from the body origin. */
function checkPolygonPoints(points: readonly Vec2[]): void {
  for (let i = 0; i < points.length; i++) {
    const p = points[i]
    if (!p || !Number.isFinite(p.x) || !Number.isFinite(p.y)) {
      throw new RangeError(`polygon vertex ${i} is not a finite point: ${JSON.stringify(p)}`)
    }
    if (Math.abs(p.x) > MAX_SHAPE_EXTENT || Math.abs(p.y) > MAX_SHAPE_EXTENT) {
      throw new RangeError(
        `polygon vertex ${i} (${p.x}, ${p.y}) is more than ${MAX_SHAPE_EXTENT} m from the body origin`,
      )
    }
  }
}

/** Fresh copies of the points, counter-clockwise (the signed area decides the winding). */
function counterClockwise(points: readonly Vec2[]): Vec2[] {
  const n = points.length
  let area2 = 0
  for (let i = 0; i < n; i++) {
    const a = points[i]
    const b = points[(i + 1) % n]
    area2 += a.x * b.y - a.y * b.x
  }
  const copy = points.map((p) => ({ x: p.x, y: p.y }))
  return area2 >= 0 ? copy : copy.reverse()
}

/** Why a counter-clockwise vertex list is not a strictly convex polygon (the message), or null. */
function convexityProblem(ccw: readonly Vec2[]): string | null {
  const n = ccw.length
  for (let i = 0; i < n; i++) {
    const a = ccw[i]
    const b = ccw[(i + 1) % n]
    const len = Math.sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y))
    if (len < MIN_SHAPE_EXTENT) {
      return `polygon is degenerate: vertices (${a.x}, ${a.y}) and (${b.x}, ${b.y}) are closer than ${MIN_SHAPE_EXTENT} m`
    }
  }
  for (let i = 0; i < n; i++) {
    const prev = ccw[(i + n - 1) % n]
    const cur = ccw[i]
    const next = ccw[(i + 1) % n]
    const turn = cross3(prev, cur, next)
    const ex = cur.x - prev.x
    const ey = cur.y - prev.y
    const fx = next.x - cur.x
    const fy = next.y - cur.y
    const scale = Math.sqrt(ex * ex + ey * ey) * Math.sqrt(fx * fx + fy * fy)
    if (turn <= 1e-9 * scale) {
      const what = Math.abs(turn) <= 1e-9 * scale ? 'collinear (degenerate)' : 'concave'
      return `polygon is not strictly convex: vertex ${i} (${cur.x}, ${cur.y}) is ${what}`
    }
  }
  // Every vertex strictly left of every edge it is not on: exactly convexity, and it rejects a
  // self-intersecting star whose turns are all left (n <= 8, so the n^2 check costs nothing).
  for (let i = 0; i < n; i++) {
    const a = ccw[i]
    const b = ccw[(i + 1) % n]
    for (let k = 0; k < n; k++) {
      if (k === i || k === (i + 1) % n) continue
      if (cross3(a, b, ccw[k]) <= 0) {
        return `polygon is not convex: vertex ${k} lies outside edge ${i} (self-intersecting or concave)`
      }
    }
  }
  return null
}

/** A two-vertex polygon: the shared layout of capsules and segments. */
function twoPointShape<T extends 'capsule' | 'segment'>(
  type: T,
  p1: Vec2,
  p2: Vec2,
  radius: number,
): {
  type: T
  radius: number
  count: 2
  vertices: Vec2[]
  normals: Vec2[]
  centroid: Vec2
  box: null
  ghost1: null
  ghost2: null
} {
  const dx = p2.x - p1.x
  const dy = p2.y - p1.y
  const length = Math.sqrt(dx * dx + dy * dy)
  if (!(length >= MIN_SHAPE_EXTENT)) {
    throw new RangeError(
      `${type} points (${p1.x}, ${p1.y}) and (${p2.x}, ${p2.y}) are closer than ${MIN_SHAPE_EXTENT} m`,
    )
  }
  for (const p of [p1, p2]) {
    if (Math.abs(p.x) + radius > MAX_SHAPE_EXTENT || Math.abs(p.y) + radius > MAX_SHAPE_EXTENT) {
      throw new RangeError(`${type} reaches more than ${MAX_SHAPE_EXTENT} m from the body origin`)
    }
  }
  const nx = dy / length
  const ny = -dx / length
  return {
    type,
    radius,
    count: 2,
    vertices: [p1, p2],
    normals: [
      { x: nx, y: ny },
      { x: -nx, y: -ny },
    ],
    centroid: { x: 0.5 * (p1.x + p2.x), y: 0.5 * (p1.y + p2.y) },
    box: null,
    ghost1: null,
    ghost2: null,
  }
}

/**
 * A capsule: the segment center1 -> center2 (body frame, m) grown by `radius` (m). Its ends are at
 * least MIN_SHAPE_EXTENT apart (a shorter one is a circle).
 */
export function capsule(center1: Vec2, center2: Vec2, radius: number): CapsuleShape {
  const p1 = checkPoint('capsule center1', center1)
  const p2 = checkPoint('capsule center2', center2)
  checkSize('capsule radius', radius)
  return twoPointShape('capsule', p1, p2, radius)
}

/**
 * A two-sided segment from point1 to point2 (body frame, m), of zero thickness and zero mass: for
 * static and kinematic bodies, or a dynamic body that also has a shape with mass.
 */
export function segment(point1: Vec2, point2: Vec2): SegmentShape {
  const p1 = checkPoint('segment point1', point1)
  const p2 = checkPoint('segment point2', point2)
  return twoPointShape('segment', p1, p2, 0)
}

/**
 * A one-sided chain of segments through `points` (body frame, m) for terrain and tracks (Box2D v3's
 * b2CreateChain), for static bodies only. Each segment collides on its right (the side of its
 * normal, the right of the direction of travel from one point to the next) and lets shapes on its
 * left pass through: a counter-clockwise loop is a solid outline (hit from outside), a clockwise
 * loop a container (hit from inside), and a floor runs from right to left (x decreasing).
 *
 * An open chain needs at least 4 points: the first and the last are ghost vertices only (they shape
 * the joins at the ends and are not collided), so it has points.length - 3 segments. A loop
 * (`loop: true`) needs at least 3 and has points.length segments (the last point joins the first;
 * do not repeat it). At most MAX_CHAIN_POINTS points; each finite, within MAX_SHAPE_EXTENT of the
 * body origin, and at least LINEAR_SLOP (5 mm) from the next one. Throws a RangeError naming the
 * problem otherwise.
 */
export function chain(points: readonly Vec2[], options: { loop?: boolean } = {}): ChainShape {
  if (options === null || typeof options !== 'object')
    throw new RangeError(
      `chain options must be an object like { loop: true }, got ${JSON.stringify(options)}`,
    )
  const loop = options.loop ?? false
  if (typeof loop !== 'boolean')
    throw new RangeError(`chain loop must be true or false, got ${JSON.stringify(loop)}`)
  if (!Array.isArray(points))
    throw new RangeError(`chain points must be an array, got ${JSON.stringify(points)}`)
  const n = points.length
  const least = loop ? 3 : 4
  if (n < least || n > MAX_CHAIN_POINTS) {
    throw new RangeError(
      `${loop ? 'a chain loop' : 'an open chain'} needs ${least} to ${MAX_CHAIN_POINTS} points, got ${n}` +
        (loop ? '' : ' (its first and last points are ghost vertices)'),
    )
  }
  const ps: Vec2[] = []
  for (let i = 0; i < n; i++) ps.push(checkPoint(`chain point ${i}`, points[i]))
  const edges = loop ? n : n - 1
  for (let i = 0; i < edges; i++) {
    const a = ps[i]
    const b = ps[i + 1 < n ? i + 1 : 0]
    const dx = b.x - a.x
    const dy = b.y - a.y
    if (!(Math.sqrt(dx * dx + dy * dy) >= LINEAR_SLOP)) {
      const which =
        i + 1 < n ? `points ${i} and ${i + 1}` : `the last point and the first (a loop closes itself)`
      throw new RangeError(
        `chain ${which} (${a.x}, ${a.y}) and (${b.x}, ${b.y}) are closer than ${LINEAR_SLOP} m: a zero-length or near-duplicate segment`,
      )
    }
  }
  const segments: ChainSegmentShape[] = []
  if (loop) {
    for (let i = 0; i < n; i++) {
      segments.push(chainSegment(ps[(i + n - 1) % n], ps[i], ps[(i + 1) % n], ps[(i + 2) % n]))
    }
  } else {
    for (let i = 0; i + 3 < n; i++) segments.push(chainSegment(ps[i], ps[i + 1], ps[i + 2], ps[i + 3]))
  }
  return { type: 'chain', loop, points: ps, segments }
}

/** One chain segment point1 -> point2 with its ghost vertices (already checked by chain()). */
function chainSegment(ghost1: Vec2, point1: Vec2, point2: Vec2, ghost2: Vec2): ChainSegmentShape {
  const s = twoPointShape('segment', point1, point2, 0)
  return {
    type: 'chainSegment',
    radius: 0,
    count: 2,
    vertices: s.vertices,
    normals: s.normals,
    centroid: s.centroid,
    box: null,
    ghost1: { x: ghost1.x, y: ghost1.y },
    ghost2: { x: ghost2.x, y: ghost2.y },
  }
}

/**
 * A lone chain segment with its ghost vertices, as a saved world stores it: the same checks as
 * chain() (finite points within reach, each edge at least LINEAR_SLOP long).
 */
export function chainSegmentShape(ghost1: Vec2, point1: Vec2, point2: Vec2, ghost2: Vec2): ChainSegmentShape {
  return chain([ghost1, point1, point2, ghost2]).segments[0]
}

/** Mass properties of a convex polygon at a density (kg/m^2), by a triangle fan from vertex 0. */
function polygonMass(vertices: readonly Vec2[], density: number): MassData {
  const n = vertices.length
  const origin = vertices[0]
  let area = 0
  let cx = 0
  let cy = 0
  let rotational = 0
  for (let i = 1; i < n - 1; i++) {
    const e1x = vertices[i].x - origin.x
    const e1y = vertices[i].y - origin.y
    const e2x = vertices[i + 1].x - origin.x
    const e2y = vertices[i + 1].y - origin.y
    const d = e1x * e2y - e1y * e2x
    const triangleArea = 0.5 * d
    area += triangleArea
    cx += (triangleArea * (e1x + e2x)) / 3
    cy += (triangleArea * (e1y + e2y)) / 3
    const intx2 = e1x * e1x + e2x * e1x + e2x * e2x
    const inty2 = e1y * e1y + e2y * e1y + e2y * e2y
    rotational += (0.25 / 3) * d * (intx2 + inty2)
  }
  const mass = density * area
  const centerX = cx / area
  const centerY = cy / area
  // Inertia about vertex 0, shifted to the centroid (parallel axis), then centroid relative to body.
  const inertiaAtCentroid = density * rotational - mass * (centerX * centerX + centerY * centerY)
  return { mass, center: { x: centerX + origin.x, y: centerY + origin.y }, inertia: inertiaAtCentroid }
}

/**
 * Mass properties of a polygon grown by radius r (exact): the polygon, a rectangle of width r on
 * each edge, and at each vertex a circular sector of radius r spanning the turn between the two
 * edge normals (the turns add up to a full circle).
 */
function roundedPolygonMass(shape: PolygonShape, density: number): MassData {
  const core = polygonMass(shape.vertices, density)
  const r = shape.radius
  const n = shape.count
  const vs = shape.vertices
  const ns = shape.normals
  // Sums about the body origin: mass, first moments, second moment (polar).
  let m = core.mass
  let mx = core.mass * core.center.x
  let my = core.mass * core.center.y
  let j = core.inertia + core.mass * (core.center.x * core.center.x + core.center.y * core.center.y)
  for (let i = 0; i < n; i++) {
    const a = vs[i]
    const b = vs[i + 1 < n ? i + 1 : 0]
    const nx = ns[i].x
    const ny = ns[i].y
    // Edge rectangle: length L along the edge, width r outward.
    const ex = b.x - a.x
    const ey = b.y - a.y
    const length = Math.sqrt(ex * ex + ey * ey)
    const rm = density * length * r
    const rcx = 0.5 * (a.x + b.x) + 0.5 * r * nx
    const rcy = 0.5 * (a.y + b.y) + 0.5 * r * ny
    m += rm
    mx += rm * rcx
    my += rm * rcy
    j += (rm * (length * length + r * r)) / 12 + rm * (rcx * rcx + rcy * rcy)
    // Vertex sector at b, from this edge's normal to the next edge's, angle theta.
    const mnx = ns[i + 1 < n ? i + 1 : 0].x
    const mny = ns[i + 1 < n ? i + 1 : 0].y
    const theta = atan2(nx * mny - ny * mnx, nx * mnx + ny * mny)
    const sm = 0.5 * density * theta * r * r
    // Centroid of a sector of half-angle t: 2 r sin(t) / (3 t) from its apex, along the bisector
    // n1 + n2, whose length is 2 cos(t).
    const bx = nx + mnx
    const by = ny + mny
    const bl = Math.sqrt(bx * bx + by * by)
    const sinHalf = Math.sqrt(Math.max(0, 1 - 0.25 * bl * bl))
    const d = theta > 0 ? (4 * r * sinHalf) / (3 * theta) : 0
    const scx = b.x + (bl > 0 ? (d * bx) / bl : 0)
    const scy = b.y + (bl > 0 ? (d * by) / bl : 0)
    m += sm
    mx += sm * scx
    my += sm * scy
    // A sector's polar moment about its apex is m r^2 / 2; move it to the body origin.
    j += 0.5 * sm * r * r - sm * d * d + sm * (scx * scx + scy * scy)
  }
  const cx = mx / m
  const cy = my / m
  return { mass: m, center: { x: cx, y: cy }, inertia: j - m * (cx * cx + cy * cy) }
}

/** Capsule: a rectangle 2r x L and two half discs (Box2D's b2ComputeCapsuleMass, exact). */
function capsuleMass(shape: CapsuleShape, density: number): MassData {
  const p1 = shape.vertices[0]
  const p2 = shape.vertices[1]
  const r = shape.radius
  const dx = p2.x - p1.x
  const dy = p2.y - p1.y
  const length = Math.sqrt(dx * dx + dy * dy)
  const boxMass = density * 2 * r * length
  const circleMass = density * PI * r * r
  // Each half disc's centroid lies 4r / (3 pi) beyond its end; h is half the length.
  const lc = (4 * r) / (3 * PI)
  const h = 0.5 * length
  const circleInertia = circleMass * (0.5 * r * r + h * h + 2 * h * lc)
  const boxInertia = (boxMass * (4 * r * r + length * length)) / 12
  return {
    mass: boxMass + circleMass,
    center: { x: shape.centroid.x, y: shape.centroid.y },
    inertia: circleInertia + boxInertia,
  }
}

/**
 * Mass, centre of mass and inertia about the centre of mass of a shape at a density (kg/m^2). A
 * segment has none (mass 0 at its midpoint).
 */
export function computeMass(shape: Shape, density: number): MassData {
  if (shape.type === 'circle') {
    const r = shape.radius
    const mass = density * PI * r * r
    return { mass, center: { x: shape.centroid.x, y: shape.centroid.y }, inertia: 0.5 * mass * r * r }
  }
  if (shape.type === 'segment' || shape.type === 'chainSegment')
    return { mass: 0, center: { x: shape.centroid.x, y: shape.centroid.y }, inertia: 0 }
  if (shape.type === 'capsule') return capsuleMass(shape, density)
  if (shape.radius > 0) return roundedPolygonMass(shape, density)
  return polygonMass(shape.vertices, density)
}

/**
 * Whether a shape is slender: thinner than SLENDER_RATIO times its length. Thickness is a polygon's
 * least width across (over its edge normals, where a convex polygon's least width lies) or a capsule's
 * diameter, plus twice the rounding radius; length is the largest distance between two vertices plus
 * twice the radius. Segments and chain segments (zero thickness) are slender; circles never are.
 * Uses only + - * / max and sqrt, so every JavaScript engine gives the same answer.
 */
export function isSlender(shape: Shape): boolean {
  return slenderAxis(shape) !== null
}

/**
 * A slender shape's long axis (isSlender), a unit vector in the body frame; null when the shape is
 * not slender. A polygon's is along the edge whose normal gives its least width (a box's long side);
 * a capsule's and a segment's runs from its first point to its second. Only + - * / max min sqrt.
 */
export function slenderAxis(shape: Shape): Vec2 | null {
  if (shape.type === 'circle') return null
  const v = shape.vertices
  const n = v.length
  if (shape.type !== 'polygon' && shape.type !== 'capsule') return unitAxis(v[1].x - v[0].x, v[1].y - v[0].y)
  let longest = 0
  for (let i = 0; i < n; i++) {
    for (let j = i + 1; j < n; j++) {
      const dx = v[j].x - v[i].x
      const dy = v[j].y - v[i].y
      longest = Math.max(longest, dx * dx + dy * dy)
    }
  }
  let thinnest = 0
  let across = 0
  if (shape.type === 'polygon') {
    thinnest = Number.POSITIVE_INFINITY
    for (let i = 0; i < n; i++) {
      const normal = shape.normals[i]
      let width = 0
      for (let j = 0; j < n; j++) {
        width = Math.max(width, (v[i].x - v[j].x) * normal.x + (v[i].y - v[j].y) * normal.y)
      }
      if (width < thinnest) {
        thinnest = width
        across = i
      }
    }
  }
  const thickness = thinnest + 2 * shape.radius
  const length = Math.sqrt(longest) + 2 * shape.radius
  if (!(thickness < SLENDER_RATIO * length)) return null
  if (shape.type === 'capsule') return unitAxis(v[1].x - v[0].x, v[1].y - v[0].y)
  // Along the edge of least width: the normal (x, y) turned a quarter, (-y, x).
  return { x: -shape.normals[across].y, y: shape.normals[across].x }
}

/** (x, y) scaled to unit length ((1, 0) for a zero vector). */
function unitAxis(x: number, y: number): Vec2 {
  const length = Math.sqrt(x * x + y * y)
  return length > 0 ? { x: x / length, y: y / length } : { x: 1, y: 0 }
}

/**
 * The mass properties of several shapes on one body (each with its own density), by the
 * parallel-axis theorem: mass = sum m_i, centre = sum m_i c_i / mass, inertia about that centre =
 * sum (I_i + m_i |c_i - centre|^2). One part is returned as it is; parts without mass count for
 * nothing (all massless: mass 0, centre at the first part's centre, or the origin if none).
 */
export function combineMass(parts: readonly MassData[]): MassData {
  if (parts.length === 1) return parts[0]
  let mass = 0
  let mx = 0
  let my = 0
  for (const p of parts) {
    mass += p.mass
    mx += p.mass * p.center.x
    my += p.mass * p.center.y
  }
  if (!(mass > 0)) {
    const c = parts.length > 0 ? parts[0].center : { x: 0, y: 0 }
    return { mass: 0, center: { x: c.x, y: c.y }, inertia: 0 }
  }
  const cx = mx / mass
  const cy = my / mass
  let inertia = 0
  for (const p of parts) {
    const dx = p.center.x - cx
    const dy = p.center.y - cy
    inertia += p.inertia + p.mass * (dx * dx + dy * dy)
  }
  return { mass, center: { x: cx, y: cy }, inertia }
}
