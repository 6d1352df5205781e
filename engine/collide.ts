/*
 * The narrowphase: a contact manifold for every pair of shape kinds, after Box2D v3's manifold.c.
 *
 * Polygon against polygon works in A's frame, shifted so that A's first vertex is the origin (small
 * coordinates keep round-off small). The separating-axis test runs over the edge normals of both
 * polygons; the face with the largest separation becomes the reference face, with a small
 * tolerance in favour of A so that the choice does not flicker between frames when two faces are
 * equally good. The incident edge is the edge of the other polygon whose normal is most
 * anti-parallel to the reference normal; it is clipped against the two side planes of the reference
 * edge, and each clipped point becomes a contact at the midpoint between the two surfaces. When the
 * polygons are apart by more than a tenth of the slop and the closest features of the two edges are
 * two vertices, the manifold is one point along the vertex-to-vertex direction instead (a face
 * normal there would make the speculative contact think the shapes are closer than they are).
 * Unlike Box2D, parallel edges that overlap along their length always take the clipping path, so
 * two aligned boxes side by side with a small gap get two speculative points, not one.
 *
 * Feature ids are makeFeatureId(feature of A, feature of B): the reference edge (or its end vertex)
 * and the incident vertex that made the point. They stay fixed while the same features touch, and
 * the two points of a manifold always differ in the reference-side feature. Circle contacts have a
 * single point with id 0.
 *
 * Points are kept only while their separation is below the speculative distance. Circle A against
 * polygon B runs polygon-against-circle with the roles swapped and flips the normal.
 *
 * Determinism and speed: only + - * / and Math.sqrt/abs; nothing is allocated per call (scratch
 * lives in module-level Float64Arrays and numbers).
 */
import type { Manifold, ManifoldPoint } from './manifold.ts'
import { makeFeatureId } from './manifold.ts'
import type { CircleShape, PolygonShape, Shape } from './shapes.ts'

/** Collision tolerance the narrowphase tolerances derive from (m), Box2D's linear slop 0.005. */
const LINEAR_SLOP = 0.005
/** How much more separated B's best face must be than A's to be the reference face (m), 0.0005. */
export const REFERENCE_FACE_TOLERANCE = 0.1 * LINEAR_SLOP
/** Distances below this are treated as zero when a direction must be normalized (m). */
const TINY_DISTANCE = 1e-12
/** Edges whose squared sine of the angle between them is below this count as parallel. */
const PARALLEL_TOLERANCE = 1e-12

// Scratch polygons in A's shifted frame: vertex x at [i], vertex y at [VY + i], normal at [NX + i], [NY + i].
const MAX_VERTICES = 8
const VY = MAX_VERTICES
const NX = 2 * MAX_VERTICES
const NY = 3 * MAX_VERTICES
const localA = new Float64Array(4 * MAX_VERTICES)
const localB = new Float64Array(4 * MAX_VERTICES)

/** Edge index found by the last findMaxSeparation call. */
let bestEdge = 0

/** Fills `out` with the contact manifold of shapeA at transform A and shapeB at transform B. */
export function collideShapes(
  shapeA: Shape,
  ax: number,
  ay: number,
  ac: number,
  as: number,
  shapeB: Shape,
  bx: number,
  by: number,
  bc: number,
  bs: number,
  speculativeDistance: number,
  out: Manifold,
): void {
  if (shapeA.type === 'polygon') {
    if (shapeB.type === 'polygon') {
      collidePolygons(shapeA, ax, ay, ac, as, shapeB, bx, by, bc, bs, speculativeDistance, out)
    } else {
      collidePolygonAndCircle(shapeA, ax, ay, ac, as, shapeB, bx, by, bc, bs, speculativeDistance, out)
    }
  } else if (shapeB.type === 'polygon') {
    collidePolygonAndCircle(shapeB, bx, by, bc, bs, shapeA, ax, ay, ac, as, speculativeDistance, out)
    if (out.pointCount > 0) {
      out.normalX = -out.normalX
      out.normalY = -out.normalY
    }
  } else {
    collideCircles(shapeA, ax, ay, ac, as, shapeB, bx, by, bc, bs, speculativeDistance, out)
  }
}

