/*
 * The column search (engine/dynamics/contact-columns.ts) on contact graphs written by hand: bodies are solver
 * state records 1, 2, ... (record 0 is the static ground), a contact is a pair of records and its
 * point count. The expected marks are read off the drawing in each test's name: a chain of at least
 * COLUMN_MIN_BODIES bodies standing on the ground, each body touching only the one below and the one
 * above, every link a two-point contact, marked with its height (at most COLUMN_MAX_BODIES). The
 * stiffness table is checked against the formula computed here with Math.pow.
 */
import { describe, expect, it } from 'vitest'
import {
  COLUMN_MAX_BODIES,
  COLUMN_MIN_BODIES,
  COLUMN_REFERENCE_FACTOR,
  COLUMN_STIFF_BODIES,
  EXTRA_SWEEP_BUDGET,
  EXTRA_SWEEP_FLOOR,
  PINCHED_EXTRA_ITERATIONS,
} from '../../engine/constants.ts'
import { STATE_STRIDE } from '../../engine/dynamics/body-state.ts'
import {
  bucklingFactor,
  ColumnMarks,
  ColumnStiffness,
  equivalentHeight,
  markColumns,
} from '../../engine/dynamics/contact-columns.ts'
import { Softness } from '../../engine/dynamics/softness.ts'

/** Marks for contacts given as [recordA, recordB, points]; returns each contact's column height or 0. */
function marksFor(contacts: [number, number, number][]): number[] {
  const n = contacts.length
  const graph = {
    stateA: Int32Array.from(contacts, ([a]) => a * STATE_STRIDE),
    stateB: Int32Array.from(contacts, ([, b]) => b * STATE_STRIDE),
    pointCount: Int32Array.from(contacts, ([, , p]) => p),
  }
  let records = 1
  for (const [a, b] of contacts) records = Math.max(records, a + 1, b + 1)
  const marks = new ColumnMarks()
  markColumns(marks, graph, n, records)
  return Array.from(marks.mark.subarray(0, n))
}

/** A column of `bodies` bodies on the ground: contact k joins body k (0 = ground) and body k + 1. */
function chain(bodies: number, points = 2): [number, number, number][] {
  const contacts: [number, number, number][] = []
  for (let k = 0; k < bodies; k++) contacts.push([k, k + 1, points])
  return contacts
}

describe('column search', () => {
  it(`marks every contact of a ${COLUMN_MIN_BODIES}-body column and none of a ${COLUMN_MIN_BODIES - 1}-body one`, () => {
    expect(marksFor(chain(COLUMN_MIN_BODIES))).toEqual(new Array(COLUMN_MIN_BODIES).fill(COLUMN_MIN_BODIES))
    expect(marksFor(chain(COLUMN_MIN_BODIES - 1))).toEqual(new Array(COLUMN_MIN_BODIES - 1).fill(0))
  })

  it('finds the column whatever the order of the contacts and of each pair', () => {
    const contacts = chain(20)
      .map(([a, b, p], k): [number, number, number] => (k % 3 === 0 ? [b, a, p] : [a, b, p]))
      .reverse()
    expect(marksFor(contacts)).toEqual(new Array(20).fill(20))
  })

  it(`marks a column taller than ${COLUMN_MAX_BODIES} bodies as ${COLUMN_MAX_BODIES} tall`, () => {
    expect(marksFor(chain(COLUMN_MAX_BODIES + 30))).toEqual(
      new Array(COLUMN_MAX_BODIES + 30).fill(COLUMN_MAX_BODIES),
    )
  })

  it('stops at a body touching a third one: a braced column is not one', () => {
    // 20 bodies; body 30 leans on body 8, so the column from the ground is bodies 1-7 (too short).
    const contacts = [...chain(20), [8, 30, 2] as [number, number, number]]
    expect(marksFor(contacts)).toEqual(new Array(21).fill(0))
  })

  it('stops at a one-point contact (a corner or a circle), and the part below counts alone', () => {
    const contacts = chain(20)
    contacts[15][2] = 1 // bodies 1-15 stand on two-point contacts
    const marks = marksFor(contacts)
    expect(marks.slice(0, 15)).toEqual(new Array(15).fill(15))
    expect(marks.slice(15)).toEqual(new Array(5).fill(0))
    contacts[0][2] = 1 // now nothing stands on the ground by a face
    expect(marksFor(contacts)).toEqual(new Array(20).fill(0))
  })

  it('a column between the ground and a static ceiling is marked once from each end', () => {
    const contacts = [...chain(14), [14, 0, 2] as [number, number, number]]
    expect(marksFor(contacts)).toEqual(new Array(15).fill(14))
  })

  it('side-by-side columns are found independently, a pyramid has none', () => {
    const left = chain(13)
    const right = chain(5).map(([a, b, p]): [number, number, number] => [a === 0 ? 0 : a + 100, b + 100, p])
    expect(marksFor([...left, ...right])).toEqual([...new Array(13).fill(13), ...new Array(5).fill(0)])
    // A 3-row pyramid: every body touches three or more, or stands on two.
    const pyramid: [number, number, number][] = [
      [0, 1, 2],
      [0, 2, 2],
      [0, 3, 2],
      [1, 2, 2],
      [2, 3, 2],
      [1, 4, 2],
      [2, 4, 2],
      [2, 5, 2],
      [3, 5, 2],
      [4, 5, 2],
      [4, 6, 2],
      [5, 6, 2],
    ]
    expect(marksFor(pyramid)).toEqual(new Array(pyramid.length).fill(0))
  })
})

