/*
 * A dynamic AABB tree (Box2D's b2DynamicTree, after Erin Catto, with Presson's bounding volume
 * hierarchy insertion). Leaves hold fat AABBs; every internal node holds the union of its two
 * children, so a query descends only into subtrees whose box overlaps the query box.
 *
 * Layout: nodes live in parallel typed arrays indexed by node id (bounds: 4 doubles per node;
 * parent, child1, child2, height, body, flags: one int each), grown by doubling. Free nodes are
 * chained through `parent` and have height -1. Leaves have child1 = -1. Nothing is allocated after
 * warm-up: queries use an explicit stack and write the leaves they find into a reusable buffer.
 *
 * Insertion picks the sibling by the surface-area heuristic (perimeter in 2D) with the cost of
 * enlarging every ancestor on the way down ("inheritance cost"), then walks back to the root,
 * refitting boxes and applying AVL rotations wherever the children's heights differ by more than
 * one (Box2D v2.4 `Balance`). This keeps the tree shallow: about 15 levels for 4,000 proxies.
 *
 * Every decision depends only on the sequence of operations and the coordinates (min, max, + and
 * comparisons), so two trees fed the same operations are identical node for node.
 */

/** The null node id. */
export const NULL_NODE = -1

const INITIAL_CAPACITY = 16

/** A bounding volume hierarchy of AABBs with stable leaf ids (node ids) and per-leaf user data. */
export class DynamicTree {
  /** minX, minY, maxX, maxY of node i at 4i..4i+3 (m). */
  bounds: Float64Array
  /** Parent node id, or the next free node for nodes on the free list. */
  parent: Int32Array
  /** First child, or -1 for a leaf. */
  child1: Int32Array
  /** Second child, or -1 for a leaf. */
  child2: Int32Array
  /** 0 for a leaf, 1 + max(children) for an internal node, -1 for a free node. */
  height: Int32Array
  /** User data of a leaf: the body id. */
  body: Int32Array
  /** User flags of a leaf (the broadphase keeps its static and moved bits here). */
  flags: Int32Array
  /** Leaf ids found by the last `queryLeaves`. */
  hits: Int32Array
  /** Root node id or NULL_NODE. */
  root = NULL_NODE
  /** Number of leaves. */
  leafCount = 0
  private capacity = 0
  private freeList = NULL_NODE
  private stack: Int32Array

  constructor() {
    this.bounds = new Float64Array(0)
    this.parent = new Int32Array(0)
    this.child1 = new Int32Array(0)
    this.child2 = new Int32Array(0)
    this.height = new Int32Array(0)
    this.body = new Int32Array(0)
    this.flags = new Int32Array(0)
    this.stack = new Int32Array(0)
    this.hits = new Int32Array(64)
    this.grow(INITIAL_CAPACITY)
  }

  /** Height of the tree: 0 for one leaf, 0 when empty. */
  get treeHeight(): number {
    return this.root === NULL_NODE ? 0 : this.height[this.root]
  }

  /** Adds a leaf with the given (already fat) box and user data; returns its id. */
  createLeaf(minX: number, minY: number, maxX: number, maxY: number, body: number, flags: number): number {
    const leaf = this.allocateNode()
    const b = this.bounds
    b[4 * leaf] = minX
    b[4 * leaf + 1] = minY
    b[4 * leaf + 2] = maxX
    b[4 * leaf + 3] = maxY
    this.body[leaf] = body
    this.flags[leaf] = flags
    this.height[leaf] = 0
    this.insertLeaf(leaf)
    this.leafCount++
    return leaf
  }

  /** Removes a leaf and frees its id for reuse. */
  destroyLeaf(leaf: number): void {
    if (leaf < 0 || leaf >= this.capacity || this.height[leaf] !== 0) {
      throw new Error(`DynamicTree: ${leaf} is not a live leaf`)
    }
    this.removeLeaf(leaf)
    this.freeNode(leaf)
    this.leafCount--
  }

  /**
   * Re-inserts a leaf whose box the caller has just rewritten in `bounds`: removes it and inserts
   * it again where the heuristic says. (Passing the box in `bounds` rather than as four number
   * arguments keeps V8 from boxing them when this call is not inlined.)
   */
  reinsertLeaf(leaf: number): void {
    this.removeLeaf(leaf)
    this.insertLeaf(leaf)
  }

