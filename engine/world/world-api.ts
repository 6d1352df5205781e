/*
 * The world's public methods: creating and destroying bodies and joints, reading and changing
 * their state, and reading contacts and joints back for drawing. Every input is validated at the
 * boundary and a bad one throws a RangeError that names the value, so a caller (the server applying
 * a player's command) can never put a NaN, an infinity or a dangling id into the simulation.
 */

import type { ChainShape, Shape } from '../collision/index.ts'
import { MAX_LINEAR_SPEED, MAX_ROTATION, STEP_SECONDS } from '../constants.ts'
import { angle as checkAngle, position as checkPosition, finite, finiteVec, inRange } from '../def-checks.ts'
import {
  Body,
  BodyShape,
  DYNAMIC,
  limitBodyVelocity,
  mixMaterials,
  STATIC,
  shouldFilterCollide,
  updateMassData,
} from '../dynamics/index.ts'
import {
  applyJointSettings,
  buildJoint,
  DISTANCE,
  JOINT_TYPE_NAMES,
  type Joint,
  jointAngle,
  jointDef,
  jointInfo,
  jointReaction,
  jointSpeed,
  jointTranslation,
  localPoint,
  MOTOR,
  MOUSE,
  PRISMATIC,
  REVOLUTE,
  WHEEL,
} from '../joints/index.ts'
import { atan2, cos, sin, type Vec2 } from '../math.ts'
import type {
  BodyDef,
  BodyId,
  BodyType,
  CompoundBodyDef,
  ContactInfo,
  ExplosionDef,
  Filter,
  JointDef,
  JointId,
  JointInfo,
  JointReaction,
  JointSettings,
  ShapeDef,
  ShapeId,
} from '../types.ts'
import { SensorState } from './sensor.ts'
import { WorldStore } from './world-store.ts'

const BODY_TYPES: readonly BodyType[] = ['static', 'kinematic', 'dynamic']

/** Numbers per body written by `writePoses`, at the offsets POSE_ID ... POSE_AWAKE. */
export const POSE_STRIDE = 6
/** Offset of the body id in a `writePoses` record. */
export const POSE_ID = 0
/** Offset of the body type: POSE_STATIC, 1 kinematic, 2 dynamic. */
export const POSE_TYPE = 1
/** Offsets of the body origin's x and y (m). */
export const POSE_X = 2
export const POSE_Y = 3
/** Offset of the angle (rad, as getAngle). */
export const POSE_ANGLE = 4
/** Offset of the awake flag (1 or 0). */
export const POSE_AWAKE = 5
/** The POSE_TYPE value of a static body. */
export const POSE_STATIC = 0

const SHAPE_TYPES: readonly string[] = ['circle', 'polygon', 'capsule', 'segment', 'chainSegment']

function checkShape(shape: Shape): Shape {
  if (shape === null || typeof shape !== 'object' || !SHAPE_TYPES.includes(shape?.type)) {
    throw new RangeError(
      'body shape must be made by circle(), box(), polygon(), capsule(), segment() or chain()',
    )
  }
  return shape
}

/** Whether any of the shapes is a chain segment (they are for static bodies only). */
function hasChain(shapes: readonly BodyShape[]): boolean {
  return shapes.some((s) => s.shape.type === 'chainSegment')
}

/** The RangeError for a chain on a body that is not static. */
function chainNotStatic(what: string, type: string): RangeError {
  return new RangeError(`chain shapes are for static bodies only: ${what} is ${type}`)
}

/**
 * A shape definition as the shape definitions it makes: a chain() gives one per segment (the same
 * material, filter and flags), any other shape itself.
 */
function expandChain(sd: ShapeDef): ShapeDef[] {
  if (sd === null || typeof sd !== 'object')
    throw new RangeError(`shape definition must be an object, got ${sd}`)
  const shape = sd.shape as Shape | ChainShape
  if (shape === null || typeof shape !== 'object' || shape.type !== 'chain') return [sd]
  if (!Array.isArray(shape.segments) || shape.segments.length === 0)
    throw new RangeError('a chain shape must be made by chain()')
  if (sd.sensor === true)
    throw new RangeError('a chain cannot be a sensor (its segments are one-sided lines)')
  return shape.segments.map((segment) => ({ ...sd, shape: segment }))
}

/** Public methods of a world. */
export class WorldApi extends WorldStore {
  /** Steps taken since creation. */
  get tick(): number {
    return this.tickCount
  }

  /** The fastest a body may spin (rad/s): MAX_ROTATION per sub-step, 188.5 rad/s at 4 sub-steps. */
  get maxAngularSpeed(): number {
    return MAX_ROTATION * this.stepContext.invH
  }

  /** Number of bodies. */
  get bodyCount(): number {
    return this.bodies.length
  }

