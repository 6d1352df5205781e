/*
 * atan2InPlace (engine/math.ts) is atan2 written without calls that return doubles, for the joint
 * solvers' hot path: it must give the same bits as atan2 for every input, or every trajectory with
 * a revolute limit or motor would change.
 */
import { describe, expect, it } from 'vitest'
import { atan2, atan2InPlace } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'

const io = new Float64Array(2)
function inPlace(y: number, x: number): number {
  io[0] = y
  io[1] = x
  atan2InPlace(io)
  return io[0]
}

describe('atan2InPlace', () => {
  it('gives the bits of atan2 on 300,000 seeded pairs over every octant and 40 orders of magnitude', () => {
    const random = new Prng(27)
    let differ = 0
    for (let i = 0; i < 300_000; i++) {
      const y = (random.next() * 2 - 1) * 10 ** Math.floor(random.next() * 40 - 20)
      const x = (random.next() * 2 - 1) * 10 ** Math.floor(random.next() * 40 - 20)
      if (!Object.is(inPlace(y, x), atan2(y, x))) differ++
      // Unit rotations, as the joint solvers pass them.
      const a = random.next() * 7 - 3.5
      const c = Math.cos(a)
      const s = Math.sin(a)
      if (!Object.is(inPlace(s, c), atan2(s, c))) differ++
    }
    expect(differ).toBe(0)
  })

  it('gives the bits of atan2 on zeros, infinities, NaN, the thresholds and the axes', () => {
    const values = [0, -0, 1, -1, 1e-300, -1e-300, 5e-324, 1e300, -1e300, Infinity, -Infinity, Number.NaN]
    for (const t of [0.4375, 0.6875, 1.1875, 2.4375, 7.37e19])
      values.push(t, -t, t * (1 + 2 ** -52), t * (1 - 2 ** -53))
    for (const y of values)
      for (const x of values) expect(Object.is(inPlace(y, x), atan2(y, x)), `atan2(${y}, ${x})`).toBe(true)
  })
})