describe('column stiffness table', () => {
  const h = 1 / 240
  const table = new ColumnStiffness()
  table.set(45, 10, h)
  it(`columns up to ${COLUMN_STIFF_BODIES} bodies get twice the contact hertz and ${PINCHED_EXTRA_ITERATIONS} extra sweeps`, () => {
    const ninety = new Softness().set(90, 10, h)
    for (const n of [COLUMN_MIN_BODIES, COLUMN_STIFF_BODIES]) {
      expect([table.biasRate[n], table.massScale[n], table.impulseScale[n]]).toEqual([
        ninety.biasRate,
        ninety.massScale,
        ninety.impulseScale,
      ])
      expect(table.sweeps[n]).toBe(PINCHED_EXTRA_ITERATIONS)
    }
  })
  it('taller columns: 90 Hz x (n / 20)^1.5 (a constant buckling factor), 3 x (hertz / 90)^1.5 extra sweeps', () => {
    // By hand: n = 25, 30, 40, 50 give 125.8, 165.3, 254.6, 355.8 Hz and 5, 8, 15, 24 sweeps.
    const hand = { 25: [125.8, 5], 30: [165.3, 8], 40: [254.6, 15], 50: [355.8, 24] } as const
    for (const [n, [hertz, sweeps]] of Object.entries(hand).map(([k, v]) => [Number(k), v] as const)) {
      const scale = (n / COLUMN_STIFF_BODIES) ** 1.5
      expect(90 * scale).toBeCloseTo(hertz, 1)
      const soft = new Softness().set(90 * scale, 10, h)
      expect(table.biasRate[n]).toBeCloseTo(soft.biasRate, 9)
      expect(table.massScale[n]).toBeCloseTo(soft.massScale, 12)
      expect(table.impulseScale[n]).toBeCloseTo(soft.impulseScale, 12)
      expect(table.sweeps[n]).toBe(sweeps)
    }
  })
})

