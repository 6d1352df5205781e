/*
 * The soft-step contact solver (Erin Catto, "Solver2D" 2024; Box2D v3 contact_solver.c).
 *
 * Stages, called by World.step in this order:
 *   prepareContacts   once per step: copy each touching contact into a flat constraint record
 *                     (anchors, effective masses, softness, pre-step normal velocity); then
 *                     planExtraSweeps (extra-sweeps.ts) picks the constraints that get extra sweeps
 *   warmStartContacts each sub-step: apply the accumulated impulses
 *   solveContacts     each sub-step with bias (soft push-out of overlap), then again without (relax)
 *   applyRestitution  once per step, after the sub-steps, for contacts closing faster than the threshold
 *   storeImpulses     copy the accumulated impulses back to the contacts for the next step
 *
 * Data layout: constraints live in one Float64Array (CONSTRAINT_STRIDE numbers each) and bodies'
 * solver state in another (body-state.ts: named offsets per awake body; record 0 is a shared,
 * never-moving state for static bodies), so the thirteen passes per step stream through contiguous memory
 * instead of chasing objects (the layout of Box2D v3's b2ContactConstraint and b2BodyState).
 *
 * Within a sub-step the separation is not recomputed by the narrowphase: it is the step-start
 * separation plus the bodies' position and rotation deltas projected on the fixed normal:
 *   s = baseSeparation + dot(dpB - dpA + rot(dqB, rB) - rot(dqA, rA), n)
 * Positive separation is handled speculatively (the contact only removes the approach speed that
 * would close more than the gap); negative separation is pushed out by a soft spring of stiffness
 * `contactHertz` (twice that against static bodies), limited to `maxContactPushSpeed`.
 * Friction is a Coulomb cone: the tangent impulse is clamped to friction * normal impulse.
 *
 * Pinched bodies: one Gauss-Seidel sweep passes a heavy body's momentum through a light one only
 * about m_light / m_heavy at a time (the light body takes the heavy one's velocity, the ground stops
 * it, repeat), so a 400 kg box landing at 16.7 m/s on two 1 kg boxes sank a metre into them and the
 * stored impulses threw it back up at 9 m/s. A dynamic body touching a dynamic body more than
 * PINCH_MASS_RATIO times heavier is pinched for the step; after every solve and relax sweep, the
 * contacts touching a pinched body (those to the heavy body and those below it) get
 * PINCHED_EXTRA_ITERATIONS more sweeps, in the same order. Scenes without such mass ratios solve
 * exactly as before; the few contacts of a heavy-on-light stack cost little.
 *
 * Slender bodies (a dynamic body touching with a shape thinner than SLENDER_RATIO times its length:
 * cards, thin planks and rods) get the same extra sweeps while they stand or lean on an end (the
 * contact's normal and gravity both nearer the shape's long axis than across it: standsOnEnd). Such
 * a body stands on a support as wide as its thickness, so the velocity error one sweep per sub-step
 * leaves tips it: issue 27's five-storey house of 2 mm x 0.4 m cards fell in 18 of 66 creation
 * orders and stands in all of them with the extra sweeps (tests/engine/card-house.test.ts). Lying
 * flat it is as stable as a box and gets none. Scenes without slender shapes solve exactly as before.
 *
 * Tall columns (contact-columns.ts: a chain of at least COLUMN_MIN_BODIES bodies on a static body,
 * each touching only the one below and the one above) buckle on 45 Hz soft contacts; their contacts
 * are solved at the static-contact stiffness (twice contactHertz; stiffer for columns taller than
 * COLUMN_STIFF_BODIES) and get the same extra sweeps (more for the stiffer ones). The extra sweeps
 * of a step solve at most EXTRA_SWEEP_BUDGET times the step's contacts (or EXTRA_SWEEP_FLOOR contacts),
 * so a forest of tall columns cannot multiply the solver's cost: within it, columns are stiffened
 * only as far as the budget pays for (ColumnStiffness.limit).
 */

