/*
 * The world: bodies, contacts, joints, and the fixed 1/60 s step.
 *
 * World.step() is Box2D v3's stage list (b2World_Step, solver.h), one call per stage:
 *
 *   applyForces          forces and torques given since the last step, as impulses
 *   updatePairs          broadphase (one proxy per shape): contacts for newly overlapping fat AABBs
 *   collide              narrowphase for every contact with an awake body; wake what gets touched
 *   buildSolverSets      awake bodies, active contacts and joints, all in id order
 *   prepareJoints        joint constraint data for the step
 *   prepareJointTree     Concord's own: the pins and rigid welds that form a tree, for the direct solver
 *   prepareContacts      flat contact constraint records
 *   planExtraSweeps      Concord's own: extra solver sweeps for pinched and slender bodies and tall columns
 *   sub-steps:
 *     integrateVelocities  gravity, damping, speed limits
 *     warmStart            joints, then contacts: apply the accumulated impulses
 *     solve                joints (Gauss-Seidel, then the joint tree exactly), then contacts, with
 *                          bias (soft push-out)
 *     integratePositions   accumulate the sub-step deltas
 *     relax                the same passes without bias
 *   applyRestitution     once, after the sub-steps
 *   storeImpulses        back into the contacts for warm starting
 *   reportHits           hit events (when a shape asked for them)
 *   finalizeBodies       fold the deltas into transforms, sleep velocities
 *   solveContinuous      time of impact for fast bodies and bullets
 *   updateBroadPhase     move the fat AABBs of awake bodies
 *   sleepIslands         islands that rested long enough go to sleep
 *   breakJoints          joints whose reaction exceeds a break threshold are destroyed
 *   updateSensors        sensor overlaps and their events
 *
 * The bodies' solver state lives in one array with named offsets (body-state.ts) that the contact
 * and joint stages read and write by a body's solver index. Every stage's working state (the joint
 * tree, the contact constraints, the continuous sweep) is owned by the world, never by a module, so
 * worlds on one thread share nothing.
 *
 * Determinism: bodies live in an array sorted by id, contacts in an array sorted by body-id pair,
 * joints by id; maps are used only for lookups by id, never iterated. Nothing allocates per step
 * once the arrays have grown.
 */

import { HIT_EVENT_SPEED, MAX_ROTATION, SPECULATIVE_DISTANCE, STEP_SECONDS } from '../constants.ts'
import {
  APPROACH,
  applyRestitution,
  type BodyShape,
  CONTACT_EVENTS,
  Contact,
  ContactConstraints,
  ContinuousSolver,
  clearContact,
  DYNAMIC,
  HIT_EVENTS,
  HIT_X,
  HIT_Y,
  hitOffset,
  integratePositions,
  integrateVelocities,
  limitBodyVelocity,
  loadSolverStates,
  measureApproach,
  POINT_0,
  POINT_FIELDS,
  planExtraSweeps,
  prepareContacts,
  NORMAL_X as RECORD_NORMAL_X,
  NORMAL_Y as RECORD_NORMAL_Y,
  STATE_STRIDE,
  STATIC,
  shouldFilterCollide,
  solveContacts,
  stateToBody,
  storeImpulses,
  TOTAL_NORMAL,
  updateContact,
  warmStartContacts,
} from '../dynamics/index.ts'
import {
  exceedsBreak,
  type Joint,
  JointTree,
  prepareJoints,
  prepareJointTree,
  solveJoints,
  solveJointTree,
  warmStartJoints,
} from '../joints/index.ts'
import type { JointEvents, WorldDef } from '../types.ts'
import type { ContactEvents, SensorEvents } from './events.ts'
import { QueryApi } from './query-api.ts'
import { ByteWriter } from './save-format.ts'
import { updateSensors } from './sensor.ts'
import { hashWorld, loadWorldState, saveWorld } from './world-state.ts'
import { resolveWorldDef } from './world-store.ts'

/** A simulation world. See engine/README.md for the public surface. */
export class World extends QueryApi {
  /** Advances the world by exactly one fixed step of 1/60 s. */
  step(): void {
    this.revision++
    this.events.beginStep()
    this.applyForces()
    this.updatePairs()
    this.collide()
    this.buildSolverSets()
    this.prepareJoints()
    this.prepareJointTree()
    this.prepareContacts()
    this.planExtraSweeps()
    for (let i = 0; i < this.settings.subSteps; i++) {
      this.integrateVelocities()
      this.warmStart()
      this.solve()
      this.integratePositions()
      this.relax()
    }
    this.applyRestitution()
    this.storeImpulses()
    this.reportHits()
    this.finalizeBodies()
    this.solveContinuous()
    this.updateBroadPhase()
    this.sleepIslands()
    this.breakJoints()
    this.updateSensors()
    this.events.finishStep()
    this.tickCount++
  }

