/*
 * Shapes on the wire (PROTOCOL.md, Shape). A body travels with its list of shapes in its own frame:
 * centred unturned boxes as half extents, circles as a radius and centre, other polygons (offset
 * or turned boxes, rounded polygons) as their vertex list in the engine's counter-clockwise order,
 * capsules and segments as their two points; each shape with the settings that differ from the
 * defaults (density 1, friction 0.6, restitution 0, rolling resistance 0, tangent speed 0, filter
 * [1, 0xffffffff, 0], not a sensor). Only creation events and full states carry shapes; snapshots
 * refer to bodies by id. A `spawn` gives shapes the same way, or an outline that the engine
 * decomposes (spawnShapeDefs), so every replica builds the same pieces.
 */
import {
  box,
  type ChainShape,
  capsule,
  chain,
  circle,
  convexPolygon,
  decomposeOutline,
  type Filter,
  type Shape,
  type ShapeDef,
  segment,
  type Vec2,
  type World,
} from '../../engine/index.ts'
import type { SpawnCommand, WireShape, WireShapeSettings } from './messages.ts'

const points = (v: readonly number[]): Vec2[] => {
  const out: Vec2[] = []
  for (let i = 0; i + 1 < v.length; i += 2) out.push({ x: v[i], y: v[i + 1] })
  return out
}
const flat = (ps: readonly Vec2[]): number[] => {
  const v: number[] = []
  for (const p of ps) v.push(p.x, p.y)
  return v
}

/** An engine shape's geometry as it travels (no settings). */
export function toWireShape(shape: Shape): WireShape {
  switch (shape.type) {
    case 'circle': {
      const c = shape.centroid
      return c.x === 0 && c.y === 0
        ? { type: 'circle', radius: shape.radius }
        : { type: 'circle', radius: shape.radius, x: c.x, y: c.y }
    }
    case 'capsule':
      return { type: 'capsule', v: flat(shape.vertices), radius: shape.radius }
    case 'segment':
      return { type: 'segment', v: flat(shape.vertices) }
    case 'chainSegment':
      // Scenery only (chains are static): drawn as its segment; replicas build the world itself.
      return { type: 'segment', v: flat(shape.vertices) }
    case 'polygon':
      if (shape.box) return { type: 'box', hw: shape.box.halfWidth, hh: shape.box.halfHeight }
      return shape.radius > 0
        ? { type: 'polygon', v: flat(shape.vertices), radius: shape.radius }
        : { type: 'polygon', v: flat(shape.vertices) }
  }
}

/** A world shape as it travels: its geometry and its settings that are not the defaults. */
export function wireShapeOf(world: World, shapeId: number): WireShape {
  const def = world.getShapeDef(shapeId)
  const out = toWireShape(def.shape as Shape) // a world's shape is one segment of a chain, never the chain
  if (def.density !== 1) out.density = def.density
  if (def.friction !== 0.6) out.friction = def.friction
  if (def.restitution !== 0) out.restitution = def.restitution
  if (def.rollingResistance !== 0) out.rolling = def.rollingResistance
  if (def.tangentSpeed !== 0) out.tangent = def.tangentSpeed
  const f = def.filter
  if (f.categoryBits !== 1 || f.maskBits !== 0xffffffff || f.groupIndex !== 0)
    out.filter = [f.categoryBits, f.maskBits, f.groupIndex]
  if (def.sensor) out.sensor = true
  return out
}

/** A body's shapes as they travel, in creation order. */
export function wireShapesOf(world: World, bodyId: number): WireShape[] {
  return world.bodyShapes(bodyId).map((id) => wireShapeOf(world, id))
}

/** A wire shape's geometry as an engine shape (a chain: all its segments); throws RangeError naming the problem if it is invalid. */
export function fromWireShape(shape: WireShape): Shape | ChainShape {
  switch (shape.type) {
    case 'circle':
      return shape.x === undefined && shape.y === undefined
        ? circle(shape.radius)
        : circle(shape.radius, { x: shape.x ?? 0, y: shape.y ?? 0 })
    case 'box':
      return shape.x === undefined && shape.y === undefined && shape.angle === undefined
        ? box(shape.hw, shape.hh)
        : box(shape.hw, shape.hh, { x: shape.x ?? 0, y: shape.y ?? 0 }, shape.angle ?? 0)
    case 'polygon':
      return convexPolygon(points(shape.v), shape.radius ?? 0)
    case 'capsule': {
      const [a, b] = points(shape.v)
      return capsule(a, b, shape.radius)
    }
    case 'segment': {
      const [a, b] = points(shape.v)
      return segment(a, b)
    }
    case 'chain':
      return chain(points(shape.v))
  }
}

/** Body-level material a spawn gives for shapes that do not give their own. */
type Material = Pick<SpawnCommand, 'density' | 'friction' | 'restitution'>

/** A wire shape as an engine shape definition (its own settings, else `material`'s); throws RangeError. */
export function fromWireShapeDef(shape: WireShape, material: Material = {}): ShapeDef {
  const def: ShapeDef = { shape: fromWireShape(shape) }
  const s: WireShapeSettings = shape
  const density = s.density ?? material.density
  const friction = s.friction ?? material.friction
  const restitution = s.restitution ?? material.restitution
  if (density !== undefined) def.density = density
  if (friction !== undefined) def.friction = friction
  if (restitution !== undefined) def.restitution = restitution
  if (s.rolling !== undefined) def.rollingResistance = s.rolling
  if (s.tangent !== undefined) def.tangentSpeed = s.tangent
  if (s.filter !== undefined) {
    const filter: Filter = { categoryBits: s.filter[0], maskBits: s.filter[1], groupIndex: s.filter[2] }
    def.filter = filter
  }
  if (s.sensor === true) def.sensor = true
  return def
}

/**
 * The shape definitions a spawn asks for: its `shape`, its `shapes`, or its `outline` decomposed
 * by the engine into convex pieces (each a polygon with the spawn's material). Throws RangeError
 * naming the problem (a self-intersecting outline gets decompose's own message).
 */
export function spawnShapeDefs(cmd: SpawnCommand): ShapeDef[] {
  if (cmd.outline !== undefined) {
    return decomposeOutline(points(cmd.outline)).map((piece) =>
      fromWireShapeDef({ type: 'polygon', v: flat(piece) }, cmd),
    )
  }
  if (cmd.shapes !== undefined) return cmd.shapes.map((s) => fromWireShapeDef(s, cmd))
  if (cmd.shape !== undefined) return [fromWireShapeDef(cmd.shape, cmd)]
  throw new RangeError('spawn needs a shape, shapes or an outline')
}

/** Vertices (m, body frame) of a polygonal wire shape's core for drawing; empty for circles. */
export function wireShapeVertices(shape: WireShape): Array<{ x: number; y: number }> {
  switch (shape.type) {
    case 'circle':
      return []
    case 'box': {
      const { hw, hh } = shape
      const corners = [
        { x: -hw, y: -hh },
        { x: hw, y: -hh },
        { x: hw, y: hh },
        { x: -hw, y: hh },
      ]
      if (shape.x === undefined && shape.y === undefined && shape.angle === undefined) return corners
      return box(hw, hh, { x: shape.x ?? 0, y: shape.y ?? 0 }, shape.angle ?? 0).vertices.map((p) => ({
        x: p.x,
        y: p.y,
      }))
    }
    default:
      return points(shape.v)
  }
}
