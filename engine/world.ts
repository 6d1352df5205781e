/*
 * The world: bodies, contacts, joints, and the fixed 1/60 s step.
 *
 * World.step() reads like Box2D v3's solver stages:
 *
 *   updatePairs        broadphase: contacts for newly overlapping fat AABBs
 *   collide            narrowphase for every contact with an awake body; wake what gets touched
 *   buildSolverSets    awake bodies, active contacts and joints, all in id order
 *   prepareJoints / prepareContacts
 *   sub-steps:         integrateVelocities, warmStart, solve (biased), integratePositions, relax
 *   applyRestitution
 *   finalizeBodies     fold the sub-step deltas into transforms, sleep velocities, fat AABBs
 *   solveContinuous    time of impact for fast bodies and bullets
 *   sleepIslands
 *
 * Determinism: bodies live in an array sorted by id, contacts in an array sorted by body-id pair,
 * joints by id; maps are used only for lookups by id, never iterated. Nothing allocates per step
 * once the arrays have grown.
 */
import { type Body, DYNAMIC, STATIC } from './body.ts'
import { Contact, clearContact, KEY_SCALE, updateContact } from './contact.ts'
import {
  applyRestitution,
  ContactConstraints,
  prepareContacts,
  STATE_STRIDE,
  solveContacts,
  storeImpulses,
  warmStartContacts,
} from './contact-solver.ts'
import { solveContinuous } from './continuous.ts'
import { type Joint, prepareJoints, solveJoints, warmStartJoints } from './joint.ts'
import {
  integratePositions,
  integrateVelocities,
  jointBodiesToStates,
  loadSolverStates,
  statesToJointBodies,
  stateToBody,
} from './solver-bodies.ts'
import type { WorldDef } from './types.ts'
import { WorldApi } from './world-api.ts'
import {
  type ByteReader,
  ByteWriter,
  beginSave,
  fnv1a,
  openSave,
  readBody,
  readContact,
  readJoint,
  sealSave,
  WorldLoadError,
  writeBody,
  writeContact,
  writeJoint,
} from './world-state.ts'
import {
  DEFAULT_WORLD_DEF,
  type ResolvedWorldDef,
  SPECULATIVE_DISTANCE,
  STEP_SECONDS,
} from './world-store.ts'

/** A simulation world. See engine/README.md for the public surface. */
export class World extends WorldApi {
  /** Advances the world by exactly one fixed step of 1/60 s. */
  step(): void {
    this.updatePairs()
    this.collide()
    this.buildSolverSets()
    this.solve()
    this.finalizeBodies()
    if (this.settings.enableContinuous) {
      solveContinuous(this.awake, this.awakeCount, this.broadPhase, this.bodyMap, shouldCollide)
    }
    this.updateBroadPhase()
    if (this.settings.enableSleep) {
      this.islands.sleepIslands(
        this.awake,
        this.awakeCount,
        this.activeContacts,
        this.activeContactCount,
        this.activeJoints,
        this.activeJointCount,
        this.settings.timeToSleep,
      )
    }
    this.tickCount++
  }

  /** Everything that influences future steps, as versioned, checksummed bytes. */
  save(): Uint8Array {
    this.writeState(this.writer)
    return sealSave(this.writer)
  }

  /** A 32-bit unsigned hash (FNV-1a) of the whole simulation state: the payload that save() writes. */
  hash(): number {
    this.writeState(this.writer)
    return fnv1a(this.writer.bytes, 16, this.writer.length)
  }

  private readonly writer = new ByteWriter()
  /** Contacts created this step (sorted), and destroyed contacts kept for reuse. */
  private readonly newContacts: Contact[] = []
  private readonly contactPool: Contact[] = []
  /** Solver state of the awake bodies (STATE_STRIDE numbers each, slot 0 static) and the constraints. */
  private state: Float64Array = new Float64Array(64 * STATE_STRIDE)
  private readonly constraints = new ContactConstraints()
  private readonly fatAABB = new Float64Array(4)

