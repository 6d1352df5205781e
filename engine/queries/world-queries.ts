/*
 * The world's queries (ray casts, shape casts, overlap tests) over the broadphase tree, as
 * functions of the world's data rather than of the World class, so that they can be wired into
 * world.castRayClosest / castRay / castShape / overlapAABB / overlapPoint / overlapShape without this
 * file knowing how the world stores its shapes (Box2D v3: b2World_CastRay, b2World_CastShape,
 * b2World_OverlapAABB, b2World_OverlapShape in world.c).
 *
 * The world hands in a QueryWorld: its tree (one leaf per shape, as in Box2D, or any number of
 * shapes per leaf), each shape's geometry in its body's frame, body, filter and sensor flag, and
 * each body's transform. A query walks the tree (TreeRayCast for casts, DynamicTree.queryLeaves
 * for overlaps), skips sensors and shapes the query filter rejects, and runs the exact test of
 * ray-cast.ts, shape-cast.ts or shape-distance.ts in the shape's own frame.
 *
 * Determinism: results depend only on the world's data and the query. Equal fractions are broken by
 * the lower shape id, and overlap results come sorted by shape id, so the answer does not depend on
 * the tree's shape either. Nothing runs user code. A WorldQueries object holds the scratch; once
 * warm, no query allocates (results go into the caller's RayHit, RayHitList or IdBuffer).
 */
import { type DynamicTree, type IdBuffer, NULL_NODE, sortKeys } from '../collision/index.ts'
import type { Vec2 } from '../math.ts'
import {
  type CapsuleGeometry,
  type CastOutput,
  type ChainSegmentGeometry,
  type CircleGeometry,
  checkRayInput,
  makeCastOutput,
  type PolygonGeometry,
  type RayCastInput,
  rayCastCapsule,
  rayCastChainSegment,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
  type SegmentGeometry,
} from './ray-cast.ts'
import { checkShapeCastInput, type ShapeCastPairInput, shapeCast } from './shape-cast.ts'
import {
  capsuleProxy,
  circleProxy,
  makeDistanceOutput,
  makeShapeProxy,
  polygonProxy,
  type ShapeProxy,
  segmentProxy,
  shapeDistance,
  type Transform,
} from './shape-distance.ts'
import { TreeRayCast } from './tree-ray-cast.ts'

/** A shape's geometry in its body's frame, tagged by kind. */
export type QueryGeometry =
  | ({ readonly type: 'circle' } & CircleGeometry)
  | ({ readonly type: 'capsule' } & CapsuleGeometry)
  | ({ readonly type: 'polygon' } & PolygonGeometry)
  | ({ readonly type: 'segment' } & SegmentGeometry)
  | ({ readonly type: 'chainSegment' } & ChainSegmentGeometry)

/** Collision bits of a shape or a query (32-bit). */
export interface QueryFilter {
  readonly categoryBits: number
  readonly maskBits: number
}

/** Box2D's b2DefaultQueryFilter: category 1, every mask bit. */
export const DEFAULT_QUERY_FILTER: QueryFilter = Object.freeze({ categoryBits: 1, maskBits: 0xffffffff })

/** Box2D's rule for queries: the shape is in the query's mask and the query in the shape's. */
export function shouldQueryShape(shape: QueryFilter, query: QueryFilter): boolean {
  return (shape.categoryBits & query.maskBits) !== 0 && (shape.maskBits & query.categoryBits) !== 0
}

/** What the queries need from a world. */
export interface QueryWorld {
  /** The broadphase tree (fat AABBs of the shapes, world frame). */
  readonly tree: DynamicTree
  /** How many shapes leaf `leaf` holds (1 when the tree has one leaf per shape). */
  leafShapeCount(leaf: number): number
  /** Shape id number i of leaf `leaf`. */
  leafShape(leaf: number, i: number): number
  shapeGeometry(shape: number): QueryGeometry
  shapeBody(shape: number): number
  shapeFilter(shape: number): QueryFilter
  isSensor(shape: number): boolean
  /** Writes the body's transform (position, cos, sin) into `out`. */
  bodyTransform(body: number, out: Transform): void
}

