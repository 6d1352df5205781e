/*
 * The broadphase against brute force. The test keeps its own model of every proxy (tight AABB and
 * the fat AABB the rules say it must have: tight +- margin for dynamic proxies, re-fattened only
 * when the tight box leaves the fat one), and compares the tree's answers with O(n^2) loops over
 * that model: same pairs, same order.
 */
import { describe, expect, it } from 'vitest'
import { BroadPhase, IdBuffer, PairBuffer, sortKeys } from '../../engine/collision/broad-phase.ts'
import { Prng } from '../../engine/prng.ts'

const MARGIN = 0.1
const SCALE = 67108864

interface Proxy {
  proxy: number
  body: number
  isStatic: boolean
  tight: number[]
  fat: number[]
}

function overlaps(p: number[], q: number[]): boolean {
  return p[0] <= q[2] && q[0] <= p[2] && p[1] <= q[3] && q[1] <= p[3]
}

function contains(fat: number[], tight: number[]): boolean {
  return fat[0] <= tight[0] && fat[1] <= tight[1] && tight[2] <= fat[2] && tight[3] <= fat[3]
}

function fatten(t: number[], r: number): number[] {
  return [t[0] - r, t[1] - r, t[2] + r, t[3] + r]
}

/** Brute force: every overlapping pair of boxes (not static-static) as sorted keys a * 2^26 + b. */
function bruteForcePairs(live: Proxy[], box: 'fat' | 'tight'): number[] {
  const n = live.length
  const flat = new Float64Array(4 * n)
  for (let i = 0; i < n; i++) flat.set(live[i][box], 4 * i)
  const keys: number[] = []
  for (let i = 0; i < n; i++) {
    const x0 = flat[4 * i]
    const y0 = flat[4 * i + 1]
    const x1 = flat[4 * i + 2]
    const y1 = flat[4 * i + 3]
    for (let j = i + 1; j < n; j++) {
      const o = 4 * j
      if (x0 > flat[o + 2] || flat[o] > x1 || y0 > flat[o + 3] || flat[o + 1] > y1) continue
      const p = live[i]
      const q = live[j]
      if (p.isStatic && q.isStatic) continue
      keys.push(Math.min(p.body, q.body) * SCALE + Math.max(p.body, q.body))
    }
  }
  return keys.sort((x, y) => x - y)
}

/** The pairs as keys, after checking count, a < b and strictly ascending order. */
function pairKeys(pairs: PairBuffer, count: number): number[] {
  expect(pairs.count).toBe(count)
  const keys: number[] = []
  let ordered = true
  for (let i = 0; i < count; i++) {
    if (!(pairs.a[i] < pairs.b[i])) ordered = false
    keys.push(pairs.a[i] * SCALE + pairs.b[i])
    if (i > 0 && !(keys[i] > keys[i - 1])) ordered = false
  }
  expect(ordered, 'pairs have a < b and are strictly ascending').toBe(true)
  return keys
}

/** A random tight AABB: mostly 0.05-2 m, some 2-10 m, a few 10-50 m, inside a square of side `world`. */
function randomBox(prng: Prng, world: number): number[] {
  const kind = prng.next()
  const size = kind < 0.85 ? prng.range(0.05, 2) : kind < 0.96 ? prng.range(2, 10) : prng.range(10, 50)
  const aspect = prng.range(0.2, 1)
  const w = prng.next() < 0.5 ? size : size * aspect
  const h = w === size ? size * aspect : size
  const x = prng.range(-world / 2, world / 2)
  const y = prng.range(-world / 2, world / 2)
  return [x - w / 2, y - h / 2, x + w / 2, y + h / 2]
}

/** A broadphase plus the test's independent model of what it should hold. */
class Harness {
  readonly bp = new BroadPhase(MARGIN)
  readonly live = new Map<number, Proxy>()
  nextBody = 1

  create(tight: number[], isStatic: boolean): Proxy {
    const body = this.nextBody++
    const proxy = this.bp.createProxy(tight[0], tight[1], tight[2], tight[3], body, isStatic)
    const entry = { proxy, body, isStatic, tight, fat: fatten(tight, isStatic ? 0 : MARGIN) }
    this.live.set(body, entry)
    return entry
  }

  destroy(entry: Proxy): void {
    this.bp.destroyProxy(entry.proxy)
    this.live.delete(entry.body)
  }

  /** Moves a proxy, checking the answer against the model; returns whether it was re-fattened. */
  move(entry: Proxy, tight: number[]): boolean {
    const expected = !contains(entry.fat, tight)
    const moved = this.bp.moveProxy(entry.proxy, tight[0], tight[1], tight[2], tight[3])
    if (moved !== expected) expect(moved, `moveProxy(body ${entry.body})`).toBe(expected)
    entry.tight = tight
    if (expected) entry.fat = fatten(tight, entry.isStatic ? 0 : MARGIN)
    return expected
  }

