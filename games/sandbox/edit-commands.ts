/*
 * The sandbox's edit commands (issue 31, the Build "Edit" tool) as game commands with JSON Schema
 * arguments: `edit` changes a body's material (density, friction, restitution: every shape of it),
 * colour, collision layer and static/dynamic state; `transform` moves, turns and scales one;
 * `duplicate` copies one beside itself; `deleteMany` removes a box selection at once.
 *
 * Which bodies a player may edit: every body that is not static, and the static bodies players
 * made (they have a colour: drawn ground, or a body a player made static). The scene's own static
 * bodies (the ground, the ramp, chains) are refused, as `delete` refuses them. A body another
 * player holds may be edited but not made static or transformed (its grab would pull a fixed
 * body); deleteMany releases grabs as `delete` does.
 *
 * Collision layers: layer 0 is the default (category bit 1, mask every bit: collides with
 * everything); layer L in 1..MAX_LAYER is category bit 1 << L with mask 1 | 1 << L, so a body on
 * layer L collides with layer L and layer 0 only (two different non-zero layers pass through each
 * other). `edit` sets every shape's category and mask and keeps its group index.
 *
 * Each command is undoable (undo-commands.ts): it records the bodies it touches as they were before
 * and after (a body with the joints on it), so an undo rebuilds the body as it was, with a new id.
 *
 * Every refusal is decided before anything changes, so a refused command changes nothing. The
 * floats computed here are products and quotients of the arguments (scale), so every replica
 * builds the same shapes bit for bit. docs/games.md ("The sandbox's edit commands") says exactly
 * what each does and in what order; PROTOCOL.md has the wire form.
 */
import {
  box,
  capsule,
  circle,
  convexPolygon,
  type Filter,
  type Shape,
  type ShapeDef,
  segment,
  type Vec2,
  type World,
} from '../../engine/index.ts'
import {
  clampToWorld,
  type GameContext,
  NO_ITEMS,
  playerBodyColor,
  SPAWN_MATERIAL,
  shapeReach,
} from '../../shared/index.ts'
import type { GameCommandDefinition } from '../game-api.ts'
import { captureBodies, recordAction } from './undo-commands.ts'

/** The highest collision layer (layers are 0..MAX_LAYER; see the file comment). */
export const MAX_LAYER = 7
/** Scale factors a transform accepts (one command; repeat it to grow further). */
export const MIN_SCALE = 0.1
export const MAX_SCALE = 10
/** The farthest a scaled body's outline may reach from its origin (m). */
export const MAX_EDIT_REACH = 50
/** The most bodies one deleteMany removes. */
export const MAX_DELETE_MANY = 256
/** The farthest a duplicate is placed from its original (m, each axis). */
export const MAX_DUPLICATE_OFFSET = 100

const bodyId = { type: 'integer', minimum: 1, maximum: Number.MAX_SAFE_INTEGER }
const coordinate = { type: 'number', minimum: -1e6, maximum: 1e6 }
const range = (r: readonly [number, number]) => ({ type: 'number', minimum: r[0], maximum: r[1] })

/** An object schema with these properties, the required ones, and nothing else. */
const args = (properties: Record<string, object>, required: string[]) =>
  ({ type: 'object', properties, required, additionalProperties: false }) as const

interface EditArgs {
  body: number
  density?: number
  friction?: number
  restitution?: number
  color?: number
  layer?: number
  static?: boolean
}
interface TransformArgs {
  body: number
  x?: number
  y?: number
  angle?: number
  scale?: number
}

/** The filter of collision layer `layer` (see the file comment), keeping a group index. */
export function layerFilter(layer: number, groupIndex = 0): Filter {
  if (layer === 0) return { categoryBits: 1, maskBits: 0xffffffff, groupIndex }
  return { categoryBits: 1 << layer, maskBits: 1 + (1 << layer), groupIndex }
}

/** The collision layer of a filter: L for layerFilter(L)'s category, else 0. */
export function filterLayer(filter: { categoryBits: number; maskBits: number }): number {
  for (let layer = 1; layer <= MAX_LAYER; layer++)
    if (filter.categoryBits === 1 << layer && filter.maskBits === 1 + (1 << layer)) return layer
  return 0
}

/** Why a player may not edit a body (missing, or the scene's static scenery), or null. */
export function editRefusal(ctx: GameContext<undefined>, body: number): string | null {
  if (!ctx.world.hasBody(body)) return `body ${body} does not exist`
  if (ctx.world.getBodyType(body) === 'static' && ctx.bodyColor(body) === null)
    return `body ${body} is the scene's static scenery: it cannot be edited`
  return null
}