/** A query hit: the shape and body, the point (m, world), the shape's unit normal there, and the fraction. */
export interface RayHit {
  shape: number
  body: number
  point: Vec2
  normal: Vec2
  fraction: number
}

/** A fresh hit to reuse. */
export function makeRayHit(): RayHit {
  return { shape: 0, body: 0, point: { x: 0, y: 0 }, normal: { x: 0, y: 0 }, fraction: 0 }
}

/** Hits of castRay: the first `count` of `hits`, sorted by fraction, then shape id. */
export class RayHitList {
  hits: RayHit[] = []
  count = 0
}

/** An axis-aligned box (m, world). */
export interface AABB {
  minX: number
  minY: number
  maxX: number
  maxY: number
}

/** The queries, with their scratch. One per world (or per caller); not re-entrant. */
export class WorldQueries {
  private readonly cursor = new TreeRayCast()
  private readonly local: RayCastInput = {
    origin: { x: 0, y: 0 },
    translation: { x: 0, y: 0 },
    maxFraction: 1,
  }
  private readonly castOut: CastOutput = makeCastOutput()
  private readonly xf: Transform = { x: 0, y: 0, c: 1, s: 0 }
  private readonly proxy: ShapeProxy = makeShapeProxy()
  private readonly distance = makeDistanceOutput()
  private readonly pair: ShapeCastPairInput
  private readonly extension: Vec2 = { x: 0, y: 0 }
  private readonly center: RayCastInput = {
    origin: { x: 0, y: 0 },
    translation: { x: 0, y: 0 },
    maxFraction: 1,
  }
  private readonly box = new Float64Array(4)
  private readonly candidate: RayHit = makeRayHit()
  private keys = new Float64Array(64)
  private readonly sortStack = new Int32Array(128)

  constructor() {
    this.pair = {
      proxyA: this.proxy,
      transformA: this.xf,
      proxyB: this.proxy,
      transformB: this.xf,
      translationB: { x: 0, y: 0 },
      maxFraction: 1,
    }
  }

