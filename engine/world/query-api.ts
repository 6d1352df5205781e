/*
 * The world's queries: ray casts, a shape cast and overlap tests against the shapes in the world
 * (Box2D v3's b2World_CastRayClosest, b2World_CastRay, b2World_CastShape, b2World_OverlapAABB,
 * b2World_OverlapShape; overlapPoint is a shape overlap with a point). The exact work is
 * engine/queries' WorldQueries; this layer validates the arguments, hands WorldQueries a view of
 * the world (WorldQueryView), and turns the results into the public forms.
 *
 * The view: the broadphase tree has one leaf per shape whose user data is the shape id and whose
 * box is the fat AABB (grown by the margin and the motion prediction), so the tree only proposes
 * candidates; every candidate is then tested exactly, in its body's frame, against its geometry
 * (circle, capsule, polygon, rounded polygon, segment). A shape's geometry is adapted once to
 * the form the query routines read (QueryGeometry) and kept in a WeakMap keyed by the immutable
 * Shape object.
 *
 * Queries read the state and never write it: no revision bump, no proxy moved, no body woken; the
 * world's hash before and after is the same. Sensor shapes are never reported (a trigger zone does
 * not block a line of sight; Box2D v3.1's world queries, which test only the filter, do report
 * them). Results are ordered by fraction and then shape id (casts) or by shape id (overlaps), so
 * they do not depend on the tree's shape.
 *
 * Two forms per query: the plain one returns fresh objects (a RayHit, an array of them, an array
 * of ids); the `out`/`...Into` one writes into the caller's RayHit, RayHitList or IdBuffer and
 * allocates nothing once warm (measured in tests/engine/world-query-allocation.test.ts).
 */

import { type DynamicTree, IdBuffer, type Shape } from '../collision/index.ts'
import { MAX_POSITION } from '../constants.ts'
import { angle as checkAngle, position as checkPosition, finiteVec } from '../def-checks.ts'
import { cos, sin, TRIG_LIMIT, type Vec2 } from '../math.ts'
import {
  type AABB,
  DEFAULT_QUERY_FILTER,
  makeRayHit,
  makeShapeProxy,
  proxyOf,
  type QueryFilter,
  type QueryGeometry,
  type QueryWorld,
  type RayCastInput,
  type RayHit,
  RayHitList,
  type ShapeProxy,
  type Transform,
  WorldQueries,
} from '../queries/index.ts'
import type { ShapeId } from '../types.ts'
import { WorldApi } from './world-api.ts'
import type { WorldStore } from './world-store.ts'

/** Longest a query may move along each axis (m): 2,000,000, across the whole world (MAX_POSITION each way). */
export const MAX_QUERY_TRANSLATION = 2 * MAX_POSITION

/**
 * Where a query shape is: the position of its frame's origin (m) and its rotation, as an angle
 * (rad, default 0) or as the exact (cos, sin) pair `world.getRotation(body)` gives; give one.
 * The rotation form allocates nothing; an angle goes through the engine's cos and sin, which box a
 * number or two unless the angle equals the last query's.
 */
export interface QueryTransform {
  position: Vec2
  angle?: number
  rotation?: { c: number; s: number }
}

/** A query's collision bits (Box2D's b2QueryFilter); both default to Box2D's (category 1, all mask bits). */
export interface QueryFilterDef {
  categoryBits?: number
  maskBits?: number
}

/** What the queries read from a world: its tree, shapes and bodies (see the file comment). */
class WorldQueryView implements QueryWorld {
  readonly tree: DynamicTree
  private readonly store: WorldStore
  private readonly geometries = new WeakMap<Shape, QueryGeometry>()

  constructor(store: WorldStore) {
    this.store = store
    this.tree = store.broadPhase.shapeTree
  }

  leafShapeCount(): number {
    return 1
  }

  leafShape(leaf: number): number {
    return this.tree.body[leaf]
  }

  shapeGeometry(shape: number): QueryGeometry {
    return this.geometryOf(this.store.shapeMap.get(shape)!.shape)
  }

  shapeBody(shape: number): number {
    return this.store.shapeMap.get(shape)!.body.id
  }

  shapeFilter(shape: number): QueryFilter {
    return this.store.shapeMap.get(shape)!
  }

  isSensor(shape: number): boolean {
    return this.store.shapeMap.get(shape)!.sensor
  }

  bodyTransform(body: number, out: Transform): void {
    const b = this.store.bodyMap.get(body)!
    out.x = b.x
    out.y = b.y
    out.c = b.c
    out.s = b.s
  }