/** Clears a manifold to "no contact" (zero normal, no points). */
function setEmpty(out: Manifold): void {
  out.normalX = 0
  out.normalY = 0
  out.pointCount = 0
}

/**
 * Circle against circle. Coincident centres (closer than 1e-12 m) use the fixed world normal (1, 0),
 * so the result is defined and deterministic; otherwise the normal is the centre-to-centre direction.
 * The point is computed in a form that is exactly mirror-symmetric when A and B are swapped.
 */
export function collideCircles(
  circleA: CircleShape,
  ax: number,
  ay: number,
  _ac: number,
  _as: number,
  circleB: CircleShape,
  bx: number,
  by: number,
  _bc: number,
  _bs: number,
  speculativeDistance: number,
  out: Manifold,
): void {
  const dx = bx - ax
  const dy = by - ay
  const distance = Math.sqrt(dx * dx + dy * dy)
  let nx = 1
  let ny = 0
  if (distance > TINY_DISTANCE) {
    nx = dx / distance
    ny = dy / distance
  }
  const ra = circleA.radius
  const rb = circleB.radius
  const separation = distance - (ra + rb)
  if (!(separation < speculativeDistance)) {
    setEmpty(out)
    return
  }
  out.normalX = nx
  out.normalY = ny
  out.pointCount = 1
  // Midpoint of (A + ra n) and (B - rb n).
  const half = 0.5 * (ra - rb)
  setPoint(out.points[0], 0.5 * (ax + bx) + half * nx, 0.5 * (ay + by) + half * ny, separation, 0)
}

function setPoint(p: ManifoldPoint, x: number, y: number, separation: number, id: number): void {
  p.x = x
  p.y = y
  p.separation = separation
  p.id = id
}

/**
 * Polygon A against circle B (Box2D v3 b2CollidePolygonAndCircle): the face of greatest separation
 * from the centre, then the vertex region if the centre lies outside past an end of that face.
 */
export function collidePolygonAndCircle(
  polygonA: PolygonShape,
  ax: number,
  ay: number,
  ac: number,
  as: number,
  circleB: CircleShape,
  bx: number,
  by: number,
  _bc: number,
  _bs: number,
  speculativeDistance: number,
  out: Manifold,
): void {
  // Circle centre in A's frame.
  const dx = bx - ax
  const dy = by - ay
  const cx = ac * dx + as * dy
  const cy = ac * dy - as * dx
  const radius = circleB.radius
  const count = polygonA.count
  const vs = polygonA.vertices
  const ns = polygonA.normals
  // Face of greatest separation.
  let face = 0
  let faceSeparation = Number.NEGATIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const s = ns[i].x * (cx - vs[i].x) + ns[i].y * (cy - vs[i].y)
    if (s > faceSeparation) {
      faceSeparation = s
      face = i
    }
  }
  if (!(faceSeparation - radius < speculativeDistance)) {
    setEmpty(out)
    return
  }
  const v1 = vs[face]
  const v2 = vs[face + 1 < count ? face + 1 : 0]
  const u1 = (cx - v1.x) * (v2.x - v1.x) + (cy - v1.y) * (v2.y - v1.y)
  const u2 = (cx - v2.x) * (v1.x - v2.x) + (cy - v2.y) * (v1.y - v2.y)
  let nx: number
  let ny: number
  let px: number
  let py: number
  let separation: number
  if (faceSeparation > TINY_DISTANCE && (u1 < 0 || u2 < 0)) {
    // Vertex region: the centre is outside, nearest to one end of the face.
    const vx = u1 < 0 ? v1.x : v2.x
    const vy = u1 < 0 ? v1.y : v2.y
    const ex = cx - vx
    const ey = cy - vy
    const distance = Math.sqrt(ex * ex + ey * ey)
    nx = ex / distance
    ny = ey / distance
    separation = distance - radius
    // Midpoint of the vertex and the circle's nearest point c - r n.
    px = 0.5 * (vx + cx - radius * nx)
    py = 0.5 * (vy + cy - radius * ny)
  } else {
    // Face region: the centre projects onto the face (it may be inside the polygon).
    nx = ns[face].x
    ny = ns[face].y
    separation = faceSeparation - radius
    const back = 0.5 * (faceSeparation + radius)
    px = cx - back * nx
    py = cy - back * ny
  }
  if (!(separation < speculativeDistance)) {
    setEmpty(out)
    return
  }
  out.normalX = ac * nx - as * ny
  out.normalY = as * nx + ac * ny
  out.pointCount = 1
  setPoint(out.points[0], ax + ac * px - as * py, ay + as * px + ac * py, separation, 0)
}