import { PINCH_MASS_RATIO, SLENDER_END_COSINE } from '../constants.ts'
import type { Body } from './body.ts'
import type { BodyShape } from './body-shape.ts'
import { DPX, DPY, DQC, DQS, STATE_STRIDE, stateOffset, VX, VY, W } from './body-state.ts'
import { type Contact, SLENDER_A, SLENDER_B } from './contact.ts'
import { ColumnMarks } from './contact-columns.ts'
import {
  ANCHOR_AX,
  ANCHOR_AY,
  ANCHOR_BX,
  ANCHOR_BY,
  FRICTION as CONTACT_FRICTION,
  NORMAL_IMPULSE as CONTACT_NORMAL_IMPULSE,
  NORMAL_X as CONTACT_NORMAL_X,
  NORMAL_Y as CONTACT_NORMAL_Y,
  RESTITUTION as CONTACT_RESTITUTION,
  ROLLING_IMPULSE as CONTACT_ROLLING_IMPULSE,
  ROLLING_RESISTANCE as CONTACT_ROLLING_RESISTANCE,
  TANGENT_IMPULSE as CONTACT_TANGENT_IMPULSE,
  TANGENT_SPEED as CONTACT_TANGENT_SPEED,
  TOTAL_NORMAL as CONTACT_TOTAL_NORMAL,
  TOTAL_TANGENT as CONTACT_TOTAL_TANGENT,
  POINT_0,
  POINT_FIELDS,
  SEPARATION,
} from './contact-record.ts'
import type { Softness } from './softness.ts'
import type { StepContext } from './step-context.ts'

// Constraint record layout
const M_A = 0
const I_A = 1
const M_B = 2
const I_B = 3
const NX = 4
const NY = 5
const FRICTION = 6
const RESTITUTION = 7
const BIAS_RATE = 8
const MASS_SCALE = 9
const IMPULSE_SCALE = 10
const POINTS = 11
// Point record layout (two per constraint)
const RAX = 0
const RAY = 1
const RBX = 2
const RBY = 3
const BASE_SEPARATION = 4
const NORMAL_MASS = 5
const TANGENT_MASS = 6
const NORMAL_IMPULSE = 7
const TANGENT_IMPULSE = 8
const TOTAL_NORMAL = 9
const TOTAL_TANGENT = 10
const RELATIVE_VELOCITY = 11
const POINT_STRIDE = 12
/** Numbers per constraint record. */
const CONSTRAINT_STRIDE = POINTS + 2 * POINT_STRIDE
// Surface record layout (ContactConstraints.surface), read only for constraints whose
// hasSurface flag is 1: those with a tangent speed (not +0) or a rolling resistance. Kept out of
// the constraint record so that contacts without them (the common case) cost what they did
// before the two existed (issue 27: a 39-number record measured 4-5 % slower on pyramid-20).
const TANGENT_SPEED = 0
const ROLLING_RESISTANCE = 1
const ROLLING_IMPULSE = 2
const ROLLING_MASS = 3
/** Numbers per surface record. */
const SURFACE_STRIDE = 4

/**
 * The constraint record layout, for code outside the solver's passes (extra-sweeps.ts). The passes
 * use the module's own constants: V8 reads an exported or imported constant through the module's
 * binding, which measured 8-18 % slower in these loops when not bundled (engine/README.md).
 */
export const CONSTRAINT_LAYOUT = Object.freeze({
  M_A,
  I_A,
  M_B,
  I_B,
  NX,
  NY,
  BIAS_RATE,
  MASS_SCALE,
  IMPULSE_SCALE,
  POINTS,
  RAX,
  RAY,
  RBX,
  RBY,
  NORMAL_MASS,
  POINT_STRIDE,
  CONSTRAINT_STRIDE,
})

/** Flat storage of the step's contact constraints. */
export class ContactConstraints {
  data = new Float64Array(64 * CONSTRAINT_STRIDE)
  /** Offsets of body A's and body B's solver state, per constraint. */
  stateA = new Int32Array(64)
  stateB = new Int32Array(64)
  pointCount = new Int32Array(64)
  /** Per constraint: 1 when its surface record (tangent speed, rolling resistance) is in use. */
  hasSurface = new Uint8Array(64)
  /** Surface records, SURFACE_STRIDE numbers per constraint (valid where hasSurface is 1). */
  surface = new Float64Array(64 * SURFACE_STRIDE)
  count = 0
  /** 0, 1, 2, ...: every constraint, in solve order. */
  all = identity(64)
  /** Constraints touching a pinched body or holding a column (see solveContacts), in solve order, and their count. */
  extra = new Int32Array(64)
  extraCount = 0
  /** Extra sweeps over them after each sweep: PINCHED_EXTRA_ITERATIONS, more for a column taller than COLUMN_STIFF_BODIES. */
  extraSweeps = 0
  /** Per solver state record (record 0 static): 1 when the body is pinched or slender this step. */
  extraRecord = new Uint8Array(64)
  /** Scratch of the column search (contact-columns.ts). */
  readonly columns = new ColumnMarks()