  /**
   * The closest shape the ray (origin, translation, maxFraction) hits, into `out`; null if none.
   * A ray starting inside a shape hits it at fraction 0 (zero normal). Ties: lower shape id.
   */
  castRayClosest(world: QueryWorld, input: RayCastInput, filter: QueryFilter, out: RayHit): RayHit | null {
    checkRayInput(input)
    const cursor = this.cursor
    const hit = this.candidate
    let found = false
    cursor.begin(world.tree, input)
    for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
      const n = world.leafShapeCount(leaf)
      for (let i = 0; i < n; i++) {
        const shape = world.leafShape(leaf, i)
        if (!this.castRayAtShape(world, shape, input, filter, true, hit)) continue
        if (found && (hit.fraction > out.fraction || (hit.fraction === out.fraction && shape > out.shape)))
          continue
        copyHit(hit, out)
        found = true
        cursor.clip(out)
      }
    }
    return found ? out : null
  }

  /** Every shape the ray hits, into `out` sorted by fraction (then shape id); returns how many. */
  castRay(world: QueryWorld, input: RayCastInput, filter: QueryFilter, out: RayHitList): number {
    checkRayInput(input)
    const cursor = this.cursor
    out.count = 0
    cursor.begin(world.tree, input)
    for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
      const n = world.leafShapeCount(leaf)
      for (let i = 0; i < n; i++) {
        const shape = world.leafShape(leaf, i)
        if (out.count === out.hits.length) out.hits.push(makeRayHit())
        if (this.castRayAtShape(world, shape, input, filter, false, out.hits[out.count])) out.count++
      }
    }
    // Insertion sort by (fraction, shape): few hits per ray; object swaps allocate nothing.
    const hits = out.hits
    for (let i = 1; i < out.count; i++) {
      const h = hits[i]
      let j = i - 1
      while (
        j >= 0 &&
        (hits[j].fraction > h.fraction || (hits[j].fraction === h.fraction && hits[j].shape > h.shape))
      ) {
        hits[j + 1] = hits[j]
        j--
      }
      hits[j + 1] = h
    }
    return out.count
  }

  /**
   * The closest shape that `proxy` at `transform`, moving by `translation` (m, no rotation), touches,
   * into `out` (fraction, point on the hit shape's surface, its outward normal); null if none.
   * Shapes touching or overlapping at the start hit at fraction 0 with a zero normal.
   */
  castShape(
    world: QueryWorld,
    proxy: ShapeProxy,
    transform: Transform,
    translation: Vec2,
    filter: QueryFilter,
    out: RayHit,
  ): RayHit | null {
    const pair = this.pair
    pair.proxyA = proxy
    pair.transformA = transform
    pair.proxyB = proxy
    pair.transformB = transform
    pair.translationB = translation
    pair.maxFraction = 1
    checkShapeCastInput(pair)
    // The cast shape's world box: the walk is a box of its half extents sweeping along the translation.
    proxyBox(proxy, transform, this.box)
    const b = this.box
    const sweep = this.center
    sweep.origin.x = 0.5 * (b[0] + b[2])
    sweep.origin.y = 0.5 * (b[1] + b[3])
    sweep.translation.x = translation.x
    sweep.translation.y = translation.y
    sweep.maxFraction = 1
    this.extension.x = 0.5 * (b[2] - b[0])
    this.extension.y = 0.5 * (b[3] - b[1])
    pair.proxyA = this.proxy
    pair.transformA = this.xf
    const cursor = this.cursor
    let found = false
    cursor.begin(world.tree, sweep, this.extension)
    for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
      const n = world.leafShapeCount(leaf)
      for (let i = 0; i < n; i++) {
        const shape = world.leafShape(leaf, i)
        if (world.isSensor(shape) || !shouldQueryShape(world.shapeFilter(shape), filter)) continue
        const body = world.shapeBody(shape)
        world.bodyTransform(body, this.xf)
        proxyOf(world.shapeGeometry(shape), this.proxy)
        pair.maxFraction = cursor.maxFraction
        const hit = shapeCast(pair, this.castOut)
        if (hit === null) continue
        if (found && (hit.fraction > out.fraction || (hit.fraction === out.fraction && shape > out.shape)))
          continue
        out.shape = shape
        out.body = body
        out.fraction = hit.fraction
        out.point.x = hit.point.x
        out.point.y = hit.point.y
        out.normal.x = hit.normal.x
        out.normal.y = hit.normal.y
        found = true
        cursor.clip(out)
      }
    }
    return found ? out : null
  }

  /** Shapes whose bounding box (tight, world) overlaps `aabb` (touching counts), sorted by id, into `out`. */
  overlapAABB(world: QueryWorld, aabb: AABB, filter: QueryFilter, out: IdBuffer): number {
    if (!(aabb.minX <= aabb.maxX && aabb.minY <= aabb.maxY)) {
      throw new RangeError(
        `overlapAABB needs minX <= maxX and minY <= maxY (finite), got ${JSON.stringify(aabb)}`,
      )
    }
    const box = this.box
    box[0] = aabb.minX
    box[1] = aabb.minY
    box[2] = aabb.maxX
    box[3] = aabb.maxY
    return this.collect(world, filter, out, OVERLAP_AABB)
  }

  /** Shapes that contain `point` (m, world; the boundary counts), sorted by id, into `out`. */
  overlapPoint(world: QueryWorld, point: Vec2, filter: QueryFilter, out: IdBuffer): number {
    if (!(Number.isFinite(point.x) && Number.isFinite(point.y))) {
      throw new RangeError(`overlapPoint needs a finite point, got ${JSON.stringify(point)}`)
    }
    const box = this.box
    box[0] = point.x
    box[1] = point.y
    box[2] = point.x
    box[3] = point.y
    this.proxy.points[0] = point.x
    this.proxy.points[1] = point.y
    this.proxy.count = 1
    this.proxy.radius = 0
    this.pair.proxyB = this.proxy
    return this.collect(world, filter, out, OVERLAP_POINT)
  }

  /** Shapes that touch or overlap `proxy` at `transform`, sorted by id, into `out`. */
  overlapShape(
    world: QueryWorld,
    proxy: ShapeProxy,
    transform: Transform,
    filter: QueryFilter,
    out: IdBuffer,
  ): number {
    const pair = this.pair
    pair.proxyA = proxy
    pair.transformA = transform
    pair.proxyB = proxy
    pair.transformB = transform
    pair.translationB = ZERO
    pair.maxFraction = 0
    checkShapeCastInput(pair)
    proxyBox(proxy, transform, this.box)
    return this.collect(world, filter, out, OVERLAP_SHAPE)
  }

  /** Candidates from the tree for this.box, the exact test of `kind`, ids sorted into `out`. */
  private collect(world: QueryWorld, filter: QueryFilter, out: IdBuffer, kind: number): number {
    const tree = world.tree
    const leaves = tree.queryLeaves(this.box, 0)
    let count = 0
    for (let k = 0; k < leaves; k++) {
      const leaf = tree.hits[k]
      const n = world.leafShapeCount(leaf)
      for (let i = 0; i < n; i++) {
        const shape = world.leafShape(leaf, i)
        if (world.isSensor(shape) || !shouldQueryShape(world.shapeFilter(shape), filter)) continue
        world.bodyTransform(world.shapeBody(shape), this.xf)
        if (!this.overlaps(world.shapeGeometry(shape), kind)) continue
        if (count === this.keys.length) {
          const keys = new Float64Array(2 * count)
          keys.set(this.keys)
          this.keys = keys
        }
        this.keys[count++] = shape
      }
    }
    sortKeys(this.keys, count, this.sortStack)
    out.count = 0
    out.reserve(count)
    for (let i = 0; i < count; i++) out.ids[i] = this.keys[i]
    out.count = count
    return count
  }

  /** The exact test of an overlap query against one shape at this.xf. */
  private overlaps(geometry: QueryGeometry, kind: number): boolean {
    if (kind === OVERLAP_AABB) {
      const shapeBox = this.shapeBoxScratch
      geometryBox(geometry, this.xf, this.proxy, shapeBox)
      const b = this.box
      return !(shapeBox[0] > b[2] || shapeBox[1] > b[3] || b[0] > shapeBox[2] || b[1] > shapeBox[3])
    }
    // Point or shape: GJK distance between the cores against the sum of the radii.
    const query = this.pair.proxyB
    const target = proxyOf(geometry, this.shapeProxy).radius + query.radius
    if (kind === OVERLAP_POINT) {
      this.pointXf.x = 0
      this.pointXf.y = 0
      shapeDistance(this.shapeProxy, this.xf, query, this.pointXf, false, this.distance)
    } else {
      shapeDistance(this.shapeProxy, this.xf, query, this.pair.transformB, false, this.distance)
    }
    return this.distance.distance <= target
  }

  private readonly shapeBoxScratch = new Float64Array(4)
  private readonly shapeProxy: ShapeProxy = makeShapeProxy()
  private readonly pointXf: Transform = { x: 0, y: 0, c: 1, s: 0 }

  /**
   * Ray against one shape (filter, sensor, then the exact cast in the shape's frame); fills `hit`
   * in world space. `clipped`: cast only as far as the cursor's current maxFraction (closest hit).
   */
  private castRayAtShape(
    world: QueryWorld,
    shape: number,
    input: RayCastInput,
    filter: QueryFilter,
    clipped: boolean,
    hit: RayHit,
  ): boolean {
    if (world.isSensor(shape) || !shouldQueryShape(world.shapeFilter(shape), filter)) return false
    const body = world.shapeBody(shape)
    const xf = this.xf
    world.bodyTransform(body, xf)
    // The ray in the body's frame: R^T (origin - p), R^T translation.
    const local = this.local
    const ox = input.origin.x - xf.x
    const oy = input.origin.y - xf.y
    local.origin.x = xf.c * ox + xf.s * oy
    local.origin.y = xf.c * oy - xf.s * ox
    local.translation.x = xf.c * input.translation.x + xf.s * input.translation.y
    local.translation.y = xf.c * input.translation.y - xf.s * input.translation.x
    local.maxFraction = clipped ? this.cursor.maxFraction : input.maxFraction
    const result = castGeometry(world.shapeGeometry(shape), local, this.castOut)
    if (result === null) return false
    hit.shape = shape
    hit.body = body
    hit.fraction = result.fraction
    hit.point.x = xf.x + xf.c * result.point.x - xf.s * result.point.y
    hit.point.y = xf.y + xf.s * result.point.x + xf.c * result.point.y
    hit.normal.x = xf.c * result.normal.x - xf.s * result.normal.y
    hit.normal.y = xf.s * result.normal.x + xf.c * result.normal.y
    return true
  }
}

