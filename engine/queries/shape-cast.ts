/*
 * A shape cast: shape B moves by translationB (no rotation) against shape A; where does it first
 * touch? Conservative advancement on the GJK distance (Box2D v3's b2ShapeCast, distance.c).
 *
 * With d(t) the distance between the cores (radius-free shapes) after B has moved t of its
 * translation, each step moves B to where the current closest-points normal n says the cores
 * reach the target distance: t += (target - d) / dot(translation, n). For convex shapes d(t) is a
 * convex function of t, so this Newton step never passes the root and converges to it (in one
 * step when a face meets a vertex, quadratically when curved parts meet). A step along which the
 * shapes do not approach (dot >= 0) is a miss.
 *
 * Box2D stops a linear slop short of touching (target = max(slop, radii - slop)). Here the target
 * is the touch itself, radiusA + radiusB, so the fraction is exact to CAST_TOLERANCE. Two sharp
 * shapes (radii summing to less than a slop) cannot be iterated to a core distance of zero, where
 * GJK has no normal; they are advanced to a slop apart and then moved the remaining distance along
 * the normal found there (exact for a vertex meeting a face, the generic case), and the contact
 * point is read from one more distance query with B pulled back by that slop along the normal.
 *
 * Start-inside rule (Box2D v3.1): shapes that touch or overlap at the start hit at fraction 0
 * with a zero normal and the point midway between the two closest surface points.
 *
 * Allocation: none per call (the caller's output; scratch transform and distance output here).
 */
import { LINEAR_SLOP } from '../constants.ts'
import type { Vec2 } from '../math.ts'
import type { CastOutput } from './ray-cast.ts'
import { makeDistanceOutput, type ShapeProxy, shapeDistance, type Transform } from './shape-distance.ts'

/** The cast stops when the shapes are within this distance of touching (m): 1e-9. */
export const CAST_TOLERANCE = 1e-9
/** Most distance queries a cast makes before it gives up and reports a miss: 50 (Box2D: 20). */
export const CAST_MAX_ITERATIONS = 50

/** Box2D's b2ShapeCastPairInput: A fixed, B moving by translationB (m) over [0, maxFraction]. */
export interface ShapeCastPairInput {
  proxyA: ShapeProxy
  transformA: Transform
  proxyB: ShapeProxy
  transformB: Transform
  translationB: Vec2
  /** Largest fraction of the translation to move, usually 1. */
  maxFraction: number
}

const moved: Transform = { x: 0, y: 0, c: 1, s: 0 }
const distance = makeDistanceOutput()

function finite(x: number): boolean {
  return Number.isFinite(x)
}

/** Throws a RangeError naming the first bad field of a shape cast input. */
export function checkShapeCastInput(input: ShapeCastPairInput): void {
  checkProxy('proxyA', input.proxyA)
  checkProxy('proxyB', input.proxyB)
  checkTransform('transformA', input.transformA)
  checkTransform('transformB', input.transformB)
  const t = input.translationB
  if (!t || !finite(t.x) || !finite(t.y)) {
    throw new RangeError(`shape cast translationB must be a finite vector, got ${JSON.stringify(t)}`)
  }
  if (!(input.maxFraction >= 0 && input.maxFraction < Number.POSITIVE_INFINITY)) {
    throw new RangeError(`shape cast maxFraction must be a finite number >= 0, got ${input.maxFraction}`)
  }
}

function checkProxy(name: string, proxy: ShapeProxy): void {
  const capacity = proxy.points.length >> 1
  if (!(proxy.count >= 1 && proxy.count <= capacity && Number.isInteger(proxy.count))) {
    throw new RangeError(`shape cast ${name} must have 1 to ${capacity} points, got ${proxy.count}`)
  }
  if (!(proxy.radius >= 0 && finite(proxy.radius))) {
    throw new RangeError(`shape cast ${name} radius must be a finite number >= 0, got ${proxy.radius}`)
  }
  for (let i = 0; i < 2 * proxy.count; i++) {
    if (!finite(proxy.points[i])) throw new RangeError(`shape cast ${name} point ${i >> 1} is not finite`)
  }
}

function checkTransform(name: string, xf: Transform): void {
  if (!(finite(xf.x) && finite(xf.y) && finite(xf.c) && finite(xf.s))) {
    throw new RangeError(`shape cast ${name} must be finite, got ${JSON.stringify(xf)}`)
  }
}

/**
 * Where B, moving by translationB from transformB, first touches A: fills `out` (fraction of the
 * translation, the contact point on A's surface, A's outward unit normal there) and returns it,
 * or null when B does not touch A within maxFraction. Shapes touching or overlapping at the start
 * hit at fraction 0 with a zero normal.
 */
export function shapeCast(input: ShapeCastPairInput, out: CastOutput): CastOutput | null {
  checkShapeCastInput(input)
  const proxyA = input.proxyA
  const proxyB = input.proxyB
  const xfA = input.transformA
  const xfB = input.transformB
  const dx = input.translationB.x
  const dy = input.translationB.y
  const radiusA = proxyA.radius
  const radiusB = proxyB.radius
  const totalRadius = radiusA + radiusB
  const target = Math.max(totalRadius, LINEAR_SLOP)
  moved.x = xfB.x
  moved.y = xfB.y
  moved.c = xfB.c
  moved.s = xfB.s
  let fraction = 0
  for (let iteration = 0; iteration < CAST_MAX_ITERATIONS; iteration++) {
    shapeDistance(proxyA, xfA, proxyB, moved, false, distance)
    const d = distance.distance
    const nx = distance.normal.x
    const ny = distance.normal.y
    if (iteration === 0 && d < totalRadius + CAST_TOLERANCE) {
      // Initial overlap: the point midway between the surfaces.
      out.fraction = 0
      out.point.x = 0.5 * (distance.pointA.x + radiusA * nx + distance.pointB.x - radiusB * nx)
      out.point.y = 0.5 * (distance.pointA.y + radiusA * ny + distance.pointB.y - radiusB * ny)
      out.normal.x = 0
      out.normal.y = 0
      return out
    }
    const approach = dx * nx + dy * ny
    if (d < target + CAST_TOLERANCE) {
      if (target === totalRadius) {
        out.fraction = fraction
        out.point.x = distance.pointA.x + radiusA * nx
        out.point.y = distance.pointA.y + radiusA * ny
        out.normal.x = nx
        out.normal.y = ny
        return out
      }
      // Sharp shapes a slop apart: the rest of the way along this normal.
      if (!(approach < 0)) return null
      fraction += (d - totalRadius) / -approach
      if (fraction > input.maxFraction) return null
      const skin = target - totalRadius
      moved.x = xfB.x + fraction * dx + skin * nx
      moved.y = xfB.y + fraction * dy + skin * ny
      shapeDistance(proxyA, xfA, proxyB, moved, false, distance)
      out.fraction = fraction
      out.normal.x = distance.normal.x
      out.normal.y = distance.normal.y
      out.point.x = distance.pointA.x + radiusA * distance.normal.x
      out.point.y = distance.pointA.y + radiusA * distance.normal.y
      return out
    }
    if (!(approach < 0)) return null // not approaching: a miss
    fraction += (target - d) / approach
    if (fraction > input.maxFraction) return null
    moved.x = xfB.x + fraction * dx
    moved.y = xfB.y + fraction * dy
  }
  return null
}