  /** Is `node` a live leaf? */
  isLeaf(node: number): boolean {
    return node >= 0 && node < this.capacity && this.height[node] === 0
  }

  /**
   * Writes into `hits` every leaf whose box overlaps the query box box[o..o+3] = minX, minY, maxX,
   * maxY (touching counts) and returns how many. Order: depth first, child1 before child2.
   */
  queryLeaves(box: Float64Array, o: number): number {
    const minX = box[o]
    const minY = box[o + 1]
    const maxX = box[o + 2]
    const maxY = box[o + 3]
    const root = this.root
    const b = this.bounds
    if (root === NULL_NODE || b[4 * root] > maxX || b[4 * root + 1] > maxY) return 0
    if (minX > b[4 * root + 2] || minY > b[4 * root + 3]) return 0
    const c1 = this.child1
    const c2 = this.child2
    const stack = this.stack
    let hits = this.hits
    let count = 0
    let top = 0
    stack[top++] = root
    // Every node on the stack overlaps the query box; children are tested before they are pushed.
    while (top > 0) {
      const node = stack[--top]
      const first = c1[node]
      if (first === NULL_NODE) {
        if (count === hits.length) hits = this.growHits()
        hits[count++] = node
        continue
      }
      const second = c2[node]
      let p = 4 * second
      if (!(b[p] > maxX || b[p + 1] > maxY || minX > b[p + 2] || minY > b[p + 3])) stack[top++] = second
      p = 4 * first
      if (!(b[p] > maxX || b[p + 1] > maxY || minX > b[p + 2] || minY > b[p + 3])) stack[top++] = first
    }
    return count
  }

  /**
   * Checks every structural invariant and throws on the first broken one: parent links, heights,
   * boxes equal to the union of the children, the leaf count and the free list. For tests.
   */
  validate(): void {
    let leaves = 0
    let live = 0
    const check = (node: number, parentId: number): void => {
      live++
      if (this.parent[node] !== parentId) throw new Error(`node ${node}: parent ${this.parent[node]}`)
      const a = this.child1[node]
      const c = this.child2[node]
      if (a === NULL_NODE) {
        if (c !== NULL_NODE || this.height[node] !== 0) throw new Error(`leaf ${node} malformed`)
        leaves++
        return
      }
      const h = 1 + Math.max(this.height[a], this.height[c])
      if (this.height[node] !== h) throw new Error(`node ${node}: height ${this.height[node]} != ${h}`)
      const b = this.bounds
      for (let k = 0; k < 2; k++) {
        const lo = Math.min(b[4 * a + k], b[4 * c + k])
        const hi = Math.max(b[4 * a + 2 + k], b[4 * c + 2 + k])
        if (b[4 * node + k] !== lo || b[4 * node + 2 + k] !== hi) throw new Error(`node ${node}: box`)
      }
      check(a, node)
      check(c, node)
    }
    if (this.root !== NULL_NODE) check(this.root, NULL_NODE)
    if (leaves !== this.leafCount) throw new Error(`leaf count ${leaves} != ${this.leafCount}`)
    let free = 0
    for (let n = this.freeList; n !== NULL_NODE; n = this.parent[n]) {
      if (this.height[n] !== -1) throw new Error(`free node ${n} has height ${this.height[n]}`)
      free++
    }
    if (free + live !== this.capacity) throw new Error(`nodes lost: ${free} free + ${live} live`)
  }

  private allocateNode(): number {
    if (this.freeList === NULL_NODE) this.grow(this.capacity * 2)
    const node = this.freeList
    this.freeList = this.parent[node]
    this.parent[node] = NULL_NODE
    this.child1[node] = NULL_NODE
    this.child2[node] = NULL_NODE
    this.height[node] = 0
    this.body[node] = 0
    this.flags[node] = 0
    return node
  }

  private freeNode(node: number): void {
    this.parent[node] = this.freeList
    this.height[node] = -1
    this.freeList = node
  }

