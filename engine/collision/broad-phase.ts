/*
 * The broadphase: one proxy per body shape in a dynamic AABB tree (Box2D's b2BroadPhase over
 * b2DynamicTree), reporting candidate pairs as body ids.
 *
 * A dynamic proxy's tree box is its tight AABB grown by a margin (the "fat" AABB). Each step the
 * world hands every awake body's tight AABB to `moveProxy`; only when it leaves the fat box is
 * the leaf re-fattened, re-inserted and put on the move list. `updatePairs` then queries the tree
 * with each moved proxy's fat box, so the work per step follows the number of bodies that crossed
 * their margin, not the number of bodies. A pair is new only if one of its proxies moved: a pair
 * whose fat boxes overlapped before still overlaps unless one moved, and the world drops a contact
 * once `testOverlap` says its fat boxes have separated.
 *
 * Overlap is closed: boxes that touch overlap (Box2D's b2TestOverlap). Pairs come out as body ids
 * (a < b) sorted by the exact key a * 2^26 + b, deduplicated, never static-static, never a body
 * with itself: the order depends only on the operations and the coordinates, never on memory.
 * Keys are sorted in place in a reusable Float64Array (no allocation once the buffers are warm).
 */
import { AABB_MARGIN, DISPLACEMENT_MULTIPLIER } from '../constants.ts'
import { DynamicTree, NULL_NODE } from './dynamic-tree.ts'

/** Body ids are below 2^26, so a * 2^26 + b is an exact integer key for a pair. */
const BODY_SCALE = 67108864
const FLAG_STATIC = 1
const FLAG_MOVED = 2

/** Pairs of body ids (a < b) in parallel arrays that grow by doubling. */
export class PairBuffer {
  /** First body of each pair. */
  a: Int32Array
  /** Second body of each pair (a[i] < b[i]). */
  b: Int32Array
  /** Number of valid pairs. */
  count = 0

  constructor(capacity = 64) {
    this.a = new Int32Array(capacity)
    this.b = new Int32Array(capacity)
  }

  /** Makes room for at least `n` pairs, keeping the first `count`. */
  reserve(n: number): void {
    if (n <= this.a.length) return
    let capacity = Math.max(1, this.a.length)
    while (capacity < n) capacity *= 2
    const a = new Int32Array(capacity)
    const b = new Int32Array(capacity)
    a.set(this.a.subarray(0, this.count))
    b.set(this.b.subarray(0, this.count))
    this.a = a
    this.b = b
  }
}

/** A growable list of body ids. */
export class IdBuffer {
  /** The ids; the first `count` are valid. */
  ids: Int32Array
  /** Number of valid ids. */
  count = 0

  constructor(capacity = 64) {
    this.ids = new Int32Array(capacity)
  }

  /** Makes room for at least `n` ids, keeping the first `count`. */
  reserve(n: number): void {
    if (n <= this.ids.length) return
    let capacity = Math.max(1, this.ids.length)
    while (capacity < n) capacity *= 2
    const ids = new Int32Array(capacity)
    ids.set(this.ids.subarray(0, this.count))
    this.ids = ids
  }
}

/** Finds the pairs of bodies whose fat AABBs overlap, incrementally, with a dynamic AABB tree. */
export class BroadPhase {
  /** Fat AABB margin for dynamic proxies (m), usually 0.1. */
  readonly margin: number
  private readonly tree = new DynamicTree()
  private moved = new Int32Array(64)
  private moveCount = 0
  private keys = new Float64Array(256)
  private keyCount = 0
  private readonly sortStack = new Int32Array(128)
  private readonly scratchBox = new Float64Array(4)

  constructor(margin = AABB_MARGIN) {
    if (!(margin >= 0) || !Number.isFinite(margin)) throw new Error(`BroadPhase: bad margin ${margin}`)
    this.margin = margin
  }

  /** Number of live proxies. */
  get proxyCount(): number {
    return this.tree.leafCount
  }

  /**
   * The tree itself, for the world's queries to walk (engine/queries): one leaf per shape, its user
   * data (`tree.body[leaf]`) the shape id, its box the fat AABB. Read it; never change it.
   */
  get shapeTree(): DynamicTree {
    return this.tree
  }

  /** Height of the tree (0 for at most one proxy); about 2 log2(n) or less. */
  get treeHeight(): number {
    return this.tree.treeHeight
  }

