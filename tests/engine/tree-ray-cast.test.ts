/*
 * The callback-free tree ray cast (engine/queries/tree-ray-cast.ts) against a brute-force loop over all
 * proxies of a random 1,000-AABB DynamicTree: the slab test (Kay-Kajiya) decides which boxes a
 * ray segment touches and where it enters each. Unclipped, the cursor must return exactly the
 * touched leaves; clipped by the closest entry so far, it must find the brute-force closest box.
 * The tree's AABB query (used by the overlap queries) is checked the same way.
 */
import { describe, expect, it } from 'vitest'
import { DynamicTree, NULL_NODE } from '../../engine/collision/dynamic-tree.ts'
import { Prng } from '../../engine/prng.ts'
import type { RayCastInput } from '../../engine/queries/ray-cast.ts'
import { TreeRayCast } from '../../engine/queries/tree-ray-cast.ts'

interface Box {
  minX: number
  minY: number
  maxX: number
  maxY: number
}

/** Entry fraction of the ray segment into the box (slab test), or null if it misses. */
function slab(input: RayCastInput, b: Box): number | null {
  let lo = 0
  let hi = input.maxFraction
  const o = [input.origin.x, input.origin.y]
  const d = [input.translation.x, input.translation.y]
  const mins = [b.minX, b.minY]
  const maxs = [b.maxX, b.maxY]
  for (let k = 0; k < 2; k++) {
    if (d[k] === 0) {
      if (o[k] < mins[k] || o[k] > maxs[k]) return null
      continue
    }
    let t1 = (mins[k] - o[k]) / d[k]
    let t2 = (maxs[k] - o[k]) / d[k]
    if (t1 > t2) [t1, t2] = [t2, t1]
    lo = Math.max(lo, t1)
    hi = Math.min(hi, t2)
    if (lo > hi) return null
  }
  return lo
}

function buildTree(seed: number, n: number): { tree: DynamicTree; boxes: Map<number, Box> } {
  const rng = new Prng(seed)
  const tree = new DynamicTree()
  const boxes = new Map<number, Box>()
  const leaves: number[] = []
  for (let i = 0; i < n + 200; i++) {
    const x = rng.range(-50, 50)
    const y = rng.range(-50, 50)
    const b = { minX: x, minY: y, maxX: x + rng.range(0.1, 3), maxY: y + rng.range(0.1, 3) }
    const leaf = tree.createLeaf(b.minX, b.minY, b.maxX, b.maxY, i + 1, 0)
    boxes.set(leaf, b)
    leaves.push(leaf)
  }
  // Destroy 200 at random so the tree has freed and reused nodes, as a world's does.
  for (let k = 0; k < 200; k++) {
    const i = rng.int(leaves.length)
    const leaf = leaves[i]
    leaves.splice(i, 1)
    tree.destroyLeaf(leaf)
    boxes.delete(leaf)
  }
  tree.validate()
  expect(boxes.size).toBe(n)
  return { tree, boxes }
}

function randomRay(rng: Prng, k: number): RayCastInput {
  const origin = { x: rng.range(-60, 60), y: rng.range(-60, 60) }
  let translation = { x: rng.range(-80, 80), y: rng.range(-80, 80) }
  if (k % 10 === 0) translation = { x: translation.x, y: 0 } // axis-parallel
  if (k % 10 === 1) translation = { x: 0, y: translation.y }
  if (k % 50 === 2) translation = { x: 0, y: 0 } // a point
  return { origin, translation, maxFraction: k % 3 === 0 ? rng.range(0.2, 1.5) : 1 }
}