  /**
   * Creates a body with its shapes (`shape`, or `shapes` in order); body ids are handed out 1, 2,
   * 3... and shape ids likewise, never reused. Throws on an invalid definition.
   */
  createBody(def: BodyDef | CompoundBodyDef): BodyId {
    this.revision++
    const shapeDefs = bodyShapeDefs(def)
    const typeIndex = BODY_TYPES.indexOf(def.type ?? 'dynamic')
    if (typeIndex < 0) throw new RangeError(`body type must be static, kinematic or dynamic, got ${def.type}`)
    const body = new Body(this.nextBodyId, typeIndex)
    const shapes = shapeDefs.map((sd, i) => buildShape(sd, this.nextShapeId + i, body, def))
    if (typeIndex !== STATIC && hasChain(shapes)) throw chainNotStatic('the body', BODY_TYPES[typeIndex])
    if (typeIndex === DYNAMIC && !shapes.some((s) => s.shape.type !== 'segment')) {
      throw new RangeError(
        'a dynamic body needs a shape with mass: a segment has none (use it on static or kinematic bodies, or add a shape with area)',
      )
    }
    const position = checkPosition('position', def.position ?? { x: 0, y: 0 })
    const angle = checkAngle('angle', def.angle ?? 0)
    body.linearDamping = inRange('linearDamping', def.linearDamping ?? 0, 0, 1e6)
    body.angularDamping = inRange('angularDamping', def.angularDamping ?? 0, 0, 1e6)
    body.gravityScale = inRange('gravityScale', def.gravityScale ?? 1, -1e3, 1e3)
    body.bullet = def.bullet === true
    body.enableSleep = def.enableSleep !== false
    body.fixedRotation = def.fixedRotation === true
    this.nextBodyId++
    this.nextShapeId += shapes.length
    for (const s of shapes) body.shapes.push(s)
    updateMassData(body)
    body.x = position.x
    body.y = position.y
    const rotation = def.rotation === undefined ? null : checkRotation(def.rotation)
    body.c = rotation ? rotation.c : cos(angle)
    body.s = rotation ? rotation.s : sin(angle)
    body.updateCenter()
    if (typeIndex !== STATIC) {
      const v = finiteVec('linearVelocity', def.linearVelocity ?? { x: 0, y: 0 })
      body.vx = v.x
      body.vy = v.y
      body.w = body.fixedRotation ? 0 : finite('angularVelocity', def.angularVelocity ?? 0)
      // As setLinearVelocity does: a definition's speeds are clamped to the limits too.
      limitBodyVelocity(body, this.maxAngularSpeed)
    }
    body.awake = typeIndex !== STATIC && def.awake !== false
    this.bodies.push(body)
    this.bodyMap.set(body.id, body)
    for (const s of shapes) this.addShape(s)
    body.syncShapes()
    return body.id
  }

  /**
   * Attaches a shape to a body and returns its id (handed out after every id so far, never
   * reused). The body's mass, centre of mass and inertia are recomputed (its origin stays put, and
   * its centre's velocity follows the body's rotation); the body wakes. A chain() (static bodies
   * only) attaches one shape per segment, with consecutive ids; the first one's is returned.
   */
  createShape(bodyId: BodyId, def: ShapeDef): ShapeId {
    const body = this.body(bodyId)
    const defs = expandChain(def)
    const shapes = defs.map((sd, i) => buildShape(sd, this.nextShapeId + i, body, {}))
    if (body.type !== STATIC && hasChain(shapes))
      throw chainNotStatic(`body ${bodyId}`, BODY_TYPES[body.type])
    this.revision++
    this.nextShapeId += shapes.length
    for (const s of shapes) body.shapes.push(s)
    this.remass(body)
    for (const s of shapes) this.addShape(s)
    body.syncShapes()
    this.islands.wake(body)
    if (body.type === STATIC) this.wakeTouching(body)
    return shapes[0].id
  }

  /**
   * Detaches a shape from its body and destroys its contacts; the body is re-massed and wakes with
   * everything the shape touched. A dynamic body must keep a shape with mass (a RangeError otherwise).
   */
  destroyShape(id: ShapeId): void {
    this.revision++
    const s = this.bodyShape(id)
    const body = s.body
    if (body.type === DYNAMIC && !body.shapes.some((o) => o !== s && o.shape.type !== 'segment')) {
      throw new RangeError(
        `shape ${id} is the last shape with mass of dynamic body ${body.id}; destroy the body instead`,
      )
    }
    this.destroyShapeContacts(s)
    this.removeShape(s)
    body.shapes.splice(body.shapes.indexOf(s), 1)
    body.syncShapes()
    this.remass(body)
    this.islands.wake(body)
  }

  /** The ids of a body's shapes, in creation order. */
  bodyShapes(bodyId: BodyId): ShapeId[] {
    return this.body(bodyId).shapes.map((s) => s.id)
  }

  /** Whether a shape with this id exists. */
  hasShape(id: ShapeId): boolean {
    return this.shapeMap.has(id)
  }

  /** The body a shape is attached to. */
  getShapeBody(id: ShapeId): BodyId {
    return this.bodyShape(id).body.id
  }

  /** A shape's geometry (shared, immutable), in its body's frame. */
  getShapeGeometry(id: ShapeId): Shape {
    return this.bodyShape(id).shape
  }

  /**
   * A shape's definition as it stands: geometry, material, filter and flags (every field given),
   * so createShape or createBody with it makes the same shape.
   */
  getShapeDef(id: ShapeId): Required<ShapeDef> {
    const s = this.bodyShape(id)
    return {
      shape: s.shape,
      density: s.density,
      friction: s.friction,
      restitution: s.restitution,
      rollingResistance: s.rollingResistance,
      tangentSpeed: s.tangentSpeed,
      filter: { categoryBits: s.categoryBits, maskBits: s.maskBits, groupIndex: s.groupIndex },
      sensor: s.sensor,
      enableSensorEvents: s.enableSensorEvents,
      enableContactEvents: s.enableContactEvents,
      enableHitEvents: s.enableHitEvents,
    }
  }