  /** Checks the tree's structural invariants; throws on the first broken one. For tests. */
  validateTree(): void {
    this.tree.validate()
  }

  /** Adds a proxy with a tight AABB; dynamic proxies are fattened by the margin. Returns its id. */
  createProxy(
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    body: number,
    isStatic: boolean,
  ): number {
    const r = isStatic ? 0 : this.margin
    return this.createProxyWithFatAABB(minX - r, minY - r, maxX + r, maxY + r, body, isStatic)
  }

  /** Adds a proxy with an exact, already fat AABB (used when loading a saved world). */
  createProxyWithFatAABB(
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    body: number,
    isStatic: boolean,
  ): number {
    if (!(body > 0 && body < BODY_SCALE && body === Math.floor(body))) {
      throw new Error(`BroadPhase: body id ${body} is not an integer in [1, 2^26)`)
    }
    if (!(minX <= maxX && minY <= maxY)) {
      throw new Error(`BroadPhase: bad AABB (${minX}, ${minY}, ${maxX}, ${maxY}) for body ${body}`)
    }
    const proxy = this.tree.createLeaf(minX, minY, maxX, maxY, body, isStatic ? FLAG_STATIC : 0)
    this.bufferMove(proxy)
    return proxy
  }

  /** Removes a proxy; it is never reported again and its id may be reused. */
  destroyProxy(proxy: number): void {
    const tree = this.tree
    if (!tree.isLeaf(proxy)) throw new Error(`BroadPhase: ${proxy} is not a live proxy`)
    if ((tree.flags[proxy] & FLAG_MOVED) !== 0) {
      const moved = this.moved
      for (let i = 0; i < this.moveCount; i++) if (moved[i] === proxy) moved[i] = NULL_NODE
    }
    tree.destroyLeaf(proxy)
  }

  /** Given the new tight AABB: if it left the fat AABB, re-fatten, move the leaf, mark it moved, return true. */
  moveProxy(proxy: number, minX: number, minY: number, maxX: number, maxY: number): boolean {
    const tree = this.tree
    const b = tree.bounds
    const o = 4 * proxy
    if (b[o] <= minX && b[o + 1] <= minY && maxX <= b[o + 2] && maxY <= b[o + 3]) return false
    if (tree.height[proxy] !== 0) throw new Error(`BroadPhase: ${proxy} is not a live proxy`)
    const r = (tree.flags[proxy] & FLAG_STATIC) !== 0 ? 0 : this.margin
    b[o] = minX - r
    b[o + 1] = minY - r
    b[o + 2] = maxX + r
    b[o + 3] = maxY + r
    tree.reinsertLeaf(proxy)
    this.bufferMove(proxy)
    return true
  }

  /**
   * moveProxy with motion prediction (Box2D v2.4's b2_aabbMultiplier): `box` holds the tight AABB
   * (minX, minY, maxX, maxY) and this step's displacement (dx, dy). When the proxy must be re-fattened,
   * its fat AABB also reaches DISPLACEMENT_MULTIPLIER displacements ahead along the motion, so a
   * falling or thrown body is re-inserted every few steps instead of every step. Pair semantics are
   * unchanged: the fat AABB still contains the tight one.
   */
  moveProxyPredicted(proxy: number, box: Float64Array): boolean {
    const tree = this.tree
    const b = tree.bounds
    const o = 4 * proxy
    if (b[o] <= box[0] && b[o + 1] <= box[1] && box[2] <= b[o + 2] && box[3] <= b[o + 3]) return false
    if (tree.height[proxy] !== 0) throw new Error(`BroadPhase: ${proxy} is not a live proxy`)
    const r = (tree.flags[proxy] & FLAG_STATIC) !== 0 ? 0 : this.margin
    const dx = DISPLACEMENT_MULTIPLIER * box[4]
    const dy = DISPLACEMENT_MULTIPLIER * box[5]
    b[o] = box[0] - r + (dx < 0 ? dx : 0)
    b[o + 1] = box[1] - r + (dy < 0 ? dy : 0)
    b[o + 2] = box[2] + r + (dx > 0 ? dx : 0)
    b[o + 3] = box[3] + r + (dy > 0 ? dy : 0)
    tree.reinsertLeaf(proxy)
    this.bufferMove(proxy)
    return true
  }

