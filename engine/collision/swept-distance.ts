/*
 * The distance between two bodies' shapes at a fraction of their motion over the step, for the
 * time-of-impact search of continuous.ts: each body's pose is interpolated between its step-start
 * and step-end transforms (the rotation by nlerp), its shape is placed there, and the signed
 * distance is exact for circles and convex polygons (SAT, then the nearest boundary points).
 *
 * Numbers travel between these functions and their callers in `sweep`, not as arguments or
 * results: V8 boxes a double argument or return value of a call it does not inline, a heap number
 * per call, and these run many times per step when players drag bodies through a pile (about
 * 800 bytes per step of a server room before this was so).
 */
import type { Body } from '../dynamics/index.ts'
import type { Shape } from './shapes.ts'

/** In and out numbers of the functions below, at the offsets that follow. */
export const sweep = new Float64Array(4)
/** In: the sweep fraction at which poseAt and sweptDistance work. */
export const FRACTION = 0
/** In: the radius of body a's core for sweptDistance (0: its whole shape). */
export const CORE = 1
/** Out: sweptDistance's signed distance (m). */
export const DISTANCE = 2
/** Out: maxEdgeSeparation's or boundaryDistance's distance (m). */
export const EDGE = 3

/** The pose poseAt found: origin x, y (m), cos, sin. */
export const pose = new Float64Array(4)
/** The world vertices of the two shapes (x, y pairs; a circle's centre). */
export const verticesA = new Float64Array(16)
export const verticesB = new Float64Array(16)

/** Sets `pose` (origin x, y, cos, sin) of body b at sweep fraction sweep[FRACTION] (nlerp of the rotation). */
export function poseAt(b: Body): void {
  if (!b.awake) {
    // Static and sleeping bodies did not move this step.
    pose[0] = b.x
    pose[1] = b.y
    pose[2] = b.c
    pose[3] = b.s
    return
  }
  const t = sweep[FRACTION]
  const cx = b.c0x + t * (b.cx - b.c0x)
  const cy = b.c0y + t * (b.cy - b.c0y)
  let qc = b.q0c + t * (b.c - b.q0c)
  let qs = b.q0s + t * (b.s - b.q0s)
  const mag = Math.sqrt(qc * qc + qs * qs)
  const inv = mag > 0 ? 1 / mag : 0
  qc *= inv
  qs *= inv
  pose[0] = cx - (qc * b.localCenterX - qs * b.localCenterY)
  pose[1] = cy - (qs * b.localCenterX + qc * b.localCenterY)
  pose[2] = qc
  pose[3] = qs
}

/** Writes `shape`'s world vertices at `pose` into `out` (a circle: its centre); returns how many. */
export function transformVertices(shape: Shape, out: Float64Array): number {
  if (shape.type === 'circle') {
    const lx = shape.centroid.x
    const ly = shape.centroid.y
    out[0] = pose[0]
    out[1] = pose[1]
    if (lx !== 0 || ly !== 0) {
      out[0] += pose[2] * lx - pose[3] * ly
      out[1] += pose[3] * lx + pose[2] * ly
    }
    return 1
  }
  for (let i = 0; i < shape.count; i++) {
    const v = shape.vertices[i]
    out[2 * i] = pose[0] + pose[2] * v.x - pose[3] * v.y
    out[2 * i + 1] = pose[1] + pose[3] * v.x + pose[2] * v.y
  }
  return shape.count
}

/** Distance from point (px, py) to segment (ax, ay)-(bx, by). */
function pointSegmentDistance(
  px: number,
  py: number,
  ax: number,
  ay: number,
  bx: number,
  by: number,
): number {
  const ex = bx - ax
  const ey = by - ay
  const len2 = ex * ex + ey * ey
  let t = len2 > 0 ? ((px - ax) * ex + (py - ay) * ey) / len2 : 0
  t = Math.max(0, Math.min(1, t))
  const dx = px - (ax + t * ex)
  const dy = py - (ay + t * ey)
  return Math.sqrt(dx * dx + dy * dy)
}

