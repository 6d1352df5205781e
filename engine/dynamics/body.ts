/*
 * A rigid body: its shapes (body-shape.ts), its mass properties, and its state.
 *
 * The state follows Box2D v3's split between the step's start and the sub-steps: (cx, cy) and the
 * rotation (c, s) are the centre of mass and orientation at the start of the step; during the
 * sub-steps the solver accumulates a position delta (dpx, dpy) and a rotation delta (dqc, dqs), and
 * `finalizeBodies` folds them back in once per step. Contacts and joints measure the current
 * separation from these deltas, so the narrowphase runs once per step, not once per sub-step.
 *
 * All fields are numbers (or fixed references) so every Body has one hidden class in V8.
 */

import { circle, combineMass, computeMass, type MassData, type Shape } from '../collision/index.ts'
import type { Joint } from '../joints/index.ts'
import type { BodyShape } from './body-shape.ts'
import type { Contact } from './contact.ts'

/** Placeholders of a body without shapes (never collided). */
const EMPTY_SHAPE: Shape = circle(1)
const EMPTY_LAYOUT = new Float64Array(0)

/** Body type codes, in the order of BodyType. */
export const STATIC = 0
export const KINEMATIC = 1
export const DYNAMIC = 2

/** A rigid body. Engine-internal; the public API addresses bodies by id. */
export class Body {
  readonly id: number
  type: number
  /** The body's shapes, in id (creation) order. */
  readonly shapes: BodyShape[] = []
  /**
   * The number of shapes, and the first shape's geometry, layout and proxy, mirrored here by
   * syncShapes() whenever the shapes or their proxies change: the per-step passes over bodies read
   * a one-shape body without touching its shape object.
   */
  shapeCount = 0
  shape0: Shape = EMPTY_SHAPE
  geometry0: Float64Array = EMPTY_LAYOUT
  proxy0 = -1
  linearDamping: number
  angularDamping: number
  gravityScale: number
  bullet: boolean
  enableSleep: boolean
  fixedRotation: boolean

  // Mass properties
  mass = 0
  invMass = 0
  inertia = 0
  invInertia = 0
  /** Centre of mass in the body frame (m). */
  localCenterX = 0
  localCenterY = 0
  /** Largest and smallest distance from the centre of mass to the shape's surface (m). */
  maxExtent = 0
  minExtent = 0

  // Transform at the start of the step
  /** Body origin, world (m). */
  x = 0
  y = 0
  /** Centre of mass, world (m). */
  cx = 0
  cy = 0
  /** Rotation as a unit (cos, sin) pair. */
  c = 1
  s = 0

  // Velocity and sub-step deltas
  vx = 0
  vy = 0
  w = 0
  dpx = 0
  dpy = 0
  dqc = 1
  dqs = 0

  // Force (N) and torque (N m) applied through the API since the last step; the next step applies
  // them over its 1/60 s and clears them (Box2D's b2Body_ApplyForce).
  fx = 0
  fy = 0
  torque = 0

  // Sleep
  awake = true
  sleepTime = 0
  /** Union-find parent slot for island building, valid during one step. */
  islandParent = 0
  /** Slot in the step's awake array, valid during one step. */
  solverIndex = -1

  // Continuous collision: centre and rotation at the start of the step
  c0x = 0
  c0y = 0
  q0c = 1
  q0s = 0

  /** Broadphase proxy id. */
  proxy = -1
  /** Contacts this body is part of (any order; used as a set). */
  readonly contacts: Contact[] = []
  /** Joints this body is part of (any order; used as a set). */
  readonly joints: Joint[] = []

  constructor(id: number, type: number) {
    this.id = id
    this.type = type
    this.linearDamping = 0
    this.angularDamping = 0
    this.gravityScale = 1
    this.bullet = false
    this.enableSleep = true
    this.fixedRotation = false
  }

  /** Refreshes the mirrored first-shape fields after the shapes or their proxies changed. */
  syncShapes(): void {
    this.shapeCount = this.shapes.length
    const first = this.shapes.length > 0 ? this.shapes[0] : null
    this.shape0 = first === null ? EMPTY_SHAPE : first.shape
    this.geometry0 = first === null ? EMPTY_LAYOUT : first.geometry
    this.proxy0 = first === null ? -1 : first.proxy
  }