  /** Makes room for n constraints and `records` body state records (grows by doubling; no allocation once warm). */
  reserve(n: number, records: number): void {
    if (records > this.extraRecord.length) this.extraRecord = new Uint8Array(2 * records)
    if (n <= this.stateA.length) return
    let size = this.stateA.length * 2
    while (size < n) size *= 2
    this.data = new Float64Array(size * CONSTRAINT_STRIDE)
    this.stateA = new Int32Array(size)
    this.stateB = new Int32Array(size)
    this.pointCount = new Int32Array(size)
    this.hasSurface = new Uint8Array(size)
    this.surface = new Float64Array(size * SURFACE_STRIDE)
    this.extra = new Int32Array(size)
    this.all = identity(size)
  }
}

/** The array 0, 1, ..., n - 1. */
function identity(n: number): Int32Array {
  const a = new Int32Array(n)
  for (let i = 0; i < n; i++) a[i] = i
  return a
}

/** Fills point record `o` of constraint `oc` from the contact's point record at `cp` (contact-record.ts). */
function preparePoint(d: Float64Array, oc: number, o: number, c: Contact, cp: number): void {
  const cd = c.store.data
  const nx = d[oc + NX]
  const ny = d[oc + NY]
  const rAx = cd[cp + ANCHOR_AX]
  const rAy = cd[cp + ANCHOR_AY]
  const rBx = cd[cp + ANCHOR_BX]
  const rBy = cd[cp + ANCHOR_BY]
  const mA = d[oc + M_A]
  const iA = d[oc + I_A]
  const mB = d[oc + M_B]
  const iB = d[oc + I_B]
  d[o + RAX] = rAx
  d[o + RAY] = rAy
  d[o + RBX] = rBx
  d[o + RBY] = rBy
  const separation = cd[cp + SEPARATION]
  d[o + BASE_SEPARATION] = separation - ((rBx - rAx) * nx + (rBy - rAy) * ny)
  const rnA = rAx * ny - rAy * nx
  const rnB = rBx * ny - rBy * nx
  const kNormal = mA + mB + iA * rnA * rnA + iB * rnB * rnB
  d[o + NORMAL_MASS] = kNormal > 0 ? 1 / kNormal : 0
  // tangent = right perpendicular of the normal (ny, -nx)
  const rtA = -rAx * nx - rAy * ny
  const rtB = -rBx * nx - rBy * ny
  const kTangent = mA + mB + iA * rtA * rtA + iB * rtB * rtB
  d[o + TANGENT_MASS] = kTangent > 0 ? 1 / kTangent : 0
  d[o + NORMAL_IMPULSE] = cd[cp + CONTACT_NORMAL_IMPULSE]
  d[o + TANGENT_IMPULSE] = cd[cp + CONTACT_TANGENT_IMPULSE]
  d[o + TOTAL_NORMAL] = 0
  d[o + TOTAL_TANGENT] = 0
  const a = c.bodyA
  const b = c.bodyB
  const dvx = b.vx - b.w * rBy - (a.vx - a.w * rAy)
  const dvy = b.vy + b.w * rBx - (a.vy + a.w * rAx)
  d[o + RELATIVE_VELOCITY] = nx * dvx + ny * dvy
}