const OVERLAP_AABB = 0
const ZERO: Vec2 = Object.freeze({ x: 0, y: 0 })
const OVERLAP_POINT = 1
const OVERLAP_SHAPE = 2

function copyHit(from: RayHit, to: RayHit): void {
  to.shape = from.shape
  to.body = from.body
  to.fraction = from.fraction
  to.point.x = from.point.x
  to.point.y = from.point.y
  to.normal.x = from.normal.x
  to.normal.y = from.normal.y
}

/** The exact ray cast of a tagged geometry (local frame). */
export function castGeometry(
  geometry: QueryGeometry,
  input: RayCastInput,
  out: CastOutput,
): CastOutput | null {
  switch (geometry.type) {
    case 'circle':
      return rayCastCircle(geometry, input, out)
    case 'capsule':
      return rayCastCapsule(geometry, input, out)
    case 'polygon':
      return rayCastPolygon(geometry, input, out)
    case 'segment':
      return rayCastSegment(geometry, input, false, out)
    default:
      return rayCastChainSegment(geometry, input, out)
  }
}

/** Fills `out` with a tagged geometry's proxy (a chain segment: its segment). */
export function proxyOf(geometry: QueryGeometry, out: ShapeProxy): ShapeProxy {
  switch (geometry.type) {
    case 'circle':
      return circleProxy(geometry, out)
    case 'capsule':
      return capsuleProxy(geometry, out)
    case 'polygon':
      return polygonProxy(geometry, out)
    case 'segment':
      return segmentProxy(geometry, out)
    default:
      return segmentProxy(geometry.segment, out)
  }
}

