/*
 * A direct solver for the point constraints of revolute joints and the rigid (0 Hz) weld joints
 * that form a tree (Baraff 1996, "Linear-Time Dynamics using Lagrange Multipliers"). A pin is a
 * 2-row block (the anchors' relative velocity); a weld adds a third row, the relative angular
 * velocity wB - wA, so its block is 3x3 with G = [1 0 -ry; 0 1 rx; 0 0 1]. A weld's angle error
 * gets the same load-scaled softness as its point error.
 *
 * Why: Gauss-Seidel (one joint at a time) converges slowly when masses differ a lot. A chain of
 * light links holding a heavy box passes the box's weight up the chain a little per iteration, so
 * the chain stretches and swings; and a soft constraint sags by K * impulse / (biasRate * a2),
 * where K, the inverse effective mass, is large for light links (a 20-link chain under a 100:1
 * box stretched 39 cm and moved at 2.5 m/s after 10 s; Box2D v3 stretches 30 cm). Solving all the
 * pins of a tree at once, exactly, removes the first: one solve gives every joint its final
 * impulse. For the second, the softness is measured against the load a joint carries: in the
 * biased pass joint k gets the compliance Gamma_k = gamma K_k with gamma = impulseScale / massScale
 * of the joint softness (Box2D's soft constraint, which uses the joint's own K, is the special case
 * of a lone joint) but with K_k the inverse effective mass of the whole subtree below the joint
 * (its pivot in the elimination). The sag at rest is then Gamma P / biasRate = gamma g h / biasRate
 * per joint whatever the masses (0.07 mm at 60 Hz), and a light joint holding a heavy load is as
 * stiff, relative to that load, as any other. The relax pass is rigid (no compliance, no bias).
 * Fully rigid pins in the biased pass were tried: they sag by nothing but fight the soft contacts,
 * and ragdolls lying on the ground jittered at 0.2 m/s.
 *
 * How: the unknowns are the bodies' velocity changes and the joints' impulses, coupled by the
 * sparse symmetric matrix
 *
 *     H = [ M    J^T  ]    H [y; z] = [0; r],  r = J v + bias + Gamma P,  z = impulses, dv = -y
 *         [ J  -Gamma ]
 *
 * Its graph (bodies and joints as nodes, an edge where a joint touches a body) is a tree when the
 * joints are, so block elimination from the leaves to the root creates no fill-in: linear time.
 * Every fixed body (static, kinematic, the world frame) is one node, the world, which is the root
 * of its tree and is never eliminated (its velocity does not change). A joint that would close a
 * loop (two pins between the same bodies, a bridge pinned at both ends counts as a loop through
 * the world) stays with Gauss-Seidel; joints are taken in id order, so the choice is deterministic.
 *
 * Body pivots are kept as inverses, Dinv = (M + W)^-1 = Minv (I + W Minv)^-1, so a body with
 * infinite rotational inertia (fixedRotation: Minv has a zero) needs no special case.
 *
 * The tree is rebuilt every step from the active joints (prepareJointTree) and solved in both the
 * biased and the relax pass of every sub-step, after the Gauss-Seidel joints (motors, limits, loop
 * joints, distance and mouse joints), so the pins end each pass exactly satisfied at the current
 * velocities. Scratch lives in typed arrays grown to the largest step seen: nothing allocates once
 * warm. Arithmetic is + - * / only.
 */
import { type Body, DPX, DPY, DQC, DQS, VX, VY, W } from '../dynamics/index.ts'
import type { Joint } from './joint.ts'
import {
  accumulateAngular,
  accumulateX,
  accumulateY,
  angleOut,
  inverse3,
  invert33,
  type JointStepContext,
  REVOLUTE,
  relativeDeltaAngle,
  sym3,
  WELD,
} from './joint-math.ts'

/** Body slot of a joint end: solverIndex + 1 for a body the solver moves, 0 for a fixed body. */
function slotOf(b: Body): number {
  return b.solverIndex >= 0 && (b.invMass > 0 || b.invInertia > 0) ? b.solverIndex + 1 : 0
}