  /** Marks a proxy as moved so the next updatePairs queries it (after waking or teleporting). */
  touchProxy(proxy: number): void {
    if (!this.tree.isLeaf(proxy)) throw new Error(`BroadPhase: ${proxy} is not a live proxy`)
    this.bufferMove(proxy)
  }

  /** Fat AABB of a proxy into out[0..3] = minX, minY, maxX, maxY (m). */
  getFatAABB(proxy: number, out: Float64Array): void {
    const b = this.tree.bounds
    const o = 4 * proxy
    out[0] = b[o]
    out[1] = b[o + 1]
    out[2] = b[o + 2]
    out[3] = b[o + 3]
  }

  /** Body id of a proxy. */
  getBody(proxy: number): number {
    return this.tree.body[proxy]
  }

  /** Do the fat AABBs of two proxies overlap (touching counts)? */
  testOverlap(proxyA: number, proxyB: number): boolean {
    const b = this.tree.bounds
    const p = 4 * proxyA
    const q = 4 * proxyB
    return !(b[p] > b[q + 2] || b[q] > b[p + 2] || b[p + 1] > b[q + 3] || b[q + 1] > b[p + 3])
  }

  /**
   * For every moved proxy, finds every proxy whose fat AABB overlaps it; writes each pair once as
   * body ids (a < b) sorted by (a, b), excluding static-static; clears the move list; returns the count.
   */
  updatePairs(pairs: PairBuffer): number {
    const tree = this.tree
    const flags = tree.flags
    this.keyCount = 0
    for (let i = 0; i < this.moveCount; i++) {
      const proxy = this.moved[i]
      if (proxy !== NULL_NODE) this.collectPairs(proxy, true)
    }
    // Clear the moved bits only now: a pair of two moved proxies is taken from one side only.
    for (let i = 0; i < this.moveCount; i++) {
      const proxy = this.moved[i]
      if (proxy !== NULL_NODE) flags[proxy] &= ~FLAG_MOVED
    }
    this.moveCount = 0
    return this.emitPairs(pairs)
  }

  /** Every overlapping pair of fat AABBs right now (excluding static-static), same format as updatePairs. */
  allPairs(pairs: PairBuffer): number {
    this.keyCount = 0
    const leaves = this.allLeaves()
    for (let i = 0; i < leaves; i++) this.collectPairs(this.scratchLeaves[i], false)
    return this.emitPairs(pairs)
  }

  /** Bodies whose fat AABB overlaps the query box (touching counts), ascending, into `out`; returns the count. */
  query(minX: number, minY: number, maxX: number, maxY: number, out: IdBuffer): number {
    const box = this.scratchBox
    box[0] = minX
    box[1] = minY
    box[2] = maxX
    box[3] = maxY
    return this.queryBox(box, out)
  }

  /**
   * As query, with the box in box[0..3] (minX, minY, maxX, maxY): the step's callers pass it this
   * way because V8 boxes each double argument of a call it does not inline (a heap number each).
   */
  queryBox(box: Float64Array, out: IdBuffer): number {
    const tree = this.tree
    const hits = tree.queryLeaves(box, 0)
    this.ensureKeys(hits)
    const keys = this.keys
    for (let i = 0; i < hits; i++) keys[i] = tree.body[tree.hits[i]]
    sortKeys(keys, hits, this.sortStack)
    out.count = 0
    out.reserve(hits)
    const ids = out.ids
    let count = 0
    for (let i = 0; i < hits; i++) {
      const id = keys[i]
      if (count === 0 || ids[count - 1] !== id) ids[count++] = id
    }
    out.count = count
    return count
  }

  private scratchLeaves = new Int32Array(64)

  /** Copies the ids of all live leaves, ascending, into scratchLeaves; returns how many. */
  private allLeaves(): number {
    const tree = this.tree
    if (this.scratchLeaves.length < tree.height.length)
      this.scratchLeaves = new Int32Array(tree.height.length)
    const height = tree.height
    const out = this.scratchLeaves
    let count = 0
    for (let n = 0; n < height.length; n++) if (height[n] === 0) out[count++] = n
    return count
  }

