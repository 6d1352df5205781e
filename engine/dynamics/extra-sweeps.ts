/*
 * Which contact constraints get extra solver sweeps this step, and how stiff (contact-solver.ts
 * solveContacts runs them): the contacts touching a pinched body (a dynamic body touching one more
 * than PINCH_MASS_RATIO times heavier) or a slender one (touching with a shape thinner than
 * SLENDER_RATIO times its length, on an end), both marked by prepareContacts, and the contacts of tall columns
 * (contact-columns.ts finds them; weighColumns below weighs them), within the step's budget
 * (ColumnStiffness.limit). Runs once per step after prepareContacts; it reads the constraint
 * records by the layout contact-solver.ts exports.
 */
import { STATE_STRIDE } from './body-state.ts'
import { bucklingFactor, equivalentHeight, markColumns } from './contact-columns.ts'
import { CONSTRAINT_LAYOUT, type ContactConstraints } from './contact-solver.ts'
import type { StepContext } from './step-context.ts'

const {
  BIAS_RATE,
  CONSTRAINT_STRIDE,
  IMPULSE_SCALE,
  M_A,
  M_B,
  MASS_SCALE,
  NORMAL_MASS,
  NX,
  NY,
  POINT_STRIDE,
  POINTS,
  RAX,
  RAY,
  RBX,
  RBY,
} = CONSTRAINT_LAYOUT

/**
 * Lists the constraints of pinched and slender bodies and tall columns in `out.extra`, sets the step's extra
 * sweeps, and stiffens the columns' constraints (after prepareContacts filled `out`; `records` is
 * the number of body state records, as there).
 */
export function planExtraSweeps(out: ContactConstraints, ctx: StepContext, records: number): void {
  const count = out.count
  const d = out.data
  const extraRecord = out.extraRecord
  markColumns(out.columns, out, count, records)
  weighColumns(out, ctx.gravityX, ctx.gravityY)
  const column = out.columns.mark
  const stiffness = ctx.columnStiffness
  let tallest = 0
  let n = 0
  for (let i = 0; i < count; i++) {
    if (column[i] > 0) {
      tallest = Math.max(tallest, column[i])
      out.extra[n++] = i
    } else if (
      extraRecord[out.stateA[i] / STATE_STRIDE] === 1 ||
      extraRecord[out.stateB[i] / STATE_STRIDE] === 1
    ) {
      out.extra[n++] = i
    }
  }
  out.extraCount = n
  // Extra sweeps within the budget; columns get the stiffness of their height, at most `cap`.
  stiffness.limit(n, count, tallest)
  out.extraSweeps = stiffness.stepSweeps
  const cap = stiffness.stepCap
  for (let q = 0; q < n; q++) {
    const i = out.extra[q]
    const height = Math.min(column[i], cap)
    if (height === 0) continue
    const o = i * CONSTRAINT_STRIDE
    d[o + BIAS_RATE] = stiffness.biasRate[height]
    d[o + MASS_SCALE] = stiffness.massScale[height]
    d[o + IMPULSE_SCALE] = stiffness.impulseScale[height]
  }
}

/**
 * Raises each column's height mark to the height of a column of 1 m boxes equally close to
 * buckling (contact-columns.ts equivalentHeight), so heavier-topped or narrower columns get the
 * stiffness of a taller one. Per body i, bottom to top: the interface below it as a rotational
 * spring of stiffness (normal mass 0 + normal mass 1) x (half the points' distance)^2 at unit
 * stiffness (a point sags F K / omega^2), and its load g (m_i c_i + M_i h_i) (bucklingFactor).
 */
function weighColumns(k: ContactConstraints, gravityX: number, gravityY: number): void {
  const cols = k.columns
  const d = k.data
  const stiffness = cols.stiffness
  const load = cols.load
  for (let c = 0; c < cols.columnCount; c++) {
    const start = cols.columnStart[c]
    const n = cols.columnLength[c]
    let below = 0
    for (let i = 0; i < n; i++) {
      const j = cols.order[start + i]
      const o = j * CONSTRAINT_STRIDE
      const upperIsB = k.stateA[j] === below
      const body = upperIsB ? k.stateB[j] : k.stateA[j]
      const sign = upperIsB ? 1 : -1
      const ax = sign * d[o + NX]
      const ay = sign * d[o + NY]
      const p0 = o + POINTS
      const p1 = p0 + POINT_STRIDE
      const rx = upperIsB ? RBX : RAX
      const ry = upperIsB ? RBY : RAY
      // Interface below body i: the points' half distance along the tangent (ny, -nx).
      const half = 0.5 * ((d[p0 + RBX] - d[p1 + RBX]) * d[o + NY] - (d[p0 + RBY] - d[p1 + RBY]) * d[o + NX])
      stiffness[i] = (d[p0 + NORMAL_MASS] + d[p1 + NORMAL_MASS]) * half * half
      // Body i: its mass and centre height over the interface below, and (in load, for now) the
      // interface's midpoint from its centre; the height to the next interface is found there.
      const invMass = upperIsB ? d[o + M_B] : d[o + M_A]
      const bottomX = 0.5 * (d[p0 + rx] + d[p1 + rx])
      const bottomY = 0.5 * (d[p0 + ry] + d[p1 + ry])
      const centreHeight = -(bottomX * ax + bottomY * ay)
      let height = 0
      if (i + 1 < n) {
        const jn = cols.order[start + i + 1]
        const on = jn * CONSTRAINT_STRIDE
        const lowerIsA = k.stateA[jn] === body
        const qx = lowerIsA ? RAX : RBX
        const qy = lowerIsA ? RAY : RBY
        const q0 = on + POINTS
        const q1 = q0 + POINT_STRIDE
        const topX = 0.5 * (d[q0 + qx] + d[q1 + qx])
        const topY = 0.5 * (d[q0 + qy] + d[q1 + qy])
        height = (topX - bottomX) * ax + (topY - bottomY) * ay
      }
      const g = -(gravityX * ax + gravityY * ay)
      // Stash m_i, g c_i and g h_i; the loads need the mass above, summed top down below.
      cols.mass[i] = invMass > 0 ? 1 / invMass : 0
      cols.centre[i] = g * centreHeight
      cols.rise[i] = g * height
      below = body
    }
    let above = 0
    for (let i = n - 1; i >= 0; i--) {
      load[i] = cols.mass[i] * cols.centre[i] + above * cols.rise[i]
      above += cols.mass[i]
    }
    const height = equivalentHeight(bucklingFactor(n, stiffness, load))
    for (let i = 0; i < n; i++) {
      const j = cols.order[start + i]
      if (height > cols.mark[j]) cols.mark[j] = height
    }
  }
}