/** The tree (rebuilt each step) and the solver's scratch. */
export class JointTree {
  /** Joints solved directly, in tree order; their count. */
  joints: Joint[] = []
  count = 0
  /** Per tree joint: the slot nearer the root (0 = world) and the one farther away. */
  parentSlot: Int32Array = new Int32Array(16)
  childSlot: Int32Array = new Int32Array(16)
  /** Per tree joint: arms of the child and parent ends (m), and signs (+1 body B, -1 body A). */
  arms: Float64Array = new Float64Array(16 * 4)
  childSign: Float64Array = new Float64Array(16)
  /**
   * Per tree joint: right-hand side b (3), its pivot inverse (6: xx, xy, xw, yy, yw, ww; a pin uses
   * xx, xy, yy), then z (3). Rows 3 are a weld's angular row.
   */
  jointData: Float64Array = new Float64Array(16 * 12)
  /** Per tree joint: 1 for a weld (3 rows), 0 for a pin (2 rows). */
  weld: Int32Array = new Int32Array(16)
  /** Body slots in breadth-first order from their roots (parents before children); count. */
  order: Int32Array = new Int32Array(16)
  orderCount = 0
  /** Per slot: the tree joint above it (-1 for a root), the body, and a union-find parent. */
  parentJoint: Int32Array = new Int32Array(16)
  bodies: Body[] = []
  unionParent: Int32Array = new Int32Array(16)
  /** Per slot: W (6: xx xy xw yy yw ww), rhs (3), Dinv (9), y (3). */
  bodyData: Float64Array = new Float64Array(16 * 21)
  /** Adjacency of slots by tree joints (CSR: start per slot, joint indices). */
  adjacencyStart: Int32Array = new Int32Array(17)
  adjacency: Int32Array = new Int32Array(32)
  /** Compliance factor of this pass: Gamma = gamma * K for each joint (see solveJointTree). */
  gamma = 0
  /** Candidate joints of this step and whether each joined the tree. */
  candidates: Int32Array = new Int32Array(16)
}

const BODY_STRIDE = 21
const RHS = 6
const DINV = 9
const Y = 18
const JOINT_STRIDE = 12
/** Offsets in a joint's data: right-hand side, pivot inverse, impulse. */
const JB = 0
const JD = 3
const JZ = 9

function grow32(a: Int32Array, n: number): Int32Array {
  return a.length >= n ? a : new Int32Array(Math.max(n, 2 * a.length))
}

function grow64(a: Float64Array, n: number): Float64Array {
  return a.length >= n ? a : new Float64Array(Math.max(n, 2 * a.length))
}

function find(parent: Int32Array, i: number): number {
  let root = i
  while (parent[root] !== root) root = parent[root]
  while (parent[i] !== root) {
    const next = parent[i]
    parent[i] = root
    i = next
  }
  return root
}

/**
 * Chooses this step's tree among the active revolute joints (id order) and orders it from the
 * roots. Marks tree joints with `inTree`; the others are solved by Gauss-Seidel.
 */
