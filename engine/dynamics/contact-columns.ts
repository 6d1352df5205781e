/*
 * Tall columns in the contact graph: chains of bodies standing on a static body, each body touching
 * at most two others (the one below and the one above), every link a two-point (face) manifold.
 *
 * Why they are special: a soft contact point sags F K / omega^2 under its load F (K its inverse
 * effective mass), so a face contact is a rotational spring, and the weight above pushes a column of
 * such springs over (P-delta). For 1 m boxes at 45 Hz a column is past its buckling load at 20 boxes
 * (the springs would have to be 1.34 times stiffer, tests/engine/README.md "Robustness"): it leans and
 * falls however well the solver converges. Pyramids and piles are braced by their neighbours and
 * have no such mode. So the contacts of a column of at least COLUMN_MIN_BODIES bodies are solved at
 * the static-contact stiffness (twice contactHertz) with the extra sweeps that make a stiffer
 * contact converge (contact-solver.ts); everything else solves as before.
 *
 * Each column is weighed (extra-sweeps.ts weighColumns, bucklingFactor below): its buckling factor
 * from its bodies' masses, the levers of its contact points and their effective masses, and it is
 * solved as a column of 1 m boxes equally close to buckling (equivalentHeight), never as a shorter
 * one than it is: heavier tops and narrower boxes count as taller columns.
 *
 * Taller columns get stiffer: the buckling factor grows as n^3 with the column's n bodies and falls
 * as 1 / hertz^2, so from COLUMN_STIFF_BODIES bodies the hertz grows as (n / COLUMN_STIFF_BODIES)^1.5,
 * which keeps the factor at its 20-box value (0.335 for 1 m boxes), up to COLUMN_MAX_BODIES (356 Hz at
 * the default 45 Hz). A stiffer contact needs more sweeps to converge: PINCHED_EXTRA_ITERATIONS times
 * (hertz / (2 contactHertz))^1.5, measured on alternating towers of 25-50 boxes (engine/README.md).
 *
 * Found once per step in constraint order (ids), without allocation: count each body's touching
 * contacts, then walk up from every two-point contact with a static body while the next body
 * touches exactly two.
 */

import {
  COLUMN_MAX_BODIES,
  COLUMN_MIN_BODIES,
  COLUMN_REFERENCE_FACTOR,
  COLUMN_STIFF_BODIES,
  EXTRA_SWEEP_BUDGET,
  EXTRA_SWEEP_FLOOR,
  PINCHED_EXTRA_ITERATIONS,
} from '../constants.ts'
import { STATE_STRIDE } from './body-state.ts'
import { Softness } from './softness.ts'

/** Soft-constraint coefficients and extra sweeps of a column's contacts, per column height. */
export class ColumnStiffness {
  readonly biasRate = new Float64Array(COLUMN_MAX_BODIES + 1)
  readonly massScale = new Float64Array(COLUMN_MAX_BODIES + 1)
  readonly impulseScale = new Float64Array(COLUMN_MAX_BODIES + 1)
  readonly sweeps = new Int32Array(COLUMN_MAX_BODIES + 1)
  /** This step's extra sweeps and the tallest column height whose stiffness they pay for (set by limit). */
  stepSweeps = PINCHED_EXTRA_ITERATIONS
  stepCap = COLUMN_MAX_BODIES

  /**
   * Chooses the step's extra sweeps over `extra` contacts (of `count`) when the tallest column is
   * `tallest` bodies (0: none): what it needs, unless that exceeds the budget of
   * max(EXTRA_SWEEP_FLOOR, EXTRA_SWEEP_BUDGET x count) contact solves; then as many sweeps as fit (at
   * least PINCHED_EXTRA_ITERATIONS, since extra <= count) and columns no stiffer than those pay for.
   */
  limit(extra: number, count: number, tallest: number): void {
    const need = tallest === 0 ? PINCHED_EXTRA_ITERATIONS : this.sweeps[tallest]
    const budget = Math.max(EXTRA_SWEEP_FLOOR, EXTRA_SWEEP_BUDGET * count)
    if (extra * need <= budget) {
      this.stepSweeps = need
      this.stepCap = COLUMN_MAX_BODIES
      return
    }
    const sweeps = Math.max(PINCHED_EXTRA_ITERATIONS, Math.floor(budget / extra))
    let cap = COLUMN_STIFF_BODIES
    while (cap < COLUMN_MAX_BODIES && this.sweeps[cap + 1] <= sweeps) cap++
    this.stepSweeps = sweeps
    this.stepCap = cap
  }