/** World box of a proxy at a transform (its points, grown by its radius) into box[0..3]. */
function proxyBox(proxy: ShapeProxy, xf: Transform, box: Float64Array): void {
  let minX = Number.POSITIVE_INFINITY
  let minY = Number.POSITIVE_INFINITY
  let maxX = Number.NEGATIVE_INFINITY
  let maxY = Number.NEGATIVE_INFINITY
  for (let i = 0; i < proxy.count; i++) {
    const px = proxy.points[2 * i]
    const py = proxy.points[2 * i + 1]
    const x = xf.x + xf.c * px - xf.s * py
    const y = xf.y + xf.s * px + xf.c * py
    minX = Math.min(minX, x)
    minY = Math.min(minY, y)
    maxX = Math.max(maxX, x)
    maxY = Math.max(maxY, y)
  }
  const r = proxy.radius
  box[0] = minX - r
  box[1] = minY - r
  box[2] = maxX + r
  box[3] = maxY + r
}

/** Tight world box of a tagged geometry at a transform (through its proxy) into box[0..3]. */
export function geometryBox(
  geometry: QueryGeometry,
  xf: Transform,
  scratch: ShapeProxy,
  box: Float64Array,
): void {
  proxyBox(proxyOf(geometry, scratch), xf, box)
}