export function prepareJointTree(t: JointTree, joints: Joint[], count: number): void {
  let slots = 1
  for (let i = 0; i < count; i++) {
    const j = joints[i]
    j.inTree = false
    slots = Math.max(slots, slotOf(j.bodyA) + 1, slotOf(j.bodyB) + 1)
  }
  t.unionParent = grow32(t.unionParent, slots)
  t.parentJoint = grow32(t.parentJoint, slots)
  t.adjacencyStart = grow32(t.adjacencyStart, slots + 1)
  t.order = grow32(t.order, slots)
  t.bodyData = grow64(t.bodyData, slots * BODY_STRIDE)
  if (t.bodies.length < slots) t.bodies.length = slots
  t.candidates = grow32(t.candidates, count)
  const parent = t.unionParent
  for (let s = 0; s < slots; s++) {
    parent[s] = s
    t.adjacencyStart[s] = 0
    t.parentJoint[s] = -2 // unvisited
  }
  t.adjacencyStart[slots] = 0
  // 1. Spanning forest by union-find, in id order.
  let n = 0
  for (let i = 0; i < count; i++) {
    const j = joints[i]
    if (j.type !== REVOLUTE && !(j.type === WELD && j.hertz === 0 && j.angularHertz === 0)) continue
    const sa = slotOf(j.bodyA)
    const sb = slotOf(j.bodyB)
    const ra = find(parent, sa)
    const rb = find(parent, sb)
    if (ra === rb) continue
    parent[ra < rb ? rb : ra] = ra < rb ? ra : rb
    j.inTree = true
    t.candidates[n++] = i
    t.adjacencyStart[sa + 1]++
    t.adjacencyStart[sb + 1]++
    if (sa > 0) t.bodies[sa] = j.bodyA
    if (sb > 0) t.bodies[sb] = j.bodyB
  }
  t.count = n
  if (n === 0) {
    t.orderCount = 0
    return
  }
  // 2. Adjacency lists (counts -> offsets -> fill; the fill cursor reuses parentJoint's -2 marks).
  for (let s = 0; s < slots; s++) t.adjacencyStart[s + 1] += t.adjacencyStart[s]
  t.adjacency = grow32(t.adjacency, 2 * n)
  const cursor = t.order // borrowed as a fill cursor before the breadth-first pass uses it
  for (let s = 0; s < slots; s++) cursor[s] = t.adjacencyStart[s]
  for (let k = 0; k < n; k++) {
    const j = joints[t.candidates[k]]
    t.adjacency[cursor[slotOf(j.bodyA)]++] = k
    t.adjacency[cursor[slotOf(j.bodyB)]++] = k
  }
  if (t.joints.length < n) t.joints.length = n
  t.weld = grow32(t.weld, n)
  for (let k = 0; k < n; k++) {
    t.joints[k] = joints[t.candidates[k]]
    t.weld[k] = t.joints[k].type === WELD ? 1 : 0
  }
  t.parentSlot = grow32(t.parentSlot, n)
  t.childSlot = grow32(t.childSlot, n)
  t.childSign = grow64(t.childSign, n)
  t.arms = grow64(t.arms, 4 * n)
  t.jointData = grow64(t.jointData, JOINT_STRIDE * n)
  // 3. Breadth-first from the world, then from each remaining body with tree joints (slot order).
  let head = 0
  let tail = 0
  for (let root = 0; root < slots; root++) {
    if (t.parentJoint[root] !== -2 || t.adjacencyStart[root + 1] === t.adjacencyStart[root]) continue
    t.parentJoint[root] = -1
    if (root > 0) {
      t.order[tail++] = root
      head = tail
    }
    let queue = root
    for (;;) {
      for (let e = t.adjacencyStart[queue]; e < t.adjacencyStart[queue + 1]; e++) {
        const k = t.adjacency[e]
        if (k === t.parentJoint[queue]) continue
        const j = t.joints[k]
        const sa = slotOf(j.bodyA)
        const child = sa === queue ? slotOf(j.bodyB) : sa
        t.parentSlot[k] = queue
        t.childSlot[k] = child
        t.childSign[k] = child === sa ? -1 : 1
        t.parentJoint[child] = k
        t.order[tail++] = child
      }
      if (head === tail) break
      queue = t.order[head++]
    }
  }
  t.orderCount = tail
}