  private grow(capacity: number): void {
    const old = this.capacity
    const bounds = new Float64Array(4 * capacity)
    bounds.set(this.bounds)
    this.bounds = bounds
    this.parent = copyInto(new Int32Array(capacity), this.parent)
    this.child1 = copyInto(new Int32Array(capacity), this.child1)
    this.child2 = copyInto(new Int32Array(capacity), this.child2)
    this.height = copyInto(new Int32Array(capacity), this.height)
    this.body = copyInto(new Int32Array(capacity), this.body)
    this.flags = copyInto(new Int32Array(capacity), this.flags)
    // A depth-first walk holds at most height + 1 <= node count entries.
    this.stack = new Int32Array(capacity + 2)
    // Chain the new nodes onto the free list in ascending order.
    for (let n = old; n < capacity; n++) {
      this.parent[n] = n + 1 < capacity ? n + 1 : this.freeList
      this.height[n] = -1
    }
    this.freeList = old
    this.capacity = capacity
  }

  private growHits(): Int32Array {
    const hits = new Int32Array(this.hits.length * 2)
    hits.set(this.hits)
    this.hits = hits
    return hits
  }

  /** Surface-area heuristic descent to the best sibling, then refit and rebalance upwards. */
  private insertLeaf(leaf: number): void {
    if (this.root === NULL_NODE) {
      this.root = leaf
      this.parent[leaf] = NULL_NODE
      return
    }
    const sibling = this.findBestSibling(leaf)
    const newParent = this.allocateNode()
    const b = this.bounds
    const parent = this.parent
    const oldParent = parent[sibling]
    parent[newParent] = oldParent
    setUnion(b, newParent, leaf, sibling)
    this.height[newParent] = this.height[sibling] + 1
    if (oldParent !== NULL_NODE) {
      if (this.child1[oldParent] === sibling) this.child1[oldParent] = newParent
      else this.child2[oldParent] = newParent
    } else {
      this.root = newParent
    }
    this.child1[newParent] = sibling
    this.child2[newParent] = leaf
    parent[sibling] = newParent
    parent[leaf] = newParent
    this.refitUpwards(parent[leaf])
  }

  /** Box2D v2.4 `InsertLeaf` descent: stop where pairing with this node is cheaper than going down. */
  private findBestSibling(leaf: number): number {
    const b = this.bounds
    const c1 = this.child1
    const c2 = this.child2
    const lx0 = b[4 * leaf]
    const ly0 = b[4 * leaf + 1]
    const lx1 = b[4 * leaf + 2]
    const ly1 = b[4 * leaf + 3]
    let index = this.root
    while (c1[index] !== NULL_NODE) {
      const o = 4 * index
      const area = b[o + 2] - b[o] + (b[o + 3] - b[o + 1])
      const combined =
        Math.max(b[o + 2], lx1) - Math.min(b[o], lx0) + (Math.max(b[o + 3], ly1) - Math.min(b[o + 1], ly0))
      // Cost of a new parent for this node and the leaf; cost of pushing the leaf further down.
      const cost = 2 * combined
      const inheritance = 2 * (combined - area)
      const child1 = c1[index]
      const child2 = c2[index]
      const cost1 = descentCost(b, child1, c1[child1] === NULL_NODE, lx0, ly0, lx1, ly1) + inheritance
      const cost2 = descentCost(b, child2, c1[child2] === NULL_NODE, lx0, ly0, lx1, ly1) + inheritance
      if (cost < cost1 && cost < cost2) break
      index = cost1 < cost2 ? child1 : child2
    }
    return index
  }

  /** Detaches a leaf, frees its parent and refits upwards. */
  private removeLeaf(leaf: number): void {
    if (leaf === this.root) {
      this.root = NULL_NODE
      return
    }
    const parent = this.parent
    const p = parent[leaf]
    const grandParent = parent[p]
    const sibling = this.child1[p] === leaf ? this.child2[p] : this.child1[p]
    if (grandParent !== NULL_NODE) {
      if (this.child1[grandParent] === p) this.child1[grandParent] = sibling
      else this.child2[grandParent] = sibling
      parent[sibling] = grandParent
      this.freeNode(p)
      this.refitUpwards(grandParent)
    } else {
      this.root = sibling
      parent[sibling] = NULL_NODE
      this.freeNode(p)
    }
  }

