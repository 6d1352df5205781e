/*
 * The world's public methods: creating and destroying bodies and joints, reading and changing
 * their state, and reading contacts and joints back for drawing. Every input is validated at the
 * boundary and a bad one throws a RangeError that names the value, so a caller (the server applying
 * a player's command) can never put a NaN, an infinity or a dangling id into the simulation.
 */
import { Body, DYNAMIC, STATIC } from './body.ts'
import { DISTANCE, JOINT_TYPE_NAMES, Joint, MOUSE, REVOLUTE } from './joint.ts'
import { atan2, cos, sin, type Vec2 } from './math.ts'
import { computeMass, type Shape } from './shapes.ts'
import type { BodyDef, BodyId, BodyType, ContactInfo, JointDef, JointId, JointInfo } from './types.ts'
import { STEP_SECONDS, WorldStore } from './world-store.ts'

const BODY_TYPES: readonly BodyType[] = ['static', 'kinematic', 'dynamic']

function finite(what: string, value: number): number {
  if (typeof value !== 'number' || !Number.isFinite(value))
    throw new RangeError(`${what} must be a finite number, got ${value}`)
  return value
}

function finiteVec(what: string, v: Vec2): Vec2 {
  if (v === null || typeof v !== 'object') throw new RangeError(`${what} must be a {x, y} vector, got ${v}`)
  finite(`${what}.x`, v.x)
  finite(`${what}.y`, v.y)
  return v
}

function inRange(what: string, value: number, lo: number, hi: number): number {
  finite(what, value)
  if (value < lo || value > hi) throw new RangeError(`${what} must be in [${lo}, ${hi}], got ${value}`)
  return value
}

function checkShape(shape: Shape): Shape {
  if (shape === null || typeof shape !== 'object' || (shape.type !== 'circle' && shape.type !== 'polygon')) {
    throw new RangeError('body shape must be made by circle(), box() or polygon()')
  }
  return shape
}

/** Public methods of a world. */
export class WorldApi extends WorldStore {
  /** Steps taken since creation. */
  get tick(): number {
    return this.tickCount
  }

  /** Number of bodies. */
  get bodyCount(): number {
    return this.bodies.length
  }

  /** Creates a body; ids are handed out 1, 2, 3... and never reused. Throws on an invalid definition. */
  createBody(def: BodyDef): BodyId {
    const typeIndex = BODY_TYPES.indexOf(def.type ?? 'dynamic')
    if (typeIndex < 0) throw new RangeError(`body type must be static, kinematic or dynamic, got ${def.type}`)
    const body = new Body(this.nextBodyId, typeIndex, checkShape(def.shape))
    const position = finiteVec('position', def.position ?? { x: 0, y: 0 })
    const angle = finite('angle', def.angle ?? 0)
    body.density = inRange('density', def.density ?? 1, 1e-6, 1e6)
    body.friction = inRange('friction', def.friction ?? 0.6, 0, 100)
    body.restitution = inRange('restitution', def.restitution ?? 0, 0, 1)
    body.linearDamping = inRange('linearDamping', def.linearDamping ?? 0, 0, 1e6)
    body.angularDamping = inRange('angularDamping', def.angularDamping ?? 0, 0, 1e6)
    body.gravityScale = inRange('gravityScale', def.gravityScale ?? 1, -1e3, 1e3)
    body.bullet = def.bullet === true
    body.enableSleep = def.enableSleep !== false
    body.fixedRotation = def.fixedRotation === true
    this.nextBodyId++
    this.updateMass(body)
    body.x = position.x
    body.y = position.y
    body.c = cos(angle)
    body.s = sin(angle)
    body.updateCenter()
    if (typeIndex !== STATIC) {
      const v = finiteVec('linearVelocity', def.linearVelocity ?? { x: 0, y: 0 })
      body.vx = v.x
      body.vy = v.y
      body.w = body.fixedRotation ? 0 : finite('angularVelocity', def.angularVelocity ?? 0)
    }
    body.awake = typeIndex !== STATIC && def.awake !== false
    this.bodies.push(body)
    this.bodyMap.set(body.id, body)
    this.createProxy(body)
    return body.id
  }