/** Solves every tree joint's point constraint at once; `useBias` adds the position correction. */
export function solveJointTree(
  t: JointTree,
  state: Float64Array,
  ctx: JointStepContext,
  useBias: boolean,
): void {
  const n = t.count
  if (n === 0) return
  const jd = t.jointData
  const bd = t.bodyData
  const arms = t.arms
  const soft = ctx.jointSoftness
  const biasRate = useBias ? soft.biasRate : 0
  t.gamma = useBias ? soft.impulseScale / soft.massScale : 0
  // 1. Arms at the current rotation, and r = J v + bias for each joint (as in solveRevolute).
  for (let k = 0; k < n; k++) {
    const j = t.joints[k]
    const oA = j.offsetA
    const oB = j.offsetB
    const rAx = state[oA + DQC] * j.anchorAx - state[oA + DQS] * j.anchorAy
    const rAy = state[oA + DQS] * j.anchorAx + state[oA + DQC] * j.anchorAy
    const rBx = state[oB + DQC] * j.anchorBx - state[oB + DQS] * j.anchorBy
    const rBy = state[oB + DQS] * j.anchorBx + state[oB + DQC] * j.anchorBy
    const wA = state[oA + W]
    const wB = state[oB + W]
    let rx = state[oB + VX] - wB * rBy - (state[oA + VX] - wA * rAy)
    let ry = state[oB + VY] + wB * rBx - (state[oA + VY] + wA * rAx)
    if (useBias) {
      rx += biasRate * (state[oB + DPX] - state[oA + DPX] + (rBx - rAx) + j.deltaCenterX)
      ry += biasRate * (state[oB + DPY] - state[oA + DPY] + (rBy - rAy) + j.deltaCenterY)
    }
    const o = JOINT_STRIDE * k
    jd[o + JB] = rx
    jd[o + JB + 1] = ry
    if (t.weld[k] === 1) {
      let rw = wB - wA
      if (useBias) {
        relativeDeltaAngle(j, state)
        const C = angleOut[0] + j.deltaAngle
        rw += biasRate * C
      }
      jd[o + JB + 2] = rw
    }
    const childIsB = t.childSign[k] > 0
    arms[4 * k] = childIsB ? rBx : rAx
    arms[4 * k + 1] = childIsB ? rBy : rAy
    arms[4 * k + 2] = childIsB ? rAx : rBx
    arms[4 * k + 3] = childIsB ? rAy : rBy
  }
  for (let i = 0; i < t.orderCount; i++) bd.fill(0, t.order[i] * BODY_STRIDE, t.order[i] * BODY_STRIDE + DINV)
  // 2. Eliminate from the leaves: each body into the joint above it, that joint into its parent.
  for (let i = t.orderCount - 1; i >= 0; i--) {
    const s = t.order[i]
    const ob = s * BODY_STRIDE
    invertBodyPivot(t.bodies[s], bd, ob)
    const k = t.parentJoint[s]
    if (k < 0) continue
    const q = t.parentSlot[k]
    if (t.weld[k] === 1) {
      eliminateBodyWeld(t, k, ob)
      if (q > 0) eliminateJointWeld(t, k, q * BODY_STRIDE)
      continue
    }
    eliminateBody(t, k, ob)
    if (q > 0) eliminateJoint(t, k, q * BODY_STRIDE)
  }
  // 3. Back-substitute from the roots.
  for (let i = 0; i < t.orderCount; i++) {
    const s = t.order[i]
    const ob = s * BODY_STRIDE
    const k = t.parentJoint[s]
    let ex = bd[ob + RHS]
    let ey = bd[ob + RHS + 1]
    let ew = bd[ob + RHS + 2]
    if (k >= 0) {
      // z_k = Dk^-1 (b_k - s_q G_q y_q); y_s = Dinv_s (rhs_s - s_s G_s^T z_k).
      const o = JOINT_STRIDE * k
      const weld = t.weld[k] === 1
      let zx: number
      let zy: number
      if (weld) {
        backSubstituteWeld(t, k)
        zx = jd[o + JZ]
        zy = jd[o + JZ + 1]
      } else {
        let bx = jd[o + JB]
        let by = jd[o + JB + 1]
        const q = t.parentSlot[k]
        if (q > 0) {
          const oq = q * BODY_STRIDE
          const sq = -t.childSign[k]
          const gx = arms[4 * k + 2]
          const gy = arms[4 * k + 3]
          bx -= sq * (bd[oq + Y] - gy * bd[oq + Y + 2])
          by -= sq * (bd[oq + Y + 1] + gx * bd[oq + Y + 2])
        }
        zx = jd[o + JD] * bx + jd[o + JD + 1] * by
        zy = jd[o + JD + 1] * bx + jd[o + JD + 3] * by
        jd[o + JZ] = zx
        jd[o + JZ + 1] = zy
      }
      const ss = t.childSign[k]
      const cx = arms[4 * k]
      const cy = arms[4 * k + 1]
      ex -= ss * zx
      ey -= ss * zy
      ew -= ss * (-cy * zx + cx * zy)
      if (weld) ew -= ss * jd[o + JZ + 2]
    }
    const d = DINV + ob
    bd[ob + Y] = bd[d] * ex + bd[d + 1] * ey + bd[d + 2] * ew
    bd[ob + Y + 1] = bd[d + 3] * ex + bd[d + 4] * ey + bd[d + 5] * ew
    bd[ob + Y + 2] = bd[d + 6] * ex + bd[d + 7] * ey + bd[d + 8] * ew
  }
  // 4. Apply the impulses z (accumulated like every joint impulse, for warm starting).
  for (let k = 0; k < n; k++) {
    const j = t.joints[k]
    const o = JOINT_STRIDE * k
    // Within the joint's cap (joint.ts): a singular or overflowing system adds nothing.
    const ix = accumulateX(j, jd[o + JZ])
    const iy = accumulateY(j, jd[o + JZ + 1])
    const iw = t.weld[k] === 1 ? accumulateAngular(j, jd[o + JZ + 2]) : 0
    const a = j.bodyA
    const b = j.bodyB
    const oA = j.offsetA
    const oB = j.offsetB
    const childIsB = t.childSign[k] > 0
    const rAx = childIsB ? arms[4 * k + 2] : arms[4 * k]
    const rAy = childIsB ? arms[4 * k + 3] : arms[4 * k + 1]
    const rBx = childIsB ? arms[4 * k] : arms[4 * k + 2]
    const rBy = childIsB ? arms[4 * k + 1] : arms[4 * k + 3]
    state[oA + VX] -= a.invMass * ix
    state[oA + VY] -= a.invMass * iy
    if (iw === 0) {
      state[oA + W] -= a.invInertia * (rAx * iy - rAy * ix)
      state[oB + VX] += b.invMass * ix
      state[oB + VY] += b.invMass * iy
      state[oB + W] += b.invInertia * (rBx * iy - rBy * ix)
    } else {
      state[oA + W] -= a.invInertia * (rAx * iy - rAy * ix + iw)
      state[oB + VX] += b.invMass * ix
      state[oB + VY] += b.invMass * iy
      state[oB + W] += b.invInertia * (rBx * iy - rBy * ix + iw)
    }
  }
}