  /** The QueryGeometry of a shape (made once per Shape object). */
  geometryOf(shape: Shape): QueryGeometry {
    let g = this.geometries.get(shape)
    if (g === undefined) {
      g = toQueryGeometry(shape)
      this.geometries.set(shape, g)
    }
    return g
  }
}

/**
 * A shape as the query routines read it. Every geometry is made by one object literal with every
 * field (the unused ones empty), its radius a double and its points copied into double-field
 * objects, so all of them share one hidden class and the casts' loads stay monomorphic: with a
 * circle's and a segment's own shapes of object, the load of `radius` after the kind switch was
 * polymorphic, and a polymorphic load of a double allocates (measured: 16 bytes per circle cast
 * in a world of circles and segments; the same rule as engine/collision/shapes.ts).
 */
function toQueryGeometry(shape: Shape): QueryGeometry {
  const vs = shape.vertices
  switch (shape.type) {
    case 'circle':
      return geometry('circle', shape.radius, 0, NO_POINTS, NO_POINTS, point(shape.centroid), ORIGIN, ORIGIN)
    case 'capsule':
      return geometry('capsule', shape.radius, 2, NO_POINTS, NO_POINTS, ORIGIN, point(vs[0]), point(vs[1]))
    case 'polygon':
      return geometry(
        'polygon',
        shape.radius,
        shape.count,
        vs.map(point),
        shape.normals.map(point),
        ORIGIN,
        ORIGIN,
        ORIGIN,
      )
    case 'segment':
      return geometry('segment', 0, 2, NO_POINTS, NO_POINTS, ORIGIN, point(vs[0]), point(vs[1]))
    case 'chainSegment':
      // One-sided: a ray from behind passes through (rayCastChainSegment); overlaps and shape casts
      // treat it as its two-sided segment, as Box2D's b2MakeProxy of a chain segment does.
      return geometry(
        'chainSegment',
        0,
        2,
        NO_POINTS,
        NO_POINTS,
        ORIGIN,
        point(vs[0]),
        point(vs[1]),
        shape.ghost1,
        shape.ghost2,
      )
  }
  throw new RangeError(`the queries do not know shape kind ${String((shape as { type?: unknown }).type)}`)
}

const NO_POINTS: readonly Vec2[] = Object.freeze([])
const ORIGIN: Vec2 = point({ x: 0, y: 0 })

/** The one literal every query geometry is made by (a segment's points are center1 and center2 as well). */
function geometry(
  type: QueryGeometry['type'],
  radius: number,
  count: number,
  vertices: readonly Vec2[],
  normals: readonly Vec2[],
  center: Vec2,
  a: Vec2,
  b: Vec2,
  ghost1: Vec2 = ORIGIN,
  ghost2: Vec2 = ORIGIN,
): QueryGeometry {
  const g = {
    type,
    radius: 0.5,
    count,
    vertices,
    normals,
    center,
    center1: a,
    center2: b,
    point1: a,
    point2: b,
    ghost1: point(ghost1),
    segment: { point1: a, point2: b },
    ghost2: point(ghost2),
  }
  g.radius = radius
  return g as QueryGeometry
}

/** A copy of p in an object whose fields V8 keeps as doubles. */
function point(p: Vec2): Vec2 {
  const q = { x: 0.5, y: 0.5 }
  q.x = p.x
  q.y = p.y
  return q
}

const SHAPE_KINDS: readonly string[] = ['circle', 'polygon', 'capsule', 'segment']

/** The world's query methods (World extends this). */
export class QueryApi extends WorldApi {
  private readonly queries = new WorldQueries()
  private readonly view = new WorldQueryView(this)
  private readonly ray: RayCastInput = { origin: { x: 0, y: 0 }, translation: { x: 0, y: 0 }, maxFraction: 1 }
  private readonly filter: { categoryBits: number; maskBits: number } = { categoryBits: 1, maskBits: 0 }
  private readonly hitList = new RayHitList()
  private readonly idList = new IdBuffer()
  private readonly proxy: ShapeProxy = makeShapeProxy()
  private readonly transform: Transform = { x: 0, y: 0, c: 1, s: 0 }
  private readonly move: Vec2 = { x: 0, y: 0 }
  private readonly box: AABB = { minX: 0, minY: 0, maxX: 0, maxY: 0 }
  /** The last query angle (rad) and its cosine and sine. */
  private readonly lastAngle = Float64Array.of(0, 1, 0)