  /**
   * A body's definition as it stands: type, pose (the exact `rotation` besides `angle`),
   * velocities, settings and its shapes' definitions in creation order. createBody of it, in a
   * world with the same gravity, makes a body in the same state (sleep timer and contacts aside).
   */
  getBodyDef(id: BodyId): CompoundBodyDef {
    const b = this.body(id)
    return {
      type: BODY_TYPES[b.type],
      position: { x: b.x, y: b.y },
      angle: atan2(b.s, b.c),
      rotation: { c: b.c, s: b.s },
      linearVelocity: { x: b.vx, y: b.vy },
      angularVelocity: b.w,
      linearDamping: b.linearDamping,
      angularDamping: b.angularDamping,
      gravityScale: b.gravityScale,
      bullet: b.bullet,
      awake: b.awake,
      enableSleep: b.enableSleep,
      fixedRotation: b.fixedRotation,
      shapes: b.shapes.map((s) => this.getShapeDef(s.id)),
    }
  }

  /** A shape's collision filter (a copy). */
  getFilter(id: ShapeId): Filter {
    const s = this.bodyShape(id)
    return { categoryBits: s.categoryBits, maskBits: s.maskBits, groupIndex: s.groupIndex }
  }

  /**
   * Sets a shape's collision filter. Contacts the new filter forbids end, and pairs it allows begin,
   * at the next step (their events come from that step); the body wakes.
   */
  setFilter(id: ShapeId, filter: Filter): void {
    this.revision++
    const s = this.bodyShape(id)
    setShapeFilter(s, filter)
    this.destroyShapeContacts(s, true)
    if (s.proxy >= 0) this.broadPhase.touchProxy(s.proxy)
    this.islands.wake(s.body)
  }

  /** Registers a new shape: the id map, its proxy, the sensor list, the hit-event count. */
  private addShape(s: BodyShape): void {
    this.shapeMap.set(s.id, s)
    this.createProxy(s)
    if (s.enableHitEvents) this.hitEventShapes++
    if (s.sensor) {
      // Sensors are kept in id order; a new shape has the largest id so far.
      this.sensors.push(new SensorState(s))
    }
  }

  /** Unregisters a shape (its contacts are already gone). */
  private removeShape(s: BodyShape): void {
    this.broadPhase.destroyProxy(s.proxy)
    s.proxy = -1
    this.shapeMap.delete(s.id)
    if (s.enableHitEvents) this.hitEventShapes--
    if (s.sensor) {
      const k = this.sensors.findIndex((t) => t.shape === s)
      if (k >= 0) this.sensors.splice(k, 1)
    }
  }

  /**
   * Destroys the contacts of one shape (with `onlyFiltered`, only those its filter now forbids)
   * and wakes the bodies it touched; touching ones report their end at the next step.
   */
  protected destroyShapeContacts(s: BodyShape, onlyFiltered = false): void {
    const body = s.body
    for (const c of body.contacts.slice()) {
      if (c.shapeA !== s && c.shapeB !== s) continue
      if (onlyFiltered && shouldFilterCollide(c.shapeA, c.shapeB)) continue
      const other = c.bodyA === body ? c.bodyB : c.bodyA
      this.endContactLater(c)
      this.unlinkContact(c)
      this.contactPool.push(c)
      this.islands.wake(other)
      this.contactArray.splice(this.contactArray.indexOf(c), 1)
    }
  }

  /**
   * Recomputes a body's mass properties after its shapes changed, keeping the origin in place; the
   * centre of mass moves, and its velocity becomes that of the body's point now at the centre
   * (v + w x (new centre - old centre), as Box2D's b2UpdateBodyMassData).
   */
  protected remass(body: Body): void {
    const oldCx = body.cx
    const oldCy = body.cy
    updateMassData(body)
    body.updateCenter()
    if (body.type !== STATIC) {
      body.vx -= body.w * (body.cy - oldCy)
      body.vy += body.w * (body.cx - oldCx)
      limitBodyVelocity(body, this.maxAngularSpeed)
    }
    body.c0x = body.cx
    body.c0y = body.cy
  }