/** Dinv = Minv (I + W Minv)^-1 for the body in slot data at `ob` (W accumulated by its children). */
function invertBodyPivot(b: Body, bd: Float64Array, ob: number): void {
  const m = b.invMass
  const i = b.invInertia
  // X = I + W Minv, W symmetric (xx xy xw yy yw ww).
  const x00 = 1 + bd[ob] * m
  const x01 = bd[ob + 1] * m
  const x02 = bd[ob + 2] * i
  const x10 = bd[ob + 1] * m
  const x11 = 1 + bd[ob + 3] * m
  const x12 = bd[ob + 4] * i
  const x20 = bd[ob + 2] * m
  const x21 = bd[ob + 4] * m
  const x22 = 1 + bd[ob + 5] * i
  const c00 = x11 * x22 - x12 * x21
  const c01 = x12 * x20 - x10 * x22
  const c02 = x10 * x21 - x11 * x20
  let det = x00 * c00 + x01 * c01 + x02 * c02
  det = det !== 0 ? 1 / det : 0
  const d = ob + DINV
  // Row r of Dinv = Minv_r * row r of X^-1 (X^-1 = adj(X) / det).
  bd[d] = m * det * c00
  bd[d + 1] = m * det * (x02 * x21 - x01 * x22)
  bd[d + 2] = m * det * (x01 * x12 - x02 * x11)
  bd[d + 3] = m * det * c01
  bd[d + 4] = m * det * (x00 * x22 - x02 * x20)
  bd[d + 5] = m * det * (x02 * x10 - x00 * x12)
  bd[d + 6] = i * det * c02
  bd[d + 7] = i * det * (x01 * x20 - x00 * x21)
  bd[d + 8] = i * det * (x00 * x11 - x01 * x10)
}

/**
 * Joint k's pivot after eliminating its child body: D = -G Dinv G^T with G = [1 0 -ry; 0 1 rx],
 * stored inverted (xx, xy, yy), and its right-hand side b -= s G Dinv rhs.
 */