  /**
   * The closest shape the ray from `origin` along `translation` (m) hits, as { shape, body, point,
   * normal, fraction } (world frame; point = origin + fraction * translation), or null. A ray that
   * starts inside a shape hits it at fraction 0 with a zero normal. Equal fractions go to the
   * lower shape id. With `out`, the hit is written there and nothing is allocated.
   */
  castRayClosest(origin: Vec2, translation: Vec2, filter?: QueryFilterDef, out?: RayHit): RayHit | null {
    const ray = this.setRay(origin, translation)
    return this.queries.castRayClosest(this.view, ray, this.queryFilter(filter), out ?? makeRayHit())
  }

  /** Every shape the ray hits, sorted by fraction and then shape id (fresh objects). */
  castRay(origin: Vec2, translation: Vec2, filter?: QueryFilterDef): RayHit[] {
    const n = this.castRayInto(origin, translation, filter, this.hitList)
    const hits: RayHit[] = []
    for (let i = 0; i < n; i++) {
      const h = this.hitList.hits[i]
      hits.push({
        shape: h.shape,
        body: h.body,
        point: { x: h.point.x, y: h.point.y },
        normal: { x: h.normal.x, y: h.normal.y },
        fraction: h.fraction,
      })
    }
    return hits
  }

  /** castRay into `out` (out.hits[0..count), reused): returns the count; allocates nothing once warm. */
  castRayInto(origin: Vec2, translation: Vec2, filter: QueryFilterDef | undefined, out: RayHitList): number {
    const ray = this.setRay(origin, translation)
    return this.queries.castRay(this.view, ray, this.queryFilter(filter), out)
  }

  /**
   * The closest shape that `shape` (made by circle(), box(), polygon(), capsule() or segment()),
   * placed at `transform` and moved by `translation` (m, without turning), touches: { shape, body,
   * point (on the hit shape's surface), normal (its outward normal there), fraction }, or null.
   * Shapes touching or overlapping it at the start hit at fraction 0 with a zero normal. With
   * `out`, nothing is allocated.
   */
  castShape(
    shape: Shape,
    transform: QueryTransform,
    translation: Vec2,
    filter?: QueryFilterDef,
    out?: RayHit,
  ): RayHit | null {
    const proxy = this.setShape('castShape', shape, transform)
    const move = this.setTranslation('castShape translation', translation)
    const f = this.queryFilter(filter)
    return this.queries.castShape(this.view, proxy, this.transform, move, f, out ?? makeRayHit())
  }

  /** Shapes whose tight world box overlaps `aabb` (m; touching counts), ascending ids (a fresh array). */
  overlapAABB(aabb: AABB, filter?: QueryFilterDef): ShapeId[] {
    return this.idArray(this.overlapAABBInto(aabb, filter, this.idList))
  }

  /** overlapAABB into `out` (out.ids[0..count)): returns the count; allocates nothing once warm. */
  overlapAABBInto(aabb: AABB, filter: QueryFilterDef | undefined, out: IdBuffer): number {
    if (aabb === null || typeof aabb !== 'object')
      throw new RangeError(`overlapAABB needs an AABB, got ${aabb}`)
    const box = this.box
    box.minX = aabb.minX
    box.minY = aabb.minY
    box.maxX = aabb.maxX
    box.maxY = aabb.maxY
    if (
      !(Number.isFinite(box.minX) && Number.isFinite(box.minY)) ||
      !(Number.isFinite(box.maxX) && Number.isFinite(box.maxY)) ||
      !(box.minX <= box.maxX && box.minY <= box.maxY)
    ) {
      throw new RangeError(
        `overlapAABB needs finite minX <= maxX and minY <= maxY, got ${JSON.stringify(aabb)}`,
      )
    }
    return this.queries.overlapAABB(this.view, box, this.queryFilter(filter), out)
  }

  /** Shapes that contain `point` (m; the boundary counts), ascending ids (a fresh array). */
  overlapPoint(point: Vec2, filter?: QueryFilterDef): ShapeId[] {
    return this.idArray(this.overlapPointInto(point, filter, this.idList))
  }

  /** overlapPoint into `out`: returns the count; allocates nothing once warm. */
  overlapPointInto(point: Vec2, filter: QueryFilterDef | undefined, out: IdBuffer): number {
    finiteVec('overlapPoint point', point)
    return this.queries.overlapPoint(this.view, point, this.queryFilter(filter), out)
  }

  /** Shapes that touch or overlap `shape` placed at `transform`, ascending ids (a fresh array). */
  overlapShape(shape: Shape, transform: QueryTransform, filter?: QueryFilterDef): ShapeId[] {
    return this.idArray(this.overlapShapeInto(shape, transform, filter, this.idList))
  }

  /** overlapShape into `out`: returns the count; allocates nothing once warm. */
  overlapShapeInto(
    shape: Shape,
    transform: QueryTransform,
    filter: QueryFilterDef | undefined,
    out: IdBuffer,
  ): number {
    const proxy = this.setShape('overlapShape', shape, transform)
    return this.queries.overlapShape(this.view, proxy, this.transform, this.queryFilter(filter), out)
  }

