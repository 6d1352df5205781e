/*
 * The column search (engine/contact-columns.ts) on contact graphs written by hand: bodies are solver
 * state records 1, 2, ... (record 0 is the static ground), a contact is a pair of records and its
 * point count. The expected marks are read off the drawing in each test's name: a chain of at least
 * COLUMN_MIN_BODIES bodies standing on the ground, each body touching only the one below and the one
 * above, every link a two-point contact.
 */
import { describe, expect, it } from 'vitest'
import { STATE_STRIDE } from '../../engine/body-state.ts'
import { COLUMN_MIN_BODIES } from '../../engine/constants.ts'
import { ColumnMarks, markColumns } from '../../engine/contact-columns.ts'

/** Marks for contacts given as [recordA, recordB, points]; returns the 0/1 mark per contact. */
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
    expect(marksFor(chain(COLUMN_MIN_BODIES))).toEqual(new Array(COLUMN_MIN_BODIES).fill(1))
    expect(marksFor(chain(COLUMN_MIN_BODIES - 1))).toEqual(new Array(COLUMN_MIN_BODIES - 1).fill(0))
  })

  it('finds the column whatever the order of the contacts and of each pair', () => {
    const contacts = chain(20)
      .map(([a, b, p], k): [number, number, number] => (k % 3 === 0 ? [b, a, p] : [a, b, p]))
      .reverse()
    expect(marksFor(contacts)).toEqual(new Array(20).fill(1))
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
    expect(marks.slice(0, 15)).toEqual(new Array(15).fill(1))
    expect(marks.slice(15)).toEqual(new Array(5).fill(0))
    contacts[0][2] = 1 // now nothing stands on the ground by a face
    expect(marksFor(contacts)).toEqual(new Array(20).fill(0))
  })

  it('a column between the ground and a static ceiling is marked once from each end', () => {
    const contacts = [...chain(14), [14, 0, 2] as [number, number, number]]
    expect(marksFor(contacts)).toEqual(new Array(15).fill(1))
  })

  it('side-by-side columns are found independently, a pyramid has none', () => {
    const left = chain(13)
    const right = chain(5).map(([a, b, p]): [number, number, number] => [a === 0 ? 0 : a + 100, b + 100, p])
    expect(marksFor([...left, ...right])).toEqual([...new Array(13).fill(1), ...new Array(5).fill(0)])
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