function eliminateBody(t: JointTree, k: number, ob: number): void {
  const bd = t.bodyData
  const jd = t.jointData
  const rx = t.arms[4 * k]
  const ry = t.arms[4 * k + 1]
  const d = ob + DINV
  // P = G Dinv (2x3).
  const p00 = bd[d] - ry * bd[d + 6]
  const p01 = bd[d + 1] - ry * bd[d + 7]
  const p02 = bd[d + 2] - ry * bd[d + 8]
  const p10 = bd[d + 3] + rx * bd[d + 6]
  const p11 = bd[d + 4] + rx * bd[d + 7]
  const p12 = bd[d + 5] + rx * bd[d + 8]
  // K = P G^T (2x2, symmetric up to rounding: the off-diagonal is averaged); D = -K.
  const g = t.gamma
  const o = JOINT_STRIDE * k
  let kxx = p00 - ry * p02
  let kxy = 0.5 * (p01 + rx * p02 + p10 - ry * p12)
  let kyy = p11 + rx * p12
  if (g > 0) {
    const j = t.joints[k]
    jd[o + JB] += g * (kxx * j.linearImpulseX + kxy * j.linearImpulseY)
    jd[o + JB + 1] += g * (kxy * j.linearImpulseX + kyy * j.linearImpulseY)
    kxx *= 1 + g
    kxy *= 1 + g
    kyy *= 1 + g
  }
  let det = kxx * kyy - kxy * kxy
  det = det !== 0 ? 1 / det : 0
  jd[o + JD] = -det * kyy
  jd[o + JD + 1] = det * kxy
  jd[o + JD + 3] = -det * kxx
  const s = t.childSign[k]
  jd[o + JB] -= s * (p00 * bd[ob + RHS] + p01 * bd[ob + RHS + 1] + p02 * bd[ob + RHS + 2])
  jd[o + JB + 1] -= s * (p10 * bd[ob + RHS] + p11 * bd[ob + RHS + 1] + p12 * bd[ob + RHS + 2])
}

/** Folds joint k into its parent body (data at `oq`): W -= G^T D^-1 G, rhs -= s G^T D^-1 b. */
function eliminateJoint(t: JointTree, k: number, oq: number): void {
  const bd = t.bodyData
  const jd = t.jointData
  const o = JOINT_STRIDE * k
  const gx = t.arms[4 * k + 2]
  const gy = t.arms[4 * k + 3]
  // E = -D^-1 (positive definite).
  const exx = -jd[o + JD]
  const exy = -jd[o + JD + 1]
  const eyy = -jd[o + JD + 3]
  // G^T E G with G = [1 0 -gy; 0 1 gx]: columns (1,0), (0,1), (-gy, gx).
  const ew0 = -gy * exx + gx * exy
  const ew1 = -gy * exy + gx * eyy
  bd[oq] += exx
  bd[oq + 1] += exy
  bd[oq + 2] += ew0
  bd[oq + 3] += eyy
  bd[oq + 4] += ew1
  bd[oq + 5] += -gy * ew0 + gx * ew1
  // rhs -= s G^T (D^-1 b) = s G^T (E b)  (D^-1 = -E).
  const s = -t.childSign[k]
  const ux = exx * jd[o + JB] + exy * jd[o + JB + 1]
  const uy = exy * jd[o + JB] + eyy * jd[o + JB + 1]
  bd[oq + RHS] += s * ux
  bd[oq + RHS + 1] += s * uy
  bd[oq + RHS + 2] += s * (-gy * ux + gx * uy)
}

/**
 * A weld's pivot after eliminating its child body (3 rows: G = [1 0 -ry; 0 1 rx; 0 0 1]):
 * D = -(1 + gamma) G Dinv G^T, stored inverted (xx xy xw yy yw ww), b -= s G Dinv rhs, and the
 * compliance term gamma K P added to b as for a pin.
 */
function eliminateBodyWeld(t: JointTree, k: number, ob: number): void {
  const bd = t.bodyData
  const jd = t.jointData
  const rx = t.arms[4 * k]
  const ry = t.arms[4 * k + 1]
  const d = ob + DINV
  // P = G Dinv (3x3).
  const p00 = bd[d] - ry * bd[d + 6]
  const p01 = bd[d + 1] - ry * bd[d + 7]
  const p02 = bd[d + 2] - ry * bd[d + 8]
  const p10 = bd[d + 3] + rx * bd[d + 6]
  const p11 = bd[d + 4] + rx * bd[d + 7]
  const p12 = bd[d + 5] + rx * bd[d + 8]
  const p20 = bd[d + 6]
  const p21 = bd[d + 7]
  const p22 = bd[d + 8]
  // K = P G^T, symmetrised.
  let kxx = p00 - ry * p02
  let kxy = 0.5 * (p01 + rx * p02 + p10 - ry * p12)
  let kxw = 0.5 * (p02 + p20 - ry * p22)
  let kyy = p11 + rx * p12
  let kyw = 0.5 * (p12 + p21 + rx * p22)
  let kww = p22
  const o = JOINT_STRIDE * k
  const g = t.gamma
  if (g > 0) {
    const j = t.joints[k]
    const px = j.linearImpulseX
    const py = j.linearImpulseY
    const pw = j.angularImpulse
    jd[o + JB] += g * (kxx * px + kxy * py + kxw * pw)
    jd[o + JB + 1] += g * (kxy * px + kyy * py + kyw * pw)
    jd[o + JB + 2] += g * (kxw * px + kyw * py + kww * pw)
    const f = 1 + g
    kxx *= f
    kxy *= f
    kxw *= f
    kyy *= f
    kyw *= f
    kww *= f
  }
  sym3[0] = kxx
  sym3[1] = kxy
  sym3[2] = kxw
  sym3[3] = kyy
  sym3[4] = kyw
  sym3[5] = kww
  invert33()
  for (let i = 0; i < 6; i++) jd[o + JD + i] = -inverse3[i]
  const s = t.childSign[k]
  const r0 = bd[ob + RHS]
  const r1 = bd[ob + RHS + 1]
  const r2 = bd[ob + RHS + 2]
  jd[o + JB] -= s * (p00 * r0 + p01 * r1 + p02 * r2)
  jd[o + JB + 1] -= s * (p10 * r0 + p11 * r1 + p12 * r2)
  jd[o + JB + 2] -= s * (p20 * r0 + p21 * r1 + p22 * r2)
}

