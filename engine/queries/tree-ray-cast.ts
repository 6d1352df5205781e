/*
 * A ray cast through a DynamicTree without a callback (Box2D v3's b2DynamicTree_RayCast turned
 * inside out). Box2D calls back into user code for every leaf the ray reaches, and the callback's
 * return value clips the ray. Here the caller drives the walk:
 *
 *   cursor.begin(tree, input)
 *   for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
 *     if (exact cast against leaf's shape hits) cursor.clip(hit)  // closest hit: shorten the ray
 *   }
 *
 * so no user code runs inside the engine, and nothing is allocated once the cursor's stack has
 * grown to the tree's height. The walk is Box2D's: a node is entered when its box overlaps the
 * box of the (clipped) ray and the ray's line passes through it (the separating axis
 * perpendicular to the ray, van den Bergen p. 80); of two children, the one whose centre is nearer
 * the origin is visited first. Every decision depends only on the tree and the ray, so the same
 * tree and ray give the same leaves in the same order.
 *
 * The tree's AABB query (all leaves overlapping a box) is DynamicTree.queryLeaves.
 */

import { type DynamicTree, NULL_NODE } from '../collision/index.ts'
import type { Vec2 } from '../math.ts'
import type { RayCastInput } from './ray-cast.ts'

const P1X = 0
const P1Y = 1
const DX = 2
const DY = 3
const VX = 4
const VY = 5
const MIN_X = 6
const MIN_Y = 7
const MAX_X = 8
const MAX_Y = 9
const EXT_X = 10
const EXT_Y = 11
const NO_EXTENSION: Vec2 = { x: 0, y: 0 }

/** A reusable cursor for ray casts through a DynamicTree. */
export class TreeRayCast {
  /** The ray's current maxFraction: the input's, lowered by clip(). */
  maxFraction = 0
  /** Nodes entered by the current walk (a measure of its cost). */
  nodeVisits = 0
  private tree: DynamicTree | null = null
  private stack = new Int32Array(64)
  private top = 0
  // Origin, translation, unit perpendicular and the clipped ray's box.
  private readonly ray = new Float64Array(12)

  /**
   * Starts a walk of `input`'s ray (origin, translation, maxFraction as in ray-cast.ts) through
   * `tree`. With `extension` (half extents, m), every node box is grown by it: the walk of a box
   * of those half extents centred on the origin sweeping along the ray (Box2D's
   * b2DynamicTree_ShapeCast, for shape casts).
   */
  begin(tree: DynamicTree, input: RayCastInput, extension: Vec2 = NO_EXTENSION): void {
    const f = input.maxFraction
    const o = input.origin
    const d = input.translation
    if (!(Number.isFinite(o.x) && Number.isFinite(o.y) && Number.isFinite(d.x) && Number.isFinite(d.y))) {
      throw new RangeError(
        `tree ray cast needs a finite origin and translation, got ${JSON.stringify(input)}`,
      )
    }
    if (!(f >= 0 && f < Number.POSITIVE_INFINITY)) {
      throw new RangeError(`tree ray cast maxFraction must be a finite number >= 0, got ${f}`)
    }
    if (
      !(
        extension.x >= 0 &&
        extension.y >= 0 &&
        extension.x < Number.POSITIVE_INFINITY &&
        extension.y < Number.POSITIVE_INFINITY
      )
    ) {
      throw new RangeError(
        `tree ray cast extension must be finite and >= 0, got ${JSON.stringify(extension)}`,
      )
    }
    this.tree = tree
    const ray = this.ray
    ray[P1X] = o.x
    ray[P1Y] = o.y
    ray[DX] = d.x
    ray[DY] = d.y
    const length = Math.sqrt(d.x * d.x + d.y * d.y)
    // v = cross(1, r): perpendicular to the unit direction (zero for a zero-length ray).
    ray[VX] = length > 0 ? -d.y / length : 0
    ray[VY] = length > 0 ? d.x / length : 0
    ray[EXT_X] = extension.x
    ray[EXT_Y] = extension.y
    this.maxFraction = f
    this.setBox()
    this.top = 0
    this.nodeVisits = 0
    if (tree.root !== NULL_NODE) this.stack[this.top++] = tree.root
  }

  /** Lowers maxFraction to `hit.fraction` when it is smaller (Box2D: the callback returned it). */
  clip(hit: { readonly fraction: number }): void {
    const f = hit.fraction
    if (f >= 0 && f < this.maxFraction) {
      this.maxFraction = f
      this.setBox()
    }
  }

  /** Ends the walk: next() returns NULL_NODE (Box2D: the callback returned 0). */
  stop(): void {
    this.top = 0
  }

  /** The next leaf the ray may touch (its node id; tree.body[leaf] is its user data), or NULL_NODE. */
  next(): number {
    const tree = this.tree
    if (tree === null) return NULL_NODE
    const b = tree.bounds
    const c1 = tree.child1
    const c2 = tree.child2
    const ray = this.ray
    while (this.top > 0) {
      const node = this.stack[--this.top]
      this.nodeVisits++
      const o = 4 * node
      const minX = b[o] - ray[EXT_X]
      const minY = b[o + 1] - ray[EXT_Y]
      const maxX = b[o + 2] + ray[EXT_X]
      const maxY = b[o + 3] + ray[EXT_Y]
      if (minX > ray[MAX_X] || minY > ray[MAX_Y] || ray[MIN_X] > maxX || ray[MIN_Y] > maxY) continue
      // Separating axis perpendicular to the ray: |dot(v, p1 - c)| > dot(|v|, h).
      const cx = 0.5 * (minX + maxX)
      const cy = 0.5 * (minY + maxY)
      const term1 = Math.abs(ray[VX] * (ray[P1X] - cx) + ray[VY] * (ray[P1Y] - cy))
      const term2 = Math.abs(ray[VX]) * 0.5 * (maxX - minX) + Math.abs(ray[VY]) * 0.5 * (maxY - minY)
      if (term2 < term1) continue
      const first = c1[node]
      if (first === NULL_NODE) return node
      const second = c2[node]
      if (this.top + 2 > this.stack.length) this.growStack()
      // Push the farther child first so the nearer one is visited first.
      const p = 4 * first
      const q = 4 * second
      const ax = 0.5 * (b[p] + b[p + 2]) - ray[P1X]
      const ay = 0.5 * (b[p + 1] + b[p + 3]) - ray[P1Y]
      const bx = 0.5 * (b[q] + b[q + 2]) - ray[P1X]
      const by = 0.5 * (b[q + 1] + b[q + 3]) - ray[P1Y]
      if (ax * ax + ay * ay < bx * bx + by * by) {
        this.stack[this.top++] = second
        this.stack[this.top++] = first
      } else {
        this.stack[this.top++] = first
        this.stack[this.top++] = second
      }
    }
    return NULL_NODE
  }

  /** The box of the ray from the origin to origin + maxFraction * translation. */
  private setBox(): void {
    const ray = this.ray
    const x2 = ray[P1X] + this.maxFraction * ray[DX]
    const y2 = ray[P1Y] + this.maxFraction * ray[DY]
    ray[MIN_X] = Math.min(ray[P1X], x2)
    ray[MIN_Y] = Math.min(ray[P1Y], y2)
    ray[MAX_X] = Math.max(ray[P1X], x2)
    ray[MAX_Y] = Math.max(ray[P1Y], y2)
  }

  private growStack(): void {
    const stack = new Int32Array(2 * this.stack.length)
    stack.set(this.stack)
    this.stack = stack
  }
}
