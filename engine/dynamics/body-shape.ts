/*
 * A shape attached to a body (Box2D v3's b2Shape): its geometry, material, collision filter, sensor
 * and event flags, and its broadphase proxy. A body owns any number of them (a compound body);
 * contacts are made per pair of shapes on different bodies.
 *
 * The geometry (`shape`, made by circle(), box(), polygon(), capsule() or segment()) is immutable
 * and in the body's frame; everything else may be changed through the world's setters.
 *
 * All fields are numbers, booleans or fixed references, so every BodyShape has one hidden class.
 */

import { polygonGeometry, type Shape, slenderAxis } from '../collision/index.ts'
import type { Body } from './body.ts'

/** Box2D's default category: bit 0. */
export const DEFAULT_CATEGORY_BITS = 1
/** Collide with every category: all 32 bits (an unsigned 32-bit number). */
export const DEFAULT_MASK_BITS = 0xffffffff

/** A shape on a body. Engine-internal; the public API addresses shapes by id. */
export class BodyShape {
  readonly id: number
  readonly body: Body
  readonly shape: Shape
  /** The shape's vertices and normals laid out for the narrowphase (polygon-geometry.ts). */
  readonly geometry: Float64Array
  /**
   * Thinner than SLENDER_RATIO times its length (isSlender): its body's contacts get extra sweeps
   * while it touches on an end (contact-solver.ts prepareContacts).
   */
  readonly slender: boolean
  /** A slender shape's long axis in the body frame (slenderAxis; 0, 0 when not slender). */
  readonly axisX: number
  readonly axisY: number
  /** Density (kg/m^2). */
  density = 1
  /** Coulomb friction coefficient; pairs mix by sqrt(a b). */
  friction = 0.6
  /** Restitution 0..1; pairs mix by max(a, b). */
  restitution = 0
  /** Rolling resistance (non-dimensional, Box2D v3.1); pairs mix by max(a, b). */
  rollingResistance = 0
  /** Surface speed along the tangent (m/s): a conveyor belt. */
  tangentSpeed = 0
  /** Collision filter (Box2D's rule; unsigned 32-bit masks). */
  categoryBits = DEFAULT_CATEGORY_BITS
  maskBits = DEFAULT_MASK_BITS
  groupIndex = 0
  /** Detects overlap, never pushes. */
  sensor = false
  /** Whether sensors see this shape (sensor events), usually true. */
  enableSensorEvents = true
  /** Begin and end contact events for this shape, usually true. */
  enableContactEvents = true
  /** Hit events (fast impacts) for this shape, usually false. */
  enableHitEvents = false
  /** Broadphase proxy id (-1: none). */
  proxy = -1

  constructor(id: number, body: Body, shape: Shape) {
    this.id = id
    this.body = body
    this.shape = shape
    this.geometry = polygonGeometry(shape)
    const axis = slenderAxis(shape)
    this.slender = axis !== null
    this.axisX = axis === null ? 0 : axis.x
    this.axisY = axis === null ? 0 : axis.y
  }
}

/**
 * Box2D's filter rule: shapes of the same non-zero group always collide (positive group) or never
 * do (negative group); otherwise each shape's category must be in the other's mask.
 */
export function shouldFilterCollide(a: BodyShape, b: BodyShape): boolean {
  if (a.groupIndex === b.groupIndex && a.groupIndex !== 0) return a.groupIndex > 0
  return (a.maskBits & b.categoryBits) !== 0 && (a.categoryBits & b.maskBits) !== 0
}
