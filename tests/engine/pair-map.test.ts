/*
 * PairMap (engine/collision/pair-map.ts), the world's contacts by body pair, against a JavaScript Map keyed
 * by the exact pair key a * 2^26 + b: the same answers after every operation of long random
 * sequences of inserts, replacements and deletions (with many collisions in a small table and
 * ids up to 2^26 - 1), including deletions that shift probe runs across the table's wrap-around.
 */
import { describe, expect, it } from 'vitest'
import { PairMap } from '../../engine/collision/pair-map.ts'
import { Prng } from '../../engine/index.ts'

const SCALE = 67108864

/** Random operations on both maps, comparing every lookup and the sizes. */
function compareRandom(seed: number, ops: number, idRange: number): void {
  const prng = new Prng(seed)
  const map = new PairMap<number>()
  const oracle = new Map<number, number>()
  const pair = (): [number, number] => {
    const x = prng.int(idRange)
    const y = prng.int(idRange)
    return x < y ? [x, y] : [y, x + 1]
  }
  for (let i = 0; i < ops; i++) {
    const [a, b] = pair()
    const key = a * SCALE + b
    const op = prng.int(10)
    if (op < 5) {
      map.set(a, b, i)
      oracle.set(key, i)
    } else if (op < 8) {
      expect(map.delete(a, b)).toBe(oracle.delete(key))
    } else {
      expect(map.get(a, b)).toBe(oracle.get(key))
      expect(map.has(a, b)).toBe(oracle.has(key))
    }
    expect(map.size).toBe(oracle.size)
  }
  for (const [key, value] of oracle) {
    const a = Math.floor(key / SCALE)
    expect(map.get(a, key - a * SCALE)).toBe(value)
  }
}

describe('PairMap', () => {
  it('matches a Map keyed by a * 2^26 + b over 20,000 random operations on 40 ids (dense, many collisions)', () => {
    compareRandom(1, 20_000, 40)
  })

  it('matches a Map over 20,000 random operations on ids up to 2^26 - 2 (keys far above 2^30)', () => {
    compareRandom(2, 20_000, SCALE - 2)
  })

  it('keeps every other pair findable when pairs are deleted in any order after growth', () => {
    const map = new PairMap<string>()
    const pairs: [number, number][] = []
    for (let a = 0; a < 30; a++) for (let b = a + 1; b < a + 8; b++) pairs.push([a, b])
    for (const [a, b] of pairs) map.set(a, b, `${a}-${b}`)
    expect(map.size).toBe(pairs.length)
    const prng = new Prng(3)
    while (pairs.length > 0) {
      const [a, b] = pairs.splice(prng.int(pairs.length), 1)[0]
      expect(map.delete(a, b)).toBe(true)
      expect(map.has(a, b)).toBe(false)
      for (const [c, d] of pairs) expect(map.get(c, d)).toBe(`${c}-${d}`)
    }
    expect(map.size).toBe(0)
    map.set(5, 9, 'again')
    expect(map.get(5, 9)).toBe('again')
    map.clear()
    expect(map.has(5, 9)).toBe(false)
  })
})