/** Fills the constraint records from the touching contacts (bodies' solverIndex must be set). */
export function prepareContacts(
  out: ContactConstraints,
  contacts: Contact[],
  count: number,
  contactSoftness: Softness,
  staticSoftness: Softness,
  records: number,
  ctx: StepContext,
): void {
  out.reserve(count, records)
  const extraRecord = out.extraRecord
  extraRecord.fill(0, 0, records)
  out.count = count
  const d = out.data
  const surface = out.surface
  const hasSurface = out.hasSurface
  for (let i = 0; i < count; i++) {
    const c = contacts[i]
    const a = c.bodyA
    const b = c.bodyB
    const mA = a.invMass
    const iA = a.invInertia
    const mB = b.invMass
    const iB = b.invInertia
    const o = i * CONSTRAINT_STRIDE
    out.stateA[i] = stateOffset(a)
    out.stateB[i] = stateOffset(b)
    out.pointCount[i] = c.pointCount
    const soft = mA === 0 || mB === 0 ? staticSoftness : contactSoftness
    d[o + M_A] = mA
    d[o + I_A] = iA
    d[o + M_B] = mB
    d[o + I_B] = iB
    const cd = c.store.data
    const cb = c.base
    d[o + NX] = cd[cb + CONTACT_NORMAL_X]
    d[o + NY] = cd[cb + CONTACT_NORMAL_Y]
    d[o + FRICTION] = cd[cb + CONTACT_FRICTION]
    d[o + RESTITUTION] = cd[cb + CONTACT_RESTITUTION]
    d[o + BIAS_RATE] = soft.biasRate
    d[o + MASS_SCALE] = soft.massScale
    d[o + IMPULSE_SCALE] = soft.impulseScale
    // Subtracting a tangent speed of +0 changes no bit, so only other values need the surface record:
    // c.surface says whether the pair has one (set with the numbers, contact.ts mixMaterials).
    if (c.surface) {
      const tangentSpeed = cd[cb + CONTACT_TANGENT_SPEED]
      const rollingResistance = cd[cb + CONTACT_ROLLING_RESISTANCE]
      const s = i * SURFACE_STRIDE
      hasSurface[i] = 1
      surface[s + TANGENT_SPEED] = tangentSpeed
      surface[s + ROLLING_RESISTANCE] = rollingResistance
      surface[s + ROLLING_IMPULSE] = rollingResistance > 0 ? cd[cb + CONTACT_ROLLING_IMPULSE] : 0
      surface[s + ROLLING_MASS] = iA + iB > 0 ? 1 / (iA + iB) : 0
    } else hasSurface[i] = 0
    preparePoint(d, o, o + POINTS, c, cb + POINT_0)
    if (c.pointCount > 1) preparePoint(d, o, o + POINTS + POINT_STRIDE, c, cb + POINT_0 + POINT_FIELDS)
    // A dynamic body touching one more than PINCH_MASS_RATIO times heavier is pinched.
    if (mA > 0 && mB > 0) {
      if (mA > PINCH_MASS_RATIO * mB) extraRecord[out.stateA[i] / STATE_STRIDE] = 1
      else if (mB > PINCH_MASS_RATIO * mA) extraRecord[out.stateB[i] / STATE_STRIDE] = 1
    }
    // A dynamic body touching with a slender shape on an end (the normal not across its long axis)
    // gets the same extra sweeps.
    const slender = c.slender
    if (slender !== 0) {
      if ((slender & SLENDER_A) !== 0 && mA > 0 && standsOnEnd(a, c.shapeA, d, o, ctx))
        extraRecord[out.stateA[i] / STATE_STRIDE] = 1
      if ((slender & SLENDER_B) !== 0 && mB > 0 && standsOnEnd(b, c.shapeB, d, o, ctx))
        extraRecord[out.stateB[i] / STATE_STRIDE] = 1
    }
  }
}

/** The square of SLENDER_END_COSINE. */
const END_COSINE_2 = SLENDER_END_COSINE * SLENDER_END_COSINE

/**
 * Whether a slender shape on `body` stands or leans on an end at this contact: both the normal of
 * constraint record `o` and gravity have a component along the shape's long axis (turned by the
 * body's rotation) above SLENDER_END_COSINE of their length. A slender body touching along its long
 * side, or lying flat, is as stable as a box. Reads the normal from the record and gravity from
 * `ctx` (no double passed: V8 boxes a double passed to a function it does not inline).
 */
