/*
 * The work measured by tests/engine/query-allocation.test.ts: a block of the per-tick queries
 * (ray casts against every shape kind, hits, misses and initial overlaps; shape casts; a
 * closest-hit ray cast through a 1,000-leaf DynamicTree with TreeRayCast), the WorldQueries over a
 * test-made QueryWorld, and the World's own query methods (WorldApiScene), run with reused inputs
 * and outputs as a game's per-tick code would.
 */

import { IdBuffer } from '../../engine/collision/broad-phase.ts'
import { DynamicTree, NULL_NODE } from '../../engine/collision/dynamic-tree.ts'
import * as engine from '../../engine/index.ts'
import { Prng } from '../../engine/prng.ts'
import {
  makeCastOutput,
  type PolygonGeometry,
  type RayCastInput,
  rayCastCapsule,
  rayCastChainSegment,
  rayCastCircle,
  rayCastPolygon,
  rayCastSegment,
} from '../../engine/queries/ray-cast.ts'
import { type ShapeCastPairInput, shapeCast } from '../../engine/queries/shape-cast.ts'
import {
  capsuleProxy,
  circleProxy,
  IDENTITY,
  makeShapeProxy,
  polygonProxy,
  type Transform,
} from '../../engine/queries/shape-distance.ts'
import { TreeRayCast } from '../../engine/queries/tree-ray-cast.ts'
import {
  DEFAULT_QUERY_FILTER,
  makeRayHit,
  type QueryGeometry,
  type QueryWorld,
  RayHitList,
  WorldQueries,
} from '../../engine/queries/world-queries.ts'

/** A QueryWorld of 400 shapes (circles, boxes, capsules) on 400 bodies, one leaf per shape. */
class GridWorld implements QueryWorld {
  readonly tree = new DynamicTree()
  private readonly shapeOfLeaf: Int32Array = new Int32Array(2048)
  private readonly geometry: QueryGeometry[] = []
  private readonly transforms: Transform[] = []
  private readonly filter = { categoryBits: 1, maskBits: 0xffffffff }

  constructor() {
    for (let i = 0; i < 400; i++) {
      const x = (i % 20) * 3 - 30
      const y = Math.floor(i / 20) * 3 - 30
      const a = 0.1 * i
      this.transforms.push({ x, y, c: Math.cos(a), s: Math.sin(a) })
      const kind = i % 3
      const g: QueryGeometry =
        kind === 0
          ? { type: 'circle', center: { x: 0.1, y: 0 }, radius: 0.6 }
          : kind === 1
            ? { type: 'polygon', ...box(0.7, 0.4, 0) }
            : { type: 'capsule', center1: { x: -0.5, y: 0 }, center2: { x: 0.5, y: 0.2 }, radius: 0.3 }
      this.geometry.push(g)
      const leaf = this.tree.createLeaf(x - 1.2, y - 1.2, x + 1.2, y + 1.2, i, 0)
      this.shapeOfLeaf[leaf] = i
    }
  }
  leafShapeCount(): number {
    return 1
  }
  leafShape(leaf: number): number {
    return this.shapeOfLeaf[leaf]
  }
  shapeGeometry(shape: number): QueryGeometry {
    return this.geometry[shape]
  }
  shapeBody(shape: number): number {
    return shape
  }
  shapeFilter(): { categoryBits: number; maskBits: number } {
    return this.filter
  }
  isSensor(): boolean {
    return false
  }
  bodyTransform(body: number, out: Transform): void {
    const t = this.transforms[body]
    out.x = t.x
    out.y = t.y
    out.c = t.c
    out.s = t.s
  }
}

const box = (hx: number, hy: number, radius: number): PolygonGeometry => ({
  vertices: [
    { x: -hx, y: -hy },
    { x: hx, y: -hy },
    { x: hx, y: hy },
    { x: -hx, y: hy },
  ],
  normals: [
    { x: 0, y: -1 },
    { x: 1, y: 0 },
    { x: 0, y: 1 },
    { x: -1, y: 0 },
  ],
  count: 4,
  radius,
})

export class QueryScene {
  private readonly out = makeCastOutput()
  private readonly input: RayCastInput = {
    origin: { x: 0, y: 0 },
    translation: { x: 0, y: 0 },
    maxFraction: 1,
  }
  private readonly circle = { center: { x: 0.5, y: 0.25 }, radius: 0.75 }
  private readonly capsule = { center1: { x: -1, y: 0 }, center2: { x: 1, y: 0.5 }, radius: 0.4 }
  private readonly sharp = box(1, 0.5, 0)
  private readonly rounded = box(1, 0.5, 0.2)
  private readonly segment = { point1: { x: -2, y: 0.1 }, point2: { x: 2, y: -0.1 } }
  private readonly chain = { ghost1: { x: -3, y: 0 }, segment: this.segment, ghost2: { x: 3, y: 0 } }
  private readonly cast: ShapeCastPairInput
  private readonly tree = new DynamicTree()
  private readonly cursor = new TreeRayCast()
  private readonly hit = { fraction: 0 }
  private k = 0
  hits = 0
  private readonly world = new GridWorld()
  private readonly queries = new WorldQueries()
  private readonly rayHit = makeRayHit()
  private readonly rayHits = new RayHitList()
  private readonly ids = new IdBuffer()
  private readonly aabb = { minX: 0, minY: 0, maxX: 0, maxY: 0 }
  private readonly point = { x: 0, y: 0 }
  private readonly probe = circleProxy({ center: { x: 0, y: 0 }, radius: 0.5 }, makeShapeProxy())
  private readonly probeXf: Transform = { x: 0, y: 0, c: 1, s: 0 }
  private readonly sweep = { x: 0, y: 0 }