describe('extra sweep budget', () => {
  const table = new ColumnStiffness()
  table.set(45, 10, 1 / 240)
  const limit = (extra: number, count: number, tallest: number) => {
    table.limit(extra, count, tallest)
    return [table.stepSweeps, table.stepCap]
  }
  it('a lone column, or one beside a large scene, gets what its height needs', () => {
    expect(limit(102, 102, 50)).toEqual([24, COLUMN_MAX_BODIES]) // two: 2,448 solves, under the 3,072 floor
    expect(limit(51, 1951, 50)).toEqual([24, COLUMN_MAX_BODIES])
    expect(limit(21, 21, 20)).toEqual([PINCHED_EXTRA_ITERATIONS, COLUMN_MAX_BODIES])
    expect(limit(5, 5, 0)).toEqual([PINCHED_EXTRA_ITERATIONS, COLUMN_MAX_BODIES])
  })
  it(`a forest of tall columns gets at most ${EXTRA_SWEEP_BUDGET} x its contacts, and columns only as stiff as that pays for`, () => {
    // 20 columns of 50: 1,020 contacts, all extra; the budget 3,060 pays 3 sweeps: 90 Hz columns.
    expect(limit(1020, 1020, 50)).toEqual([3, COLUMN_STIFF_BODIES])
    // 6 columns of 50 alone: 306 contacts, budget the floor 3,072: 10 sweeps, which pay up to 34
    // bodies (by hand: 3 x ((34 / 20)^1.5)^1.5 = 9.9, at 35 10.6).
    expect(limit(306, 306, 50)).toEqual([10, 34])
    expect(EXTRA_SWEEP_FLOOR).toBe(3072)
    // Never fewer sweeps than a pinched contact gets, and never more solves than the budget then.
    for (const [extra, count] of [
      [1020, 1020],
      [700, 2000],
      [306, 306],
    ]) {
      const [sweeps] = limit(extra, count, 50)
      expect(sweeps).toBeGreaterThanOrEqual(PINCHED_EXTRA_ITERATIONS)
      expect(extra * sweeps).toBeLessThanOrEqual(Math.max(EXTRA_SWEEP_FLOOR, EXTRA_SWEEP_BUDGET * count))
    }
  })
})

describe('buckling factor', () => {
  // The README's model of the alternating tower at 45 Hz: n rigid 1 m blocks (1 kg, g = 10) on
  // rotational springs 2 a^2 omega^2 / K (points at +-a = 0.475 m, K = 5 per kg between two boxes,
  // 2.5 against the ground, which runs at twice the hertz), load g (n - i - 0.5) on block i. An
  // independent implementation (Python, 200 halvings) gives 0.158509 / 1.338414 / 4.600697 for 10 /
  // 20 / 30 blocks.
  function tower(n: number): [Float64Array, Float64Array] {
    const omega = 2 * Math.PI * 45
    const k = new Float64Array(n).fill((2 * 0.475 ** 2 * omega ** 2) / 5)
    k[0] = (2 * 0.475 ** 2 * (2 * omega) ** 2) / 2.5
    const load = Float64Array.from({ length: n }, (_, i) => 10 * (n - i - 0.5))
    return [k, load]
  }
  it('matches the hand model of the 10-, 20- and 30-box towers at 45 Hz', () => {
    for (const [n, factor] of [
      [10, 0.158509],
      [20, 1.338414],
      [30, 4.600697],
    ]) {
      const [k, load] = tower(n)
      expect(bucklingFactor(n, k, load) / factor).toBeCloseTo(1, 4)
    }
  })
  it('a column of 1 m boxes counts as its own height; a heavier load as a taller one', () => {
    // c(n) = 106,384 (n / 20)^3 at unit stiffness, as extra-sweeps.ts weighs 1 m boxes.
    for (const n of [12, 20, 25, 30, 50])
      expect(equivalentHeight(106384 * (n / 20) ** 3)).toBeLessThanOrEqual(n)
    expect(equivalentHeight(106384 * (30 / 20) ** 3)).toBe(30)
    // 12.5 times the 20-box factor (a top five boxes 20 times denser) counts as 20 x 12.5^(1/3) = 46.4.
    expect(equivalentHeight(12.5 * COLUMN_REFERENCE_FACTOR)).toBe(47)
    expect(equivalentHeight(1e12)).toBe(COLUMN_MAX_BODIES)
  })
})