/** Largest separation of the points of `q` from the edges of convex polygon `p` (SAT, one side), into sweep[EDGE]. */
export function maxEdgeSeparation(p: Float64Array, pn: number, q: Float64Array, qn: number): void {
  let best = Number.NEGATIVE_INFINITY
  for (let i = 0; i < pn; i++) {
    const ax = p[2 * i]
    const ay = p[2 * i + 1]
    const j = i + 1 === pn ? 0 : i + 1
    const ex = p[2 * j] - ax
    const ey = p[2 * j + 1] - ay
    const len = Math.sqrt(ex * ex + ey * ey)
    const nx = ey / len
    const ny = -ex / len
    let minProjection = Number.POSITIVE_INFINITY
    for (let k = 0; k < qn; k++) {
      const d = (q[2 * k] - ax) * nx + (q[2 * k + 1] - ay) * ny
      if (d < minProjection) minProjection = d
    }
    if (minProjection > best) best = minProjection
  }
  sweep[EDGE] = best
}

/** Smallest distance between the boundaries of two polygons (or a polygon and a point), into sweep[EDGE]. */
function boundaryDistance(p: Float64Array, pn: number, q: Float64Array, qn: number): void {
  let best = Number.POSITIVE_INFINITY
  for (let i = 0; i < pn; i++) {
    const j = i + 1 === pn ? 0 : i + 1
    for (let k = 0; k < qn; k++) {
      const d = pointSegmentDistance(q[2 * k], q[2 * k + 1], p[2 * i], p[2 * i + 1], p[2 * j], p[2 * j + 1])
      if (d < best) best = d
    }
  }
  sweep[EDGE] = best
}

/**
 * Signed distance between shape A of body a and shape B of body b at sweep fraction sweep[FRACTION] (negative when
 * overlapping), into sweep[DISTANCE]. With sweep[CORE] > 0, body a is replaced by its core: a circle of
 * that radius at its centre of mass.
 */
export function sweptDistance(a: Body, shapeA: Shape, b: Body, shapeB: Shape): void {
  const core = sweep[CORE]
  poseAt(a)
  let na: number
  let ra: number
  if (core > 0) {
    verticesA[0] = pose[0] + pose[2] * a.localCenterX - pose[3] * a.localCenterY
    verticesA[1] = pose[1] + pose[3] * a.localCenterX + pose[2] * a.localCenterY
    na = 1
    ra = core
  } else {
    na = transformVertices(shapeA, verticesA)
    ra = shapeA.radius
  }
  poseAt(b)
  const nb = transformVertices(shapeB, verticesB)
  const rb = shapeB.radius
  if (na === 1 && nb === 1) {
    const dx = verticesB[0] - verticesA[0]
    const dy = verticesB[1] - verticesA[1]
    sweep[DISTANCE] = Math.sqrt(dx * dx + dy * dy) - ra - rb
    return
  }
  let sat = Number.NEGATIVE_INFINITY
  if (na > 1) {
    maxEdgeSeparation(verticesA, na, verticesB, nb)
    sat = Math.max(sat, sweep[EDGE])
  }
  if (nb > 1) {
    maxEdgeSeparation(verticesB, nb, verticesA, na)
    sat = Math.max(sat, sweep[EDGE])
  }
  if (sat <= 0) {
    sweep[DISTANCE] = sat - ra - rb
    return
  }
  let d = Number.POSITIVE_INFINITY
  if (na > 1) {
    boundaryDistance(verticesA, na, verticesB, nb)
    d = Math.min(d, sweep[EDGE])
  }
  if (nb > 1) {
    boundaryDistance(verticesB, nb, verticesA, na)
    d = Math.min(d, sweep[EDGE])
  }
  sweep[DISTANCE] = d - ra - rb
}