  /** Joints that broke in the last step (ascending ids); they no longer exist. */
  jointEvents(): JointEvents {
    return { broken: this.brokenJoints.slice() }
  }

  /** Ids of the joints the last step broke (reused: cleared every step). */
  private readonly brokenJoints: number[] = []

  /**
   * Destroys every active joint whose reaction over this step exceeds its breakForce or
   * breakTorque (as getJointReaction reads it), in id order, waking its bodies.
   */
  private breakJoints(): void {
    this.brokenJoints.length = 0
    const scale = this.settings.subSteps / STEP_SECONDS
    for (let i = 0; i < this.activeJointCount; i++) {
      const j = this.activeJoints[i]
      if (exceedsBreak(j, scale)) this.brokenJoints.push(j.id)
    }
    for (let i = 0; i < this.brokenJoints.length; i++) this.destroyJoint(this.brokenJoints[i])
  }

  /** The last step's contact events (begin, end, hit), in shape-id order; valid until the next step. */
  contactEvents(): ContactEvents {
    return this.events.contactEvents()
  }

  /** The last step's sensor events (begin, end), in (sensor, visitor) id order; valid until the next step. */
  sensorEvents(): SensorEvents {
    return this.events.sensorEvents()
  }

  /** Everything that influences future steps, as versioned, checksummed bytes. */
  save(): Uint8Array {
    return saveWorld(this.writer, this)
  }

  /**
   * A 32-bit unsigned hash (FNV-1a) of the whole simulation state: the payload that save() writes.
   * Computed once per revision (nothing changed since the last call: the same value).
   */
  hash(): number {
    if (this.hashedRevision !== this.revision) {
      this.hashValue = hashWorld(this.writer, this)
      this.hashedRevision = this.revision
    }
    return this.hashValue
  }

  private hashedRevision = -1
  private hashValue = 0

  private readonly writer = new ByteWriter()
  /** Contacts created this step (sorted; the count is local to updatePairs). */
  private readonly newContacts: Contact[] = []
  /** Scratch: the step's active contacts with a static or kinematic body, before they are appended. */
  private readonly groundedContacts: Contact[] = []
  /** Solver state of the awake bodies (body-state.ts; record 0 static) and the contact constraints. */
  private state: Float64Array = new Float64Array(64 * STATE_STRIDE)
  private readonly constraints = new ContactConstraints()
  /** The direct solver's tree of pins and rigid welds, rebuilt every step (joint-tree.ts). */
  private readonly jointTree = new JointTree()
  /** The continuous stage's search state (continuous.ts). */
  private readonly continuous = new ContinuousSolver()

  /**
   * Forces and torques given since the last step act over this step: as the impulse F dt (and T dt)
   * at its start, then they are cleared (Box2D spreads them over the sub-steps; the velocity
   * reached at the step's end is the same).
   */
  private applyForces(): void {
    const forced = this.forced
    if (forced.length === 0) return
    const maxAngularSpeed = MAX_ROTATION * this.stepContext.invH
    for (let i = 0; i < forced.length; i++) {
      const b = forced[i]
      if (b.type === DYNAMIC) {
        b.vx += b.invMass * b.fx * STEP_SECONDS
        b.vy += b.invMass * b.fy * STEP_SECONDS
        b.w += b.invInertia * b.torque * STEP_SECONDS
        limitBodyVelocity(b, maxAngularSpeed)
      }
      b.fx = 0
      b.fy = 0
      b.torque = 0
    }
    forced.length = 0
  }

