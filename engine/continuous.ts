/*
 * Continuous collision (Box2D v3's b2SolveContinuous, with conservative advancement for the time
 * of impact; Mirtich 1996, "Impulse-based dynamic simulation of rigid body systems").
 *
 * After the sub-steps, a body that moved more than half its smallest extent in one step ("fast"),
 * or any body flagged `bullet`, is swept from its step-start pose to its end pose. Against every
 * candidate the broadphase finds in the swept box, the time of impact is found by conservative
 * advancement: at fraction t the signed distance d between the two shapes is computed exactly;
 * no point of either shape can approach faster than the bound mu = |relative centre motion| +
 * |rotation A| * extentA + |rotation B| * extentB per unit t, so the shapes cannot touch before
 * t + (d - target) / mu. Iterating converges to the first time the gap reaches the target
 * (linear slop). The body is then moved back to the earliest impact; its velocity is kept, so the
 * next step's speculative contact stops it at the surface instead of inside or beyond it.
 *
 * Who is swept against what:
 * - fast non-bullet bodies: static bodies (as Box2D v3).
 * - bullets: static bodies, and dynamic bodies (bullets or not) along their own sweeps: the
 *   broadphase candidates around the bullet's swept box, plus every body that moved farther than
 *   the fat-AABB margin this step (its proxy no longer shows where it went, e.g. a plank crossing
 *   the bullet's path sideways). At the impact both the bullet and the body it hit are moved back
 *   to the impact time, so the next step's contact sees them in their true order (moving only the
 *   bullet left a fast plank already past it).
 * A pair closer than the speculative distance at the step start is left to its regular contact,
 * which exists by then and stops the approach speculatively; only the fast body's core (a small
 * circle at its centre of mass) is swept for it, so its centre can never cross (see timeOfImpact).
 *
 * What remains is in engine/README.md: kinematic bodies are never swept against, a non-bullet
 * fast body passes through thin dynamic bodies, and a rotation over ~half a turn in one step is
 * swept along the shorter arc.
 */
import { type Body, DYNAMIC, STATIC } from './body.ts'
import { type BroadPhase, IdBuffer } from './broad-phase.ts'
import type { Shape } from './shapes.ts'

/** Gap (m) at which conservative advancement stops: the linear slop. */
const TOI_TARGET = 0.005
const TOI_TOLERANCE = 0.00125
const MAX_ITERATIONS = 30
/** Pairs closer than this at the start of the sweep are left to their contact: 4 x slop. */
const START_SKIP_DISTANCE = 0.02

const candidates = new IdBuffer()
const pose = new Float64Array(4)
const verticesA = new Float64Array(16)
const verticesB = new Float64Array(16)

