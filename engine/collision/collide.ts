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
 * polygon B runs polygon-against-circle with the roles swapped and flips the normal. A chain segment
 * against anything goes to chain-collide.ts (one-sided, with ghost vertices).
 *
 * Determinism and speed: only + - * / and Math.sqrt/abs/min/max. Nothing is allocated per call:
 * scratch lives in module-level Float64Arrays. V8 boxes a non-integer number into a fresh heap
 * object whenever it crosses a call that was not inlined (argument or return value) or is stored
 * in a module-level `let`, so the transforms are copied once into the `frame` array and the
 * internal helpers pass only integers, booleans and objects, returning doubles through `found`.
 */
import { LINEAR_SLOP, MAX_POLYGON_VERTICES, SPECULATIVE_DISTANCE } from '../constants.ts'
import { collideChainSegmentInFrame } from './chain-collide.ts'
import { type Manifold, makeFeatureId } from './manifold.ts'
import { NORMAL_X, NORMAL_Y, polygonGeometry, VERTEX_X, VERTEX_Y } from './polygon-geometry.ts'
import type { CircleShape, PolygonalShape, Shape } from './shapes.ts'

/** How much more separated B's best face must be than A's to be the reference face (m), 0.0005. */
export const REFERENCE_FACE_TOLERANCE = 0.1 * LINEAR_SLOP
/** Distances below this are treated as zero when a direction must be normalized (m). */
const TINY_DISTANCE = 1e-12
/** Edges whose squared sine of the angle between them is below this count as parallel. */
const PARALLEL_TOLERANCE = 1e-12

// Polygons in A's shifted frame: vertex x at [i], vertex y at [VY + i], normal at [NX + i], [NY + i]
// (polygon-geometry.ts: A's own geometry array is already laid out this way; B is moved into it).
const MAX_VERTICES = MAX_POLYGON_VERTICES
const VY = MAX_VERTICES
const NX = NORMAL_X
const NY = NORMAL_Y
const localB = new Float64Array(4 * MAX_VERTICES)

// The current call's transforms and speculative distance, unboxed.
const AX = 0
const AY = 1
const AC = 2
const AS = 3
const BX = 4
const BY = 5
const BC = 6
const BS = 7
const SPEC = 8
const frame = new Float64Array(9)
// Results of findMaxSeparation: separation at [0], edge index at [1].
const found = new Float64Array(2)
// The rounding radii of polygons A and B in the current polygonsInFrame call.
const radii = new Float64Array(2)

/**
 * Fills `out` with the contact manifold of shapeA at transform A and shapeB at transform B. For
 * tests and tools: the world calls collideGeometry with each body's precomputed geometry.
 */
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
  const geometryA = polygonGeometry(shapeA)
  const geometryB = polygonGeometry(shapeB)
  if (shapeA.type === 'chainSegment' || shapeB.type === 'chainSegment') {
    setFrame(ax, ay, ac, as, bx, by, bc, bs, speculativeDistance)
    collideChainSegmentInFrame(
      frame,
      shapeA.type === 'chainSegment',
      shapeA,
      geometryA,
      null,
      shapeB,
      geometryB,
      null,
      out,
    )
    return
  }
  collideGeometry(
    shapeA,
    geometryA,
    ax,
    ay,
    ac,
    as,
    shapeB,
    geometryB,
    bx,
    by,
    bc,
    bs,
    speculativeDistance,
    out,
  )
}

/** collideShapes with each shape's polygonGeometry given (no allocation). */
export function collideGeometry(
  shapeA: Shape,
  geometryA: Float64Array,
  ax: number,
  ay: number,
  ac: number,
  as: number,
  shapeB: Shape,
  geometryB: Float64Array,
  bx: number,
  by: number,
  bc: number,
  bs: number,
  speculativeDistance: number,
  out: Manifold,
): void {
  setFrame(ax, ay, ac, as, bx, by, bc, bs, speculativeDistance)
  if (shapeA.type !== 'circle') {
    if (shapeB.type !== 'circle') polygonsInFrame(shapeA, geometryA, shapeB, geometryB, out)
    else {
      moveToCenter(geometryB, BX)
      if (shapeA.count === 2) capsuleAndCircleInFrame(shapeA, shapeB, false, out)
      else polygonAndCircleInFrame(shapeA, geometryA, shapeB, false, out)
    }
  } else if (shapeB.type !== 'circle') {
    moveToCenter(geometryA, AX)
    if (shapeB.count === 2) capsuleAndCircleInFrame(shapeB, shapeA, true, out)
    else polygonAndCircleInFrame(shapeB, geometryB, shapeA, true, out)
  } else {
    moveToCenter(geometryA, AX)
    moveToCenter(geometryB, BX)
    circlesInFrame(shapeA, shapeB, out)
  }
}

