/*
 * Hit testing: which body is under a world point. Shapes are tested in the body frame (rotate the
 * point by -angle): a circle by distance, a convex polygon by the sign of every edge's cross
 * product (counter-clockwise vertices, as the engine and the wire store them), a rounded polygon
 * or capsule by distance to its core, a segment within SEGMENT_PICK_DISTANCE; a body is hit when
 * any of its shapes is.
 */
import type { Vec2 } from '../../engine/index.ts'
import { type WireShape, wireShapeVertices } from '../../shared/index.ts'
import type { ViewBody } from '../modes/index.ts'

const verticesCache = new WeakMap<WireShape, Vec2[]>()

/** A wire shape's vertices in the body frame (cached per shape object); empty for circles. */
export function shapeVertices(shape: WireShape): Vec2[] {
  let v = verticesCache.get(shape)
  if (!v) {
    v = wireShapeVertices(shape)
    verticesCache.set(shape, v)
  }
  return v
}

/** Largest distance of the shape's outline (rounding included) from the body origin (m). */
export function shapeRadius(shape: WireShape): number {
  if (shape.type === 'circle') return Math.sqrt((shape.x ?? 0) ** 2 + (shape.y ?? 0) ** 2) + shape.radius
  let r = 0
  for (const v of shapeVertices(shape)) r = Math.max(r, Math.sqrt(v.x * v.x + v.y * v.y))
  return (
    r + (shape.type === 'box' || shape.type === 'segment' || shape.type === 'chain' ? 0 : (shape.radius ?? 0))
  )
}

/** Largest distance of a body's outline, over all its shapes, from its origin (m). */
export function bodyRadius(body: { shapes: readonly WireShape[] }): number {
  let r = 0
  for (const shape of body.shapes) r = Math.max(r, shapeRadius(shape))
  return r
}

/** How close (m) a point must come to a segment shape to pick it: segments have no inside. */
const SEGMENT_PICK_DISTANCE = 0.15

/** True when the body-frame point lies inside (or on) the shape. */
function shapeContains(shape: WireShape, l: Vec2): boolean {
  if (shape.type === 'circle')
    return (l.x - (shape.x ?? 0)) ** 2 + (l.y - (shape.y ?? 0)) ** 2 <= shape.radius ** 2
  const v = shapeVertices(shape)
  if (shape.type === 'segment' || shape.type === 'capsule') {
    const r = shape.type === 'capsule' ? shape.radius : SEGMENT_PICK_DISTANCE
    return distanceToSegment(l, v[0].x, v[0].y, v[1].x, v[1].y) <= r
  }
  const r = shape.type === 'polygon' ? (shape.radius ?? 0) : 0
  let inside = true
  for (let i = 0; i < v.length; i++) {
    const a = v[i]
    const b = v[(i + 1) % v.length]
    if ((b.x - a.x) * (l.y - a.y) - (b.y - a.y) * (l.x - a.x) < 0) inside = false
  }
  if (inside || r === 0) return inside
  // A rounded polygon: within the radius of its core's outline.
  for (let i = 0; i < v.length; i++) {
    const a = v[i]
    const b = v[(i + 1) % v.length]
    if (distanceToSegment(l, a.x, a.y, b.x, b.y) <= r) return true
  }
  return false
}

/** A world point in the body's frame. */
export function toLocal(body: ViewBody, p: Vec2): Vec2 {
  const dx = p.x - body.x
  const dy = p.y - body.y
  const c = Math.cos(body.angle)
  const s = Math.sin(body.angle)
  return { x: c * dx + s * dy, y: -s * dx + c * dy }
}

/** A body-frame point in world space. */
export function toWorld(body: { x: number; y: number; angle: number }, lx: number, ly: number): Vec2 {
  const c = Math.cos(body.angle)
  const s = Math.sin(body.angle)
  return { x: body.x + c * lx - s * ly, y: body.y + s * lx + c * ly }
}

/** True when the world point lies inside one of the body's shapes. */
export function containsPoint(body: ViewBody, p: Vec2): boolean {
  const l = toLocal(body, p)
  for (const shape of body.shapes) if (shapeContains(shape, l)) return true
  return false
}

/** The topmost body under a point (drawn last = on top) that passes `accept`, or null. */
export function pickBody(
  bodies: readonly ViewBody[],
  p: Vec2,
  accept: (b: ViewBody) => boolean = () => true,
  skip = 0,
): ViewBody | null {
  for (let i = bodies.length - 1; i >= 0; i--) {
    const b = bodies[i]
    if (b.id === skip || !accept(b)) continue
    const r = bodyRadius(b) + SEGMENT_PICK_DISTANCE
    if (Math.abs(p.x - b.x) > r || Math.abs(p.y - b.y) > r) continue
    if (containsPoint(b, p)) return b
  }
  return null
}

/** Distance (m) from a point to the segment a-b (to a when they coincide, as for a pin). */
export function distanceToSegment(p: Vec2, ax: number, ay: number, bx: number, by: number): number {
  const dx = bx - ax
  const dy = by - ay
  const l2 = dx * dx + dy * dy
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p.x - ax) * dx + (p.y - ay) * dy) / l2)) : 0
  return Math.hypot(p.x - (ax + t * dx), p.y - (ay + t * dy))
}

/**
 * The joint drawn nearest a point within `reach` (m): measured to the line between its anchors (a
 * rope, rod or spring) or to its anchor (a pin); null when none is that close.
 */
export function pickJoint<J extends { ax: number; ay: number; bx: number; by: number }>(
  joints: readonly J[],
  p: Vec2,
  reach: number,
): J | null {
  let best: J | null = null
  let bestDistance = reach
  for (const j of joints) {
    const d = distanceToSegment(p, j.ax, j.ay, j.bx, j.by)
    if (d <= bestDistance) {
      best = j
      bestDistance = d
    }
  }
  return best
}