  /**
   * From `index` towards the root: rebalance, then recompute height and box from the children.
   * Stops early once a node (after the first) keeps its height and box and was not rotated: its
   * ancestors then depend on exactly what they depended on before.
   */
  private refitUpwards(index: number): void {
    const b = this.bounds
    const height = this.height
    const c1 = this.child1
    const c2 = this.child2
    let first = true
    while (index !== NULL_NODE) {
      const top = this.balance(index)
      const child1 = c1[top]
      const child2 = c2[top]
      const h = 1 + Math.max(height[child1], height[child2])
      const o = 4 * top
      const p = 4 * child1
      const q = 4 * child2
      const minX = Math.min(b[p], b[q])
      const minY = Math.min(b[p + 1], b[q + 1])
      const maxX = Math.max(b[p + 2], b[q + 2])
      const maxY = Math.max(b[p + 3], b[q + 3])
      if (
        !first &&
        top === index &&
        height[top] === h &&
        b[o] === minX &&
        b[o + 1] === minY &&
        b[o + 2] === maxX &&
        b[o + 3] === maxY
      ) {
        return
      }
      first = false
      height[top] = h
      b[o] = minX
      b[o + 1] = minY
      b[o + 2] = maxX
      b[o + 3] = maxY
      index = this.parent[top]
    }
  }

  /** Box2D v2.4 `Balance`: if one child of A is more than one level taller, rotate it up. */
  private balance(iA: number): number {
    const height = this.height
    if (this.child1[iA] === NULL_NODE || height[iA] < 2) return iA
    const iB = this.child1[iA]
    const iC = this.child2[iA]
    const diff = height[iC] - height[iB]
    if (diff > 1) return this.rotateUp(iA, iC, iB, true)
    if (diff < -1) return this.rotateUp(iA, iB, iC, false)
    return iA
  }

  /**
   * Rotates the tall child `iT` of `iA` above it (`iS` is A's other child). A keeps `iS` and the
   * shorter of T's children; T keeps A and its taller child. `tallIsSecond` says which slot of A
   * held T, so the result matches Box2D's two mirrored cases exactly.
   */
  private rotateUp(iA: number, iT: number, iS: number, tallIsSecond: boolean): number {
    const b = this.bounds
    const parent = this.parent
    const c1 = this.child1
    const c2 = this.child2
    const height = this.height
    const iF = c1[iT]
    const iG = c2[iT]
    // T takes A's place under A's parent.
    c1[iT] = iA
    parent[iT] = parent[iA]
    parent[iA] = iT
    const up = parent[iT]
    if (up !== NULL_NODE) {
      if (c1[up] === iA) c1[up] = iT
      else c2[up] = iT
    } else {
      this.root = iT
    }
    const keep = height[iF] > height[iG] ? iF : iG
    const give = keep === iF ? iG : iF
    c2[iT] = keep
    if (tallIsSecond) c2[iA] = give
    else c1[iA] = give
    parent[give] = iA
    setUnion(b, iA, iS, give)
    setUnion(b, iT, iA, keep)
    height[iA] = 1 + Math.max(height[iS], height[give])
    height[iT] = 1 + Math.max(height[iA], height[keep])
    return iT
  }
}

/** Cost of descending into `child` with the leaf box: Box2D v2.4's cost1/cost2 without inheritance. */
function descentCost(
  b: Float64Array,
  child: number,
  isLeaf: boolean,
  lx0: number,
  ly0: number,
  lx1: number,
  ly1: number,
): number {
  const o = 4 * child
  const union =
    Math.max(b[o + 2], lx1) - Math.min(b[o], lx0) + (Math.max(b[o + 3], ly1) - Math.min(b[o + 1], ly0))
  if (isLeaf) return union
  return union - (b[o + 2] - b[o] + (b[o + 3] - b[o + 1]))
}

/** bounds[node] = union(bounds[a], bounds[c]). */
function setUnion(b: Float64Array, node: number, a: number, c: number): void {
  const o = 4 * node
  const p = 4 * a
  const q = 4 * c
  b[o] = Math.min(b[p], b[q])
  b[o + 1] = Math.min(b[p + 1], b[q + 1])
  b[o + 2] = Math.max(b[p + 2], b[q + 2])
  b[o + 3] = Math.max(b[p + 3], b[q + 3])
}

function copyInto(to: Int32Array, from: Int32Array): Int32Array {
  to.set(from)
  return to
}