/** Folds weld k into its parent body (data at `oq`): W -= G^T D^-1 G, rhs -= s G^T D^-1 b (3 rows). */
function eliminateJointWeld(t: JointTree, k: number, oq: number): void {
  const bd = t.bodyData
  const jd = t.jointData
  const o = JOINT_STRIDE * k
  const gx = t.arms[4 * k + 2]
  const gy = t.arms[4 * k + 3]
  // E = -D^-1 (positive definite).
  const exx = -jd[o + JD]
  const exy = -jd[o + JD + 1]
  const exw = -jd[o + JD + 2]
  const eyy = -jd[o + JD + 3]
  const eyw = -jd[o + JD + 4]
  const eww = -jd[o + JD + 5]
  // u = E G's third column (-gy, gx, 1).
  const u0 = -gy * exx + gx * exy + exw
  const u1 = -gy * exy + gx * eyy + eyw
  const u2 = -gy * exw + gx * eyw + eww
  bd[oq] += exx
  bd[oq + 1] += exy
  bd[oq + 2] += u0
  bd[oq + 3] += eyy
  bd[oq + 4] += u1
  bd[oq + 5] += -gy * u0 + gx * u1 + u2
  const s = -t.childSign[k]
  const b0 = jd[o + JB]
  const b1 = jd[o + JB + 1]
  const b2 = jd[o + JB + 2]
  const v0 = exx * b0 + exy * b1 + exw * b2
  const v1 = exy * b0 + eyy * b1 + eyw * b2
  const v2 = exw * b0 + eyw * b1 + eww * b2
  bd[oq + RHS] += s * v0
  bd[oq + RHS + 1] += s * v1
  bd[oq + RHS + 2] += s * (-gy * v0 + gx * v1 + v2)
}

/** A weld's impulse z = D^-1 (b - s_q G_q y_q), all three rows, into its data. */
function backSubstituteWeld(t: JointTree, k: number): void {
  const bd = t.bodyData
  const jd = t.jointData
  const o = JOINT_STRIDE * k
  let b0 = jd[o + JB]
  let b1 = jd[o + JB + 1]
  let b2 = jd[o + JB + 2]
  const q = t.parentSlot[k]
  if (q > 0) {
    const oq = q * BODY_STRIDE
    const sq = -t.childSign[k]
    const gx = t.arms[4 * k + 2]
    const gy = t.arms[4 * k + 3]
    b0 -= sq * (bd[oq + Y] - gy * bd[oq + Y + 2])
    b1 -= sq * (bd[oq + Y + 1] + gx * bd[oq + Y + 2])
    b2 -= sq * bd[oq + Y + 2]
  }
  const d = o + JD
  jd[o + JZ] = jd[d] * b0 + jd[d + 1] * b1 + jd[d + 2] * b2
  jd[o + JZ + 1] = jd[d + 1] * b0 + jd[d + 3] * b1 + jd[d + 4] * b2
  jd[o + JZ + 2] = jd[d + 2] * b0 + jd[d + 4] * b1 + jd[d + 5] * b2
}