  /** Sets mass, inertia, centre of mass and extents from the shape and density. */
  protected updateMass(body: Body): void {
    const shape = body.shape
    const md = computeMass(shape, body.density)
    body.localCenterX = md.center.x
    body.localCenterY = md.center.y
    if (body.type === DYNAMIC) {
      body.mass = md.mass
      body.invMass = 1 / md.mass
      body.inertia = body.fixedRotation ? 0 : md.inertia
      body.invInertia = body.fixedRotation ? 0 : 1 / md.inertia
    }
    if (shape.type === 'circle') {
      body.maxExtent = shape.radius
      body.minExtent = shape.radius
      return
    }
    let maxExtent = 0
    let minExtent = Number.POSITIVE_INFINITY
    for (let i = 0; i < shape.count; i++) {
      const v = shape.vertices[i]
      const dx = v.x - md.center.x
      const dy = v.y - md.center.y
      maxExtent = Math.max(maxExtent, Math.sqrt(dx * dx + dy * dy))
      const n = shape.normals[i]
      minExtent = Math.min(minExtent, n.x * dx + n.y * dy)
    }
    body.maxExtent = maxExtent
    body.minExtent = minExtent
  }

  /** Destroys a body, its contacts and its joints, and wakes everything it touched. */
  destroyBody(id: BodyId): void {
    const body = this.body(id)
    for (const j of body.joints.slice()) this.destroyJoint(j.id)
    for (const c of body.contacts.slice()) {
      const other = c.bodyA === body ? c.bodyB : c.bodyA
      this.unlinkContact(c)
      this.islands.wake(other)
      this.broadPhase.touchProxy(other.proxy)
    }
    const contacts = this.contactArray
    let kept = 0
    for (let i = 0; i < contacts.length; i++) {
      if (contacts[i].bodyA !== body && contacts[i].bodyB !== body) contacts[kept++] = contacts[i]
    }
    contacts.length = kept
    this.broadPhase.destroyProxy(body.proxy)
    this.bodies.splice(this.bodies.indexOf(body), 1)
    this.bodyMap.delete(id)
  }

  /** Whether a body with this id exists. */
  hasBody(id: BodyId): boolean {
    return this.bodyMap.has(id)
  }

  /** All body ids, ascending. */
  bodyIds(): BodyId[] {
    return this.bodies.map((b) => b.id)
  }

  /** Number of awake (non-static) bodies. */
  awakeBodyCount(): number {
    let n = 0
    for (const b of this.bodies) if (b.awake) n++
    return n
  }

  getBodyType(id: BodyId): BodyType {
    return BODY_TYPES[this.body(id).type]
  }

  /** The body's shape (shared, immutable). */
  getShape(id: BodyId): Shape {
    return this.body(id).shape
  }

  /** World position of the body origin (m). */
  getPosition(id: BodyId, out: Vec2 = { x: 0, y: 0 }): Vec2 {
    const b = this.body(id)
    out.x = b.x
    out.y = b.y
    return out
  }

  /** Rotation angle in [-pi, pi] (rad). */
  getAngle(id: BodyId): number {
    const b = this.body(id)
    return atan2(b.s, b.c)
  }

  /** Rotation as its (cos, sin) pair, exact (no angle round trip). */
  getRotation(id: BodyId, out: { c: number; s: number } = { c: 1, s: 0 }): { c: number; s: number } {
    const b = this.body(id)
    out.c = b.c
    out.s = b.s
    return out
  }

  /** Velocity of the centre of mass (m/s). */
  getLinearVelocity(id: BodyId, out: Vec2 = { x: 0, y: 0 }): Vec2 {
    const b = this.body(id)
    out.x = b.vx
    out.y = b.vy
    return out
  }

  /** Angular velocity (rad/s). */
  getAngularVelocity(id: BodyId): number {
    return this.body(id).w
  }

  /** Mass (kg); 0 for static and kinematic bodies. */
  getMass(id: BodyId): number {
    return this.body(id).mass
  }

  /** Rotational inertia about the centre of mass (kg m^2). */
  getInertia(id: BodyId): number {
    return this.body(id).inertia
  }

  /** World position of the centre of mass (m). */
  getWorldCenter(id: BodyId, out: Vec2 = { x: 0, y: 0 }): Vec2 {
    const b = this.body(id)
    out.x = b.cx
    out.y = b.cy
    return out
  }