describe('TreeRayCast against brute force over a 1,000-AABB tree', () => {
  const { tree, boxes } = buildTree(42, 1000)

  it('unclipped: returns exactly the leaves whose boxes the ray segment touches, each once (600 rays)', () => {
    const rng = new Prng(1)
    const cursor = new TreeRayCast()
    let total = 0
    for (let k = 0; k < 600; k++) {
      const input = randomRay(rng, k)
      const expected = [...boxes.entries()]
        .filter(([, b]) => slab(input, b) !== null)
        .map(([leaf]) => leaf)
        .sort((a, b) => a - b)
      const got: number[] = []
      cursor.begin(tree, input)
      for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) got.push(leaf)
      expect(got.length).toBe(new Set(got).size)
      expect([...got].sort((a, b) => a - b)).toEqual(expected)
      total += expected.length
    }
    expect(total).toBeGreaterThan(1000)
  })

  it('clipped by the closest entry so far: finds the brute-force closest box and fraction (600 rays), visiting fewer nodes', () => {
    const rng = new Prng(2)
    const cursor = new TreeRayCast()
    const hit = { fraction: 0 }
    let hits = 0
    let clippedVisits = 0
    let fullVisits = 0
    for (let k = 0; k < 600; k++) {
      const input = randomRay(rng, k)
      let bestLeaf = NULL_NODE
      let bestFraction = Number.POSITIVE_INFINITY
      for (const [leaf, b] of boxes) {
        const f = slab(input, b)
        if (f !== null && (f < bestFraction || (f === bestFraction && leaf < bestLeaf))) {
          bestFraction = f
          bestLeaf = leaf
        }
      }
      cursor.begin(tree, input)
      let gotLeaf = NULL_NODE
      let gotFraction = Number.POSITIVE_INFINITY
      for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) {
        const f = slab({ ...input, maxFraction: cursor.maxFraction }, boxes.get(leaf) as Box)
        if (f !== null && (f < gotFraction || (f === gotFraction && leaf < gotLeaf))) {
          gotFraction = f
          gotLeaf = leaf
          hit.fraction = f
          cursor.clip(hit)
        }
      }
      clippedVisits += cursor.nodeVisits
      expect(gotLeaf).toBe(bestLeaf)
      if (bestLeaf !== NULL_NODE) {
        hits++
        expect(gotFraction).toBe(bestFraction)
        expect(cursor.maxFraction).toBe(bestFraction)
      }
      cursor.begin(tree, input)
      while (cursor.next() !== NULL_NODE) {}
      fullVisits += cursor.nodeVisits
    }
    console.log(
      `tree ray cast: ${hits} closest hits; node visits clipped ${clippedVisits}, unclipped ${fullVisits}`,
    )
    expect(hits).toBeGreaterThan(200)
    expect(clippedVisits).toBeLessThan(fullVisits)
  })

  it('with an extension: exactly the leaves a swept box of those half extents touches (Minkowski-inflated slab test, 300 sweeps)', () => {
    const rng = new Prng(5)
    const cursor = new TreeRayCast()
    let total = 0
    for (let k = 0; k < 300; k++) {
      const input = randomRay(rng, k)
      const h = { x: rng.range(0, 2), y: rng.range(0, 2) }
      const expected = [...boxes.entries()]
        .filter(
          ([, b]) =>
            slab(input, {
              minX: b.minX - h.x,
              minY: b.minY - h.y,
              maxX: b.maxX + h.x,
              maxY: b.maxY + h.y,
            }) !== null,
        )
        .map(([leaf]) => leaf)
        .sort((a, b) => a - b)
      const got: number[] = []
      cursor.begin(tree, input, h)
      for (let leaf = cursor.next(); leaf !== NULL_NODE; leaf = cursor.next()) got.push(leaf)
      expect([...got].sort((a, b) => a - b)).toEqual(expected)
      total += expected.length
    }
    expect(total).toBeGreaterThan(1000)
    expect(() => cursor.begin(tree, randomRay(rng, 1), { x: -1, y: 0 })).toThrow(
      /extension must be finite and >= 0/,
    )
  })

  it('gives the same leaves in the same order twice, and nothing for an empty tree', () => {
    const rng = new Prng(3)
    const a = new TreeRayCast()
    const b = new TreeRayCast()
    for (let k = 0; k < 50; k++) {
      const input = randomRay(rng, k)
      a.begin(tree, input)
      b.begin(tree, input)
      for (let leaf = a.next(); ; leaf = a.next()) {
        expect(b.next()).toBe(leaf)
        if (leaf === NULL_NODE) break
      }
    }
    const empty = new TreeRayCast()
    empty.begin(new DynamicTree(), randomRay(rng, 5))
    expect(empty.next()).toBe(NULL_NODE)
  })

  it('stop() ends the walk; bad input is refused by name', () => {
    const cursor = new TreeRayCast()
    cursor.begin(tree, { origin: { x: -60, y: 0 }, translation: { x: 120, y: 0 }, maxFraction: 1 })
    expect(cursor.next()).not.toBe(NULL_NODE)
    cursor.stop()
    expect(cursor.next()).toBe(NULL_NODE)
    expect(() =>
      cursor.begin(tree, { origin: { x: Number.NaN, y: 0 }, translation: { x: 1, y: 0 }, maxFraction: 1 }),
    ).toThrow(/finite origin and translation/)
    expect(() =>
      cursor.begin(tree, { origin: { x: 0, y: 0 }, translation: { x: 1, y: 0 }, maxFraction: Number.NaN }),
    ).toThrow(/maxFraction must be a finite number >= 0, got NaN/)
  })

  it('the AABB query (DynamicTree.queryLeaves) matches a brute-force overlap loop (300 boxes)', () => {
    const rng = new Prng(4)
    const query = new Float64Array(4)
    for (let k = 0; k < 300; k++) {
      const x = rng.range(-60, 60)
      const y = rng.range(-60, 60)
      query.set([x, y, x + rng.range(0, 20), y + rng.range(0, 20)])
      const expected = [...boxes.entries()]
        .filter(
          ([, b]) => !(b.minX > query[2] || b.minY > query[3] || query[0] > b.maxX || query[1] > b.maxY),
        )
        .map(([leaf]) => leaf)
        .sort((a, b) => a - b)
      const count = tree.queryLeaves(query, 0)
      expect([...tree.hits.subarray(0, count)].sort((a, b) => a - b)).toEqual(expected)
    }
  })
})