  /** One block of world queries over a 400-shape world. */
  worldUnit(): void {
    const k = this.k++ % 64
    const input = this.input
    input.origin.x = -35 + 0.25 * k
    input.origin.y = -34 + 0.5 * k
    input.translation.x = 70
    input.translation.y = 40 - 1.1 * k
    input.maxFraction = 1
    const world = this.world
    const q = this.queries
    if (q.castRayClosest(world, input, DEFAULT_QUERY_FILTER, this.rayHit) !== null) this.hits++
    this.hits += q.castRay(world, input, DEFAULT_QUERY_FILTER, this.rayHits)
    this.aabb.minX = -30 + 0.5 * k
    this.aabb.minY = -28 + 0.25 * k
    this.aabb.maxX = this.aabb.minX + 6.5
    this.aabb.maxY = this.aabb.minY + 4.5
    this.hits += q.overlapAABB(world, this.aabb, DEFAULT_QUERY_FILTER, this.ids)
    this.point.x = -30 + 0.75 * k
    this.point.y = -29.9 + 0.5 * k
    this.hits += q.overlapPoint(world, this.point, DEFAULT_QUERY_FILTER, this.ids)
    this.probeXf.x = this.point.x + 0.25
    this.probeXf.y = this.point.y - 0.5
    this.hits += q.overlapShape(world, this.probe, this.probeXf, DEFAULT_QUERY_FILTER, this.ids)
    this.probeXf.x = -34
    this.probeXf.y = -30.5 + 0.75 * k
    this.sweep.x = 60
    this.sweep.y = 3 - 0.1 * k
    if (q.castShape(world, this.probe, this.probeXf, this.sweep, DEFAULT_QUERY_FILTER, this.rayHit) !== null)
      this.hits++
  }

  constructor() {
    const a = polygonProxy(this.sharp, makeShapeProxy())
    const b = circleProxy({ center: { x: 0, y: 0 }, radius: 0.3 }, makeShapeProxy())
    this.cast = {
      proxyA: a,
      transformA: IDENTITY,
      proxyB: b,
      transformB: { x: -4, y: 0.1, c: 1, s: 0 },
      translationB: { x: 8, y: 0.05 },
      maxFraction: 1,
    }
    capsuleProxy(this.capsule, makeShapeProxy())
    const rng = new Prng(9)
    for (let i = 0; i < 1000; i++) {
      const x = rng.range(-50, 50)
      const y = rng.range(-50, 50)
      this.tree.createLeaf(x, y, x + rng.range(0.1, 3), y + rng.range(0.1, 3), i + 1, 0)
    }
  }

  /** One block of queries; the ray's origin sweeps so hits, misses and overlaps all occur. */
  unit(): void {
    const k = this.k++ % 64
    const input = this.input
    const out = this.out
    input.origin.x = -4 + 0.125 * k
    input.origin.y = -2 + 0.0625 * k
    input.translation.x = 8 - 0.1 * k
    input.translation.y = 4 - 0.05 * k
    input.maxFraction = 1
    if (rayCastCircle(this.circle, input, out) !== null) this.hits++
    if (rayCastCapsule(this.capsule, input, out) !== null) this.hits++
    if (rayCastPolygon(this.sharp, input, out) !== null) this.hits++
    if (rayCastPolygon(this.rounded, input, out) !== null) this.hits++
    if (rayCastSegment(this.segment, input, false, out) !== null) this.hits++
    if (rayCastChainSegment(this.chain, input, out) !== null) this.hits++
    this.cast.transformB.y = -1 + 0.03125 * k
    if (shapeCast(this.cast, out) !== null) this.hits++
    // Closest box along a long ray through the tree (slab test as the leaf's exact cast).
    input.origin.x = -60 + k
    input.origin.y = -55 + 0.5 * k
    input.translation.x = 120
    input.translation.y = 100 - 3 * k
    const cursor = this.cursor
    cursor.begin(this.tree, input)
    for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
      const f = this.slab(leaf)
      if (f >= 0) {
        this.hit.fraction = f
        cursor.clip(this.hit)
      }
    }
    if (cursor.maxFraction < 1) this.hits++
  }

  /** Entry fraction of the current ray into leaf's box, or -1. */
  private slab(leaf: number): number {
    const b = this.tree.bounds
    const o = this.input.origin
    const d = this.input.translation
    let lo = 0
    let hi = this.cursor.maxFraction
    for (let axis = 0; axis < 2; axis++) {
      const p = axis === 0 ? o.x : o.y
      const v = axis === 0 ? d.x : d.y
      const min = b[4 * leaf + axis]
      const max = b[4 * leaf + 2 + axis]
      if (v === 0) {
        if (p < min || p > max) return -1
        continue
      }
      const t1 = (min - p) / v
      const t2 = (max - p) / v
      lo = Math.max(lo, Math.min(t1, t2))
      hi = Math.min(hi, Math.max(t1, t2))
      if (lo > hi) return -1
    }
    return lo
  }
}