/**
 * Polygon against polygon (Box2D v3 b2CollidePolygons): SAT over both polygons' edge normals,
 * reference face with a tolerance favouring A, incident edge clipped to the reference side planes.
 */
export function collidePolygons(
  polygonA: PolygonShape,
  ax: number,
  ay: number,
  ac: number,
  as: number,
  polygonB: PolygonShape,
  bx: number,
  by: number,
  bc: number,
  bs: number,
  speculativeDistance: number,
  out: Manifold,
): void {
  const countA = polygonA.count
  const countB = polygonB.count
  const ox = polygonA.vertices[0].x
  const oy = polygonA.vertices[0].y
  loadPolygons(polygonA, polygonB, ax, ay, ac, as, bx, by, bc, bs)

  let edgeA = 0
  let edgeB = 0
  const separationA = findMaxSeparation(localA, countA, localB, countB)
  edgeA = bestEdge
  const separationB = findMaxSeparation(localB, countB, localA, countA)
  edgeB = bestEdge
  if (!(separationA < speculativeDistance && separationB < speculativeDistance)) {
    setEmpty(out)
    return
  }
  // Reference face: A's unless B's is clearly better; the incident edge is on the other polygon.
  const flip = separationB > separationA + REFERENCE_FACE_TOLERANCE
  if (flip) {
    edgeA = findIncidentEdge(localB[NX + edgeB], localB[NY + edgeB], localA, countA)
  } else {
    edgeB = findIncidentEdge(localA[NX + edgeA], localA[NY + edgeA], localB, countB)
  }
  // Apart by more than a tenth of the slop: the closest features may be two vertices.
  const apart = Math.max(separationA, separationB) > 0.1 * LINEAR_SLOP
  if (!(apart && collideVertices(edgeA, countA, edgeB, countB, speculativeDistance, out))) {
    if (flip) {
      clipPolygons(localB, countB, edgeB, localA, countA, edgeA, true, speculativeDistance, out)
    } else {
      clipPolygons(localA, countA, edgeA, localB, countB, edgeB, false, speculativeDistance, out)
    }
  }
  if (out.pointCount === 0) {
    setEmpty(out)
    return
  }
  // Back to world space.
  const nx = out.normalX
  const ny = out.normalY
  out.normalX = ac * nx - as * ny
  out.normalY = as * nx + ac * ny
  for (let i = 0; i < out.pointCount; i++) {
    const p = out.points[i]
    const px = p.x + ox
    const py = p.y + oy
    p.x = ax + ac * px - as * py
    p.y = ay + as * px + ac * py
  }
}

/** Loads A (shifted by its vertex 0) and B (moved into that frame) into the scratch polygons. */
function loadPolygons(
  polygonA: PolygonShape,
  polygonB: PolygonShape,
  ax: number,
  ay: number,
  ac: number,
  as: number,
  bx: number,
  by: number,
  bc: number,
  bs: number,
): void {
  const va = polygonA.vertices
  const na = polygonA.normals
  const ox = va[0].x
  const oy = va[0].y
  for (let i = 0; i < polygonA.count; i++) {
    localA[i] = va[i].x - ox
    localA[VY + i] = va[i].y - oy
    localA[NX + i] = na[i].x
    localA[NY + i] = na[i].y
  }
  // B relative to the shifted A frame: rotation qA^T qB, translation qA^T (pB - pA - qA o).
  const qc = ac * bc + as * bs
  const qs = ac * bs - as * bc
  const dx = bx - (ax + ac * ox - as * oy)
  const dy = by - (ay + as * ox + ac * oy)
  const px = ac * dx + as * dy
  const py = ac * dy - as * dx
  const vb = polygonB.vertices
  const nb = polygonB.normals
  for (let i = 0; i < polygonB.count; i++) {
    const vx = vb[i].x
    const vy = vb[i].y
    localB[i] = qc * vx - qs * vy + px
    localB[VY + i] = qs * vx + qc * vy + py
    localB[NX + i] = qc * nb[i].x - qs * nb[i].y
    localB[NY + i] = qs * nb[i].x + qc * nb[i].y
  }
}