  private writeState(w: ByteWriter): void {
    beginSave(w)
    const s = this.settings
    w.f64(this.gravityX)
    w.f64(this.gravityY)
    w.u32(s.subSteps)
    w.u8((s.enableSleep ? 1 : 0) | (s.enableContinuous ? 2 : 0))
    for (const key of SETTINGS_NUMBERS) w.f64(s[key])
    w.f64(this.tickCount)
    w.f64(this.nextBodyId)
    w.f64(this.nextJointId)
    w.u32(this.bodies.length)
    for (const b of this.bodies) {
      writeBody(w, b)
      this.broadPhase.getFatAABB(b.proxy, this.fatAABB)
      for (let i = 0; i < 4; i++) w.f64(this.fatAABB[i])
    }
    w.u32(this.contactArray.length)
    for (const c of this.contactArray) writeContact(w, c)
    w.u32(this.jointList.length)
    for (const j of this.jointList) writeJoint(w, j)
  }

  /** Rebuilds a world from saved bytes (see world-state.ts for the format). */
  static fromBytes(bytes: Uint8Array): World {
    const r = openSave(bytes)
    const gravity = { x: r.num('gravity'), y: r.num('gravity') }
    const subSteps = r.u32('subSteps')
    const flags = r.u8('world flags')
    const def: WorldDef = {
      gravity,
      subSteps,
      enableSleep: (flags & 1) !== 0,
      enableContinuous: (flags & 2) !== 0,
    }
    for (const key of SETTINGS_NUMBERS) def[key] = r.num(key)
    let world: World
    try {
      world = new World(resolveWorldDef(def))
    } catch (e) {
      throw new WorldLoadError(`saved world has invalid settings: ${(e as Error).message}`)
    }
    world.tickCount = r.num('tick')
    world.nextBodyId = r.num('next body id')
    world.nextJointId = r.num('next joint id')
    world.readBodies(r)
    const lookup = (id: number): Body => {
      const b = id === 0 ? world.ground : world.bodyMap.get(id)
      if (b === undefined) throw new WorldLoadError(`saved world refers to missing body ${id}`)
      return b
    }
    const contactCount = r.u32('contact count')
    for (let i = 0; i < contactCount; i++) {
      const c = readContact(r, lookup)
      if (world.contactMap.has(c.key))
        throw new WorldLoadError(`saved world has a duplicate contact ${c.bodyA.id}-${c.bodyB.id}`)
      if (i > 0 && world.contactArray[i - 1].key > c.key)
        throw new WorldLoadError('saved world has contacts out of order')
      world.contactArray.push(c)
      world.contactMap.set(c.key, c)
      c.bodyA.contacts.push(c)
      c.bodyB.contacts.push(c)
    }
    const jointCount = r.u32('joint count')
    for (let i = 0; i < jointCount; i++) {
      const j = readJoint(r, lookup)
      if (world.jointMap.has(j.id) || j.id >= world.nextJointId)
        throw new WorldLoadError(`saved world has an invalid joint id ${j.id}`)
      world.jointList.push(j)
      world.jointMap.set(j.id, j)
      j.bodyA.joints.push(j)
      j.bodyB.joints.push(j)
    }
    r.finish()
    return world
  }

  private readBodies(r: ByteReader): void {
    const count = r.u32('body count')
    let lastId = 0
    for (let i = 0; i < count; i++) {
      const b = readBody(r)
      if (!(b.id > lastId) || b.id >= this.nextBodyId || !Number.isInteger(b.id)) {
        throw new WorldLoadError(`saved world has an invalid or out-of-order body id ${b.id}`)
      }
      lastId = b.id
      this.updateMass(b)
      const box = [r.num('fat AABB'), r.num('fat AABB'), r.num('fat AABB'), r.num('fat AABB')]
      b.proxy = this.broadPhase.createProxyWithFatAABB(
        box[0],
        box[1],
        box[2],
        box[3],
        b.id,
        b.type === STATIC,
      )
      // Every proxy is queried at the next step; pairs that already have a contact are skipped.
      this.broadPhase.touchProxy(b.proxy)
      this.bodies.push(b)
      this.bodyMap.set(b.id, b)
    }
  }

  /** Creates contacts for pairs whose fat AABBs began to overlap, keeping pair-key order. */
  private updatePairs(): void {
    const pairs = this.pairBuffer
    const n = this.broadPhase.updatePairs(pairs)
    const fresh = this.newContacts
    fresh.length = 0
    for (let i = 0; i < n; i++) {
      const key = pairs.a[i] * KEY_SCALE + pairs.b[i]
      if (this.contactMap.has(key)) continue
      const a = this.bodyMap.get(pairs.a[i])!
      const b = this.bodyMap.get(pairs.b[i])!
      if (!shouldCollide(a, b)) continue
      const contact = this.contactPool.pop()?.reset(a, b) ?? new Contact(a, b)
      this.contactMap.set(key, contact)
      a.contacts.push(contact)
      b.contacts.push(contact)
      fresh.push(contact)
    }
    if (fresh.length > 0) mergeContacts(this.contactArray, fresh)
  }