export function standsOnEnd(
  body: Body,
  shape: BodyShape,
  d: Float64Array,
  o: number,
  ctx: StepContext,
): boolean {
  const ux = shape.axisX
  const uy = shape.axisY
  const c = body.c
  const s = body.s
  const ax = c * ux - s * uy
  const ay = s * ux + c * uy
  const normal = d[o + NX] * ax + d[o + NY] * ay
  if (!(normal * normal > END_COSINE_2)) return false
  const gx = ctx.gravityX
  const gy = ctx.gravityY
  const gravity = gx * ax + gy * ay
  return gravity * gravity > END_COSINE_2 * (gx * gx + gy * gy)
}

/** Applies the accumulated impulses (each sub-step). */
export function warmStartContacts(k: ContactConstraints, state: Float64Array): void {
  const d = k.data
  const hasSurface = k.hasSurface
  const surface = k.surface
  for (let i = 0; i < k.count; i++) {
    const o = i * CONSTRAINT_STRIDE
    const sa = k.stateA[i]
    const sb = k.stateB[i]
    const mA = d[o + M_A]
    const iA = d[o + I_A]
    const mB = d[o + M_B]
    const iB = d[o + I_B]
    const nx = d[o + NX]
    const ny = d[o + NY]
    let vAx = state[sa + VX]
    let vAy = state[sa + VY]
    let wA = state[sa + W]
    let vBx = state[sb + VX]
    let vBy = state[sb + VY]
    let wB = state[sb + W]
    const end = o + POINTS + k.pointCount[i] * POINT_STRIDE
    for (let p = o + POINTS; p < end; p += POINT_STRIDE) {
      const ni = d[p + NORMAL_IMPULSE]
      const ti = d[p + TANGENT_IMPULSE]
      const px = ni * nx + ti * ny
      const py = ni * ny - ti * nx
      d[p + TOTAL_NORMAL] += ni
      d[p + TOTAL_TANGENT] += ti
      wA -= iA * (d[p + RAX] * py - d[p + RAY] * px)
      vAx -= mA * px
      vAy -= mA * py
      wB += iB * (d[p + RBX] * py - d[p + RBY] * px)
      vBx += mB * px
      vBy += mB * py
    }
    if (hasSurface[i] !== 0) {
      const rolling = surface[i * SURFACE_STRIDE + ROLLING_IMPULSE]
      if (rolling !== 0) {
        wA -= iA * rolling
        wB += iB * rolling
      }
    }
    state[sa + VX] = vAx
    state[sa + VY] = vAy
    state[sa + W] = wA
    state[sb + VX] = vBx
    state[sb + VY] = vBy
    state[sb + W] = wB
  }
}

/** One iteration over the contacts; `useBias` pushes overlap apart, false is the relax pass. */
export function solveContacts(
  k: ContactConstraints,
  state: Float64Array,
  ctx: StepContext,
  useBias: boolean,
): void {
  solveContactRange(k, state, ctx, useBias, k.all, k.count)
  if (k.extraCount === 0) return
  for (let it = 0; it < k.extraSweeps; it++) {
    solveContactRange(k, state, ctx, useBias, k.extra, k.extraCount)
  }
}