/** Largest over poly1's edges of the smallest signed distance of poly2's vertices; sets bestEdge. */
function findMaxSeparation(poly1: Float64Array, count1: number, poly2: Float64Array, count2: number): number {
  let best = 0
  let maxSeparation = Number.NEGATIVE_INFINITY
  for (let i = 0; i < count1; i++) {
    const nx = poly1[NX + i]
    const ny = poly1[NY + i]
    const vx = poly1[i]
    const vy = poly1[VY + i]
    let si = Number.POSITIVE_INFINITY
    for (let j = 0; j < count2; j++) {
      const sij = nx * (poly2[j] - vx) + ny * (poly2[VY + j] - vy)
      if (sij < si) si = sij
    }
    if (si > maxSeparation) {
      maxSeparation = si
      best = i
    }
  }
  bestEdge = best
  return maxSeparation
}

/** The edge of `poly` whose normal is most anti-parallel to (nx, ny). */
function findIncidentEdge(nx: number, ny: number, poly: Float64Array, count: number): number {
  let edge = 0
  let minDot = Number.POSITIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const dot = nx * poly[NX + i] + ny * poly[NY + i]
    if (dot < minDot) {
      minDot = dot
      edge = i
    }
  }
  return edge
}

/**
 * If the closest points of edge edgeA of A and edge edgeB of B are two vertices, writes the one-point
 * vertex-vertex manifold (in A's shifted frame) and returns true (Box2D v3; segment distance after
 * Ericson 5.1.9). Returns false when the closest features include an edge interior.
 */
function collideVertices(
  edgeA: number,
  countA: number,
  edgeB: number,
  countB: number,
  speculativeDistance: number,
  out: Manifold,
): boolean {
  const a2 = edgeA + 1 < countA ? edgeA + 1 : 0
  const b2 = edgeB + 1 < countB ? edgeB + 1 : 0
  const p1x = localA[edgeA]
  const p1y = localA[VY + edgeA]
  const d1x = localA[a2] - p1x
  const d1y = localA[VY + a2] - p1y
  const p2x = localB[edgeB]
  const p2y = localB[VY + edgeB]
  const d2x = localB[b2] - p2x
  const d2y = localB[VY + b2] - p2y
  const rx = p1x - p2x
  const ry = p1y - p2y
  const dd1 = d1x * d1x + d1y * d1y
  const dd2 = d2x * d2x + d2y * d2y
  const rd1 = rx * d1x + ry * d1y
  const rd2 = rx * d2x + ry * d2y
  const d12 = d1x * d2x + d1y * d2y
  const denom = dd1 * dd2 - d12 * d12
  if (denom <= PARALLEL_TOLERANCE * dd1 * dd2) {
    // Parallel edges (Ericson would pick f1 = 0 arbitrarily): if their extents overlap along the
    // edge, the closest features are edge and edge, so clip (two points, same for A-B and B-A).
    const s1 = -rd1
    const s2 = d1x * (localB[b2] - p1x) + d1y * (localB[VY + b2] - p1y)
    if (Math.min(dd1, Math.max(s1, s2)) > Math.max(0, Math.min(s1, s2))) return false
  }
  let f1 = denom > 0 ? clamp01((d12 * rd2 - rd1 * dd2) / denom) : 0
  let f2 = (d12 * f1 + rd2) / dd2
  if (f2 < 0) {
    f2 = 0
    f1 = clamp01(-rd1 / dd1)
  } else if (f2 > 1) {
    f2 = 1
    f1 = clamp01((d12 - rd1) / dd1)
  }
  if ((f1 !== 0 && f1 !== 1) || (f2 !== 0 && f2 !== 1)) return false
  const iA = f1 === 0 ? edgeA : a2
  const iB = f2 === 0 ? edgeB : b2
  const vax = localA[iA]
  const vay = localA[VY + iA]
  const ex = localB[iB] - vax
  const ey = localB[VY + iB] - vay
  const distance = Math.sqrt(ex * ex + ey * ey)
  if (distance < speculativeDistance) {
    out.normalX = ex / distance
    out.normalY = ey / distance
    out.pointCount = 1
    setPoint(out.points[0], vax + 0.5 * ex, vay + 0.5 * ey, distance, makeFeatureId(iA, iB))
  } else {
    out.pointCount = 0
  }
  return true
}