  /** Fills the table for contact stiffness `contactHertz` (Hz, clamped), damping ratio `zeta`, sub-step `h` (s). */
  set(contactHertz: number, zeta: number, h: number): void {
    const soft = new Softness()
    for (let n = COLUMN_MIN_BODIES; n <= COLUMN_MAX_BODIES; n++) {
      const r = n > COLUMN_STIFF_BODIES ? n / COLUMN_STIFF_BODIES : 1
      const scale = r * Math.sqrt(r)
      soft.set(2 * contactHertz * scale, zeta, h)
      this.biasRate[n] = soft.biasRate
      this.massScale[n] = soft.massScale
      this.impulseScale[n] = soft.impulseScale
      this.sweeps[n] = Math.ceil(PINCHED_EXTRA_ITERATIONS * scale * Math.sqrt(scale))
    }
  }
}

/** Scratch arrays of the column search, grown by doubling (no allocation once warm). */
export class ColumnMarks {
  /** Per body state record (record 0 static): touching contacts this step, and the first two. */
  degree = new Int32Array(64)
  first = new Int32Array(64)
  second = new Int32Array(64)
  /** Per constraint: the bodies of the column it holds (at most COLUMN_MAX_BODIES), 0 if none. */
  mark = new Int32Array(64)
  /** The columns' constraints, each column bottom to top, and each column's first index and length. */
  order = new Int32Array(64)
  columnStart = new Int32Array(64)
  columnLength = new Int32Array(64)
  columnCount = 0
  /** Scratch of bucklingFactor, per body of a column: interface stiffness and load. */
  stiffness = new Float64Array(64)
  load = new Float64Array(64)
  /** Scratch of the column weighing (extra-sweeps.ts), per body: mass, g x centre height, g x height. */
  mass = new Float64Array(64)
  centre = new Float64Array(64)
  rise = new Float64Array(64)

  /** Makes room for `records` body state records and `constraints` constraints. */
  reserve(records: number, constraints: number): void {
    if (records > this.degree.length) {
      this.degree = new Int32Array(2 * records)
      this.first = new Int32Array(2 * records)
      this.second = new Int32Array(2 * records)
    }
    if (constraints > this.mark.length) {
      this.mark = new Int32Array(2 * constraints)
      this.order = new Int32Array(2 * constraints)
      this.columnStart = new Int32Array(2 * constraints)
      this.columnLength = new Int32Array(2 * constraints)
      this.stiffness = new Float64Array(2 * constraints)
      this.load = new Float64Array(2 * constraints)
      this.mass = new Float64Array(2 * constraints)
      this.centre = new Float64Array(2 * constraints)
      this.rise = new Float64Array(2 * constraints)
    }
  }
}

/** The constraints' solver state offsets and point counts, as contact-solver.ts keeps them. */
export interface ColumnGraph {
  stateA: Int32Array
  stateB: Int32Array
  pointCount: Int32Array
}

/** Marks (in `marks.mark`, with its height) the constraints of every column of at least COLUMN_MIN_BODIES bodies. */
export function markColumns(marks: ColumnMarks, g: ColumnGraph, count: number, records: number): void {
  marks.reserve(records, count)
  const degree = marks.degree
  degree.fill(0, 0, records)
  marks.mark.fill(0, 0, count)
  marks.columnCount = 0
  const stateA = g.stateA
  const stateB = g.stateB
  for (let i = 0; i < count; i++) {
    addContact(marks, stateA[i], i)
    addContact(marks, stateB[i], i)
  }
  for (let i = 0; i < count; i++) {
    if (stateA[i] !== 0 && stateB[i] !== 0) continue // a column stands on a static body
    const n = walkColumn(marks, g, i, 0)
    if (n < COLUMN_MIN_BODIES) continue
    // A column between two static bodies is listed once, from the end found first.
    if (marks.mark[i] === 0) {
      const c = marks.columnCount++
      marks.columnStart[c] = c === 0 ? 0 : marks.columnStart[c - 1] + marks.columnLength[c - 1]
      marks.columnLength[c] = 0
    }
    walkColumn(marks, g, i, Math.min(n, COLUMN_MAX_BODIES))
  }
}