/** A body pose as the World's bodies hold it: origin (m) and rotation as a (cos, sin) pair. */
export interface Pose {
  readonly x: number
  readonly y: number
  readonly c: number
  readonly s: number
}

/**
 * collideGeometry with the poses read from the two bodies here rather than passed as numbers: a
 * caller V8 does not inline collideGeometry into would box each double argument per call (measured:
 * about 3 KB per step in the compound allocation scene from the sensor stage, 2 KB per step in the
 * machines scene from the narrowphase once the world's collide loop grew past V8's inlining budget).
 * The narrowphase (updateContact) and the sensor stage (speculative distance 0) both call this.
 * Same arithmetic.
 */
export function collideGeometryAt(
  shapeA: Shape,
  geometryA: Float64Array,
  poseA: Pose,
  shapeB: Shape,
  geometryB: Float64Array,
  poseB: Pose,
  out: Manifold,
  speculativeDistance = 0,
): void {
  frame[AX] = poseA.x
  frame[AY] = poseA.y
  frame[AC] = poseA.c
  frame[AS] = poseA.s
  frame[BX] = poseB.x
  frame[BY] = poseB.y
  frame[BC] = poseB.c
  frame[BS] = poseB.s
  frame[SPEC] = speculativeDistance
  if (shapeA.type === 'chainSegment' || shapeB.type === 'chainSegment') {
    collideChainSegmentInFrame(
      frame,
      shapeA.type === 'chainSegment',
      shapeA,
      geometryA,
      null,
      shapeB,
      geometryB,
      null,
      out,
    )
  } else if (shapeA.type !== 'circle') {
    if (shapeB.type !== 'circle') polygonsInFrame(shapeA, geometryA, shapeB, geometryB, out)
    else {
      moveToCenter(geometryB, BX)
      if (shapeA.count === 2) capsuleAndCircleInFrame(shapeA, shapeB, false, out)
      else polygonAndCircleInFrame(shapeA, geometryA, shapeB, false, out)
    }
  } else if (shapeB.type !== 'circle') {
    moveToCenter(geometryA, AX)
    if (shapeB.count === 2) capsuleAndCircleInFrame(shapeB, shapeA, true, out)
    else polygonAndCircleInFrame(shapeB, geometryB, shapeA, true, out)
  } else {
    moveToCenter(geometryA, AX)
    moveToCenter(geometryB, BX)
    circlesInFrame(shapeA, shapeB, out)
  }
}

/**
 * The manifold of a contact in which one shape is a chain segment, at the speculative distance, with
 * the poses read from the two bodies inside the chain routine. The contact update calls this for
 * such pairs instead of collideGeometry (whose double arguments, and any double this function read,
 * would be boxed: it is called too rarely for V8 to optimize it, and in its interpreter every double
 * read is a heap number; measured: 80 bytes per step for one chain contact, 2.4 KB in the marble run).
 */
export function collideChainSegmentAt(
  shapeA: Shape,
  geometryA: Float64Array,
  poseA: Pose,
  shapeB: Shape,
  geometryB: Float64Array,
  poseB: Pose,
  out: Manifold,
): void {
  frame[SPEC] = SPECULATIVE_DISTANCE
  const chainIsA = shapeA.type === 'chainSegment'
  collideChainSegmentInFrame(frame, chainIsA, shapeA, geometryA, poseA, shapeB, geometryB, poseB, out)
}

/**
 * Moves a circle's position in `frame` (at `at`: AX or BX) from its body origin to its centre, read
 * from the circle's layout (polygon-geometry.ts: [x, y], or empty for a circle centred on the origin,
 * which is left alone so its numbers are exactly the body's).
 */
function moveToCenter(layout: Float64Array, at: number): void {
  if (layout.length === 0) return
  const lx = layout[0]
  const ly = layout[1]
  const c = frame[at + 2]
  const s = frame[at + 3]
  frame[at] += c * lx - s * ly
  frame[at + 1] += s * lx + c * ly
}