/** One Gauss-Seidel sweep over constraints indices[0], ..., indices[count - 1]. */
function solveContactRange(
  k: ContactConstraints,
  state: Float64Array,
  ctx: StepContext,
  useBias: boolean,
  indices: Int32Array,
  count: number,
): void {
  const invH = ctx.invH
  const maxPushSpeed = ctx.maxPushSpeed
  const d = k.data
  const hasSurface = k.hasSurface
  const surface = k.surface
  for (let q = 0; q < count; q++) {
    const i = indices[q]
    const o = i * CONSTRAINT_STRIDE
    const sa = k.stateA[i]
    const sb = k.stateB[i]
    const mA = d[o + M_A]
    const iA = d[o + I_A]
    const mB = d[o + M_B]
    const iB = d[o + I_B]
    let vAx = state[sa + VX]
    let vAy = state[sa + VY]
    let wA = state[sa + W]
    let vBx = state[sb + VX]
    let vBy = state[sb + VY]
    let wB = state[sb + W]
    const dpx = state[sb + DPX] - state[sa + DPX]
    const dpy = state[sb + DPY] - state[sa + DPY]
    const qAc = state[sa + DQC]
    const qAs = state[sa + DQS]
    const qBc = state[sb + DQC]
    const qBs = state[sb + DQS]
    const nx = d[o + NX]
    const ny = d[o + NY]
    const end = o + POINTS + k.pointCount[i] * POINT_STRIDE
    const surfaced = hasSurface[i] !== 0

    // Non-penetration
    for (let p = o + POINTS; p < end; p += POINT_STRIDE) {
      const rAx = d[p + RAX]
      const rAy = d[p + RAY]
      const rBx = d[p + RBX]
      const rBy = d[p + RBY]
      // current separation from the sub-step deltas
      const dx = dpx + (qBc * rBx - qBs * rBy) - (qAc * rAx - qAs * rAy)
      const dy = dpy + (qBs * rBx + qBc * rBy) - (qAs * rAx + qAc * rAy)
      const s = d[p + BASE_SEPARATION] + dx * nx + dy * ny
      let velocityBias = 0
      let massScale = 1
      let impulseScale = 0
      if (s > 0) {
        velocityBias = s * invH // speculative: close at most the gap this sub-step
      } else if (useBias) {
        velocityBias = Math.max(d[o + MASS_SCALE] * d[o + BIAS_RATE] * s, -maxPushSpeed)
        massScale = d[o + MASS_SCALE]
        impulseScale = d[o + IMPULSE_SCALE]
      }
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vn = dvx * nx + dvy * ny
      const accumulated = d[p + NORMAL_IMPULSE]
      let impulse = -d[p + NORMAL_MASS] * (massScale * vn + velocityBias) - impulseScale * accumulated
      const newImpulse = Math.max(accumulated + impulse, 0)
      impulse = newImpulse - accumulated
      d[p + NORMAL_IMPULSE] = newImpulse
      d[p + TOTAL_NORMAL] += impulse
      const px = impulse * nx
      const py = impulse * ny
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }

    // Friction (Coulomb cone), tangent = (ny, -nx), towards the surfaces' relative speed (conveyors)
    const friction = d[o + FRICTION]
    const tangentSpeed = surfaced ? surface[i * SURFACE_STRIDE + TANGENT_SPEED] : 0
    for (let p = o + POINTS; p < end; p += POINT_STRIDE) {
      const rAx = d[p + RAX]
      const rAy = d[p + RAY]
      const rBx = d[p + RBX]
      const rBy = d[p + RBY]
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vt = dvx * ny - dvy * nx - tangentSpeed
      const accumulated = d[p + TANGENT_IMPULSE]
      let impulse = -d[p + TANGENT_MASS] * vt
      const maxFriction = friction * d[p + NORMAL_IMPULSE]
      const newImpulse = Math.max(-maxFriction, Math.min(accumulated + impulse, maxFriction))
      impulse = newImpulse - accumulated
      d[p + TANGENT_IMPULSE] = newImpulse
      d[p + TOTAL_TANGENT] += impulse
      const px = impulse * ny
      const py = -impulse * nx
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }

    // Rolling resistance (Box2D v3.1): an angular impulse against the relative spin, at most
    // resistance (m) x the normal impulse (the sum of the points' accumulated normal impulses).
    if (surfaced && surface[i * SURFACE_STRIDE + ROLLING_RESISTANCE] > 0) {
      const sr = i * SURFACE_STRIDE
      let totalNormalImpulse = 0
      for (let p = o + POINTS; p < end; p += POINT_STRIDE) totalNormalImpulse += d[p + NORMAL_IMPULSE]
      const lambda = surface[sr + ROLLING_IMPULSE]
      const maxLambda = surface[sr + ROLLING_RESISTANCE] * totalNormalImpulse
      const next = Math.max(-maxLambda, Math.min(lambda - surface[sr + ROLLING_MASS] * (wB - wA), maxLambda))
      surface[sr + ROLLING_IMPULSE] = next
      wA -= iA * (next - lambda)
      wB += iB * (next - lambda)
    }
    state[sa + VX] = vAx
    state[sa + VY] = vAy
    state[sa + W] = wA
    state[sb + VX] = vBx
    state[sb + VY] = vBy
    state[sb + W] = wB
  }
}