  /** Validates a ray into this.ray: origin within MAX_POSITION, translation within MAX_QUERY_TRANSLATION per axis. */
  private setRay(origin: Vec2, translation: Vec2): RayCastInput {
    checkPosition('ray origin', origin)
    const ray = this.ray
    ray.origin.x = origin.x
    ray.origin.y = origin.y
    const t = this.setTranslation('ray translation', translation)
    ray.translation.x = t.x
    ray.translation.y = t.y
    ray.maxFraction = 1
    return ray
  }

  /** Validates a translation into this.move. */
  private setTranslation(what: string, v: Vec2): Vec2 {
    finiteVec(what, v)
    if (Math.abs(v.x) > MAX_QUERY_TRANSLATION || Math.abs(v.y) > MAX_QUERY_TRANSLATION) {
      throw new RangeError(
        `${what} must be within ${MAX_QUERY_TRANSLATION} m on each axis, got (${v.x}, ${v.y})`,
      )
    }
    this.move.x = v.x
    this.move.y = v.y
    return this.move
  }

  /** Validates a query shape and its transform into this.proxy and this.transform. */
  private setShape(what: string, shape: Shape, transform: QueryTransform): ShapeProxy {
    if (shape === null || typeof shape !== 'object' || !SHAPE_KINDS.includes(shape.type)) {
      throw new RangeError(
        `${what} shape must be made by circle(), box(), polygon(), capsule() or segment(), got ${String(shape?.type ?? shape)}`,
      )
    }
    if (transform === null || typeof transform !== 'object') {
      throw new RangeError(
        `${what} transform must be { position, angle } or { position, rotation }, got ${transform}`,
      )
    }
    // The name is built only for the error (a template string per call would allocate).
    const p = transform.position
    if (
      p === null ||
      typeof p !== 'object' ||
      !(Math.abs(p.x) <= MAX_POSITION && Math.abs(p.y) <= MAX_POSITION)
    )
      checkPosition(`${what} position`, p)
    const xf = this.transform
    xf.x = transform.position.x
    xf.y = transform.position.y
    const r = transform.rotation
    if (r !== undefined) {
      if (transform.angle !== undefined)
        throw new RangeError(`${what} transform gives both angle and rotation; give one`)
      if (r === null || typeof r !== 'object' || !(Math.abs(r.c * r.c + r.s * r.s - 1) <= 1e-9)) {
        throw new RangeError(
          `${what} rotation must be a unit (c, s) pair (c^2 + s^2 within 1e-9 of 1), got ${JSON.stringify(r)}`,
        )
      }
      xf.c = r.c
      xf.s = r.s
    } else {
      // The angle is compared, not passed: a double argument of a call V8 does not inline is boxed.
      const a = transform.angle ?? 0
      if (!(a > -TRIG_LIMIT && a < TRIG_LIMIT)) checkAngle(`${what} angle`, a)
      if (a !== this.lastAngle[0]) {
        this.lastAngle[0] = a
        this.lastAngle[1] = cos(a)
        this.lastAngle[2] = sin(a)
      }
      xf.c = this.lastAngle[1]
      xf.s = this.lastAngle[2]
    }
    return proxyOf(this.view.geometryOf(shape), this.proxy)
  }

  /** The query filter (validated) into this.filter; Box2D's default when none is given. */
  private queryFilter(f: QueryFilterDef | undefined): QueryFilter {
    if (f === undefined) return DEFAULT_QUERY_FILTER
    if (f === null || typeof f !== 'object') throw new RangeError(`query filter must be an object, got ${f}`)
    const category = f.categoryBits ?? DEFAULT_QUERY_FILTER.categoryBits
    const mask = f.maskBits ?? DEFAULT_QUERY_FILTER.maskBits
    if (!Number.isInteger(category) || category < 0 || category > 0xffffffff)
      throw new RangeError(`query filter categoryBits must be an integer in [0, 2^32), got ${category}`)
    if (!Number.isInteger(mask) || mask < 0 || mask > 0xffffffff)
      throw new RangeError(`query filter maskBits must be an integer in [0, 2^32), got ${mask}`)
    this.filter.categoryBits = category
    this.filter.maskBits = mask
    return this.filter
  }

  /** The first `count` ids of this.idList as a fresh array. */
  private idArray(count: number): ShapeId[] {
    const ids: ShapeId[] = []
    for (let i = 0; i < count; i++) ids.push(this.idList.ids[i])
    return ids
  }
}