/**
 * Capsule or segment against circle in `frame` (Box2D v3 b2CollideCapsuleAndCircle): the point of
 * the capsule's segment nearest to the circle's centre, then the normal along that gap. `swapped`
 * means the capsule is B.
 */
function capsuleAndCircleInFrame(
  capsule: PolygonalShape,
  circle: CircleShape,
  swapped: boolean,
  out: Manifold,
): void {
  const px = frame[swapped ? BX : AX]
  const py = frame[swapped ? BY : AY]
  const pc = frame[swapped ? BC : AC]
  const ps = frame[swapped ? BS : AS]
  // Circle centre in the capsule's frame.
  const dx = frame[swapped ? AX : BX] - px
  const dy = frame[swapped ? AY : BY] - py
  const cx = pc * dx + ps * dy
  const cy = pc * dy - ps * dx
  const v1 = capsule.vertices[0]
  const v2 = capsule.vertices[1]
  const ex = v2.x - v1.x
  const ey = v2.y - v1.y
  const s1 = (cx - v1.x) * ex + (cy - v1.y) * ey
  const s2 = (v2.x - cx) * ex + (v2.y - cy) * ey
  let qx = v1.x
  let qy = v1.y
  if (s1 >= 0) {
    if (s2 < 0) {
      qx = v2.x
      qy = v2.y
    } else {
      const t = s1 / (ex * ex + ey * ey)
      qx = v1.x + t * ex
      qy = v1.y + t * ey
    }
  }
  const gx = cx - qx
  const gy = cy - qy
  const distance = Math.sqrt(gx * gx + gy * gy)
  // The centre on the segment itself: the segment's own normal (deterministic choice).
  let nx = capsule.normals[0].x
  let ny = capsule.normals[0].y
  if (distance > TINY_DISTANCE) {
    nx = gx / distance
    ny = gy / distance
  }
  const ra = capsule.radius
  const rb = circle.radius
  const separation = distance - ra - rb
  if (!(separation < frame[SPEC])) {
    setEmpty(out)
    return
  }
  // Midpoint of the capsule's surface point q + ra n and the circle's c - rb n.
  const mx = 0.5 * (qx + ra * nx + cx - rb * nx)
  const my = 0.5 * (qy + ra * ny + cy - rb * ny)
  const sign = swapped ? -1 : 1
  out.normalX = sign * (pc * nx - ps * ny)
  out.normalY = sign * (ps * nx + pc * ny)
  out.pointCount = 1
  const p = out.points[0]
  p.x = px + pc * mx - ps * my
  p.y = py + ps * mx + pc * my
  p.separation = separation
  p.id = 0
}

function setFrame(
  ax: number,
  ay: number,
  ac: number,
  as: number,
  bx: number,
  by: number,
  bc: number,
  bs: number,
  speculativeDistance: number,
): void {
  frame[AX] = ax
  frame[AY] = ay
  frame[AC] = ac
  frame[AS] = as
  frame[BX] = bx
  frame[BY] = by
  frame[BC] = bc
  frame[BS] = bs
  frame[SPEC] = speculativeDistance
}

/** Clears a manifold to "no contact" (zero normal, no points). */
function setEmpty(out: Manifold): void {
  out.normalX = 0
  out.normalY = 0
  out.pointCount = 0
}

/**
 * Circles in `frame`. The formulas are exactly mirror-symmetric when A and B are swapped. Coincident
 * centres (closer than 1e-12 m) use the fixed world normal (1, 0), so the result is defined and
 * deterministic; otherwise the normal is the centre-to-centre direction.
 */
function circlesInFrame(circleA: CircleShape, circleB: CircleShape, out: Manifold): void {
  const ax = frame[AX]
  const ay = frame[AY]
  const dx = frame[BX] - ax
  const dy = frame[BY] - ay
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
  if (!(separation < frame[SPEC])) {
    setEmpty(out)
    return
  }
  out.normalX = nx
  out.normalY = ny
  out.pointCount = 1
  // Midpoint of (A + ra n) and (B - rb n).
  const half = 0.5 * (ra - rb)
  const p = out.points[0]
  p.x = 0.5 * (ax + frame[BX]) + half * nx
  p.y = 0.5 * (ay + frame[BY]) + half * ny
  p.separation = separation
  p.id = 0
}

