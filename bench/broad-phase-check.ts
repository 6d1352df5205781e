/*
 * Checks a running Concord world's broadphase against brute force: every pair of fat AABBs that
 * overlap (touching counts; pairs of static shapes excluded), one proxy per shape, found by the dynamic tree (allPairs)
 * and by an O(n^2) loop over the same boxes read back from the tree, must be the same list. The
 * benchmark page runs this on every run; tests/engine/broad-phase.test.ts does the same
 * comparison against its own model of the proxies.
 */

import type { World } from '../engine/index.ts'
import { PairBuffer } from '../engine/internal.ts'

/** Outcome of one comparison. */
export interface BroadPhaseCheck {
  /** Proxies compared (shapes with a broadphase proxy). */
  proxies: number
  /** Pairs the tree reported. */
  treePairs: number
  /** Pairs the brute-force loop found. */
  bruteForcePairs: number
  /** Whether both lists hold exactly the same pairs. */
  match: boolean
  /** The first pair only one side found, as "a-b (tree)" or "a-b (brute force)", or null. */
  firstDifference: string | null
}

const SCALE = 2 ** 26

/** Compares the world's broadphase pairs with brute force over the same fat AABBs. */
export function checkBroadPhase(world: World): BroadPhaseCheck {
  const bp = world.broadPhase
  // One proxy per shape (compound bodies have several); pairs are reported by shape ids.
  const live = world.bodies.flatMap((b) =>
    b.shapes
      .filter((s) => s.proxy >= 0)
      .map((s) => ({ id: s.id, proxy: s.proxy, isStatic: world.getBodyType(b.id) === 'static' })),
  )
  const n = live.length
  const boxes = new Float64Array(4 * n)
  const box = new Float64Array(4)
  const isStatic = live.map((s) => s.isStatic)
  live.forEach((s, i) => {
    bp.getFatAABB(s.proxy, box)
    boxes.set(box, 4 * i)
  })
  const brute: number[] = []
  for (let i = 0; i < n; i++) {
    for (let j = i + 1; j < n; j++) {
      if (isStatic[i] && isStatic[j]) continue
      const p = 4 * i
      const q = 4 * j
      if (
        boxes[p] > boxes[q + 2] ||
        boxes[q] > boxes[p + 2] ||
        boxes[p + 1] > boxes[q + 3] ||
        boxes[q + 1] > boxes[p + 3]
      )
        continue
      const a = Math.min(live[i].id, live[j].id)
      const b = Math.max(live[i].id, live[j].id)
      brute.push(a * SCALE + b)
    }
  }
  brute.sort((x, y) => x - y)
  const pairs = new PairBuffer()
  const count = bp.allPairs(pairs)
  const tree: number[] = []
  for (let i = 0; i < count; i++) tree.push(pairs.a[i] * SCALE + pairs.b[i])
  tree.sort((x, y) => x - y)
  const inTree = new Set(tree)
  const inBrute = new Set(brute)
  const name = (key: number): string => `${Math.floor(key / SCALE)}-${key % SCALE}`
  const onlyTree = tree.find((key) => !inBrute.has(key))
  const onlyBrute = brute.find((key) => !inTree.has(key))
  const firstDifference =
    onlyTree !== undefined
      ? `${name(onlyTree)} (tree)`
      : onlyBrute !== undefined
        ? `${name(onlyBrute)} (brute force)`
        : null
  const match = firstDifference === null && tree.length === brute.length
  return { proxies: n, treePairs: tree.length, bruteForcePairs: brute.length, match, firstDifference }
}
