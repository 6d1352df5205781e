/*
 * Shapes and their mass properties.
 *
 * A body has one shape. Circles are centred on the body origin. Polygons are convex, counter-
 * clockwise, 3 to 8 vertices, given in the body's local frame; `polygon()` computes the convex hull
 * of its input and rejects input that is not already a strictly convex polygon (a concave,
 * collinear or degenerate vertex list throws an error naming what is wrong), so a shape is always
 * exactly what the caller wrote. Boxes are polygons of four vertices.
 *
 * Mass, centroid and rotational inertia come from density by the polygon triangle-fan formulas
 * (Box2D's b2ComputePolygonMass; Ericson, "Real-Time Collision Detection" 2.6).
 */
import { MAX_POLYGON_VERTICES, MAX_SHAPE_EXTENT, MIN_SHAPE_EXTENT } from '../constants.ts'
import { PI, type Vec2 } from '../math.ts'

/*
 * Every shape object has every field, in the same order (type, radius, count, vertices, normals,
 * centroid, box), so all shapes share one hidden class in V8 and the engine's shape reads stay
 * monomorphic: a polymorphic load of `radius` was measured to allocate in the step.
 */

/** A circle centred on the body origin. */
export interface CircleShape {
  readonly type: 'circle'
  /** Radius (m). */
  readonly radius: number
  /** Always 0, [] and [] for circles (uniform layout). */
  readonly count: 0
  readonly vertices: readonly Vec2[]
  readonly normals: readonly Vec2[]
  /** Always the origin. */
  readonly centroid: Vec2
  readonly box: null
}

/** A convex polygon in the body frame, counter-clockwise, with outward unit edge normals. */
export interface PolygonShape {
  readonly type: 'polygon'
  /** Always 0 for polygons (uniform layout; no rounded polygons). */
  readonly radius: 0
  /** Number of vertices, 3..8. */
  readonly count: number
  /** Vertices in the body frame (m), counter-clockwise. */
  readonly vertices: readonly Vec2[]
  /** normals[i] is the outward unit normal of edge vertices[i] -> vertices[i + 1]. */
  readonly normals: readonly Vec2[]
  /** Area centroid in the body frame (m). */
  readonly centroid: Vec2
  /** Set for shapes made by box(): half extents (m), for compact encoding and drawing. */
  readonly box: { readonly halfWidth: number; readonly halfHeight: number } | null
}

/** Every shape kind a body can have. */
export type Shape = CircleShape | PolygonShape

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

/** A circle of the given radius (m) centred on the body origin. */
export function circle(radius: number): CircleShape {
  checkSize('circle radius', radius)
  return { type: 'circle', radius, count: 0, vertices: [], normals: [], centroid: { x: 0, y: 0 }, box: null }
}

/** An axis-aligned box (in the body frame) of the given half extents (m), centred on the origin. */
export function box(halfWidth: number, halfHeight: number): PolygonShape {
  checkSize('box halfWidth', halfWidth)
  checkSize('box halfHeight', halfHeight)
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
  }
}

function cross3(o: Vec2, a: Vec2, b: Vec2): number {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

/**
 * A convex polygon from 3..8 vertices in the body frame (m). The vertices may be given in either
 * winding and any starting vertex; they are stored counter-clockwise. Throws if the list is not a
 * strictly convex polygon: repeated points, collinear vertices, a concave vertex, or too small.
 */
export function polygon(points: readonly Vec2[]): PolygonShape {
  const n = points.length
  if (n < 3 || n > MAX_POLYGON_VERTICES) {
    throw new RangeError(`polygon needs 3 to ${MAX_POLYGON_VERTICES} vertices, got ${n}`)
  }
  for (let i = 0; i < n; i++) {
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
  // Signed area decides the winding; make the list counter-clockwise.
  let area2 = 0
  for (let i = 0; i < n; i++) {
    const a = points[i]
    const b = points[(i + 1) % n]
    area2 += a.x * b.y - a.y * b.x
  }
  const ccw =
    area2 >= 0 ? points.map((p) => ({ x: p.x, y: p.y })) : points.map((p) => ({ x: p.x, y: p.y })).reverse()
  for (let i = 0; i < n; i++) {
    const a = ccw[i]
    const b = ccw[(i + 1) % n]
    const len = Math.sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y))
    if (len < MIN_SHAPE_EXTENT) {
      throw new RangeError(
        `polygon is degenerate: vertices (${a.x}, ${a.y}) and (${b.x}, ${b.y}) are closer than ${MIN_SHAPE_EXTENT} m`,
      )
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
      throw new RangeError(`polygon is not strictly convex: vertex ${i} (${cur.x}, ${cur.y}) is ${what}`)
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
        throw new RangeError(
          `polygon is not convex: vertex ${k} lies outside edge ${i} (self-intersecting or concave)`,
        )
      }
    }
  }
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
  return { type: 'polygon', radius: 0, count: n, vertices: ccw, normals, centroid: mass.center, box: null }
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

/** Mass, centre of mass and inertia about the centre of mass of a shape at a density (kg/m^2). */
export function computeMass(shape: Shape, density: number): MassData {
  if (shape.type === 'circle') {
    const r = shape.radius
    const mass = density * PI * r * r
    return { mass, center: { x: 0, y: 0 }, inertia: 0.5 * mass * r * r }
  }
  return polygonMass(shape.vertices, density)
}