/**
 * Polygon (possibly rounded) against circle in `frame` (Box2D v3 b2CollidePolygonAndCircle): the
 * face of greatest separation from the centre, then the vertex region if the centre lies outside
 * past an end of that face. `swapped` means the polygon is B and the circle A.
 */
function polygonAndCircleInFrame(
  poly: PolygonalShape,
  g: Float64Array,
  circle: CircleShape,
  swapped: boolean,
  out: Manifold,
): void {
  const px = frame[swapped ? BX : AX]
  const py = frame[swapped ? BY : AY]
  const pc = frame[swapped ? BC : AC]
  const ps = frame[swapped ? BS : AS]
  // Circle centre in the polygon's frame.
  const dx = frame[swapped ? AX : BX] - px
  const dy = frame[swapped ? AY : BY] - py
  const cx = pc * dx + ps * dy
  const cy = pc * dy - ps * dx
  const radius = circle.radius
  const rounding = poly.radius
  const count = poly.count
  // Face of greatest separation.
  let face = 0
  let faceSeparation = Number.NEGATIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const s = g[NORMAL_X + i] * (cx - g[VERTEX_X + i]) + g[NORMAL_Y + i] * (cy - g[VERTEX_Y + i])
    if (s > faceSeparation) {
      faceSeparation = s
      face = i
    }
  }
  const next = face + 1 < count ? face + 1 : 0
  const v1x = g[VERTEX_X + face]
  const v1y = g[VERTEX_Y + face]
  const v2x = g[VERTEX_X + next]
  const v2y = g[VERTEX_Y + next]
  const u1 = (cx - v1x) * (v2x - v1x) + (cy - v1y) * (v2y - v1y)
  const u2 = (cx - v2x) * (v1x - v2x) + (cy - v2y) * (v1y - v2y)
  let nx = g[NORMAL_X + face]
  let ny = g[NORMAL_Y + face]
  // (With rounding 0 every expression below is bit for bit the sharp polygon's.)
  let separation = faceSeparation - rounding - radius
  // Face region: the centre projects onto the face (it may be inside the polygon); the point is
  // halfway between the rounded face and the circle's deepest point.
  const back = 0.5 * (faceSeparation - rounding + radius)
  let qx = cx - back * nx
  let qy = cy - back * ny
  if (faceSeparation > TINY_DISTANCE && (u1 < 0 || u2 < 0)) {
    // Vertex region: the centre is outside, nearest to one end of the face.
    const vx = u1 < 0 ? v1x : v2x
    const vy = u1 < 0 ? v1y : v2y
    const ex = cx - vx
    const ey = cy - vy
    const distance = Math.sqrt(ex * ex + ey * ey)
    nx = ex / distance
    ny = ey / distance
    separation = distance - rounding - radius
    // Midpoint of the rounded vertex v + rounding n and the circle's nearest point c - r n.
    qx = 0.5 * (vx + cx - (radius - rounding) * nx)
    qy = 0.5 * (vy + cy - (radius - rounding) * ny)
  }
  if (!(separation < frame[SPEC])) {
    setEmpty(out)
    return
  }
  const sign = swapped ? -1 : 1
  out.normalX = sign * (pc * nx - ps * ny)
  out.normalY = sign * (ps * nx + pc * ny)
  out.pointCount = 1
  const p = out.points[0]
  p.x = px + pc * qx - ps * qy
  p.y = py + ps * qx + pc * qy
  p.separation = separation
  p.id = 0
}

/**
 * Polygons in `frame` (Box2D v3 b2CollidePolygons): SAT over both polygons' edge normals, reference
 * face with a tolerance favouring A, then vertex-vertex or the incident edge clipped to the
 * reference side planes. Rounded polygons, capsules (two vertices and a radius) and segments (two
 * vertices) go through the same code: the core shapes are collided and the radii subtracted from the
 * separations, the points put halfway between the rounded surfaces.
 */