  /** Creates contacts for pairs whose fat AABBs began to overlap, keeping pair-key order. */
  private updatePairs(): void {
    const pairs = this.pairBuffer
    const n = this.broadPhase.updatePairs(pairs)
    // A count, not fresh.length = 0: V8 drops an array's storage when its length is set to 0, and
    // the pushes that follow would allocate it again every step.
    const fresh = this.newContacts
    let freshCount = 0
    for (let i = 0; i < n; i++) {
      const idA = pairs.a[i]
      const idB = pairs.b[i]
      if (this.contactMap.has(idA, idB)) continue
      const sa = this.shapeMap.get(idA)!
      const sb = this.shapeMap.get(idB)!
      if (!shouldCollide(sa, sb)) continue
      const contact = this.contactPool.pop()?.reset(sa, sb) ?? new Contact(sa, sb, this.contactStore)
      this.contactMap.set(idA, idB, contact)
      sa.body.contacts.push(contact)
      sb.body.contacts.push(contact)
      fresh[freshCount++] = contact
    }
    if (freshCount > 0) mergeContacts(this.contactArray, fresh, freshCount)
  }

  /**
   * Narrowphase for contacts with an awake body; destroys contacts whose fat AABBs parted. Also
   * sorts the touching contacts into the step's active list the way buildSolverSets does (pairs of
   * dynamic bodies, then pairs with a static or kinematic body), while each contact is in cache;
   * that list is only used if no body woke during the loop (a woken island can make contacts
   * visited earlier active).
   */
  private collide(): void {
    const contacts = this.contactArray
    const active = this.activeContacts
    const grounded = this.groundedContacts
    let kept = 0
    let m = 0
    let g = 0
    let woke = false
    const events = this.events
    for (let i = 0; i < contacts.length; i++) {
      const c = contacts[i]
      const a = c.bodyA
      const b = c.bodyB
      if (!a.awake && !b.awake) {
        contacts[kept++] = c
        continue
      }
      // Begin and end events: the touching flag before this step's narrowphase.
      const was = c.touching && (c.events & CONTACT_EVENTS) !== 0
      if (!this.broadPhase.testOverlap(c.proxyA, c.proxyB)) {
        if (was) events.addEnd(events.end, c.shapeA.id, c.shapeB.id)
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
      if (dx * dx + dy * dy > 1.0001 * reach * reach) {
        clearContact(c)
        if (was) events.addEnd(events.end, c.shapeA.id, c.shapeB.id)
      } else if (updateContact(c, SPECULATIVE_DISTANCE)) {
        if (c.events !== 0) {
          if ((c.events & CONTACT_EVENTS) !== 0 && !was) events.addEnd(events.begin, c.shapeA.id, c.shapeB.id)
          if ((c.events & HIT_EVENTS) !== 0) measureApproach(c)
        }
        if (!a.awake) {
          this.islands.wake(a)
          woke ||= a.awake
        }
        if (!b.awake) {
          this.islands.wake(b)
          woke ||= b.awake
        }
        if (a.invMass > 0 && b.invMass > 0) active[m++] = c
        else grounded[g++] = c
      } else if (was) events.addEnd(events.end, c.shapeA.id, c.shapeB.id)
    }
    contacts.length = kept
    this.collidedActive = woke ? -1 : m
    this.collidedGrounded = g
  }

  /** Active contacts sorted by collide(): the counts of both groups, or -1 when a body woke. */
  private collidedActive = -1
  private collidedGrounded = 0

  /** Collects awake bodies (loading their solver state), touching contacts and joints with an awake body, in id order. */
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
    // Contacts between two dynamic bodies first, then contacts with a static or kinematic body, so
    // that in each Gauss-Seidel pass the contacts that hold the world up are solved last (Box2D v3
    // keeps static contacts out of the first graph colour for the same reason). One pass: the
    // second group goes to a scratch list and is appended.
    const active = this.activeContacts
    const grounded = this.groundedContacts
    let m = this.collidedActive
    let g = this.collidedGrounded
    if (m < 0) {
      // A body woke during collide: sort again now that every island is awake or asleep for the step.
      const contacts = this.contactArray
      m = 0
      g = 0
      for (let i = 0; i < contacts.length; i++) {
        const c = contacts[i]
        const a = c.bodyA
        const b = c.bodyB
        if (!c.touching || (!a.awake && !b.awake)) continue
        if (a.invMass > 0 && b.invMass > 0) active[m++] = c
        else grounded[g++] = c
      }
    }
    for (let i = 0; i < g; i++) active[m++] = grounded[i]
    this.activeContactCount = m
    const activeJoints = this.activeJoints
    let k = 0
    for (let i = 0; i < this.jointList.length; i++) {
      const j = this.jointList[i]
      if (j.bodyA.awake || j.bodyB.awake) activeJoints[k++] = j
    }
    this.activeJointCount = k
    this.state = loadSolverStates(this.awake, n, this.state)
    this.stepContext.gravityX = this.gravityX
    this.stepContext.gravityY = this.gravityY
  }

