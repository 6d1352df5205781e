/*
 * Shapes on the wire. Boxes travel as half extents, circles as a radius, other polygons as their
 * vertex list in the body frame (the engine's counter-clockwise order), taken exactly as sent
 * (convexPolygon: a list that is not a strictly convex polygon is refused, not replaced by its hull). Only creation events and
 * full states carry shapes; snapshots refer to bodies by id.
 */
import { box, circle, convexPolygon, type Shape } from '../../engine/index.ts'
import type { WireShape } from './messages.ts'

/** An engine shape as it travels. */
export function toWireShape(shape: Shape): WireShape {
  if (shape.type === 'circle') return { type: 'circle', radius: shape.radius }
  if (shape.box) return { type: 'box', hw: shape.box.halfWidth, hh: shape.box.halfHeight }
  const v: number[] = []
  for (const p of shape.vertices) v.push(p.x, p.y)
  return { type: 'polygon', v }
}

/** A wire shape as an engine shape; throws RangeError naming the problem if it is invalid. */
export function fromWireShape(shape: WireShape): Shape {
  if (shape.type === 'circle') return circle(shape.radius)
  if (shape.type === 'box') return box(shape.hw, shape.hh)
  const points = []
  for (let i = 0; i + 1 < shape.v.length; i += 2) points.push({ x: shape.v[i], y: shape.v[i + 1] })
  return convexPolygon(points)
}

/** Vertices (m, body frame) of a wire shape for drawing; empty for circles. */
export function wireShapeVertices(shape: WireShape): Array<{ x: number; y: number }> {
  if (shape.type === 'circle') return []
  if (shape.type === 'box') {
    const { hw, hh } = shape
    return [
      { x: -hw, y: -hh },
      { x: hw, y: -hh },
      { x: hw, y: hh },
      { x: -hw, y: hh },
    ]
  }
  const out = []
  for (let i = 0; i + 1 < shape.v.length; i += 2) out.push({ x: shape.v[i], y: shape.v[i + 1] })
  return out
}