/** Sets `pose` (origin x, y, cos, sin) of body b at sweep fraction t (nlerp of the rotation). */
function poseAt(b: Body, t: number): void {
  if (!b.awake) {
    // Static and sleeping bodies did not move this step.
    pose[0] = b.x
    pose[1] = b.y
    pose[2] = b.c
    pose[3] = b.s
    return
  }
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

function transformVertices(shape: Shape, out: Float64Array): number {
  if (shape.type === 'circle') {
    out[0] = pose[0]
    out[1] = pose[1]
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

/** Largest separation of the points of `q` from the edges of convex polygon `p` (SAT, one side). */
function maxEdgeSeparation(p: Float64Array, pn: number, q: Float64Array, qn: number): number {
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
  return best
}

/** Smallest distance between the boundaries of two polygons (or a polygon and a point). */
function boundaryDistance(p: Float64Array, pn: number, q: Float64Array, qn: number): number {
  let best = Number.POSITIVE_INFINITY
  for (let i = 0; i < pn; i++) {
    const j = i + 1 === pn ? 0 : i + 1
    for (let k = 0; k < qn; k++) {
      const d = pointSegmentDistance(q[2 * k], q[2 * k + 1], p[2 * i], p[2 * i + 1], p[2 * j], p[2 * j + 1])
      if (d < best) best = d
    }
  }
  return best
}

/**
 * Signed distance between the shapes of a and b at sweep fraction t (negative when overlapping).
 * With `core` > 0, body a is replaced by its core: a circle of that radius at its centre of mass.
 */
export function sweptDistance(a: Body, b: Body, t: number, core = 0): number {
  poseAt(a, t)
  let na: number
  let ra: number
  if (core > 0) {
    verticesA[0] = pose[0] + pose[2] * a.localCenterX - pose[3] * a.localCenterY
    verticesA[1] = pose[1] + pose[3] * a.localCenterX + pose[2] * a.localCenterY
    na = 1
    ra = core
  } else {
    na = transformVertices(a.shape, verticesA)
    ra = a.shape.type === 'circle' ? a.shape.radius : 0
  }
  poseAt(b, t)
  const nb = transformVertices(b.shape, verticesB)
  const rb = b.shape.type === 'circle' ? b.shape.radius : 0
  if (na === 1 && nb === 1) {
    const dx = verticesB[0] - verticesA[0]
    const dy = verticesB[1] - verticesA[1]
    return Math.sqrt(dx * dx + dy * dy) - ra - rb
  }
  let sat = Number.NEGATIVE_INFINITY
  if (na > 1) sat = Math.max(sat, maxEdgeSeparation(verticesA, na, verticesB, nb))
  if (nb > 1) sat = Math.max(sat, maxEdgeSeparation(verticesB, nb, verticesA, na))
  if (sat <= 0) return sat - ra - rb
  let d = Number.POSITIVE_INFINITY
  if (na > 1) d = Math.min(d, boundaryDistance(verticesA, na, verticesB, nb))
  if (nb > 1) d = Math.min(d, boundaryDistance(verticesB, nb, verticesA, na))
  return d - ra - rb
}

/**
 * First sweep fraction in (0, 1) at which the fast body a comes within the target gap of b, or 1.
 *
 * A pair already closer than the speculative distance at the start has a contact, and a time of
 * impact of 0 would freeze both bodies in place every step (Box2D's "pausing"). For such a pair
 * only a's core, a circle of a quarter of its smallest extent at its centre of mass, is swept (as
 * Box2D v3.1 does): the contact handles the surfaces, and the core stops a body that the contact
 * failed to stop (a thin bar spun up by the impact and rotating through a wall) from crossing.
 */
export function timeOfImpact(a: Body, b: Body): number {
  let d = sweptDistance(a, b, 0)
  if (d >= START_SKIP_DISTANCE) return advance(a, b, d, 0, sweepArc(a) * a.maxExtent, TOI_TARGET)
  const core = 0.25 * a.minExtent
  d = sweptDistance(a, b, 0, core)
  if (d <= 0) return 1
  // The core sits at the centre of mass: a's rotation does not move it. It may close at most half
  // of its remaining gap per step, so it never crosses and never freezes completely.
  const t = advance(a, b, d, core, 0, Math.min(TOI_TARGET, 0.5 * d))
  coreHit = t < 1
  return t
}

/** Whether the last timeOfImpact that found a hit found it with the core sweep. */
let coreHit = false

/**
 * After a core hit on a static body: removes the centre's velocity into that body (along the
 * direction from its nearest point to the centre). The contact failed to stop the centre (or the
 * core would not have been needed), so without this the body would press on, be held back again
 * every step, and finally slip through.
 */
function stopCore(b: Body, other: Body): void {
  poseAt(other, 1)
  const n = transformVertices(other.shape, verticesB)
  let nx = b.cx - verticesB[0]
  let ny = b.cy - verticesB[1]
  if (n > 1) {
    verticesA[0] = b.cx
    verticesA[1] = b.cy
    if (maxEdgeSeparation(verticesB, n, verticesA, 1) <= 0) return
    nearestOnBoundary(verticesB, n, b.cx, b.cy)
    nx = b.cx - nearest[0]
    ny = b.cy - nearest[1]
  }
  const len = Math.sqrt(nx * nx + ny * ny)
  if (len === 0) return
  nx /= len
  ny /= len
  const vn = b.vx * nx + b.vy * ny
  if (vn < 0) {
    b.vx -= vn * nx
    b.vy -= vn * ny
  }
}

/** The nearest point found by nearestOnBoundary (x, y). */
const nearest = new Float64Array(2)

/** Sets `nearest` to the point of polygon p's boundary nearest to (px, py). */
function nearestOnBoundary(p: Float64Array, pn: number, px: number, py: number): void {
  let best = Number.POSITIVE_INFINITY
  for (let i = 0; i < pn; i++) {
    const j = i + 1 === pn ? 0 : i + 1
    const ax = p[2 * i]
    const ay = p[2 * i + 1]
    const ex = p[2 * j] - ax
    const ey = p[2 * j + 1] - ay
    const len2 = ex * ex + ey * ey
    let t = len2 > 0 ? ((px - ax) * ex + (py - ay) * ey) / len2 : 0
    t = Math.max(0, Math.min(1, t))
    const qx = ax + t * ex
    const qy = ay + t * ey
    const d = (px - qx) * (px - qx) + (py - qy) * (py - qy)
    if (d < best) {
      best = d
      nearest[0] = qx
      nearest[1] = qy
    }
  }
}

/** Conservative advancement from distance d at t = 0; `spinA` bounds a's rotational speed. */
function advance(a: Body, b: Body, d: number, core: number, spinA: number, target: number): number {
  const dax = a.awake ? a.cx - a.c0x : 0
  const day = a.awake ? a.cy - a.c0y : 0
  const dbx = b.awake ? b.cx - b.c0x : 0
  const dby = b.awake ? b.cy - b.c0y : 0
  const relative = Math.sqrt((dbx - dax) * (dbx - dax) + (dby - day) * (dby - day))
  const mu = relative + spinA + sweepArc(b) * b.maxExtent
  if (mu <= 0) return 1
  let t = 0
  for (let i = 0; i < MAX_ITERATIONS; i++) {
    if (d < target + TOI_TOLERANCE * (target / TOI_TARGET)) return t
    t += (d - target) / mu
    if (t >= 1) return 1
    d = sweptDistance(a, b, t, core)
  }
  return t
}

/**
 * Bound on how fast (per unit sweep fraction) a point at unit distance from the centre moves:
 * the nlerp q(t) = q0 + t (q1 - q0) moves at the chord length |q1 - q0|, and its normalised angle
 * turns at most chord / |q(t)|^2 <= chord / cos^2(angle / 2) = 2 chord / (1 + cos angle). The
 * denominator is floored so a half-turn in one step still gives a finite (very slow, safe) bound.
 */
function sweepArc(b: Body): number {
  if (!b.awake) return 0
  const sinAngle = b.c * b.q0s - b.s * b.q0c
  const cosAngle = b.c * b.q0c + b.s * b.q0s
  const chord = Math.sqrt(sinAngle * sinAngle + (1 - cosAngle) * (1 - cosAngle))
  return (2 * chord) / Math.max(1 + cosAngle, 0.05)
}

/** Moves a body to fraction t of its sweep. */
function advanceTo(b: Body, t: number): void {
  poseAt(b, t)
  b.x = pose[0]
  b.y = pose[1]
  b.c = pose[2]
  b.s = pose[3]
  b.updateCenter()
}

/** How far a body's surface moved this step at most (m): centre travel plus the rotation's chord. */
function travel(b: Body): number {
  const dx = b.cx - b.c0x
  const dy = b.cy - b.c0y
  return Math.sqrt(dx * dx + dy * dy) + sweepArc(b) * b.maxExtent
}

/** Awake dynamic bodies that may have left their fat AABB this step, in id order (reused). */
const movers: Body[] = []
let moverCount = 0

/**
 * Sweeps fast bodies and bullets (awake, in id order) and moves each back to its first impact.
 * Non-bullets go first (against static bodies only) so that bullets see the final sweeps of the
 * bodies they may hit.
 */
export function solveContinuous(
  awake: Body[],
  count: number,
  broadPhase: BroadPhase,
  bodies: Map<number, Body>,
  canCollide: (a: Body, b: Body) => boolean,
): void {
  moverCount = 0
  let bullets = 0
  for (let i = 0; i < count; i++) {
    const b = awake[i]
    if (b.type !== DYNAMIC) continue
    if (b.bullet) bullets++
    const d = travel(b)
    if (d > broadPhase.margin) movers[moverCount++] = b
    if (!b.bullet && d > 0.5 * b.minExtent) sweepBody(b, broadPhase, bodies, canCollide)
  }
  if (bullets === 0) return
  for (let i = 0; i < count; i++) {
    const b = awake[i]
    if (b.type === DYNAMIC && b.bullet && travel(b) > 0.5 * b.minExtent) {
      sweepBody(b, broadPhase, bodies, canCollide)
    }
  }
}

// The earliest impact found by sweepBody so far, and the dynamic body hit there.
/** [0]: the earliest impact fraction found so far (typed: a module-level double would allocate). */
const earliest = new Float64Array(1)
let hitBody: Body | null = null
/** The static body whose core hit is the earliest, if it is. */
let coreStop: Body | null = null

function sweepAgainst(b: Body, other: Body, canCollide: (a: Body, b: Body) => boolean): void {
  if (other === b) return
  const sweepable = other.type === STATIC || (b.bullet && other.type === DYNAMIC)
  if (!sweepable || !canCollide(b, other)) return
  coreHit = false
  const t = timeOfImpact(b, other)
  if (t < earliest[0]) {
    earliest[0] = t
    hitBody = other.type === DYNAMIC && other.awake ? other : null
    coreStop = coreHit && other.type === STATIC ? other : null
  }
}

/**
 * Sweeps one body against the broadphase candidates around its swept box and, for a bullet, also
 * against every body that moved farther than the fat-AABB margin (its proxy may not show where it
 * went). At the earliest impact the body, and a dynamic body it hit, are moved back to that time:
 * both keep their velocities, so the next step's speculative contact resolves the collision.
 */
function sweepBody(
  b: Body,
  broadPhase: BroadPhase,
  bodies: Map<number, Body>,
  canCollide: (a: Body, b: Body) => boolean,
): void {
  const r = b.maxExtent
  const minX = Math.min(b.c0x, b.cx) - r
  const minY = Math.min(b.c0y, b.cy) - r
  const maxX = Math.max(b.c0x, b.cx) + r
  const maxY = Math.max(b.c0y, b.cy) + r
  const n = broadPhase.query(minX, minY, maxX, maxY, candidates)
  earliest[0] = 1
  hitBody = null
  coreStop = null
  for (let k = 0; k < n; k++) {
    const other = bodies.get(candidates.ids[k])
    if (other !== undefined) sweepAgainst(b, other, canCollide)
  }
  if (b.bullet) {
    for (let k = 0; k < moverCount; k++) {
      const other = movers[k]
      const ro = other.maxExtent
      if (Math.min(other.c0x, other.cx) - ro > maxX || Math.max(other.c0x, other.cx) + ro < minX) continue
      if (Math.min(other.c0y, other.cy) - ro > maxY || Math.max(other.c0y, other.cy) + ro < minY) continue
      sweepAgainst(b, other, canCollide)
    }
  }
  const minT = earliest[0]
  if (minT < 1) {
    advanceTo(b, minT)
    if (hitBody !== null) advanceTo(hitBody, minT)
    if (coreStop !== null) stopCore(b, coreStop)
  }
}