  /** Destroys a body, its contacts and its joints, and wakes everything it touched. */
  destroyBody(id: BodyId): void {
    this.revision++
    const body = this.body(id)
    for (const j of body.joints.slice()) this.destroyJoint(j.id)
    for (const c of body.contacts.slice()) {
      const other = c.bodyA === body ? c.bodyB : c.bodyA
      this.endContactLater(c)
      this.unlinkContact(c)
      this.contactPool.push(c)
      this.islands.wake(other)
      this.touchProxies(other)
    }
    const contacts = this.contactArray
    let kept = 0
    for (let i = 0; i < contacts.length; i++) {
      if (contacts[i].bodyA !== body && contacts[i].bodyB !== body) contacts[kept++] = contacts[i]
    }
    contacts.length = kept
    for (const s of body.shapes) this.removeShape(s)
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

  /**
   * Every body's pose, in ascending id order, as POSE_STRIDE numbers each into `out` (which must
   * hold bodyCount * POSE_STRIDE); returns the body count. Allocates nothing, unlike reading
   * bodyIds() and getAngle() body by body (an array per call and a boxed number per angle), so a
   * server can build a snapshot frame of every body twenty times a second without garbage.
   */
  writePoses(out: Float64Array): number {
    const bodies = this.bodies
    const n = bodies.length
    if (out.length < n * POSE_STRIDE) {
      throw new RangeError(`writePoses needs room for ${n * POSE_STRIDE} numbers, got ${out.length}`)
    }
    for (let i = 0, o = 0; i < n; i++, o += POSE_STRIDE) {
      const b = bodies[i]
      out[o + POSE_ID] = b.id
      out[o + POSE_TYPE] = b.type
      out[o + POSE_X] = b.x
      out[o + POSE_Y] = b.y
      out[o + POSE_ANGLE] = atan2(b.s, b.c)
      out[o + POSE_AWAKE] = b.awake ? 1 : 0
    }
    return n
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

  /** The body's first shape (shared, immutable); bodyShapes() lists them all. */
  getShape(id: BodyId): Shape {
    const shapes = this.body(id).shapes
    if (shapes.length === 0) throw new RangeError(`body ${id} has no shapes`)
    return shapes[0].shape
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
    return localPoint(this.body(id), p)
  }

  /** A local point of the body in world space (m). */
  getWorldPoint(id: BodyId, p: Vec2): Vec2 {
    const b = this.body(id)
    return { x: b.x + b.c * p.x - b.s * p.y, y: b.y + b.s * p.x + b.c * p.y }
  }

  /** Teleports a body (origin in m, angle in rad) and wakes it. */
  setTransform(id: BodyId, position: Vec2, angle: number): void {
    this.revision++
    const b = this.body(id)
    checkPosition('position', position)
    checkAngle('angle', angle)
    b.x = position.x
    b.y = position.y
    b.c = cos(angle)
    b.s = sin(angle)
    b.updateCenter()
    this.moveProxy(b, false)
    this.touchProxies(b)
    this.islands.wake(b)
    if (b.type === STATIC) this.wakeTouching(b)
  }

  /** Sets the velocity of the centre of mass (m/s) and wakes the body. */
  setLinearVelocity(id: BodyId, v: Vec2): void {
    this.revision++
    const b = this.body(id)
    finiteVec('linearVelocity', v)
    if (b.type === STATIC) return
    b.vx = v.x
    b.vy = v.y
    limitBodyVelocity(b, this.maxAngularSpeed)
    this.islands.wake(b)
  }

  /** Sets the angular velocity (rad/s) and wakes the body. */
  setAngularVelocity(id: BodyId, w: number): void {
    this.revision++
    const b = this.body(id)
    finite('angularVelocity', w)
    if (b.type === STATIC || b.fixedRotation) return
    b.w = w
    limitBodyVelocity(b, this.maxAngularSpeed)
    this.islands.wake(b)
  }

  /** Wakes a body's island, or puts it to sleep. */
  setAwake(id: BodyId, awake: boolean): void {
    this.revision++
    const b = this.body(id)
    if (awake) this.islands.wake(b)
    else this.islands.sleep(b)
  }

  /**
   * Applies an impulse (N s) at a world point (m) to a dynamic body and wakes it. The resulting
   * velocity is clamped to the speed limits (MAX_LINEAR_SPEED, maxAngularSpeed), whatever the impulse.
   */
  applyLinearImpulse(id: BodyId, impulse: Vec2, point: Vec2): void {
    this.revision++
    const b = this.body(id)
    finiteVec('impulse', impulse)
    finiteVec('point', point)
    if (b.type !== DYNAMIC) return
    this.islands.wake(b)
    b.vx += b.invMass * impulse.x
    b.vy += b.invMass * impulse.y
    b.w += b.invInertia * ((point.x - b.cx) * impulse.y - (point.y - b.cy) * impulse.x)
    limitBodyVelocity(b, this.maxAngularSpeed)
  }

  /**
   * Adds a force (N) at a world point (m) to a dynamic body and wakes it; it acts over the next step
   * (as the impulse force x 1/60 s at its start) and is then cleared, like Box2D's forces. Forces
   * given several times before a step add up.
   */
  applyForce(id: BodyId, force: Vec2, point: Vec2): void {
    this.revision++
    const b = this.body(id)
    finiteVec('force', force)
    finiteVec('point', point)
    if (b.type !== DYNAMIC) return
    this.addForce(b, force.x, force.y, (point.x - b.cx) * force.y - (point.y - b.cy) * force.x)
  }

  /** Adds a torque (N m) to a dynamic body for the next step (see applyForce) and wakes it. */
  applyTorque(id: BodyId, torque: number): void {
    this.revision++
    const b = this.body(id)
    finite('torque', torque)
    if (b.type !== DYNAMIC) return
    this.addForce(b, 0, 0, torque)
  }

  /** Applies an angular impulse (N m s) to a dynamic body now and wakes it; the spin is clamped to the limit. */
  applyAngularImpulse(id: BodyId, impulse: number): void {
    this.revision++
    const b = this.body(id)
    finite('impulse', impulse)
    if (b.type !== DYNAMIC) return
    this.islands.wake(b)
    b.w += b.invInertia * impulse
    limitBodyVelocity(b, this.maxAngularSpeed)
  }

  private addForce(b: Body, fx: number, fy: number, torque: number): void {
    const pending = b.fx !== 0 || b.fy !== 0 || b.torque !== 0
    // Sums stay finite: each part is clamped to what could change the velocity by twice the limit.
    const cap = (2 * MAX_LINEAR_SPEED * b.mass) / STEP_SECONDS
    const torqueCap =
      (2 * this.maxAngularSpeed * Math.max(b.inertia, 1e-300)) / STEP_SECONDS + cap * b.maxExtent
    b.fx = Math.max(-cap, Math.min(cap, b.fx + fx))
    b.fy = Math.max(-cap, Math.min(cap, b.fy + fy))
    b.torque = Math.max(-torqueCap, Math.min(torqueCap, b.torque + torque))
    if (!pending && (b.fx !== 0 || b.fy !== 0 || b.torque !== 0)) this.forced.push(b)
    this.islands.wake(b)
  }

  /** Sets a shape's friction (0..100); its contacts take the new mix at once; the body and what it touches wake. */
  setFriction(id: ShapeId, friction: number): void {
    this.revision++
    const s = this.bodyShape(id)
    s.friction = inRange('friction', friction, 0, 100)
    this.remixContacts(s)
  }

  /** Sets a shape's restitution (0..1); its contacts take the new mix at once; the body and what it touches wake. */
  setRestitution(id: ShapeId, restitution: number): void {
    this.revision++
    const s = this.bodyShape(id)
    s.restitution = inRange('restitution', restitution, 0, 1)
    this.remixContacts(s)
  }

  /** Sets a shape's density (kg/m^2, 1e-6..1e6) and re-masses its body (origin kept); wakes it. */
  setDensity(id: ShapeId, density: number): void {
    this.revision++
    const s = this.bodyShape(id)
    s.density = inRange('density', density, 1e-6, 1e6)
    this.remass(s.body)
    this.islands.wake(s.body)
  }

  /** Re-mixes the friction and restitution of a shape's contacts and wakes what it touches. */
  private remixContacts(s: BodyShape): void {
    this.islands.wake(s.body)
    for (const c of s.body.contacts) {
      if (c.shapeA !== s && c.shapeB !== s) continue
      mixMaterials(c)
      this.islands.wake(c.bodyA === s.body ? c.bodyB : c.bodyA)
    }
  }

  /**
   * Changes a body's type. Its contacts end (reported by the next step) and its proxies are made
   * again, so the broadphase pairs it afresh at the next step; a body made static stops; a body made
   * dynamic needs a shape with mass (a RangeError otherwise) and is re-massed. The body and what it
   * touched wake.
   */
  setBodyType(id: BodyId, type: BodyType): void {
    this.revision++
    const b = this.body(id)
    const typeIndex = BODY_TYPES.indexOf(type)
    if (typeIndex < 0) throw new RangeError(`body type must be static, kinematic or dynamic, got ${type}`)
    if (typeIndex === b.type) return
    if (typeIndex !== STATIC && hasChain(b.shapes))
      throw chainNotStatic(`body ${id}, which has a chain,`, type)
    if (typeIndex === DYNAMIC && !b.shapes.some((s) => s.shape.type !== 'segment')) {
      throw new RangeError(`body ${id} has no shape with mass and cannot be dynamic`)
    }
    for (const c of b.contacts.slice()) {
      const other = c.bodyA === b ? c.bodyB : c.bodyA
      this.endContactLater(c)
      this.unlinkContact(c)
      this.contactPool.push(c)
      this.contactArray.splice(this.contactArray.indexOf(c), 1)
      this.islands.wake(other)
    }
    this.islands.wake(b)
    b.type = typeIndex
    for (const s of b.shapes) {
      this.broadPhase.destroyProxy(s.proxy)
      this.createProxy(s)
    }
    b.syncShapes()
    if (typeIndex === STATIC) {
      b.vx = 0
      b.vy = 0
      b.w = 0
      b.awake = false
      b.sleepTime = 0
    } else b.awake = true
    b.fx = 0
    b.fy = 0
    b.torque = 0
    updateMassData(b)
    b.updateCenter()
    b.c0x = b.cx
    b.c0y = b.cy
    b.q0c = b.c
    b.q0s = b.s
    // Joints to it may now join or leave a tree of pins: they wake with it.
    for (const j of b.joints) {
      this.islands.wake(j.bodyA)
      this.islands.wake(j.bodyB)
    }
  }

  /**
   * An explosion (Box2D v3.1's b2World_Explode): every shape of a dynamic body within radius +
   * falloff of `position` (m) whose category is in `maskBits` gets an impulse away from the
   * position at its nearest point, of impulsePerLength (N s/m) times the shape's width across that
   * direction, full within `radius` and falling linearly to 0 over `falloff` (m) beyond it.
   * Bodies are visited in id order and shapes in creation order.
   */
  explode(def: ExplosionDef): void {
    this.revision++
    const p = finiteVec('position', def.position)
    const radius = inRange('radius', def.radius, 0, 1e6)
    const falloff = inRange('falloff', def.falloff ?? 0, 0, 1e6)
    const perLength = finite('impulsePerLength', def.impulsePerLength)
    const mask = def.maskBits ?? 0xffffffff
    if (!Number.isInteger(mask) || mask < 0 || mask > 0xffffffff)
      throw new RangeError(`maskBits must be an integer in [0, 2^32), got ${mask}`)
    const reach = radius + falloff
    const near = { x: 0, y: 0, distance: 0 }
    for (const b of this.bodies.slice()) {
      if (b.type !== DYNAMIC) continue
      for (const s of b.shapes) {
        if ((s.categoryBits & mask) === 0) continue
        nearestPoint(s, p, near)
        if (near.distance > reach) continue
        let dx = near.x - p.x
        let dy = near.y - p.y
        let len = Math.sqrt(dx * dx + dy * dy)
        if (len === 0) {
          // The position is inside the shape: push from it toward the body's centre of mass.
          dx = b.cx - p.x
          dy = b.cy - p.y
          len = Math.sqrt(dx * dx + dy * dy)
          if (len === 0) continue
        }
        dx /= len
        dy /= len
        const scale =
          near.distance <= radius || falloff === 0 ? 1 : Math.max(0, (reach - near.distance) / falloff)
        const magnitude = perLength * projectedWidth(s, -dy, dx) * scale
        this.applyLinearImpulse(b.id, { x: magnitude * dx, y: magnitude * dy }, { x: near.x, y: near.y })
      }
    }
  }

  /** Gravity (m/s^2). */
  getGravity(): Vec2 {
    return { x: this.gravityX, y: this.gravityY }
  }

  /** Sets gravity (m/s^2) and wakes every body so the change takes effect. */
  setGravity(g: Vec2): void {
    this.revision++
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
      out.push({
        bodyA: c.bodyA.id,
        bodyB: c.bodyB.id,
        shapeA: c.shapeA.id,
        shapeB: c.shapeB.id,
        normal: { x: c.normalX, y: c.normalY },
        points,
      })
    }
    return out
  }

  /** Creates a joint; ids are handed out 1, 2, 3... and never reused. Wakes both bodies. */
  createJoint(def: JointDef): JointId {
    this.revision++
    const g = Math.sqrt(this.gravityX * this.gravityX + this.gravityY * this.gravityY) || 10
    const joint = buildJoint(def, this.nextJointId, (id) => this.body(id), this.ground, g)
    this.nextJointId++
    this.addJoint(joint)
    return joint.id
  }

  /** Inserts a joint in id order, links it to its bodies, removes their contact unless they may collide, and wakes them. */
  protected addJoint(joint: Joint): void {
    this.revision++
    this.jointList.push(joint)
    this.jointMap.set(joint.id, joint)
    joint.bodyA.joints.push(joint)
    joint.bodyB.joints.push(joint)
    this.islands.wake(joint.bodyA)
    this.islands.wake(joint.bodyB)
    if (joint.collideConnected) return
    for (const contact of joint.bodyA.contacts.slice()) {
      if (contact.bodyA !== joint.bodyB && contact.bodyB !== joint.bodyB) continue
      this.endContactLater(contact)
      this.unlinkContact(contact)
      this.contactArray.splice(this.contactArray.indexOf(contact), 1)
      this.contactPool.push(contact)
    }
  }

  /** Destroys a joint and wakes both bodies so nothing hangs in mid-air. */
  destroyJoint(id: JointId): void {
    this.revision++
    const joint = this.joint(id)
    this.jointList.splice(this.jointList.indexOf(joint), 1)
    this.jointMap.delete(id)
    const { bodyA, bodyB } = joint
    bodyA.joints.splice(bodyA.joints.indexOf(joint), 1)
    bodyB.joints.splice(bodyB.joints.indexOf(joint), 1)
    this.islands.wake(bodyA)
    this.islands.wake(bodyB)
    // Bodies that may now collide get a contact from the broadphase again.
    this.touchProxies(bodyA)
    this.touchProxies(bodyB)
  }

  /** Whether a joint with this id exists. */
  hasJoint(id: JointId): boolean {
    return this.jointMap.has(id)
  }

  /** All joint ids, ascending. */
  jointIds(): JointId[] {
    return this.jointList.map((j) => j.id)
  }

  /**
   * Moves what a joint pulls toward, and wakes its bodies: a mouse joint's target (a world point,
   * m); a motor joint's linear offset (a point in A's frame, m) and optionally its angular offset
   * (rad); a prismatic joint's spring target translation (m); a revolute joint's spring target
   * angle (rad, within [-pi, pi]).
   */
  setJointTarget(id: JointId, target: Vec2 | number, angularOffset?: number): void {
    this.revision++
    const joint = this.joint(id)
    const type = joint.type
    if (type === MOUSE || type === MOTOR) {
      if (typeof target !== 'object' || target === null)
        throw new RangeError(
          `a ${JOINT_TYPE_NAMES[type]} joint's target must be a point {x, y}, got ${String(target)}`,
        )
      finiteVec('target', target)
      if (type === MOUSE) {
        joint.targetX = target.x
        joint.targetY = target.y
        this.islands.wake(joint.bodyB)
        return
      }
      if (Math.abs(target.x) > 1e6 || Math.abs(target.y) > 1e6)
        throw new RangeError(`target must lie within 1000000 m of body A, got (${target.x}, ${target.y})`)
      joint.linearOffsetX = target.x
      joint.linearOffsetY = target.y
      joint.localAnchorAx = target.x
      joint.localAnchorAy = target.y
      if (angularOffset !== undefined) joint.angularOffset = checkAngle('angularOffset', angularOffset)
    } else if (type === PRISMATIC) {
      joint.springTarget = inRange('targetTranslation', target as number, -1e6, 1e6)
    } else if (type === REVOLUTE) {
      joint.springTarget = inRange('targetAngle', target as number, -Math.PI, Math.PI)
    } else {
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[type]} joint, which has no target`)
    }
    this.islands.wake(joint.bodyA)
    this.islands.wake(joint.bodyB)
  }

  /** Sets the motor speed of a revolute or wheel (rad/s), prismatic or distance (m/s) joint, and wakes its bodies. */
  setJointMotorSpeed(id: JointId, speed: number): void {
    this.revision++
    const joint = this.joint(id)
    const type = joint.type
    if (type !== REVOLUTE && type !== WHEEL && type !== PRISMATIC && type !== DISTANCE)
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[type]} joint, which has no motor`)
    joint.motorSpeed = finite('motorSpeed', speed)
    this.islands.wake(joint.bodyA)
    this.islands.wake(joint.bodyB)
  }