/**
 * The buckling factor of a column of n rigid bodies on rotational springs (engine/README.md
 * "Robustness"): the smallest c for which c K - G is positive definite, K the springs' tridiagonal
 * stiffness matrix (stiffness[0] between the support and body 0, stiffness[i] between bodies i - 1
 * and i) and G the diagonal of the load's destabilising moments, load[i] = g (m_i c_i + M_i h_i) for
 * body i's mass m_i, centre height c_i over its lower interface, height h_i between its interfaces
 * and the mass M_i above it. Bisection on c (geometric: 24 halvings of 1e-9..1e9, relative
 * precision 2.5e-6) with an LDL^T test of the tridiagonal matrix; 1e9 when even that is not stiff
 * enough.
 */
export function bucklingFactor(n: number, stiffness: Float64Array, load: Float64Array): number {
  let lo = 1e-9
  let hi = 1e9
  if (!columnStable(n, stiffness, load, hi)) return hi
  for (let it = 0; it < 24; it++) {
    const mid = Math.sqrt(lo * hi)
    if (columnStable(n, stiffness, load, mid)) hi = mid
    else lo = mid
  }
  return hi
}

/** Whether c K - G is positive definite (every pivot of its LDL^T factorisation positive). */
function columnStable(n: number, k: Float64Array, load: Float64Array, c: number): boolean {
  let pivot = 0
  for (let i = 0; i < n; i++) {
    const above = i + 1 < n ? k[i + 1] : 0
    const diagonal = c * (k[i] + above) - load[i]
    const coupling = i > 0 ? c * k[i] : 0
    pivot = i > 0 ? diagonal - (coupling * coupling) / pivot : diagonal
    if (!(pivot > 0)) return false
  }
  return true
}

/**
 * The height of a column of 1 m boxes as close to buckling as a column of factor c (at unit
 * contact stiffness): the smallest height h from COLUMN_MIN_BODIES with COLUMN_REFERENCE_FACTOR x
 * (h / COLUMN_STIFF_BODIES)^3 >= c, at most COLUMN_MAX_BODIES.
 */
export function equivalentHeight(c: number): number {
  for (let h = COLUMN_MIN_BODIES; h < COLUMN_MAX_BODIES; h++) {
    const r = h / COLUMN_STIFF_BODIES
    if (COLUMN_REFERENCE_FACTOR * r * r * r >= c) return h
  }
  return COLUMN_MAX_BODIES
}

/** Appends constraint i to the last listed column. */
function recordConstraint(marks: ColumnMarks, i: number): void {
  const c = marks.columnCount - 1
  marks.order[marks.columnStart[c] + marks.columnLength[c]++] = i
}

/** Counts contact i on the body whose solver state starts at `offset` (the static record 0 is not counted). */
function addContact(marks: ColumnMarks, offset: number, i: number): void {
  if (offset === 0) return
  const r = offset / STATE_STRIDE
  const n = marks.degree[r]++
  if (n === 0) marks.first[r] = i
  else if (n === 1) marks.second[r] = i
}

/**
 * Bodies in the column standing on constraint i (0 unless i is a two-point contact between a static
 * body and a body touching at most two); a positive `mark` is written for each of the column's constraints.
 */
function walkColumn(marks: ColumnMarks, g: ColumnGraph, i: number, mark: number): number {
  const a = g.stateA[i] / STATE_STRIDE
  const b = g.stateB[i] / STATE_STRIDE
  if ((a === 0) === (b === 0) || g.pointCount[i] < 2) return 0
  let r = a === 0 ? b : a
  if (marks.degree[r] > 2) return 0
  if (mark > 0) {
    if (marks.mark[i] === 0) recordConstraint(marks, i)
    marks.mark[i] = mark
  }
  let via = i
  let length = 1
  while (marks.degree[r] === 2 && length <= g.stateA.length) {
    const j = marks.first[r] === via ? marks.second[r] : marks.first[r]
    const ja = g.stateA[j] / STATE_STRIDE
    const next = ja === r ? g.stateB[j] / STATE_STRIDE : ja
    if (g.pointCount[j] < 2 || next === 0 || marks.degree[next] > 2) break
    if (mark > 0) {
      if (marks.mark[j] === 0) recordConstraint(marks, j)
      marks.mark[j] = mark
    }
    length++
    via = j
    r = next
  }
  return length
}