  /** Every proxy's fat AABB in the tree equals the model's. */
  checkFatAABBs(): void {
    const out = new Float64Array(4)
    const wrong: number[] = []
    for (const e of this.live.values()) {
      this.bp.getFatAABB(e.proxy, out)
      if (out[0] !== e.fat[0] || out[1] !== e.fat[1] || out[2] !== e.fat[2] || out[3] !== e.fat[3]) {
        wrong.push(e.body)
      }
    }
    expect(wrong, 'bodies whose fat AABB differs from the model').toEqual([])
  }

  entries(): Proxy[] {
    return [...this.live.values()]
  }
}

function randomScene(n: number, seed: number): Harness {
  const prng = new Prng(seed)
  const h = new Harness()
  const world = 2 * Math.sqrt(n)
  for (let i = 0; i < n; i++) h.create(randomBox(prng, world), prng.next() < 0.1)
  return h
}

describe('BroadPhase', () => {
  it('reports touching fat boxes and nothing else in a hand-built scene', () => {
    const bp = new BroadPhase(0.5)
    bp.createProxy(0, 0, 1, 1, 7, false) // fat [-0.5, 1.5]
    bp.createProxy(2.5, 0, 3, 1, 3, false) // fat [2, 3.5]: touches nothing (gap 0.5)
    bp.createProxy(1.5, 1.5, 1.9, 2, 9, true) // static, not fattened: touches body 7's fat corner
    bp.createProxy(2, 0, 2.1, 0.1, 5, true) // static, touches body 3's fat box at x = 2
    const pairs = new PairBuffer(1)
    expect(bp.allPairs(pairs)).toBe(2)
    expect([pairs.a[0], pairs.b[0], pairs.a[1], pairs.b[1]]).toEqual([3, 5, 7, 9])
    expect(bp.updatePairs(pairs)).toBe(2)
    expect(bp.updatePairs(pairs)).toBe(0)
  })

  for (const [n, seed] of [
    [250, 1],
    [1000, 2],
    [4000, 3],
  ]) {
    it(`allPairs equals the brute-force list for ${n} mixed-size proxies`, () => {
      const h = randomScene(n, seed)
      h.bp.validateTree()
      h.checkFatAABBs()
      const pairs = new PairBuffer()
      const count = h.bp.allPairs(pairs)
      expect(pairKeys(pairs, count)).toEqual(bruteForcePairs(h.entries(), 'fat'))
      expect(count).toBeGreaterThan(n / 4)
      // The first updatePairs sees every proxy as new, so it finds the same list.
      expect(pairKeys(pairs, h.bp.updatePairs(pairs))).toEqual(bruteForcePairs(h.entries(), 'fat'))
    })
  }

  it('keeps the tree shallow: 4,000 random proxies give a height within 2 log2(n)', () => {
    const h = randomScene(4000, 4)
    const height = h.bp.treeHeight
    console.log(`tree height for 4,000 random proxies: ${height}`)
    expect(height).toBeLessThanOrEqual(2 * Math.log2(4000))
  })

  for (const [n, seed] of [
    [250, 5],
    [1000, 6],
  ]) {
    it(`over 50 frames of motion, the kept pair set equals brute force (${n} proxies)`, () => {
      const prng = new Prng(seed)
      const world = 2 * Math.sqrt(n)
      const h = new Harness()
      for (let i = 0; i < n; i++) h.create(randomBox(prng, world), prng.next() < 0.1)
      const kept = new Set<number>()
      const pairs = new PairBuffer(4)
      for (let frame = 0; frame < 50; frame++) {
        stepFrame(h, prng, world, kept)
        const count = h.bp.updatePairs(pairs)
        const reported = pairKeys(pairs, count)
        const invalid = reported.filter((key) => {
          const e = h.live.get(Math.floor(key / SCALE))
          const f = h.live.get(key % SCALE)
          return !e || !f || (e.isStatic && f.isStatic)
        })
        expect(invalid, 'pairs of destroyed proxies or of two statics').toEqual([])
        for (const key of reported) kept.add(key)
        // The world drops contacts whose fat boxes separated.
        for (const key of kept) {
          const a = Math.floor(key / SCALE)
          if (!overlaps(h.live.get(a)!.fat, h.live.get(key - a * SCALE)!.fat)) kept.delete(key)
        }
        const entries = h.entries()
        expect([...kept].sort((x, y) => x - y)).toEqual(bruteForcePairs(entries, 'fat'))
        const missed = bruteForcePairs(entries, 'tight').filter((key) => !kept.has(key))
        expect(missed, 'tight-overlapping pairs missing').toEqual([])
        h.checkFatAABBs()
      }
      h.bp.validateTree()
    })
  }

  it('never reports static-static pairs, even when statics are touched', () => {
    const h = new Harness()
    const statics = [
      h.create([0, 0, 10, 10], true),
      h.create([5, 5, 15, 15], true),
      h.create([1, 1, 2, 2], true),
    ]
    const ball = h.create([9, 9, 9.5, 9.5], false)
    const pairs = new PairBuffer()
    h.bp.updatePairs(pairs)
    for (const s of statics) h.bp.touchProxy(s.proxy)
    h.move(statics[2], [30, 30, 31, 31])
    const keys = pairKeys(pairs, h.bp.updatePairs(pairs))
    expect(keys).toEqual([1 * SCALE + 4, 2 * SCALE + 4])
    expect(pairKeys(pairs, h.bp.allPairs(pairs))).toEqual([1 * SCALE + 4, 2 * SCALE + 4])
    expect(ball.body).toBe(4)
  })

  it('never reports a destroyed proxy, even one destroyed while on the move list', () => {
    const h = new Harness()
    const a = h.create([0, 0, 1, 1], false)
    const b = h.create([0.5, 0.5, 1.5, 1.5], false)
    const c = h.create([0.2, 0.2, 0.8, 0.8], false)
    h.destroy(b)
    const pairs = new PairBuffer()
    expect(pairKeys(pairs, h.bp.updatePairs(pairs))).toEqual([a.body * SCALE + c.body])
    h.move(a, [5, 5, 6, 6])
    h.destroy(a)
    const d = h.create([0.1, 0.1, 0.3, 0.3], false) // may reuse a's or b's proxy id
    expect(pairKeys(pairs, h.bp.updatePairs(pairs))).toEqual([c.body * SCALE + d.body])
    expect(h.bp.proxyCount).toBe(2)
    h.bp.validateTree()
  })

  it('reports a body with two proxies once per partner and never with itself', () => {
    const bp = new BroadPhase()
    bp.createProxy(0, 0, 1, 1, 2, false)
    bp.createProxy(0.5, 0, 1.5, 1, 2, false) // a second shape of body 2, overlapping the first
    bp.createProxy(0.8, 0.8, 2, 2, 1, false) // overlaps both shapes of body 2
    const pairs = new PairBuffer()
    expect(pairKeys(pairs, bp.updatePairs(pairs))).toEqual([1 * SCALE + 2])
    expect(pairKeys(pairs, bp.allPairs(pairs))).toEqual([1 * SCALE + 2])
    const out = new IdBuffer()
    expect(bp.query(0.9, 0.9, 1, 1, out)).toBe(2)
    expect(Array.from(out.ids.subarray(0, 2))).toEqual([1, 2])
  })

  it('touchProxy makes the next updatePairs report exactly that proxy’s overlaps', () => {
    const h = randomScene(500, 7)
    const pairs = new PairBuffer()
    h.bp.updatePairs(pairs)
    expect(h.bp.updatePairs(pairs)).toBe(0)
    const entries = h.entries()
    const target = entries[123]
    h.bp.touchProxy(target.proxy)
    const expected = bruteForcePairs(entries, 'fat').filter((key) => {
      const a = Math.floor(key / SCALE)
      return a === target.body || key - a * SCALE === target.body
    })
    expect(pairKeys(pairs, h.bp.updatePairs(pairs))).toEqual(expected)
  })

  it('query returns the bodies a brute-force scan finds, ascending', () => {
    const h = randomScene(1000, 8)
    const prng = new Prng(9)
    const out = new IdBuffer(1)
    const entries = h.entries()
    for (let q = 0; q < 200; q++) {
      const box = q === 0 ? [...entries[5].fat] : randomBox(prng, 70)
      if (q === 1)
        box.splice(0, 4, entries[9].fat[2], entries[9].fat[3], entries[9].fat[2], entries[9].fat[3])
      const expected = entries
        .filter((e) => overlaps(e.fat, box))
        .map((e) => e.body)
        .sort((x, y) => x - y)
      const count = h.bp.query(box[0], box[1], box[2], box[3], out)
      expect(Array.from(out.ids.subarray(0, count))).toEqual(expected)
      if (q < 2) expect(count).toBeGreaterThan(0)
    }
  })

  it('a tree rebuilt from saved fat AABBs behaves identically from then on', () => {
    const prng = new Prng(10)
    const h = randomScene(600, 11)
    const pairs = new PairBuffer()
    for (let frame = 0; frame < 5; frame++) stepFrame(h, prng, 50, new Set())
    h.bp.updatePairs(pairs)
    const loaded = new BroadPhase(MARGIN)
    const proxyOf = new Map<number, number>()
    const fat = new Float64Array(4)
    for (const e of h.entries()) {
      h.bp.getFatAABB(e.proxy, fat)
      proxyOf.set(e.body, loaded.createProxyWithFatAABB(fat[0], fat[1], fat[2], fat[3], e.body, e.isStatic))
    }
    const loadedPairs = new PairBuffer()
    expect(pairKeys(loadedPairs, loaded.allPairs(loadedPairs))).toEqual(pairKeys(pairs, h.bp.allPairs(pairs)))
    loaded.updatePairs(loadedPairs)
    for (let frame = 0; frame < 10; frame++) {
      for (const e of h.entries()) {
        if (e.isStatic || prng.next() < 0.5) continue
        const t = e.tight
        const dx = prng.range(-0.15, 0.15)
        const box = [t[0] + dx, t[1], t[2] + dx, t[3]]
        const refattened = h.move(e, box)
        expect(loaded.moveProxy(proxyOf.get(e.body)!, box[0], box[1], box[2], box[3])).toBe(refattened)
      }
      const expected = pairKeys(pairs, h.bp.updatePairs(pairs))
      expect(pairKeys(loadedPairs, loaded.updatePairs(loadedPairs))).toEqual(expected)
    }
  })

  it('rejects body ids outside [1, 2^26), inverted boxes and dead proxies, naming the value', () => {
    const bp = new BroadPhase()
    expect(() => bp.createProxy(0, 0, 1, 1, 0, false)).toThrow(/body id 0/)
    expect(() => bp.createProxy(0, 0, 1, 1, SCALE, false)).toThrow(/67108864/)
    expect(() => bp.createProxy(0, 0, 1, 1, 1.5, false)).toThrow(/1.5/)
    expect(() => bp.createProxyWithFatAABB(2, 0, 1, 1, 3, false)).toThrow(/bad AABB/)
    const p = bp.createProxy(0, 0, 1, 1, SCALE - 1, false)
    bp.destroyProxy(p)
    expect(() => bp.destroyProxy(p)).toThrow(/not a live proxy/)
    expect(() => bp.touchProxy(p)).toThrow(/not a live proxy/)
    expect(() => bp.moveProxy(p, 5, 5, 6, 6)).toThrow(/not a live proxy/)
    expect(() => new BroadPhase(-1)).toThrow(/margin -1/)
  })

  it('is deterministic: the same operations give the same fat boxes, pairs and tree height', () => {
    const run = (): number[] => {
      const prng = new Prng(13)
      const h = randomScene(300, 14)
      const pairs = new PairBuffer()
      const out: number[] = []
      for (let frame = 0; frame < 10; frame++) {
        stepFrame(h, prng, 35, new Set())
        out.push(...pairKeys(pairs, h.bp.updatePairs(pairs)), h.bp.treeHeight)
      }
      const fat = new Float64Array(4)
      for (const e of h.entries()) {
        h.bp.getFatAABB(e.proxy, fat)
        out.push(e.proxy, ...fat)
      }
      return out
    }
    expect(run()).toEqual(run())
  })

  it('sortKeys sorts like TypedArray.prototype.sort, duplicates and presorted runs included', () => {
    const prng = new Prng(12)
    const stack = new Int32Array(128)
    for (const n of [0, 1, 2, 15, 16, 17, 100, 1000, 5000]) {
      for (const pattern of ['random', 'dups', 'sorted', 'reversed']) {
        const keys = new Float64Array(n + 3).fill(-1)
        for (let i = 0; i < n; i++) {
          if (pattern === 'random') keys[i] = prng.int(1 << 30) * SCALE + prng.int(1 << 26)
          else if (pattern === 'dups') keys[i] = prng.int(8)
          else keys[i] = pattern === 'sorted' ? i : n - i
        }
        const expected = keys.slice(0, n).sort()
        sortKeys(keys, n, stack)
        expect(keys.slice(0, n)).toEqual(expected)
        expect(Array.from(keys.subarray(n))).toEqual([-1, -1, -1])
      }
    }
  })
})

/** One frame of random motion: most proxies drift, some jump, a few are destroyed and created. */
function stepFrame(h: Harness, prng: Prng, world: number, kept: Set<number>): void {
  for (const e of h.entries()) {
    const roll = prng.next()
    if (roll < 0.01) {
      h.destroy(e)
      for (const key of [...kept]) {
        const a = Math.floor(key / SCALE)
        if (a === e.body || key - a * SCALE === e.body) kept.delete(key)
      }
      continue
    }
    if (e.isStatic || roll < 0.4) continue
    const t = e.tight
    const jump = roll > 0.97 ? prng.range(-world / 4, world / 4) : 0
    const dx = jump + prng.range(-0.08, 0.08)
    const dy = jump + prng.range(-0.08, 0.08)
    h.move(e, [t[0] + dx, t[1] + dy, t[2] + dx, t[3] + dy])
  }
  const births = prng.int(Math.max(2, h.live.size / 100))
  for (let i = 0; i < births; i++) h.create(randomBox(prng, world), prng.next() < 0.1)
}