  /**
   * Queries the tree with the fat box of `proxy` and appends a key for each new pair. With
   * `fromMoveList`, a partner that is itself moved is skipped when its id is larger (it reports
   * the pair); otherwise (allPairs) each pair is taken from its smaller proxy id.
   */
  private collectPairs(proxy: number, fromMoveList: boolean): void {
    const tree = this.tree
    const hitCount = tree.queryLeaves(tree.bounds, 4 * proxy)
    const hits = tree.hits
    const flags = tree.flags
    const bodies = tree.body
    const selfStatic = flags[proxy] & FLAG_STATIC
    const selfBody = bodies[proxy]
    this.ensureKeys(this.keyCount + hitCount)
    const keys = this.keys
    let k = this.keyCount
    for (let i = 0; i < hitCount; i++) {
      const other = hits[i]
      if (other === proxy) continue
      const f = flags[other]
      if ((f & selfStatic) !== 0) continue
      if (fromMoveList ? (f & FLAG_MOVED) !== 0 && other > proxy : other < proxy) continue
      const body = bodies[other]
      if (body === selfBody) continue
      keys[k++] = body < selfBody ? body * BODY_SCALE + selfBody : selfBody * BODY_SCALE + body
    }
    this.keyCount = k
  }

  /** Sorts the collected keys, drops duplicates and splits them into `pairs`. */
  private emitPairs(pairs: PairBuffer): number {
    const keys = this.keys
    const n = this.keyCount
    sortKeys(keys, n, this.sortStack)
    pairs.count = 0
    pairs.reserve(n)
    const pa = pairs.a
    const pb = pairs.b
    let count = 0
    let last = -1
    for (let i = 0; i < n; i++) {
      const key = keys[i]
      if (key === last) continue
      last = key
      const a = Math.floor(key / BODY_SCALE)
      pa[count] = a
      pb[count] = key - a * BODY_SCALE
      count++
    }
    pairs.count = count
    this.keyCount = 0
    return count
  }

  private bufferMove(proxy: number): void {
    const flags = this.tree.flags
    if ((flags[proxy] & FLAG_MOVED) !== 0) return
    flags[proxy] |= FLAG_MOVED
    if (this.moveCount === this.moved.length) {
      const moved = new Int32Array(this.moved.length * 2)
      moved.set(this.moved)
      this.moved = moved
    }
    this.moved[this.moveCount++] = proxy
  }

  private ensureKeys(n: number): void {
    if (n <= this.keys.length) return
    let capacity = this.keys.length
    while (capacity < n) capacity *= 2
    const keys = new Float64Array(capacity)
    keys.set(this.keys.subarray(0, this.keyCount))
    this.keys = keys
  }
}

/**
 * Sorts keys[0..n) ascending in place: quicksort with a median-of-three pivot and an insertion
 * sort below 16 elements, iterative on an explicit stack, smaller side first (depth <= log2 n).
 */
export function sortKeys(keys: Float64Array, n: number, stack: Int32Array): void {
  let top = 0
  let lo = 0
  let hi = n - 1
  for (;;) {
    if (hi - lo < 16) {
      insertionSort(keys, lo, hi)
      if (top === 0) return
      hi = stack[--top]
      lo = stack[--top]
      continue
    }
    const mid = lo + ((hi - lo) >> 1)
    // Median of three into keys[mid], then Hoare partition around its value.
    if (keys[mid] < keys[lo]) swap(keys, mid, lo)
    if (keys[hi] < keys[lo]) swap(keys, hi, lo)
    if (keys[hi] < keys[mid]) swap(keys, hi, mid)
    const pivot = keys[mid]
    let i = lo
    let j = hi
    while (i <= j) {
      while (keys[i] < pivot) i++
      while (keys[j] > pivot) j--
      if (i <= j) {
        swap(keys, i, j)
        i++
        j--
      }
    }
    // Now [lo, j] <= pivot <= [i, hi]; push the larger side, continue with the smaller.
    if (j - lo < hi - i) {
      stack[top++] = i
      stack[top++] = hi
      hi = j
    } else {
      stack[top++] = lo
      stack[top++] = j
      lo = i
    }
  }
}

function insertionSort(keys: Float64Array, lo: number, hi: number): void {
  for (let i = lo + 1; i <= hi; i++) {
    const key = keys[i]
    let j = i - 1
    while (j >= lo && keys[j] > key) {
      keys[j + 1] = keys[j]
      j--
    }
    keys[j + 1] = key
  }
}

function swap(keys: Float64Array, i: number, j: number): void {
  const t = keys[i]
  keys[i] = keys[j]
  keys[j] = t
}