  /** Recomputes the origin from the centre of mass and rotation. */
  updateOrigin(): void {
    this.x = this.cx - (this.c * this.localCenterX - this.s * this.localCenterY)
    this.y = this.cy - (this.s * this.localCenterX + this.c * this.localCenterY)
  }

  /** Recomputes the centre of mass from the origin and rotation. */
  updateCenter(): void {
    this.cx = this.x + (this.c * this.localCenterX - this.s * this.localCenterY)
    this.cy = this.y + (this.s * this.localCenterX + this.c * this.localCenterY)
  }
}

/**
 * The mass properties of a body's shapes (each at its own density), summed by the parallel-axis
 * theorem; one shape's are its own, bit for bit.
 */
export function bodyMass(body: Body): MassData {
  const shapes = body.shapes
  if (shapes.length === 1) return computeMass(shapes[0].shape, shapes[0].density)
  return combineMass(shapes.map((s) => computeMass(s.shape, s.density)))
}

/**
 * Sets mass, inertia, centre of mass and extents from the shapes and their densities. A body without
 * shapes keeps its centre at the origin and its extents at 0. Bodies that are not dynamic keep mass 0.
 */
export function updateMassData(body: Body): void {
  const md = bodyMass(body)
  body.localCenterX = md.center.x
  body.localCenterY = md.center.y
  body.mass = 0
  body.invMass = 0
  body.inertia = 0
  body.invInertia = 0
  if (body.type === DYNAMIC) {
    body.mass = md.mass
    body.invMass = 1 / md.mass
    body.inertia = body.fixedRotation ? 0 : md.inertia
    body.invInertia = body.fixedRotation ? 0 : 1 / md.inertia
  }
  const shapes = body.shapes
  if (shapes.length === 1) {
    const shape = shapes[0].shape
    body.maxExtent = shapeMaxExtent(shape, md.center.x, md.center.y)
    body.minExtent = shapeMinExtent(shape, md.center.x, md.center.y)
    return
  }
  let maxExtent = 0
  let minExtent = shapes.length > 0 ? Number.POSITIVE_INFINITY : 0
  for (const s of shapes) {
    maxExtent = Math.max(maxExtent, shapeMaxExtent(s.shape, md.center.x, md.center.y))
    const own = computeMass(s.shape, 1).center
    minExtent = Math.min(minExtent, shapeMinExtent(s.shape, own.x, own.y))
  }
  body.maxExtent = maxExtent
  body.minExtent = minExtent
}

/** Farthest reach of a shape's surface from a point (cx, cy) of the body frame (m). */
export function shapeMaxExtent(shape: Shape, cx: number, cy: number): number {
  if (shape.type === 'circle') {
    const dx = shape.centroid.x - cx
    const dy = shape.centroid.y - cy
    if (dx === 0 && dy === 0) return shape.radius
    return Math.sqrt(dx * dx + dy * dy) + shape.radius
  }
  let maxExtent = 0
  for (let i = 0; i < shape.count; i++) {
    const v = shape.vertices[i]
    const dx = v.x - cx
    const dy = v.y - cy
    maxExtent = Math.max(maxExtent, Math.sqrt(dx * dx + dy * dy))
  }
  return shape.radius > 0 ? maxExtent + shape.radius : maxExtent
}

/**
 * The smallest distance from a polygon's centre (cx, cy) (its centre of mass) to its surface (m):
 * how far it can move before it could pass through something (continuous collision; Box2D's
 * b2ComputeShapeExtent). A circle's is its radius, a capsule's its radius, a segment's 0.
 */
export function shapeMinExtent(shape: Shape, cx: number, cy: number): number {
  if (shape.type === 'circle') return shape.radius
  if (shape.count === 2) return shape.radius
  let minExtent = Number.POSITIVE_INFINITY
  for (let i = 0; i < shape.count; i++) {
    const v = shape.vertices[i]
    const n = shape.normals[i]
    minExtent = Math.min(minExtent, n.x * (v.x - cx) + n.y * (v.y - cy))
  }
  return shape.radius > 0 ? minExtent + shape.radius : minExtent
}
