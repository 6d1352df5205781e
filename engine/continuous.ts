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
 * - bullets: static bodies, dynamic non-bullet bodies (using their own sweep, so a moving thin
 *   plank is caught), and other bullets: both bullets are moved back to the impact time.
 * A pair that already overlaps at the step start is left to the regular contact.
 */
import { type Body, DYNAMIC, STATIC } from './body.ts'
import { type BroadPhase, IdBuffer } from './broad-phase.ts'
import type { Shape } from './shapes.ts'

/** Gap (m) at which conservative advancement stops: the linear slop. */
const TOI_TARGET = 0.005
const TOI_TOLERANCE = 0.00125
const MAX_ITERATIONS = 30

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

/** Signed distance between the shapes of a and b at sweep fraction t (negative when overlapping). */
export function sweptDistance(a: Body, b: Body, t: number): number {
  poseAt(a, t)
  const na = transformVertices(a.shape, verticesA)
  poseAt(b, t)
  const nb = transformVertices(b.shape, verticesB)
  const ra = a.shape.type === 'circle' ? a.shape.radius : 0
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

/** First sweep fraction in (0, 1) at which a and b come within the target gap, or 1 if none. */
export function timeOfImpact(a: Body, b: Body): number {
  const dax = a.awake ? a.cx - a.c0x : 0
  const day = a.awake ? a.cy - a.c0y : 0
  const dbx = b.awake ? b.cx - b.c0x : 0
  const dby = b.awake ? b.cy - b.c0y : 0
  const relative = Math.sqrt((dbx - dax) * (dbx - dax) + (dby - day) * (dby - day))
  const mu = relative + sweepArc(a) * a.maxExtent + sweepArc(b) * b.maxExtent
  if (mu <= 0) return 1
  let t = 0
  let d = sweptDistance(a, b, 0)
  if (d < TOI_TARGET) return 1 // overlapping or touching at the start: the regular contact handles it
  for (let i = 0; i < MAX_ITERATIONS; i++) {
    if (d < TOI_TARGET + TOI_TOLERANCE) return t
    t += (d - TOI_TARGET) / mu
    if (t >= 1) return 1
    d = sweptDistance(a, b, t)
  }
  return t
}

/**
 * Bound on how far a point at unit distance from the centre moves over the sweep: the chord of the
 * rotation, doubled for the nlerp (whose angular speed varies along the sweep).
 */
function sweepArc(b: Body): number {
  if (!b.awake) return 0
  const sinAngle = b.c * b.q0s - b.s * b.q0c
  const cosAngle = b.c * b.q0c + b.s * b.q0s
  return 2 * Math.sqrt(sinAngle * sinAngle + (1 - cosAngle) * (1 - cosAngle))
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

/** Whether a body moved far enough this step to need a sweep. */
function isFast(b: Body): boolean {
  const dx = b.cx - b.c0x
  const dy = b.cy - b.c0y
  const rotation = Math.abs(b.c * b.q0s - b.s * b.q0c)
  const travel = Math.sqrt(dx * dx + dy * dy) + rotation * b.maxExtent
  return travel > 0.5 * b.minExtent
}

/**
 * Sweeps fast bodies and bullets (awake, in id order) and moves each back to its first impact.
 * Non-bullets go first so that bullets see the final sweeps of the bodies they may hit.
 */
export function solveContinuous(
  awake: Body[],
  count: number,
  broadPhase: BroadPhase,
  bodies: Map<number, Body>,
  canCollide: (a: Body, b: Body) => boolean,
): void {
  for (let pass = 0; pass < 2; pass++) {
    for (let i = 0; i < count; i++) {
      const b = awake[i]
      if (b.type !== DYNAMIC || b.bullet !== (pass === 1) || !isFast(b)) continue
      sweepBody(b, broadPhase, bodies, canCollide)
    }
  }
}

function sweepBody(
  b: Body,
  broadPhase: BroadPhase,
  bodies: Map<number, Body>,
  canCollide: (a: Body, b: Body) => boolean,
): void {
  const r = b.maxExtent
  const x0 = b.c0x
  const y0 = b.c0y
  const n = broadPhase.query(
    Math.min(x0, b.cx) - r,
    Math.min(y0, b.cy) - r,
    Math.max(x0, b.cx) + r,
    Math.max(y0, b.cy) + r,
    candidates,
  )
  let minT = 1
  let hitBullet: Body | null = null
  for (let k = 0; k < n; k++) {
    const other = bodies.get(candidates.ids[k])
    if (other === undefined || other === b) continue
    const sweepable = other.type === STATIC || (b.bullet && other.type === DYNAMIC)
    if (!sweepable || !canCollide(b, other)) continue
    const t = timeOfImpact(b, other)
    if (t < minT) {
      minT = t
      hitBullet = other.bullet && other.awake ? other : null
    }
  }
  if (minT < 1) {
    advanceTo(b, minT)
    if (hitBullet !== null) advanceTo(hitBullet, minT)
  }
}