  /** Whether the body is awake (static bodies never are). */
  isAwake(id: BodyId): boolean {
    return this.body(id).awake
  }

  /** A world point in the body's local frame (m). */
  getLocalPoint(id: BodyId, p: Vec2): Vec2 {
    const b = this.body(id)
    const dx = p.x - b.x
    const dy = p.y - b.y
    return { x: b.c * dx + b.s * dy, y: -b.s * dx + b.c * dy }
  }

  /** A local point of the body in world space (m). */
  getWorldPoint(id: BodyId, p: Vec2): Vec2 {
    const b = this.body(id)
    return { x: b.x + b.c * p.x - b.s * p.y, y: b.y + b.s * p.x + b.c * p.y }
  }

  /** Teleports a body (origin in m, angle in rad) and wakes it. */
  setTransform(id: BodyId, position: Vec2, angle: number): void {
    const b = this.body(id)
    finiteVec('position', position)
    finite('angle', angle)
    b.x = position.x
    b.y = position.y
    b.c = cos(angle)
    b.s = sin(angle)
    b.updateCenter()
    this.moveProxy(b, false)
    this.broadPhase.touchProxy(b.proxy)
    this.islands.wake(b)
    if (b.type === STATIC) this.wakeTouching(b)
  }

  /** Sets the velocity of the centre of mass (m/s) and wakes the body. */
  setLinearVelocity(id: BodyId, v: Vec2): void {
    const b = this.body(id)
    finiteVec('linearVelocity', v)
    if (b.type === STATIC) return
    b.vx = v.x
    b.vy = v.y
    this.islands.wake(b)
  }

  /** Sets the angular velocity (rad/s) and wakes the body. */
  setAngularVelocity(id: BodyId, w: number): void {
    const b = this.body(id)
    finite('angularVelocity', w)
    if (b.type === STATIC || b.fixedRotation) return
    b.w = w
    this.islands.wake(b)
  }

  /** Wakes a body's island, or puts it to sleep. */
  setAwake(id: BodyId, awake: boolean): void {
    const b = this.body(id)
    if (awake) this.islands.wake(b)
    else this.islands.sleep(b)
  }

  /** Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it. */
  applyLinearImpulse(id: BodyId, impulse: Vec2, point: Vec2): void {
    const b = this.body(id)
    finiteVec('impulse', impulse)
    finiteVec('point', point)
    if (b.type !== DYNAMIC) return
    this.islands.wake(b)
    b.vx += b.invMass * impulse.x
    b.vy += b.invMass * impulse.y
    b.w += b.invInertia * ((point.x - b.cx) * impulse.y - (point.y - b.cy) * impulse.x)
  }

  /** Gravity (m/s^2). */
  getGravity(): Vec2 {
    return { x: this.gravityX, y: this.gravityY }
  }

  /** Sets gravity (m/s^2) and wakes every body so the change takes effect. */
  setGravity(g: Vec2): void {
    finiteVec('gravity', g)
    if (g.x === this.gravityX && g.y === this.gravityY) return
    this.gravityX = g.x
    this.gravityY = g.y
    for (const b of this.bodies) this.islands.wake(b)
  }

  /** Wakes every body touching `b` (used when a static body moves or disappears). */
  protected wakeTouching(b: Body): void {
    for (const c of b.contacts) this.islands.wake(c.bodyA === b ? c.bodyB : c.bodyA)
  }

  /** Touching contacts with the impulses of the last step, in pair order. */
  contacts(): ContactInfo[] {
    const out: ContactInfo[] = []
    for (const c of this.contactArray) {
      if (!c.touching) continue
      const points = []
      for (let j = 0; j < c.pointCount; j++) {
        points.push({
          point: { x: j === 0 ? c.px0 : c.px1, y: j === 0 ? c.py0 : c.py1 },
          separation: j === 0 ? c.separation0 : c.separation1,
          normalImpulse: j === 0 ? c.totalNormalImpulse0 : c.totalNormalImpulse1,
          tangentImpulse: j === 0 ? c.totalTangentImpulse0 : c.totalTangentImpulse1,
        })
      }
      out.push({ bodyA: c.bodyA.id, bodyB: c.bodyB.id, normal: { x: c.normalX, y: c.normalY }, points })
    }
    return out
  }