/**
 * The World's own query methods (engine/world/query-api.ts) in their reusing forms, over a real
 * world of 400 shapes (every kind; compound bodies; sensors; a filter), with reused arguments and
 * results as a game's per-tick code would pass them.
 */
export class WorldApiScene {
  hits = 0
  private readonly world: engine.World = engine.createWorld()
  private k = 0
  private readonly origin = { x: 0, y: 0 }
  private readonly translation = { x: 0, y: 0 }
  private readonly filter = { categoryBits: 1, maskBits: 0xffffffff }
  private readonly hit = makeRayHit()
  private readonly list = new RayHitList()
  private readonly ids = new IdBuffer()
  private readonly aabb = { minX: 0, minY: 0, maxX: 0, maxY: 0 }
  private readonly probe = engine.circle(0.5)
  private readonly probeBox = engine.box(0.4, 0.2)
  private readonly at = { position: { x: 0, y: 0 }, rotation: { c: 1, s: 0 } }

  constructor() {
    const kinds = [
      engine.circle(0.6, { x: 0.1, y: 0 }),
      engine.box(0.7, 0.4),
      engine.polygon(
        [
          { x: -0.5, y: -0.4 },
          { x: 0.6, y: -0.3 },
          { x: 0.3, y: 0.5 },
        ],
        0.1,
      ),
      engine.capsule({ x: -0.5, y: 0 }, { x: 0.5, y: 0.2 }, 0.3),
    ]
    for (let i = 0; i < 200; i++) {
      const x = (i % 20) * 3 - 30
      const y = Math.floor(i / 20) * 6 - 30
      this.world.createBody({
        type: i % 7 === 0 ? 'dynamic' : 'static',
        position: { x, y },
        angle: 0.1 * i,
        shapes: [
          { shape: kinds[i % 4] },
          i % 2 === 0
            ? { shape: engine.segment({ x: -1, y: 1.5 }, { x: 1, y: 2 }) }
            : { shape: kinds[(i + 1) % 4], sensor: i % 5 === 0 },
        ].map((d, j) => ({
          ...d,
          filter: { categoryBits: 1 << ((i + j) % 3), maskBits: 0xffffffff, groupIndex: 0 },
        })),
      })
    }
    this.world.step()
  }

  /** One block of the six queries in their reusing forms. */
  unit(): void {
    const k = this.k++ % 64
    const world = this.world
    this.origin.x = -35 + 0.25 * k
    this.origin.y = -34 + 0.5 * k
    this.translation.x = 70
    this.translation.y = 40 - 1.1 * k
    this.filter.maskBits = k % 2 === 0 ? 0xffffffff : 3
    if (world.castRayClosest(this.origin, this.translation, this.filter, this.hit) !== null) this.hits++
    this.hits += world.castRayInto(this.origin, this.translation, this.filter, this.list)
    this.aabb.minX = -30 + 0.5 * k
    this.aabb.minY = -28 + 0.25 * k
    this.aabb.maxX = this.aabb.minX + 6.5
    this.aabb.maxY = this.aabb.minY + 4.5
    this.hits += world.overlapAABBInto(this.aabb, this.filter, this.ids)
    this.origin.x = -30 + 0.75 * k
    this.origin.y = -29.9 + 0.5 * k
    this.hits += world.overlapPointInto(this.origin, undefined, this.ids)
    this.at.position.x = this.origin.x + 0.25
    this.at.position.y = this.origin.y - 0.5
    this.at.rotation.c = Math.cos(0.05 * k)
    this.at.rotation.s = Math.sin(0.05 * k)
    this.hits += world.overlapShapeInto(
      k % 2 === 0 ? this.probe : this.probeBox,
      this.at,
      this.filter,
      this.ids,
    )
    this.at.position.x = -34
    this.at.position.y = -30.5 + 0.75 * k
    this.translation.x = 60
    this.translation.y = 3 - 0.1 * k
    if (world.castShape(this.probeBox, this.at, this.translation, undefined, this.hit) !== null) this.hits++
  }
}