function clamp01(x: number): number {
  return Math.max(0, Math.min(x, 1))
}

/**
 * Clips the incident edge of `inc` against the side planes of the reference edge of `ref` (Box2D v3
 * b2ClipPolygons) and writes the points closer than the speculative distance, in A's shifted frame.
 * `flip` says the reference polygon is B: the normal is negated so that it still points from A to B
 * and the feature ids stay (feature of A, feature of B).
 */
function clipPolygons(
  ref: Float64Array,
  refCount: number,
  i11: number,
  inc: Float64Array,
  incCount: number,
  i21: number,
  flip: boolean,
  speculativeDistance: number,
  out: Manifold,
): void {
  const i12 = i11 + 1 < refCount ? i11 + 1 : 0
  const i22 = i21 + 1 < incCount ? i21 + 1 : 0
  const nx = ref[NX + i11]
  const ny = ref[NY + i11]
  const v11x = ref[i11]
  const v11y = ref[VY + i11]
  const v21x = inc[i21]
  const v21y = inc[VY + i21]
  const v22x = inc[i22]
  const v22y = inc[VY + i22]
  // Positions along the tangent (-ny, nx), measured from v11. The incident edge runs against the
  // tangent (both polygons are counter-clockwise), so its v22 end is the lower one.
  const upper1 = -ny * (ref[i12] - v11x) + nx * (ref[VY + i12] - v11y)
  const upper2 = -ny * (v21x - v11x) + nx * (v21y - v11y)
  const lower2 = -ny * (v22x - v11x) + nx * (v22y - v11y)
  const span = upper2 - lower2
  let lowerX = v22x
  let lowerY = v22y
  let upperX = v21x
  let upperY = v21y
  if (lower2 < 0 && span > 0) {
    const t = clamp01(-lower2 / span)
    lowerX = v22x + t * (v21x - v22x)
    lowerY = v22y + t * (v21y - v22y)
  }
  if (upper2 > upper1 && span > 0) {
    const t = clamp01((upper1 - lower2) / span)
    upperX = v22x + t * (v21x - v22x)
    upperY = v22y + t * (v21y - v22y)
  }
  const separationLower = nx * (lowerX - v11x) + ny * (lowerY - v11y)
  const separationUpper = nx * (upperX - v11x) + ny * (upperY - v11y)
  // The incident edge lies wholly beyond one side plane (only in degenerate overlaps): the two
  // clipped points coincide, so keep one.
  const single = upper2 < 0 || lower2 > upper1
  // Midpoints between the incident point and its projection on the reference face.
  const lowerMidX = lowerX - 0.5 * separationLower * nx
  const lowerMidY = lowerY - 0.5 * separationLower * ny
  const upperMidX = upperX - 0.5 * separationUpper * nx
  const upperMidY = upperY - 0.5 * separationUpper * ny
  let n = 0
  if (flip) {
    out.normalX = -nx
    out.normalY = -ny
    if (separationUpper < speculativeDistance && !(single && lower2 > upper1)) {
      setPoint(out.points[n++], upperMidX, upperMidY, separationUpper, makeFeatureId(i21, i12))
    }
    if (separationLower < speculativeDistance && !(single && upper2 < 0)) {
      setPoint(out.points[n++], lowerMidX, lowerMidY, separationLower, makeFeatureId(i22, i11))
    }
  } else {
    out.normalX = nx
    out.normalY = ny
    if (separationLower < speculativeDistance && !(single && upper2 < 0)) {
      setPoint(out.points[n++], lowerMidX, lowerMidY, separationLower, makeFeatureId(i11, i22))
    }
    if (separationUpper < speculativeDistance && !(single && lower2 > upper1)) {
      setPoint(out.points[n++], upperMidX, upperMidY, separationUpper, makeFeatureId(i12, i21))
    }
  }
  out.pointCount = n
}