/** Restitution after the sub-steps: bounce contacts that closed faster than the threshold (m/s). */
export function applyRestitution(k: ContactConstraints, state: Float64Array, ctx: StepContext): void {
  const threshold = ctx.restitutionThreshold
  const d = k.data
  for (let i = 0; i < k.count; i++) {
    const o = i * CONSTRAINT_STRIDE
    const restitution = d[o + RESTITUTION]
    if (restitution === 0) continue
    const sa = k.stateA[i]
    const sb = k.stateB[i]
    const mA = d[o + M_A]
    const iA = d[o + I_A]
    const mB = d[o + M_B]
    const iB = d[o + I_B]
    const nx = d[o + NX]
    const ny = d[o + NY]
    let vAx = state[sa + VX]
    let vAy = state[sa + VY]
    let wA = state[sa + W]
    let vBx = state[sb + VX]
    let vBy = state[sb + VY]
    let wB = state[sb + W]
    const end = o + POINTS + k.pointCount[i] * POINT_STRIDE
    for (let p = o + POINTS; p < end; p += POINT_STRIDE) {
      // Skip slow contacts and speculative points that never pushed.
      if (d[p + RELATIVE_VELOCITY] > -threshold || d[p + TOTAL_NORMAL] === 0) continue
      const rAx = d[p + RAX]
      const rAy = d[p + RAY]
      const rBx = d[p + RBX]
      const rBy = d[p + RBY]
      const dvx = vBx - wB * rBy - (vAx - wA * rAy)
      const dvy = vBy + wB * rBx - (vAy + wA * rAx)
      const vn = dvx * nx + dvy * ny
      const accumulated = d[p + NORMAL_IMPULSE]
      let impulse = -d[p + NORMAL_MASS] * (vn + restitution * d[p + RELATIVE_VELOCITY])
      const newImpulse = Math.max(accumulated + impulse, 0)
      impulse = newImpulse - accumulated
      d[p + NORMAL_IMPULSE] = newImpulse
      d[p + TOTAL_NORMAL] += impulse
      const px = impulse * nx
      const py = impulse * ny
      vAx -= mA * px
      vAy -= mA * py
      wA -= iA * (rAx * py - rAy * px)
      vBx += mB * px
      vBy += mB * py
      wB += iB * (rBx * py - rBy * px)
    }
    state[sa + VX] = vAx
    state[sa + VY] = vAy
    state[sa + W] = wA
    state[sb + VX] = vBx
    state[sb + VY] = vBy
    state[sb + W] = wB
  }
}

/** Copies the accumulated impulses back to the contacts (warm starting and read-back). */
export function storeImpulses(k: ContactConstraints, contacts: Contact[]): void {
  const d = k.data
  const hasSurface = k.hasSurface
  const surface = k.surface
  for (let i = 0; i < k.count; i++) {
    const c = contacts[i]
    const cd = c.store.data
    const cp = c.base + POINT_0
    const p = i * CONSTRAINT_STRIDE + POINTS
    // Without a surface record the contact's rolling impulse is zero and stays so (Contact.surface).
    if (hasSurface[i] !== 0)
      cd[c.base + CONTACT_ROLLING_IMPULSE] = surface[i * SURFACE_STRIDE + ROLLING_IMPULSE]
    cd[cp + CONTACT_NORMAL_IMPULSE] = d[p + NORMAL_IMPULSE]
    cd[cp + CONTACT_TANGENT_IMPULSE] = d[p + TANGENT_IMPULSE]
    cd[cp + CONTACT_TOTAL_NORMAL] = d[p + TOTAL_NORMAL]
    cd[cp + CONTACT_TOTAL_TANGENT] = d[p + TOTAL_TANGENT]
    if (k.pointCount[i] > 1) {
      const q = p + POINT_STRIDE
      const cq = cp + POINT_FIELDS
      cd[cq + CONTACT_NORMAL_IMPULSE] = d[q + NORMAL_IMPULSE]
      cd[cq + CONTACT_TANGENT_IMPULSE] = d[q + TANGENT_IMPULSE]
      cd[cq + CONTACT_TOTAL_NORMAL] = d[q + TOTAL_NORMAL]
      cd[cq + CONTACT_TOTAL_TANGENT] = d[q + TOTAL_TANGENT]
    }
  }
}