  /**
   * Changes any of a joint's settings (JointSettings: the names its definition uses, checked as
   * createJoint checks them; a setting its kind lacks is a RangeError naming it, and a refused call
   * changes nothing), and wakes its bodies. Accumulated impulses are kept as Box2D v3.1's setters
   * keep them (joints/joint-settings.ts). Allocates nothing.
   */
  setJointSettings(id: JointId, settings: JointSettings): void {
    const joint = this.joint(id)
    applyJointSettings(joint, id, settings)
    this.revision++
    this.islands.wake(joint.bodyA)
    this.islands.wake(joint.bodyB)
  }

  /** Prismatic, wheel: translation along the axis (m, 0 at creation); distance: the length (m). */
  getJointTranslation(id: JointId): number {
    const joint = this.joint(id)
    const type = joint.type
    if (type !== PRISMATIC && type !== WHEEL && type !== DISTANCE)
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[type]} joint, which has no translation`)
    return jointTranslation(joint)
  }

  /** Revolute, wheel: wB - wA (rad/s); prismatic, distance: rate of the translation or length (m/s). */
  getJointSpeed(id: JointId): number {
    const joint = this.joint(id)
    const type = joint.type
    if (type !== REVOLUTE && type !== WHEEL && type !== PRISMATIC && type !== DISTANCE)
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[type]} joint, which has no speed`)
    return jointSpeed(joint)
  }

  /** angleB - angleA relative to creation (rad, [-pi, pi]); a motor joint's is absolute. Not distance or mouse. */
  getJointAngle(id: JointId): number {
    const joint = this.joint(id)
    if (joint.type === DISTANCE || joint.type === MOUSE)
      throw new RangeError(`joint ${id} is a ${JOINT_TYPE_NAMES[joint.type]} joint, which has no angle`)
    return jointAngle(joint)
  }

  /** Every joint's anchors and last reaction, for drawing, in id order. */
  joints(): JointInfo[] {
    const scale = this.settings.subSteps / STEP_SECONDS
    return this.jointList.map((j) => jointInfo(j, scale))
  }

  /**
   * A joint's definition as it stands (settings changed since creation included), with its exact
   * frames (JointFrames): createJoint of it, with the bodies posed as now, makes the same joint.
   */
  getJointDef(id: JointId): JointDef {
    return jointDef(this.joint(id))
  }

  /** The force (N) and torque (N m) a joint applied to body B over the last step; A gets the opposite. */
  getJointReaction(id: JointId): JointReaction {
    // Joint impulses accumulate per sub-step, so force = impulse / h.
    return jointReaction(this.joint(id), this.settings.subSteps / STEP_SECONDS)
  }
}