  /** Creates a joint; ids are handed out 1, 2, 3... and never reused. Wakes both bodies. */
  createJoint(def: JointDef): JointId {
    let joint: Joint
    if (def.type === 'mouse') {
      const b = this.body(def.body)
      const target = finiteVec('target', def.target)
      joint = new Joint(this.nextJointId, MOUSE, this.ground, b)
      const local = def.localAnchor
        ? finiteVec('localAnchor', def.localAnchor)
        : this.getLocalPoint(b.id, target)
      joint.localAnchorBx = local.x
      joint.localAnchorBy = local.y
      joint.targetX = target.x
      joint.targetY = target.y
      const g = Math.sqrt(this.gravityX * this.gravityX + this.gravityY * this.gravityY) || 10
      joint.maxForce = inRange('maxForce', def.maxForce ?? 1000 * b.mass * g, 0, 1e12)
      joint.hertz = inRange('hertz', def.hertz ?? 5, 0, 1000)
      joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? 0.7, 0, 1000)
    } else {
      const a = def.bodyA === null ? this.ground : this.body(def.bodyA)
      const b = this.body(def.bodyB)
      if (a === b) throw new RangeError(`a joint needs two different bodies, got ${b.id} twice`)
      const anchorA = finiteVec('anchor', def.type === 'revolute' ? def.anchor : def.anchorA)
      const anchorB = def.type === 'revolute' ? anchorA : finiteVec('anchorB', def.anchorB)
      joint = new Joint(this.nextJointId, def.type === 'revolute' ? REVOLUTE : DISTANCE, a, b)
      const la = localPoint(a, anchorA)
      const lb = localPoint(b, anchorB)
      joint.localAnchorAx = la.x
      joint.localAnchorAy = la.y
      joint.localAnchorBx = lb.x
      joint.localAnchorBy = lb.y
      if (def.type === 'revolute') this.configureRevolute(joint, def)
      else this.configureDistance(joint, def, anchorA, anchorB)
    }
    this.nextJointId++
    this.addJoint(joint)
    return joint.id
  }

  private configureRevolute(joint: Joint, def: Extract<JointDef, { type: 'revolute' }>): void {
    joint.referenceAngle = atan2(
      joint.bodyB.s * joint.bodyA.c - joint.bodyB.c * joint.bodyA.s,
      joint.bodyB.c * joint.bodyA.c + joint.bodyB.s * joint.bodyA.s,
    )
    joint.enableLimit = def.enableLimit === true
    joint.lowerAngle = inRange('lowerAngle', def.lowerAngle ?? 0, -Math.PI, Math.PI)
    joint.upperAngle = inRange('upperAngle', def.upperAngle ?? 0, joint.lowerAngle, Math.PI)
    joint.enableMotor = def.enableMotor === true
    joint.motorSpeed = finite('motorSpeed', def.motorSpeed ?? 0)
    joint.maxMotorTorque = inRange('maxMotorTorque', def.maxMotorTorque ?? 0, 0, 1e12)
  }

  private configureDistance(
    joint: Joint,
    def: Extract<JointDef, { type: 'distance' }>,
    pa: Vec2,
    pb: Vec2,
  ): void {
    const dx = pb.x - pa.x
    const dy = pb.y - pa.y
    const current = Math.sqrt(dx * dx + dy * dy)
    joint.length = inRange('length', def.length ?? current, 0.001, 1e6)
    // A def that gives only maxLength (and no spring) is a rope: it must never push.
    const ropeDefault = def.maxLength !== undefined && def.hertz === undefined ? 0 : joint.length
    joint.minLength = inRange('minLength', def.minLength ?? ropeDefault, 0, joint.length)
    joint.maxLength = inRange('maxLength', def.maxLength ?? joint.length, joint.length, 1e6)
    joint.hertz = inRange('hertz', def.hertz ?? 0, 0, 1e6)
    joint.dampingRatio = inRange('dampingRatio', def.dampingRatio ?? (joint.hertz > 0 ? 0.7 : 0), 0, 1e6)
  }

  /** Inserts a joint in id order, links it to its bodies, removes their contact, and wakes them. */
  protected addJoint(joint: Joint): void {
    this.jointList.push(joint)
    this.jointMap.set(joint.id, joint)
    joint.bodyA.joints.push(joint)
    joint.bodyB.joints.push(joint)
    this.islands.wake(joint.bodyA)
    this.islands.wake(joint.bodyB)
    const lo = Math.min(joint.bodyA.id, joint.bodyB.id)
    const hi = Math.max(joint.bodyA.id, joint.bodyB.id)
    const contact = this.contactMap.get(lo * 67108864 + hi)
    if (contact !== undefined && joint.type !== MOUSE) {
      this.unlinkContact(contact)
      this.contactArray.splice(this.contactArray.indexOf(contact), 1)
    }
  }

  /** Destroys a joint and wakes both bodies so nothing hangs in mid-air. */
  destroyJoint(id: JointId): void {
    const joint = this.joint(id)
    this.jointList.splice(this.jointList.indexOf(joint), 1)
    this.jointMap.delete(id)
    const { bodyA, bodyB } = joint
    bodyA.joints.splice(bodyA.joints.indexOf(joint), 1)
    bodyB.joints.splice(bodyB.joints.indexOf(joint), 1)
    this.islands.wake(bodyA)
    this.islands.wake(bodyB)
    // Jointed bodies had no contact; let the broadphase pair them again.
    if (bodyA.proxy >= 0) this.broadPhase.touchProxy(bodyA.proxy)
    if (bodyB.proxy >= 0) this.broadPhase.touchProxy(bodyB.proxy)
  }

  /** Whether a joint with this id exists. */
  hasJoint(id: JointId): boolean {
    return this.jointMap.has(id)
  }

  /** All joint ids, ascending. */
  jointIds(): JointId[] {
    return this.jointList.map((j) => j.id)
  }

  /** Moves a mouse joint's target (m) and wakes its body. */
  setJointTarget(id: JointId, target: Vec2): void {
    const joint = this.joint(id)
    if (joint.type !== MOUSE)
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[joint.type]} joint, not a mouse joint`)
    finiteVec('target', target)
    joint.targetX = target.x
    joint.targetY = target.y
    this.islands.wake(joint.bodyB)
  }

  /** Every joint's anchors and last reaction, for drawing, in id order. */
  joints(): JointInfo[] {
    // Joint impulses accumulate per sub-step, so force = impulse / h.
    const scale = this.settings.subSteps / STEP_SECONDS
    return this.jointList.map((j) => jointInfo(j, scale))
  }
}

function localPoint(b: Body, p: Vec2): Vec2 {
  const dx = p.x - b.x
  const dy = p.y - b.y
  return { x: b.c * dx + b.s * dy, y: -b.s * dx + b.c * dy }
}

function worldPoint(b: Body, lx: number, ly: number): Vec2 {
  return { x: b.x + b.c * lx - b.s * ly, y: b.y + b.s * lx + b.c * ly }
}

function jointInfo(j: Joint, impulseToForce: number): JointInfo {
  const type = JOINT_TYPE_NAMES[j.type]
  const anchorB = worldPoint(j.bodyB, j.localAnchorBx, j.localAnchorBy)
  const anchorA =
    j.type === MOUSE ? { x: j.targetX, y: j.targetY } : worldPoint(j.bodyA, j.localAnchorAx, j.localAnchorAy)
  let fx = j.linearImpulseX
  let fy = j.linearImpulseY
  if (j.type === DISTANCE) {
    const dx = anchorB.x - anchorA.x
    const dy = anchorB.y - anchorA.y
    const len = Math.sqrt(dx * dx + dy * dy) || 1
    const axial = j.impulse + j.lowerImpulse - j.upperImpulse
    fx = (axial * dx) / len
    fy = (axial * dy) / len
  }
  const torque = j.type === REVOLUTE ? j.motorImpulse + j.lowerImpulse - j.upperImpulse : 0
  return {
    id: j.id,
    type,
    bodyA: j.bodyA.id === 0 ? null : j.bodyA.id,
    bodyB: j.bodyB.id,
    anchorA,
    anchorB,
    force: { x: fx * impulseToForce, y: fy * impulseToForce },
    torque: torque * impulseToForce,
  }
}