/** The player holding a body, or 0. */
function holder(ctx: GameContext<undefined>, body: number): number {
  for (const p of ctx.players) if (ctx.grabbedBody(p) === body) return p
  return 0
}

/** Why a body may not become dynamic (a chain, or no shape with mass), or null. */
function dynamicRefusal(world: World, body: number): string | null {
  let massive = false
  for (const s of world.bodyShapes(body)) {
    const type = world.getShapeGeometry(s).type
    if (type === 'chainSegment') return `body ${body} is a chain: it can only be static`
    if (type !== 'segment') massive = true
  }
  return massive ? null : `body ${body} is made of segments only: it can only be static`
}

const scaled = (p: Vec2, k: number): Vec2 => ({ x: p.x * k, y: p.y * k })

/** A shape's geometry scaled by k about the body origin; throws a RangeError (a too small shape). */
export function scaleShape(shape: Shape, k: number): Shape {
  switch (shape.type) {
    case 'circle':
      return circle(shape.radius * k, scaled(shape.centroid, k))
    case 'polygon':
      if (shape.box) return box(shape.box.halfWidth * k, shape.box.halfHeight * k)
      return convexPolygon(
        shape.vertices.map((v) => scaled(v, k)),
        shape.radius * k,
      )
    case 'capsule':
      return capsule(scaled(shape.vertices[0], k), scaled(shape.vertices[1], k), shape.radius * k)
    case 'segment':
      return segment(scaled(shape.vertices[0], k), scaled(shape.vertices[1], k))
    case 'chainSegment':
      throw new RangeError('a chain cannot be scaled')
  }
}

/** The shape definitions of a body scaled by k (material, filter and flags kept), or a refusal. */
function scaledShapes(world: World, body: number, k: number): ShapeDef[] | string {
  const reach = shapeReach(world, body) * k
  if (reach > MAX_EDIT_REACH)
    return `scale ${k} would make body ${body} reach ${reach.toFixed(2)} m from its origin; at most ${MAX_EDIT_REACH} m`
  const defs: ShapeDef[] = []
  for (const s of world.bodyShapes(body)) {
    const def = world.getShapeDef(s)
    const shape = def.shape as Shape
    if (shape.type === 'chainSegment') return `body ${body} is a chain: it cannot be scaled`
    try {
      defs.push({ ...def, shape: scaleShape(shape, k) })
    } catch (e) {
      return `scale ${k} refused for body ${body}: ${(e as Error).message}`
    }
  }
  return defs
}