/** The shape definitions of a body definition: `shapes`, or `shape` as a one-shape list. */
function bodyShapeDefs(def: BodyDef | CompoundBodyDef): ShapeDef[] {
  if (def === null || typeof def !== 'object') throw new RangeError('body definition must be an object')
  if ('shapes' in def && def.shapes !== undefined) {
    if (def.shape !== undefined) throw new RangeError('body definition gives both shape and shapes; give one')
    if (!Array.isArray(def.shapes) || def.shapes.length === 0 || def.shapes.length > MAX_BODY_SHAPES) {
      throw new RangeError(`body shapes must be an array of 1 to ${MAX_BODY_SHAPES} shape definitions`)
    }
    const defs = def.shapes.flatMap(expandChain)
    if (defs.length > MAX_BODY_SEGMENTS)
      throw new RangeError(`a body definition makes at most ${MAX_BODY_SEGMENTS} shapes, got ${defs.length}`)
    return defs
  }
  return expandChain({ shape: (def as BodyDef).shape })
}

/** Most shapes one body definition may make, chain segments included: 16,384. */
const MAX_BODY_SEGMENTS = 16384

/** A body definition's exact rotation: finite, unit length within 1e-6. */
function checkRotation(r: { c: number; s: number }): { c: number; s: number } {
  if (r === null || typeof r !== 'object') throw new RangeError(`rotation must be a {c, s} pair, got ${r}`)
  finite('rotation.c', r.c)
  finite('rotation.s', r.s)
  if (!(Math.abs(r.c * r.c + r.s * r.s - 1) <= 1e-6))
    throw new RangeError(`rotation must have length 1 (c^2 + s^2 = 1 within 1e-6), got (${r.c}, ${r.s})`)
  return r
}

