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
 * A chain segment is swept against only by a shape whose centre crosses its line from the front to
 * the back during the step (Box2D v3's rule, per shape): one that starts behind passes through
 * (one-sided), one that ends in front is left to its contacts (see skipsChain).
 *
 * What remains is in engine/README.md: kinematic bodies are never swept against, a non-bullet
 * fast body passes through thin dynamic bodies, and a rotation over ~half a turn in one step is
 * swept along the shorter arc.
 */

import {
  type BroadPhase,
  CORE,
  DISTANCE,
  EDGE,
  FRACTION,
  IdBuffer,
  maxEdgeSeparation,
  pose,
  poseAt,
  sweep,
  sweptDistance,
  transformVertices,
  verticesA,
  verticesB,
} from '../collision/index.ts'
import { type Body, DYNAMIC, STATIC } from './body.ts'
import type { BodyShape } from './body-shape.ts'

/** Gap (m) at which conservative advancement stops: the linear slop. */
const TOI_TARGET = 0.005
const TOI_TOLERANCE = 0.00125
const MAX_ITERATIONS = 30
/** Pairs closer than this at the start of the sweep are left to their contact: 4 x slop. */
const START_SKIP_DISTANCE = 0.02

/** In for advance: the bound on a's rotational speed, and the gap at which to stop (m). */
const SPIN = 0
const TARGET = 1
/** Out: the fraction found by timeOfImpact (1: no impact within the step). */
const IMPACT = 2
/** The earliest impact fraction sweepBody found so far. */
const EARLIEST = 3

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

/** Moves a body to fraction sweep[FRACTION] of its sweep. */
function advanceTo(b: Body): void {
  poseAt(b)
  b.x = pose[0]
  b.y = pose[1]
  b.c = pose[2]
  b.s = pose[3]
  // Body.updateCenter written out: the method, called from here only on hits, was left in V8's
  // baseline tier (a heap number per intermediate double) instead of being inlined.
  b.cx = b.x + (b.c * b.localCenterX - b.s * b.localCenterY)
  b.cy = b.y + (b.s * b.localCenterX + b.c * b.localCenterY)
}

/**
 * Whether the sweep of shape `bs` of body b against chain segment `chain` is skipped (Box2D v3's
 * continuous rule for chain segments, applied to the shape's centre rather than the body's so that
 * each wheel of a car counts): when the shape's centre started the step behind the segment's line
 * (on its left, the side that does not collide: it passes through) or ends the step in front of it
 * (it did not cross: its contact handles it, and sweeping would hold back a body that rolls or
 * slides along a chain, whose next segment's end lies on the body's path).
 */
function skipsChain(b: Body, bs: BodyShape, chain: BodyShape): boolean {
  const o = chain.body
  const v = chain.shape.vertices
  const p1x = o.x + o.c * v[0].x - o.s * v[0].y
  const p1y = o.y + o.s * v[0].x + o.c * v[0].y
  const p2x = o.x + o.c * v[1].x - o.s * v[1].y
  const p2y = o.y + o.s * v[1].x + o.c * v[1].y
  const ex = p2x - p1x
  const ey = p2y - p1y
  // The shape's centre relative to the centre of mass, at the start and at the end of the step.
  const rx = bs.shape.centroid.x - b.localCenterX
  const ry = bs.shape.centroid.y - b.localCenterY
  const x0 = b.c0x + b.q0c * rx - b.q0s * ry
  const y0 = b.c0y + b.q0s * rx + b.q0c * ry
  const x1 = b.cx + b.c * rx - b.s * ry
  const y1 = b.cy + b.s * rx + b.c * ry
  return ey * (x0 - p1x) - ex * (y0 - p1y) < 0 || ey * (x1 - p1x) - ex * (y1 - p1y) > 0
}

/** How far a body's surface moved this step at most (m): centre travel plus the rotation's chord. */
function travel(b: Body): number {
  const dx = b.cx - b.c0x
  const dy = b.cy - b.c0y
  return Math.sqrt(dx * dx + dy * dy) + sweepArc(b) * b.maxExtent
}

/**
 * The continuous stage of one world: its search state lives here, not in the module, so worlds on
 * one thread share nothing.
 */
export class ContinuousSolver {
  private readonly candidates = new IdBuffer()
  /** The swept box of the body being swept (minX, minY, maxX, maxY) for the broadphase query. */
  private readonly sweptBox = new Float64Array(4)
  /**
   * The numbers of one time-of-impact search, passed between the methods below in this array
   * rather than as arguments or results (see swept-distance.ts: V8 boxes those).
   */
  private readonly search = new Float64Array(4)
  /** Whether the last timeOfImpact that found a hit found it with the core sweep. */
  private coreHit = false
  /** Awake dynamic bodies that may have left their fat AABB this step, in id order (reused). */
  private readonly movers: Body[] = []
  private moverCount = 0
  /** The dynamic body hit at the earliest impact sweepBody found so far (search[EARLIEST]). */
  private hitBody: Body | null = null
  /** The static body whose core hit is the earliest, if it is. */
  private coreStop: BodyShape | null = null

  /**
   * First sweep fraction in (0, 1) at which the fast body a comes within the target gap of b, or 1,
   * into search[IMPACT].
   *
   * A pair already closer than the speculative distance at the start has a contact, and a time of
   * impact of 0 would freeze both bodies in place every step (Box2D's "pausing"). For such a pair
   * only a's core, a circle of a quarter of its smallest extent at its centre of mass, is swept (as
   * Box2D v3.1 does): the contact handles the surfaces, and the core stops a body that the contact
   * failed to stop (a thin bar spun up by the impact and rotating through a wall) from crossing.
   */
  private timeOfImpact(a: Body, sa: BodyShape, b: Body, sb: BodyShape): void {
    sweep[FRACTION] = 0
    sweep[CORE] = 0
    sweptDistance(a, sa.shape, b, sb.shape)
    if (sweep[DISTANCE] >= START_SKIP_DISTANCE) {
      this.search[SPIN] = sweepArc(a) * a.maxExtent
      this.search[TARGET] = TOI_TARGET
      this.advance(a, sa, b, sb)
      return
    }
    sweep[CORE] = 0.25 * a.minExtent
    sweptDistance(a, sa.shape, b, sb.shape)
    const d = sweep[DISTANCE]
    if (d <= 0) {
      this.search[IMPACT] = 1
      return
    }
    // The core sits at the centre of mass: a's rotation does not move it. It may close at most half
    // of its remaining gap per step, so it never crosses and never freezes completely.
    this.search[SPIN] = 0
    this.search[TARGET] = Math.min(TOI_TARGET, 0.5 * d)
    this.advance(a, sa, b, sb)
    this.coreHit = this.search[IMPACT] < 1
  }

  /**
   * Conservative advancement from distance sweep[DISTANCE] at t = 0 to the gap search[TARGET], into
   * search[IMPACT]; search[SPIN] bounds a's rotational speed, sweep[CORE] is passed on to sweptDistance.
   */
  private advance(a: Body, sa: BodyShape, b: Body, sb: BodyShape): void {
    let d = sweep[DISTANCE]
    const target = this.search[TARGET]
    const dax = a.awake ? a.cx - a.c0x : 0
    const day = a.awake ? a.cy - a.c0y : 0
    const dbx = b.awake ? b.cx - b.c0x : 0
    const dby = b.awake ? b.cy - b.c0y : 0
    const relative = Math.sqrt((dbx - dax) * (dbx - dax) + (dby - day) * (dby - day))
    const mu = relative + this.search[SPIN] + sweepArc(b) * b.maxExtent
    if (mu <= 0) {
      this.search[IMPACT] = 1
      return
    }
    let t = 0
    for (let i = 0; i < MAX_ITERATIONS; i++) {
      if (d < target + TOI_TOLERANCE * (target / TOI_TARGET)) break
      t += (d - target) / mu
      if (t >= 1) {
        t = 1
        break
      }
      sweep[FRACTION] = t
      sweptDistance(a, sa.shape, b, sb.shape)
      d = sweep[DISTANCE]
    }
    this.search[IMPACT] = t
  }

  /**
   * Sweeps fast bodies and bullets (awake, in id order) and moves each back to its first impact.
   * Non-bullets go first (against static bodies only) so that bullets see the final sweeps of the
   * bodies they may hit.
   */
  solve(
    awake: Body[],
    count: number,
    broadPhase: BroadPhase,
    shapes: Map<number, BodyShape>,
    canCollide: (a: BodyShape, b: BodyShape) => boolean,
  ): void {
    this.moverCount = 0
    let bullets = 0
    for (let i = 0; i < count; i++) {
      const b = awake[i]
      if (b.type !== DYNAMIC) continue
      if (b.bullet) bullets++
      const d = travel(b)
      if (d > broadPhase.margin) this.movers[this.moverCount++] = b
      if (!b.bullet && d > 0.5 * b.minExtent) this.sweepBody(b, broadPhase, shapes, canCollide)
    }
    if (bullets === 0) return
    for (let i = 0; i < count; i++) {
      const b = awake[i]
      if (b.type === DYNAMIC && b.bullet && travel(b) > 0.5 * b.minExtent) {
        this.sweepBody(b, broadPhase, shapes, canCollide)
      }
    }
  }

  /** Sweeps each shape of body b against one shape of another body. */
  private sweepAgainst(b: Body, os: BodyShape, canCollide: (a: BodyShape, b: BodyShape) => boolean): void {
    const other = os.body
    if (other === b) return
    const sweepable = other.type === STATIC || (b.bullet && other.type === DYNAMIC)
    if (!sweepable) return
    const shapes = b.shapes
    for (let i = 0; i < shapes.length; i++) this.sweepShapeAgainst(b, shapes[i], other, os, canCollide)
  }

  private sweepShapeAgainst(
    b: Body,
    bs: BodyShape,
    other: Body,
    os: BodyShape,
    canCollide: (a: BodyShape, b: BodyShape) => boolean,
  ): void {
    if (!canCollide(bs, os)) return
    if (os.shape.type === 'chainSegment' && skipsChain(b, bs, os)) return
    this.coreHit = false
    this.timeOfImpact(b, bs, other, os)
    const t = this.search[IMPACT]
    if (t < this.search[EARLIEST]) {
      this.search[EARLIEST] = t
      this.hitBody = other.type === DYNAMIC && other.awake ? other : null
      this.coreStop = this.coreHit && other.type === STATIC ? os : null
    }
  }

  /**
   * Sweeps one body against the broadphase candidates around its swept box and, for a bullet, also
   * against every body that moved farther than the fat-AABB margin (its proxy may not show where it
   * went). At the earliest impact the body, and a dynamic body it hit, are moved back to that time:
   * both keep their velocities, so the next step's speculative contact resolves the collision.
   */
  private sweepBody(
    b: Body,
    broadPhase: BroadPhase,
    shapes: Map<number, BodyShape>,
    canCollide: (a: BodyShape, b: BodyShape) => boolean,
  ): void {
    const r = b.maxExtent
    const minX = Math.min(b.c0x, b.cx) - r
    const minY = Math.min(b.c0y, b.cy) - r
    const maxX = Math.max(b.c0x, b.cx) + r
    const maxY = Math.max(b.c0y, b.cy) + r
    this.sweptBox[0] = minX
    this.sweptBox[1] = minY
    this.sweptBox[2] = maxX
    this.sweptBox[3] = maxY
    const n = broadPhase.queryBox(this.sweptBox, this.candidates)
    this.search[EARLIEST] = 1
    this.hitBody = null
    this.coreStop = null
    for (let k = 0; k < n; k++) {
      const other = shapes.get(this.candidates.ids[k])
      if (other !== undefined) this.sweepAgainst(b, other, canCollide)
    }
    if (b.bullet) {
      for (let k = 0; k < this.moverCount; k++) {
        const other = this.movers[k]
        const ro = other.maxExtent
        if (Math.min(other.c0x, other.cx) - ro > maxX || Math.max(other.c0x, other.cx) + ro < minX) continue
        if (Math.min(other.c0y, other.cy) - ro > maxY || Math.max(other.c0y, other.cy) + ro < minY) continue
        const otherShapes = other.shapes
        for (let j = 0; j < otherShapes.length; j++) this.sweepAgainst(b, otherShapes[j], canCollide)
      }
    }
    this.finishSweep(b)
  }

  /**
   * Moves a swept body, and a dynamic body it hit, back to the earliest impact found. After a core
   * hit on a static body, also removes the centre's velocity into that body (along the direction
   * from its nearest point to the centre): the contact failed to stop the centre (or the core would
   * not have been needed), so without this the body would press on, be held back again every step,
   * and finally slip through.
   *
   * One function, called after every sweep, hit or not: code that runs only on hits (about once in
   * a hundred steps of a server room) stays in V8's baseline tier, where every intermediate double
   * is a heap number (a few kilobytes per core stop), and sweepBody, whose inlining budget the
   * time-of-impact search uses up, calls it without inlining. Called every sweep, it is optimized
   * with its hit paths.
   */
  private finishSweep(b: Body): void {
    const minT = this.search[EARLIEST]
    if (minT >= 1) return
    sweep[FRACTION] = minT
    advanceTo(b)
    if (this.hitBody !== null) advanceTo(this.hitBody)
    const stop = this.coreStop
    if (stop === null) return
    sweep[FRACTION] = 1
    poseAt(stop.body)
    const n = transformVertices(stop.shape, verticesB)
    let nx = b.cx - verticesB[0]
    let ny = b.cy - verticesB[1]
    if (n > 1) {
      const px = b.cx
      const py = b.cy
      verticesA[0] = px
      verticesA[1] = py
      maxEdgeSeparation(verticesB, n, verticesA, 1)
      if (sweep[EDGE] <= 0) return
      // The point of the polygon's boundary nearest to the centre.
      let best = Number.POSITIVE_INFINITY
      for (let i = 0; i < n; i++) {
        const j = i + 1 === n ? 0 : i + 1
        const ax = verticesB[2 * i]
        const ay = verticesB[2 * i + 1]
        const ex = verticesB[2 * j] - ax
        const ey = verticesB[2 * j + 1] - ay
        const len2 = ex * ex + ey * ey
        let t = len2 > 0 ? ((px - ax) * ex + (py - ay) * ey) / len2 : 0
        t = Math.max(0, Math.min(1, t))
        const qx = ax + t * ex
        const qy = ay + t * ey
        const d = (px - qx) * (px - qx) + (py - qy) * (py - qy)
        if (d < best) {
          best = d
          nx = px - qx
          ny = py - qy
        }
      }
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
}