function polygonsInFrame(
  polygonA: PolygonalShape,
  localA: Float64Array,
  polygonB: PolygonalShape,
  geometryB: Float64Array,
  out: Manifold,
): void {
  const countA = polygonA.count
  const countB = polygonB.count
  radii[0] = polygonA.radius
  radii[1] = polygonB.radius
  // Shapes are kept while their cores are closer than the speculative distance plus both radii.
  const spec = frame[SPEC] + (radii[0] + radii[1])
  loadPolygonB(localA, geometryB, countB)
  findMaxSeparation(localA, countA, localB, countB)
  const separationA = found[0]
  let edgeA = found[1]
  // Apart along one of A's normals already: B's axes cannot bring them closer (the same answer as
  // testing both, without the second test; many pairs near each other in a pile get here).
  if (!(separationA < spec)) {
    setEmpty(out)
    return
  }
  findMaxSeparation(localB, countB, localA, countA)
  const separationB = found[0]
  let edgeB = found[1]
  if (!(separationB < spec)) {
    setEmpty(out)
    return
  }
  // Reference face: A's unless B's is clearly better; the incident edge is on the other polygon.
  const flip = separationB > separationA + REFERENCE_FACE_TOLERANCE
  if (flip) edgeA = findIncidentEdge(localB, edgeB, localA, countA)
  else edgeB = findIncidentEdge(localA, edgeA, localB, countB)
  // Apart by more than a tenth of the slop: the closest features may be two vertices.
  const apart = separationA > 0.1 * LINEAR_SLOP || separationB > 0.1 * LINEAR_SLOP
  if (!(apart && collideVertices(localA, edgeA, countA, edgeB, countB, out))) {
    if (flip) clipPolygons(localB, countB, edgeB, localA, countA, edgeA, true, out)
    else clipPolygons(localA, countA, edgeA, localB, countB, edgeB, false, out)
  }
  if (out.pointCount === 0) {
    setEmpty(out)
    return
  }
  // Back to world space.
  const ax = frame[AX]
  const ay = frame[AY]
  const ac = frame[AC]
  const as = frame[AS]
  const ox = localA[VERTEX_X]
  const oy = localA[VERTEX_Y]
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

/** Moves B (its geometry) into A's shifted frame (A's geometry), into the scratch polygon localB. */
function loadPolygonB(geometryA: Float64Array, geometryB: Float64Array, countB: number): void {
  const ox = geometryA[VERTEX_X]
  const oy = geometryA[VERTEX_Y]
  // B relative to the shifted A frame: rotation qA^T qB, translation qA^T (pB - pA - qA o).
  const ac = frame[AC]
  const as = frame[AS]
  const bc = frame[BC]
  const bs = frame[BS]
  const qc = ac * bc + as * bs
  const qs = ac * bs - as * bc
  const dx = frame[BX] - (frame[AX] + ac * ox - as * oy)
  const dy = frame[BY] - (frame[AY] + as * ox + ac * oy)
  const px = ac * dx + as * dy
  const py = ac * dy - as * dx
  for (let i = 0; i < countB; i++) {
    const vx = geometryB[VERTEX_X + i]
    const vy = geometryB[VERTEX_Y + i]
    const nx = geometryB[NX + i]
    const ny = geometryB[NY + i]
    localB[i] = qc * vx - qs * vy + px
    localB[VY + i] = qs * vx + qc * vy + py
    localB[NX + i] = qc * nx - qs * ny
    localB[NY + i] = qs * nx + qc * ny
  }
}

/** found = (largest over poly1's edges of the least signed distance of poly2's vertices, that edge). */
function findMaxSeparation(poly1: Float64Array, count1: number, poly2: Float64Array, count2: number): void {
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
  found[0] = maxSeparation
  found[1] = best
}

/** The edge of `inc` whose normal is most anti-parallel to the normal of edge `edge` of `ref`. */
function findIncidentEdge(ref: Float64Array, edge: number, inc: Float64Array, count: number): number {
  const nx = ref[NX + edge]
  const ny = ref[NY + edge]
  let incident = 0
  let minDot = Number.POSITIVE_INFINITY
  for (let i = 0; i < count; i++) {
    const dot = nx * inc[NX + i] + ny * inc[NY + i]
    if (dot < minDot) {
      minDot = dot
      incident = i
    }
  }
  return incident
}

/**
 * If the closest points of edge edgeA of A and edge edgeB of B are two vertices, writes the one-point
 * vertex-vertex manifold (in A's shifted frame) and returns true (Box2D v3; segment distance after
 * Ericson 5.1.9). Returns false when the closest features include an edge interior.
 */
function collideVertices(
  localA: Float64Array,
  edgeA: number,
  countA: number,
  edgeB: number,
  countB: number,
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
  let f1 = denom > 0 ? Math.max(0, Math.min((d12 * rd2 - rd1 * dd2) / denom, 1)) : 0
  let f2 = (d12 * f1 + rd2) / dd2
  if (f2 < 0) {
    f2 = 0
    f1 = Math.max(0, Math.min(-rd1 / dd1, 1))
  } else if (f2 > 1) {
    f2 = 1
    f1 = Math.max(0, Math.min((d12 - rd1) / dd1, 1))
  }
  if ((f1 !== 0 && f1 !== 1) || (f2 !== 0 && f2 !== 1)) return false
  const iA = f1 === 0 ? edgeA : a2
  const iB = f2 === 0 ? edgeB : b2
  const vax = localA[iA]
  const vay = localA[VY + iA]
  const ex = localB[iB] - vax
  const ey = localB[VY + iB] - vay
  const distance = Math.sqrt(ex * ex + ey * ey)
  const ra = radii[0]
  const rb = radii[1]
  out.pointCount = 0
  if (distance < frame[SPEC] + (ra + rb)) {
    const nx = ex / distance
    const ny = ey / distance
    out.normalX = nx
    out.normalY = ny
    out.pointCount = 1
    const p = out.points[0]
    // Halfway between the rounded vertices vA + ra n and vB - rb n (sharp: between the vertices).
    p.x = vax + 0.5 * ex
    p.y = vay + 0.5 * ey
    if (ra !== rb) {
      p.x += 0.5 * (ra - rb) * nx
      p.y += 0.5 * (ra - rb) * ny
    }
    p.separation = distance - (ra + rb)
    p.id = makeFeatureId(iA, iB)
  }
  return true
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
    const t = Math.min(-lower2 / span, 1)
    lowerX = v22x + t * (v21x - v22x)
    lowerY = v22y + t * (v21y - v22y)
  }
  if (upper2 > upper1 && span > 0) {
    const t = Math.max(0, (upper1 - lower2) / span)
    upperX = v22x + t * (v21x - v22x)
    upperY = v22y + t * (v21y - v22y)
  }
  // Separations of the rounded surfaces (the core's less both radii; r1 the reference's).
  const r1 = radii[flip ? 1 : 0]
  const r2 = radii[flip ? 0 : 1]
  const separationLower = nx * (lowerX - v11x) + ny * (lowerY - v11y) - (r1 + r2)
  const separationUpper = nx * (upperX - v11x) + ny * (upperY - v11y) - (r1 + r2)
  // If the incident edge lies wholly beyond one side plane (only in degenerate overlaps) the two
  // clipped points coincide: keep one.
  const spec = frame[SPEC]
  const keepLower = separationLower < spec && !(upper2 < 0)
  const keepUpper = separationUpper < spec && !(lower2 > upper1)
  // Each point moves halfway between the incident surface and the reference surface:
  // v + (r1 - r2 - core separation) / 2 n, which is v - separation / 2 n for sharp polygons.
  const lowerShift = 0.5 * (separationLower + 2 * r2)
  const upperShift = 0.5 * (separationUpper + 2 * r2)
  const lowerMidX = lowerX - lowerShift * nx
  const lowerMidY = lowerY - lowerShift * ny
  const upperMidX = upperX - upperShift * nx
  const upperMidY = upperY - upperShift * ny
  out.normalX = flip ? -nx : nx
  out.normalY = flip ? -ny : ny
  // Points written field by field: a call with double arguments that V8 does not inline boxes
  // each of them (a heap number per value; 1.7-2.2 KB per step in a scene of box towers).
  let n = 0
  if (keepLower && !flip) {
    const p = out.points[n++]
    p.x = lowerMidX
    p.y = lowerMidY
    p.separation = separationLower
    p.id = makeFeatureId(i11, i22)
  }
  if (keepUpper) {
    const p = out.points[n++]
    p.x = upperMidX
    p.y = upperMidY
    p.separation = separationUpper
    p.id = flip ? makeFeatureId(i21, i12) : makeFeatureId(i12, i21)
  }
  if (keepLower && flip) {
    const p = out.points[n++]
    p.x = lowerMidX
    p.y = lowerMidY
    p.separation = separationLower
    p.id = makeFeatureId(i22, i11)
  }
  out.pointCount = n
}