/** Most shapes one body definition may give at once (m): 1,024. */
const MAX_BODY_SHAPES = 1024

/** Builds a validated BodyShape; material the shape definition omits comes from the body's definition. */
function buildShape(
  sd: ShapeDef,
  id: number,
  body: Body,
  bodyDef: { density?: number; friction?: number; restitution?: number },
): BodyShape {
  if (sd === null || typeof sd !== 'object')
    throw new RangeError(`shape definition must be an object, got ${sd}`)
  const s = new BodyShape(id, body, checkShape(sd.shape as Shape))
  if (sd.sensor === true && s.shape.type === 'chainSegment')
    throw new RangeError('a chain cannot be a sensor (its segments are one-sided lines)')
  s.density = inRange('density', sd.density ?? bodyDef.density ?? 1, 1e-6, 1e6)
  s.friction = inRange('friction', sd.friction ?? bodyDef.friction ?? 0.6, 0, 100)
  s.restitution = inRange('restitution', sd.restitution ?? bodyDef.restitution ?? 0, 0, 1)
  s.rollingResistance = inRange('rollingResistance', sd.rollingResistance ?? 0, 0, 100)
  s.tangentSpeed = inRange('tangentSpeed', sd.tangentSpeed ?? 0, -1e3, 1e3)
  if (sd.filter !== undefined) setShapeFilter(s, sd.filter)
  s.sensor = sd.sensor === true
  s.enableSensorEvents = sd.enableSensorEvents !== false
  s.enableContactEvents = sd.enableContactEvents !== false
  s.enableHitEvents = sd.enableHitEvents === true
  return s
}