  /** Narrowphase for contacts with an awake body; destroys contacts whose fat AABBs parted. */
  private collide(): void {
    const contacts = this.contactArray
    let kept = 0
    for (let i = 0; i < contacts.length; i++) {
      const c = contacts[i]
      const a = c.bodyA
      const b = c.bodyB
      if (!a.awake && !b.awake) {
        contacts[kept++] = c
        continue
      }
      if (!this.broadPhase.testOverlap(a.proxy, b.proxy)) {
        this.unlinkContact(c)
        this.contactPool.push(c)
        continue
      }
      contacts[kept++] = c
      // Bounding circles about the centres of mass farther apart than the speculative distance
      // cannot produce a point: skip the narrowphase (many broadphase pairs are near, not touching).
      // The 1e-4 relative slack keeps borderline pairs on the exact path, so results are unchanged.
      const dx = b.cx - a.cx
      const dy = b.cy - a.cy
      const reach = a.maxExtent + b.maxExtent + SPECULATIVE_DISTANCE
      if (dx * dx + dy * dy > 1.0001 * reach * reach) clearContact(c)
      else if (updateContact(c, SPECULATIVE_DISTANCE)) {
        if (!a.awake) this.islands.wake(a)
        if (!b.awake) this.islands.wake(b)
      }
    }
    contacts.length = kept
  }

  /** Collects awake bodies, touching contacts and joints with an awake body, in id order. */
  private buildSolverSets(): void {
    const bodies = this.bodies
    const awake = this.awake
    let n = 0
    for (let i = 0; i < bodies.length; i++) {
      const b = bodies[i]
      if (b.awake && b.type !== STATIC) {
        b.solverIndex = n
        awake[n++] = b
      } else {
        b.solverIndex = -1
      }
    }
    this.awakeCount = n
    const active = this.activeContacts
    let m = 0
    for (let i = 0; i < this.contactArray.length; i++) {
      const c = this.contactArray[i]
      if (c.touching && (c.bodyA.awake || c.bodyB.awake)) active[m++] = c
    }
    this.activeContactCount = m
    const activeJoints = this.activeJoints
    let k = 0
    for (let i = 0; i < this.jointList.length; i++) {
      const j = this.jointList[i]
      if (j.bodyA.awake || j.bodyB.awake) activeJoints[k++] = j
    }
    this.activeJointCount = k
  }

  /** The soft step: prepare, then sub-steps of integrate, warm start, solve, integrate, relax. */
  private solve(): void {
    const s = this.settings
    const subSteps = s.subSteps
    const ctx = this.stepContext
    ctx.gravityX = this.gravityX
    ctx.gravityY = this.gravityY
    const k = this.constraints
    const joints = this.activeJoints
    const jointCount = this.activeJointCount
    const hasJoints = jointCount > 0
    this.state = loadSolverStates(this.awake, this.awakeCount, this.state)
    prepareJoints(joints, jointCount, ctx)
    prepareContacts(
      k,
      this.activeContacts,
      this.activeContactCount,
      this.contactSoftness,
      this.staticSoftness,
    )
    const state = this.state
    for (let i = 0; i < subSteps; i++) {
      integrateVelocities(this.awake, this.awakeCount, state, ctx)
      if (hasJoints) {
        statesToJointBodies(state, joints, jointCount)
        warmStartJoints(joints, jointCount)
        jointBodiesToStates(state, joints, jointCount)
      }
      warmStartContacts(k, state)
      if (hasJoints) {
        statesToJointBodies(state, joints, jointCount)
        solveJoints(joints, jointCount, ctx, true)
        jointBodiesToStates(state, joints, jointCount)
      }
      solveContacts(k, state, ctx, true)
      integratePositions(state, this.awakeCount, ctx)
      if (hasJoints) {
        statesToJointBodies(state, joints, jointCount)
        solveJoints(joints, jointCount, ctx, false)
        jointBodiesToStates(state, joints, jointCount)
      }
      solveContacts(k, state, ctx, false)
    }
    applyRestitution(k, state, ctx)
    storeImpulses(k, this.activeContacts)
  }

