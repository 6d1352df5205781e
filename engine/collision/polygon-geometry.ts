/*
 * A polygon's vertices and normals as one flat Float64Array, computed once per body, in the layout
 * the narrowphase works in: the polygon shifted so that vertex 0 is the origin (the frame
 * polygon-against-polygon uses for small round-off), its unit normals, and the unshifted vertices.
 * Reading numbers from one typed array instead of chasing `{x, y}` objects per vertex halves the
 * cost of loading a polygon pair; the values are the same subtractions the narrowphase did per call,
 * so results are bit-identical.
 *
 * Layout, MAX_POLYGON_VERTICES slots per block: [SHIFTED_X | SHIFTED_Y | NORMAL_X | NORMAL_Y |
 * VERTEX_X | VERTEX_Y]. Capsules and segments are two-vertex polygons. A chain segment also keeps
 * its ghost vertices, at vertex slots 2 (ghost1) and 3 (ghost2).
 *
 * A circle's layout is its centre: [x, y] in the body frame, or one shared empty array when the
 * centre is the body origin (most circles). The per-step passes that place a circle (the
 * narrowphase's moveToCenter, the shape bounds) test `layout.length === 0` to skip the offset: the
 * shared array is always in cache, where the shape's centroid object is a cache miss per circle.
 */
import { MAX_POLYGON_VERTICES } from '../constants.ts'
import type { Shape } from './shapes.ts'

/** Offset of the shifted vertices' x (vertex i minus vertex 0). */
export const SHIFTED_X = 0
/** Offset of the shifted vertices' y. */
export const SHIFTED_Y = MAX_POLYGON_VERTICES
/** Offset of the edge normals' x (normal i belongs to edge i -> i + 1). */
export const NORMAL_X = 2 * MAX_POLYGON_VERTICES
/** Offset of the edge normals' y. */
export const NORMAL_Y = 3 * MAX_POLYGON_VERTICES
/** Offset of the vertices' x in the body frame (m). */
export const VERTEX_X = 4 * MAX_POLYGON_VERTICES
/** Offset of the vertices' y in the body frame (m). */
export const VERTEX_Y = 5 * MAX_POLYGON_VERTICES
/** Numbers in a polygon's geometry array. */
export const GEOMETRY_SIZE = 6 * MAX_POLYGON_VERTICES

const EMPTY = new Float64Array(0)

/** The flat geometry of a shape (for a circle its centre, or the shared empty array at the origin). */
export function polygonGeometry(shape: Shape): Float64Array {
  if (shape.type === 'circle') {
    const { x, y } = shape.centroid
    return x === 0 && y === 0 ? EMPTY : Float64Array.of(x, y)
  }
  const g = new Float64Array(GEOMETRY_SIZE)
  const vs = shape.vertices
  const ns = shape.normals
  const ox = vs[0].x
  const oy = vs[0].y
  for (let i = 0; i < shape.count; i++) {
    g[SHIFTED_X + i] = vs[i].x - ox
    g[SHIFTED_Y + i] = vs[i].y - oy
    g[NORMAL_X + i] = ns[i].x
    g[NORMAL_Y + i] = ns[i].y
    g[VERTEX_X + i] = vs[i].x
    g[VERTEX_Y + i] = vs[i].y
  }
  if (shape.type === 'chainSegment') {
    g[VERTEX_X + 2] = shape.ghost1.x
    g[VERTEX_Y + 2] = shape.ghost1.y
    g[VERTEX_X + 3] = shape.ghost2.x
    g[VERTEX_Y + 3] = shape.ghost2.y
  }
  return g
}