/** Validates a filter and writes it into a shape (masks as unsigned 32-bit numbers). */
export function setShapeFilter(s: BodyShape, f: Filter): void {
  if (f === null || typeof f !== 'object') throw new RangeError(`filter must be an object, got ${f}`)
  const category = f.categoryBits ?? 1
  const mask = f.maskBits ?? 0xffffffff
  const group = f.groupIndex ?? 0
  if (!Number.isInteger(category) || category < 0 || category > 0xffffffff)
    throw new RangeError(`filter categoryBits must be an integer in [0, 2^32), got ${category}`)
  if (!Number.isInteger(mask) || mask < 0 || mask > 0xffffffff)
    throw new RangeError(`filter maskBits must be an integer in [0, 2^32), got ${mask}`)
  if (!Number.isInteger(group) || group < -2147483648 || group > 2147483647)
    throw new RangeError(`filter groupIndex must be an integer in [-2^31, 2^31), got ${group}`)
  s.categoryBits = category
  s.maskBits = mask
  s.groupIndex = group
}

/** The nearest point of a shape's surface (world) to p, and its distance (0 when p is inside). */
function nearestPoint(s: BodyShape, p: Vec2, out: { x: number; y: number; distance: number }): void {
  const b = s.body
  const shape = s.shape
  // p in the body frame.
  const dx = p.x - b.x
  const dy = p.y - b.y
  const lx = b.c * dx + b.s * dy
  const ly = -b.s * dx + b.c * dy
  let qx = shape.centroid.x
  let qy = shape.centroid.y
  let inside = false
  if (shape.type !== 'circle') {
    // Nearest point of the core (polygon or segment) to p.
    const vs = shape.vertices
    const n = shape.count
    let best = Number.POSITIVE_INFINITY
    for (let i = 0; i < (n === 2 ? 1 : n); i++) {
      const a = vs[i]
      const e = vs[i + 1 < n ? i + 1 : 0]
      const ex = e.x - a.x
      const ey = e.y - a.y
      const t = Math.max(0, Math.min(1, ((lx - a.x) * ex + (ly - a.y) * ey) / (ex * ex + ey * ey)))
      const cx = a.x + t * ex
      const cy = a.y + t * ey
      const d = (lx - cx) * (lx - cx) + (ly - cy) * (ly - cy)
      if (d < best) {
        best = d
        qx = cx
        qy = cy
      }
    }
    if (n > 2) {
      inside = true
      for (let i = 0; i < n; i++) {
        if (shape.normals[i].x * (lx - vs[i].x) + shape.normals[i].y * (ly - vs[i].y) > 0) inside = false
      }
    }
  }
  const gx = lx - qx
  const gy = ly - qy
  const gap = Math.sqrt(gx * gx + gy * gy)
  const r = shape.radius
  if (inside || gap <= r) {
    out.x = p.x
    out.y = p.y
    out.distance = 0
    return
  }
  // Surface point: r along the gap from the core's nearest point.
  const sx = qx + (r * gx) / gap
  const sy = qy + (r * gy) / gap
  out.x = b.x + b.c * sx - b.s * sy
  out.y = b.y + b.s * sx + b.c * sy
  out.distance = gap - r
}

/** A shape's width along the world direction (tx, ty) (unit): its projection's length (m). */
function projectedWidth(s: BodyShape, tx: number, ty: number): number {
  const b = s.body
  const shape = s.shape
  // The direction in the body frame.
  const lx = b.c * tx + b.s * ty
  const ly = -b.s * tx + b.c * ty
  if (shape.type === 'circle') return 2 * shape.radius
  let lo = Number.POSITIVE_INFINITY
  let hi = Number.NEGATIVE_INFINITY
  for (let i = 0; i < shape.count; i++) {
    const d = shape.vertices[i].x * lx + shape.vertices[i].y * ly
    lo = Math.min(lo, d)
    hi = Math.max(hi, d)
  }
  return hi - lo + 2 * shape.radius
}