/** The sandbox's edit commands (see the file comment). */
export const editCommands: Record<string, GameCommandDefinition<undefined>> = {
  edit: {
    args: args(
      {
        body: bodyId,
        density: range(SPAWN_MATERIAL.density),
        friction: range(SPAWN_MATERIAL.friction),
        restitution: range(SPAWN_MATERIAL.restitution),
        color: { type: 'integer', minimum: 0, maximum: 0xffffff },
        layer: { type: 'integer', minimum: 0, maximum: MAX_LAYER },
        static: { type: 'boolean' },
      },
      ['body'],
    ),
    apply(ctx, player, c: EditArgs) {
      const world = ctx.world
      const refusal = editRefusal(ctx, c.body)
      if (refusal) return refusal
      const wasStatic = world.getBodyType(c.body) === 'static'
      if (c.static === true && !wasStatic) {
        const held = holder(ctx, c.body)
        if (held !== 0) return `body ${c.body} is held by player ${held}: it cannot be made static`
      }
      if (c.static === false && wasStatic) {
        const why = dynamicRefusal(world, c.body)
        if (why) return why
      }
      const before = captureBodies(ctx, [c.body])
      // 1. material and layer, shape by shape in creation order
      for (const s of world.bodyShapes(c.body)) {
        if (c.density !== undefined) world.setDensity(s, c.density)
        if (c.friction !== undefined) world.setFriction(s, c.friction)
        if (c.restitution !== undefined) world.setRestitution(s, c.restitution)
        if (c.layer !== undefined) world.setFilter(s, layerFilter(c.layer, world.getFilter(s).groupIndex))
      }
      // 2. colour; a body made static keeps (or gets) a colour, so players can edit it again
      if (c.color !== undefined) ctx.setBodyColor(c.body, c.color)
      // 3. static or dynamic (a static body stops; a dynamic one starts at rest)
      if (c.static !== undefined && c.static !== wasStatic) {
        if (c.static && ctx.bodyColor(c.body) === null) ctx.setBodyColor(c.body, playerBodyColor(player))
        world.setBodyType(c.body, c.static ? 'static' : 'dynamic')
      }
      ctx.bodyChanged(c.body)
      recordAction(ctx, player, 'edit', before, captureBodies(ctx, [c.body]))
    },
  },
  transform: {
    args: args(
      {
        body: bodyId,
        x: coordinate,
        y: coordinate,
        angle: { type: 'number', minimum: -Math.PI, maximum: Math.PI },
        scale: { type: 'number', minimum: MIN_SCALE, maximum: MAX_SCALE },
      },
      ['body'],
    ),
    apply(ctx, player, c: TransformArgs) {
      const world = ctx.world
      if ((c.x === undefined) !== (c.y === undefined)) return 'transform refused: give x and y together'
      const posed = c.x !== undefined || c.angle !== undefined
      if (!posed && c.scale === undefined) return 'transform refused: give x and y, angle or scale'
      const refusal = editRefusal(ctx, c.body)
      if (refusal) return refusal
      const held = holder(ctx, c.body)
      if (held !== 0) return `body ${c.body} is held by player ${held}: it cannot be moved`
      const k = c.scale ?? 1
      const defs = k === 1 ? null : scaledShapes(world, c.body, k)
      if (typeof defs === 'string') return defs
      const before = captureBodies(ctx, [c.body])
      // 1. the new shapes (made before the old go: a dynamic body always keeps a shape with mass)
      if (defs) {
        const old = world.bodyShapes(c.body)
        for (const def of defs) world.createShape(c.body, def)
        for (const s of old) world.destroyShape(s)
      }
      // 2. the pose (clamped to the world; what is not given is kept), and a moved body starts at rest
      if (!posed) {
        ctx.bodyChanged(c.body)
        recordAction(ctx, player, 'transform', before, captureBodies(ctx, [c.body]))
        return
      }
      const at = c.x === undefined || c.y === undefined ? world.getPosition(c.body) : clampToWorld(c.x, c.y)
      world.setTransform(c.body, at, c.angle ?? world.getAngle(c.body))
      if (world.getBodyType(c.body) !== 'static') {
        world.setLinearVelocity(c.body, { x: 0, y: 0 })
        world.setAngularVelocity(c.body, 0)
      }
      ctx.bodyChanged(c.body)
      recordAction(ctx, player, 'transform', before, captureBodies(ctx, [c.body]))
    },
  },
  duplicate: {
    args: args(
      {
        body: bodyId,
        dx: { type: 'number', minimum: -MAX_DUPLICATE_OFFSET, maximum: MAX_DUPLICATE_OFFSET },
        dy: { type: 'number', minimum: -MAX_DUPLICATE_OFFSET, maximum: MAX_DUPLICATE_OFFSET },
      },
      ['body', 'dx', 'dy'],
    ),
    apply(ctx, player, c: { body: number; dx: number; dy: number }) {
      const world = ctx.world
      const refusal = editRefusal(ctx, c.body)
      if (refusal) return refusal
      const def = world.getBodyDef(c.body)
      const p = def.position ?? { x: 0, y: 0 }
      const made = ctx.createBody({
        ...def,
        position: clampToWorld(p.x + c.dx, p.y + c.dy),
        linearVelocity: { x: 0, y: 0 },
        angularVelocity: 0,
        awake: true,
      })
      if (typeof made === 'string') return made
      // The copy's colour: the original's, else the copier's (so a copy of a scene body is a player's).
      ctx.setBodyColor(made, ctx.bodyColor(c.body) ?? playerBodyColor(player))
      ctx.bodyChanged(made)
      recordAction(ctx, player, 'duplicate', NO_ITEMS, captureBodies(ctx, [made]))
    },
  },
  deleteMany: {
    args: args(
      {
        bodies: { type: 'array', items: bodyId, minItems: 1, maxItems: MAX_DELETE_MANY, uniqueItems: true },
      },
      ['bodies'],
    ),
    apply(ctx, player, c: { bodies: number[] }) {
      for (const id of c.bodies) {
        const refusal = editRefusal(ctx, id)
        if (refusal) return refusal
      }
      const ids = [...c.bodies].sort((a, b) => a - b)
      const before = captureBodies(ctx, ids)
      for (const id of ids) ctx.destroyBody(id)
      recordAction(ctx, player, 'deleteMany', before, NO_ITEMS)
    },
  },
}