  /** Prepares the active joints for the step. */
  private prepareJoints(): void {
    prepareJoints(this.activeJoints, this.activeJointCount, this.state, this.stepContext)
  }

  /** Chooses this step's tree among the active pins and rigid welds; the others stay Gauss-Seidel. */
  private prepareJointTree(): void {
    prepareJointTree(this.jointTree, this.activeJoints, this.activeJointCount)
  }

  /** Copies the touching contacts into flat constraint records. */
  private prepareContacts(): void {
    prepareContacts(
      this.constraints,
      this.activeContacts,
      this.activeContactCount,
      this.contactSoftness,
      this.staticSoftness,
      this.awakeCount + 1,
      this.stepContext,
    )
  }

  /** Picks the contact constraints that get extra sweeps this step, and how stiff (extra-sweeps.ts). */
  private planExtraSweeps(): void {
    planExtraSweeps(this.constraints, this.stepContext, this.awakeCount + 1)
  }

  /** Sub-step: gravity, damping and the speed limits. */
  private integrateVelocities(): void {
    integrateVelocities(this.awake, this.awakeCount, this.state, this.stepContext)
  }

  /** Sub-step: applies the accumulated joint and contact impulses. */
  private warmStart(): void {
    if (this.activeJointCount > 0) warmStartJoints(this.activeJoints, this.activeJointCount, this.state)
    warmStartContacts(this.constraints, this.state)
  }

  /** Sub-step: one iteration over joints, then contacts, with bias (position error is pushed out). */
  private solve(): void {
    if (this.activeJointCount > 0) {
      solveJoints(this.activeJoints, this.activeJointCount, this.state, this.stepContext, true)
      solveJointTree(this.jointTree, this.state, this.stepContext, true)
    }
    solveContacts(this.constraints, this.state, this.stepContext, true)
  }

  /** Sub-step: accumulates the position and rotation deltas. */
  private integratePositions(): void {
    integratePositions(this.state, this.awakeCount, this.stepContext)
  }

  /** Sub-step: one iteration over joints, then contacts, without bias (removes the push-out speed). */
  private relax(): void {
    if (this.activeJointCount > 0) {
      solveJoints(this.activeJoints, this.activeJointCount, this.state, this.stepContext, false)
      solveJointTree(this.jointTree, this.state, this.stepContext, false)
    }
    solveContacts(this.constraints, this.state, this.stepContext, false)
  }

  /** Bounces contacts that closed faster than the restitution threshold, once per step. */
  private applyRestitution(): void {
    applyRestitution(this.constraints, this.state, this.stepContext)
  }

  /** Copies the accumulated contact impulses back for warm starting and read-back. */
  private storeImpulses(): void {
    storeImpulses(this.constraints, this.activeContacts)
  }

  /** Folds the deltas into the transforms and updates sleep timers. */
  private finalizeBodies(): void {
    const enableSleep = this.settings.enableSleep
    const state = this.state
    const maxAngularSpeed = MAX_ROTATION * this.stepContext.invH
    // The threshold is read from the step context, not the settings object: the settings' number
    // fields are not known doubles to V8, and comparing with one boxed the sleep velocity (a heap
    // number per resting body per step; bench:alloc's room).
    const sleepThreshold = this.stepContext.sleepThreshold
    for (let i = 0; i < this.awakeCount; i++) {
      const b = this.awake[i]
      stateToBody(state, b)
      // Restitution runs after the last clamp; keep the stored velocity within the limits too.
      limitBodyVelocity(b, maxAngularSpeed)
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
      if (!enableSleep || !b.enableSleep || sleepVelocity > sleepThreshold) b.sleepTime = 0
      else b.sleepTime += STEP_SECONDS
      b.dpx = 0
      b.dpy = 0
      b.dqc = 1
      b.dqs = 0
      b.updateOrigin()
    }
  }

