/*
 * The work measured by tests/engine/query-allocation.test.ts: a block of the per-tick queries
 * (ray casts against every shape kind, hits, misses and initial overlaps; shape casts; a
 * closest-hit ray cast through a 1,000-leaf DynamicTree with TreeRayCast), run with reused inputs
 * and outputs as a game's per-tick code would.
 */
import { DynamicTree, NULL_NODE } from '../../engine/dynamic-tree.ts'
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
} from '../../engine/ray-cast.ts'
import { type ShapeCastPairInput, shapeCast } from '../../engine/shape-cast.ts'
import {
  capsuleProxy,
  circleProxy,
  IDENTITY,
  makeShapeProxy,
  polygonProxy,
} from '../../engine/shape-distance.ts'
import { TreeRayCast } from '../../engine/tree-ray-cast.ts'

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