  /** Folds the deltas into the transforms and updates sleep timers. */
  private finalizeBodies(): void {
    const s = this.settings
    const enableSleep = s.enableSleep
    const state = this.state
    for (let i = 0; i < this.awakeCount; i++) {
      const b = this.awake[i]
      stateToBody(state, b)
      b.c0x = b.cx
      b.c0y = b.cy
      b.q0c = b.c
      b.q0s = b.s
      b.cx += b.dpx
      b.cy += b.dpy
      const qc = b.dqc * b.c - b.dqs * b.s
      const qs = b.dqs * b.c + b.dqc * b.s
      const mag = Math.sqrt(qc * qc + qs * qs)
      const inv = mag > 0 ? 1 / mag : 0
      b.c = qc * inv
      b.s = qs * inv
      // Sleep velocity: the fastest point, and half of any position-correction motion.
      const maxVelocity = Math.sqrt(b.vx * b.vx + b.vy * b.vy) + Math.abs(b.w) * b.maxExtent
      const maxDelta = Math.sqrt(b.dpx * b.dpx + b.dpy * b.dpy) + Math.abs(b.dqs) * b.maxExtent
      const sleepVelocity = Math.max(maxVelocity, (0.5 * maxDelta) / STEP_SECONDS)
      if (!enableSleep || !b.enableSleep || sleepVelocity > s.sleepThreshold) b.sleepTime = 0
      else b.sleepTime += STEP_SECONDS
      b.dpx = 0
      b.dpy = 0
      b.dqc = 1
      b.dqs = 0
      b.updateOrigin()
    }
  }

  /** Moves the fat AABBs of awake bodies in the broadphase. */
  private updateBroadPhase(): void {
    for (let i = 0; i < this.awakeCount; i++) this.moveProxy(this.awake[i], true)
  }
}

const SETTINGS_NUMBERS = [
  'contactHertz',
  'contactDampingRatio',
  'maxContactPushSpeed',
  'restitutionThreshold',
  'sleepThreshold',
  'timeToSleep',
] as const

/** Creates a world; every setting not given takes its default (DEFAULT_WORLD_DEF). */
export function createWorld(def: WorldDef = {}): World {
  return new World(resolveWorldDef(def))
}

/** Validates a WorldDef and fills in the defaults; throws a RangeError naming a bad value. */
export function resolveWorldDef(def: WorldDef): ResolvedWorldDef {
  const d = { ...DEFAULT_WORLD_DEF, ...def }
  const g = d.gravity
  if (!g || !Number.isFinite(g.x) || !Number.isFinite(g.y))
    throw new RangeError(`gravity must be a finite vector, got ${JSON.stringify(g)}`)
  if (!Number.isInteger(d.subSteps) || d.subSteps < 1 || d.subSteps > 64) {
    throw new RangeError(`subSteps must be an integer in [1, 64], got ${d.subSteps}`)
  }
  for (const key of SETTINGS_NUMBERS) {
    const v = d[key]
    if (typeof v !== 'number' || !Number.isFinite(v) || v < 0)
      throw new RangeError(`${key} must be a finite number >= 0, got ${v}`)
  }
  return {
    ...d,
    gravity: { x: g.x, y: g.y },
    enableSleep: d.enableSleep !== false,
    enableContinuous: d.enableContinuous !== false,
  }
}

/** Builds a world from bytes made by World.save(); it steps bit-identically to the original. */
export function loadWorld(bytes: Uint8Array): World {
  return World.fromBytes(bytes)
}

/** Whether two bodies should get a contact: one must be dynamic, and no joint between them may forbid it. */
export function shouldCollide(a: Body, b: Body): boolean {
  if (a.type !== DYNAMIC && b.type !== DYNAMIC) return false
  const joints = a.joints.length < b.joints.length ? a.joints : b.joints
  for (let i = 0; i < joints.length; i++) {
    const j: Joint = joints[i]
    if (j.collideConnected) continue
    if ((j.bodyA === a && j.bodyB === b) || (j.bodyA === b && j.bodyB === a)) return false
  }
  return true
}

/** Merges sorted `fresh` contacts into the sorted `contacts` array in place, O(n + k). */
function mergeContacts(contacts: Contact[], fresh: Contact[]): void {
  let i = contacts.length - 1
  let j = fresh.length - 1
  let w = contacts.length + fresh.length - 1
  contacts.length = w + 1
  while (j >= 0) {
    if (i >= 0 && contacts[i].key > fresh[j].key) contacts[w--] = contacts[i--]
    else contacts[w--] = fresh[j--]
  }
}