  /**
   * Hit events: touching contacts that ask for them, closed faster than HIT_EVENT_SPEED at the step
   * start and pushed this step (Box2D's hit events), in shape-id order.
   */
  private reportHits(): void {
    if (this.hitEventShapes === 0) return
    const contacts = this.contactArray
    const events = this.events
    for (let i = 0; i < contacts.length; i++) {
      const c = contacts[i]
      if ((c.events & HIT_EVENTS) === 0 || !c.touching || (!c.bodyA.awake && !c.bodyB.awake)) continue
      const d = c.store.data
      const o = c.base
      const h = c.store.hits
      const ho = hitOffset(o)
      if (!(h[ho + APPROACH] > HIT_EVENT_SPEED)) continue
      const pushed =
        d[o + POINT_0 + TOTAL_NORMAL] > 0 ||
        (c.pointCount > 1 && d[o + POINT_0 + POINT_FIELDS + TOTAL_NORMAL] > 0)
      if (!pushed) continue
      const e = events.hit.next()
      e.shapeA = c.shapeA.id
      e.shapeB = c.shapeB.id
      e.point.x = h[ho + HIT_X]
      e.point.y = h[ho + HIT_Y]
      e.normal.x = d[o + RECORD_NORMAL_X]
      e.normal.y = d[o + RECORD_NORMAL_Y]
      e.approachSpeed = h[ho + APPROACH]
    }
  }

  /** Sensor overlaps and their begin and end events. */
  private updateSensors(): void {
    if (this.sensors.length === 0) return
    updateSensors(this.sensors, this.broadPhase, this.shapeMap, this.events, this.aabb, this.sensorBox)
  }

  /** The tight AABB of a sensor into `aabb` (a bound method made once: no closure per step). */
  private readonly sensorBox = (s: BodyShape): void => this.computeAABB(s, false)

  /** Time of impact for fast bodies and bullets (when continuous collision is on). */
  private solveContinuous(): void {
    if (!this.settings.enableContinuous) return
    this.continuous.solve(this.awake, this.awakeCount, this.broadPhase, this.shapeMap, shouldCollide)
  }

  /** Puts islands to sleep that rested long enough (when sleeping is on). */
  private sleepIslands(): void {
    if (!this.settings.enableSleep) return
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

  /** Moves the fat AABBs of awake bodies in the broadphase. */
  private updateBroadPhase(): void {
    for (let i = 0; i < this.awakeCount; i++) this.moveProxy(this.awake[i], true)
  }
}

/** Creates a world; every setting not given takes its default (DEFAULT_WORLD_DEF). */
export function createWorld(def: WorldDef = {}): World {
  return new World(resolveWorldDef(def))
}

/** Builds a world from bytes made by World.save(); it steps bit-identically to the original. */
export function loadWorld(bytes: Uint8Array): World {
  return loadWorldState(bytes, (settings) => new World(settings))
}

/**
 * Whether two shapes should get a contact: they are on different bodies, one of which is dynamic;
 * neither is a sensor; their filters agree (Box2D's rule); and no joint between the bodies forbids it.
 */
function shouldCollide(sa: BodyShape, sb: BodyShape): boolean {
  const a = sa.body
  const b = sb.body
  if (a === b) return false
  if (a.type !== DYNAMIC && b.type !== DYNAMIC) return false
  if (sa.sensor || sb.sensor || !shouldFilterCollide(sa, sb)) return false
  const joints = a.joints.length < b.joints.length ? a.joints : b.joints
  for (let i = 0; i < joints.length; i++) {
    const j: Joint = joints[i]
    if (j.collideConnected) continue
    if ((j.bodyA === a && j.bodyB === b) || (j.bodyA === b && j.bodyB === a)) return false
  }
  return true
}

/**
 * Merges the first `count` contacts of `fresh` (sorted) into the sorted `contacts` array in place. Each fresh contact's
 * place is found by binary search, and the old contacts after it move up as a block: O(k log n)
 * key reads instead of one per moved contact (a key read touches the contact object, a cache miss
 * in a big world), plus the pointer moves.
 */
function mergeContacts(contacts: Contact[], fresh: Contact[], count: number): void {
  let end = contacts.length
  contacts.length = end + count
  for (let j = count - 1; j >= 0; j--) {
    const key = fresh[j].key
    // First old contact in [0, end) with a larger key (fresh keys are never in `contacts`).
    let lo = 0
    let hi = end
    while (lo < hi) {
      const mid = (lo + hi) >>> 1
      if (contacts[mid].key > key) hi = mid
      else lo = mid + 1
    }
    for (let m = end - 1; m >= lo; m--) contacts[m + j + 1] = contacts[m]
    contacts[lo + j] = fresh[j]
    end = lo
  }
}
