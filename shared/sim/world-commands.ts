/*
 * The world-level half of applying a command: what a spawn, grab, move, pin, rope, delete, unjoint
 * or gravity change does to an engine World, with every clamp and cap the protocol promises
 * (positions to WORLD_HALF_EXTENT, spawn speeds to MAX_SPAWN_SPEED, grab force per kg, grab
 * anchors to the body's outline, pin and rope anchors within ANCHOR_MARGIN of their bodies' reach,
 * rope length to MAX_ROPE_LENGTH). The server's rooms and the
 * offline sandbox both call these, so the two cannot drift apart. What is not the world's stays
 * with the caller: sessions, recorders, per-room limits and events on the server; views and the
 * page's own grab on the client. A refusal comes back as a reason; nothing here throws (an engine
 * precondition failure becomes "<command> refused: <message>").
 */
import type { BodyId, JointId, Vec2, World } from '../../engine/index.ts'
import {
  ANCHOR_MARGIN,
  MAX_ROPE_LENGTH,
  MAX_SPAWN_SPEED,
  type PinCommand,
  type RopeCommand,
  type SpawnCommand,
  spawnShapeDefs,
  type WireJoint,
  type WireJointDef,
  WORLD_HALF_EXTENT,
  wireJoint,
} from '../protocol/index.ts'

/** Grab force cap per kg of the grabbed body (N/kg): 1000 as in Box2D's samples. */
export const GRAB_FORCE_PER_KG = 1000
/** Absolute grab force cap (N), 1e7. */
export const MAX_GRAB_FORCE = 1e7

/** What a world command did: its result, or the reason it was refused. */
export type WorldResult<T> = { ok: true; value: T } | { ok: false; reason: string }

/** A grab just created: the mouse joint and its starting target (world m). */
export interface CreatedGrab {
  joint: JointId
  target: Vec2
}

const clampTo = (v: number, limit: number): number => Math.min(limit, Math.max(-limit, v))
const refused = <T>(reason: string): WorldResult<T> => ({ ok: false, reason })

/** A point clamped into the world square [-WORLD_HALF_EXTENT, WORLD_HALF_EXTENT]^2 (m). */
export function clampToWorld(x: number, y: number): Vec2 {
  return { x: clampTo(x, WORLD_HALF_EXTENT), y: clampTo(y, WORLD_HALF_EXTENT) }
}

/** Whether a body exists and is not static (the bodies players may delete, pin or inspect). */
export function isMovable(world: World, id: number): boolean {
  return world.hasBody(id) && world.getBodyType(id) !== 'static'
}

/** Run an engine call that may throw on a precondition; the error becomes a refusal. */
function guarded<T>(command: string, create: () => T): WorldResult<T> {
  try {
    return { ok: true, value: create() }
  } catch (error) {
    return refused(`${command} refused: ${(error as Error).message}`)
  }
}

/**
 * Create the body a spawn command asks for (static when `cmd.static`, else dynamic) with the
 * shapes of spawnShapeDefs (an outline decomposed by the engine): position and speeds clamped;
 * density 1, friction 0.6 and restitution 0 for every shape that gives none, unless the command
 * gives them (validated in SPAWN_MATERIAL's ranges). An engine refusal (a self-intersecting
 * outline, a dynamic body of segments only) comes back as "spawn refused: <the engine's message>".
 */
export function spawnBody(world: World, cmd: SpawnCommand): WorldResult<BodyId> {
  return guarded('spawn', () =>
    world.createBody({
      type: cmd.static === true ? 'static' : 'dynamic',
      shapes: spawnShapeDefs(cmd),
      position: clampToWorld(cmd.x, cmd.y),
      angle: cmd.angle ?? 0,
      linearVelocity: { x: clampTo(cmd.vx ?? 0, MAX_SPAWN_SPEED), y: clampTo(cmd.vy ?? 0, MAX_SPAWN_SPEED) },
      angularVelocity: clampTo(cmd.w ?? 0, MAX_SPAWN_SPEED),
    }),
  )
}

/** Why a body cannot be grabbed (it is missing or not dynamic), or null when it can. */
export function grabRefusal(world: World, body: number): string | null {
  if (!world.hasBody(body) || world.getBodyType(body) !== 'dynamic') return `body ${body} cannot be grabbed`
  return null
}

/** Largest distance of the body's outline (every shape, rounding included) from its origin (m). */
export function shapeReach(world: World, id: BodyId): number {
  let r = 0
  for (const sid of world.bodyShapes(id)) {
    const shape = world.getShapeGeometry(sid)
    if (shape.type === 'circle') {
      const c = shape.centroid
      r = Math.max(r, Math.sqrt(c.x * c.x + c.y * c.y) + shape.radius)
      continue
    }
    for (const v of shape.vertices) r = Math.max(r, Math.sqrt(v.x * v.x + v.y * v.y) + shape.radius)
  }
  return r
}

/**
 * Grab a dynamic body at a local point (m) with a mouse joint: the anchor is pulled in to the
 * shape's reach, the target starts at the anchor's world position, the force is capped at
 * min(MAX_GRAB_FORCE, GRAB_FORCE_PER_KG * mass). The caller releases any earlier grab first.
 */
export function grabBody(world: World, body: number, lx: number, ly: number): WorldResult<CreatedGrab> {
  const refusal = grabRefusal(world, body)
  if (refusal) return refused(refusal)
  return guarded('grab', () => {
    const reach = shapeReach(world, body)
    const length = Math.sqrt(lx * lx + ly * ly)
    const scale = length > reach ? reach / length : 1
    const localAnchor = { x: lx * scale, y: ly * scale }
    const target = world.getWorldPoint(body, localAnchor)
    const maxForce = Math.min(MAX_GRAB_FORCE, GRAB_FORCE_PER_KG * world.getMass(body))
    const joint = world.createJoint({ type: 'mouse', body, target, localAnchor, maxForce })
    return { joint, target }
  })
}

/** Move a grab's target to a point clamped to the world (if the joint still exists); returns the point. */
export function moveGrab(world: World, joint: JointId | null, x: number, y: number): Vec2 {
  const p = clampToWorld(x, y)
  if (joint !== null && world.hasJoint(joint)) world.setJointTarget(joint, p)
  return p
}

/** Destroy a joint if it still exists (a grab's mouse joint, or a pin or rope). */
export function removeJoint(world: World, joint: JointId): void {
  if (world.hasJoint(joint)) world.destroyJoint(joint)
}

/** Destroy a movable body and its joints; refused for a missing or static body. */
export function deleteBody(world: World, body: number): string | null {
  if (!isMovable(world, body)) return `body ${body} does not exist or is static`
  world.destroyBody(body)
  return null
}

/** Why a pin or rope cannot join its bodies (b missing or static, a missing, a = b), or null. */
export function jointRefusal(world: World, cmd: PinCommand | RopeCommand): string | null {
  if (!isMovable(world, cmd.b)) return `body ${cmd.b} does not exist or is static`
  if (cmd.a !== 0 && !world.hasBody(cmd.a)) return `body ${cmd.a} does not exist`
  if (cmd.a === cmd.b) return 'a joint needs two different bodies'
  return null
}

/**
 * Why an anchor (world m) is too far from a body to hold it, or null: it must lie within the
 * body's reach (the farthest point of its outline from its origin) plus ANCHOR_MARGIN. A joint
 * anchored hundreds of metres away acts through a lever arm that flings bodies past the speed
 * cap, to kilometres and to NaN (issue 11).
 */
export function anchorRefusal(world: World, body: number, anchor: Vec2, what: string): string | null {
  const p = world.getPosition(body)
  const d = Math.sqrt((anchor.x - p.x) ** 2 + (anchor.y - p.y) ** 2)
  const limit = shapeReach(world, body) + ANCHOR_MARGIN
  if (d <= limit) return null
  return `${what} (${anchor.x.toFixed(2)}, ${anchor.y.toFixed(2)}) is ${d.toFixed(2)} m from body ${body}; it must be within ${limit.toFixed(2)} m`
}

/**
 * Create a pin (revolute joint at a world point) or a rope (distance joint between two world
 * points, slack allowed, at most MAX_ROPE_LENGTH) with anchors clamped to the world and each
 * anchor on or near its body (anchorRefusal; a world end, a = 0, may be anywhere); returns the
 * joint as it travels, anchors in each body's frame (the world frame when a = 0).
 */
export function addUserJoint(world: World, cmd: PinCommand | RopeCommand): WorldResult<WireJoint> {
  const refusal = jointRefusal(world, cmd)
  if (refusal) return refused(refusal)
  const near = (anchorA: Vec2, anchorB: Vec2): string | null =>
    anchorRefusal(world, cmd.b, anchorB, `${cmd.k} anchor`) ??
    (cmd.a === 0 ? null : anchorRefusal(world, cmd.a, anchorA, `${cmd.k} anchor`))
  const bodyA = cmd.a === 0 ? null : cmd.a
  if (cmd.k === 'pin') {
    const anchor = clampToWorld(cmd.x, cmd.y)
    const far = near(anchor, anchor)
    if (far) return refused(far)
    const def: WireJointDef = { type: 'revolute', bodyA, bodyB: cmd.b, anchor }
    return guarded('pin', () => wireJoint(world, world.createJoint(def), def))
  }
  const anchorA = clampToWorld(cmd.ax, cmd.ay)
  const anchorB = clampToWorld(cmd.bx, cmd.by)
  const length = Math.sqrt((anchorB.x - anchorA.x) ** 2 + (anchorB.y - anchorA.y) ** 2)
  if (length > MAX_ROPE_LENGTH) return refused(`rope longer than ${MAX_ROPE_LENGTH} m`)
  const far = near(anchorA, anchorB)
  if (far) return refused(far)
  const def: WireJointDef = {
    type: 'distance',
    bodyA,
    bodyB: cmd.b,
    anchorA,
    anchorB,
    length,
    minLength: 0,
    maxLength: length,
  }
  return guarded('rope', () => wireJoint(world, world.createJoint(def), def))
}

/** The anchors of a joint definition that must lie near their bodies (world m): [a's, b's]. */
function definitionAnchors(def: WireJointDef): [Vec2, Vec2] | null {
  if (def.type === 'distance') return [def.anchorA, def.anchorB]
  if (def.type === 'motor') return null
  return [def.anchor, def.anchor]
}

/**
 * Create a player's joint of any kind that travels (a weld, hinge, spring, slider or wheel from
 * a game command) for player `owner`: the bodies as for a pin (b movable, a the world or an
 * existing body, a != b), each anchor within its body's reach plus ANCHOR_MARGIN (anchorRefusal),
 * and an engine precondition failure refused as "<kind> refused: MESSAGE". Anchors are taken as
 * given: the caller clamps them to the world. Returns the joint as it travels.
 */
export function createUserJoint(
  world: World,
  def: WireJointDef,
  owner: number,
  what: string,
): WorldResult<WireJoint> {
  const a = def.bodyA ?? 0
  const refusal = jointRefusal(world, { k: 'pin', a, b: def.bodyB, x: 0, y: 0 })
  if (refusal) return refused(refusal)
  const anchors = definitionAnchors(def)
  if (anchors) {
    const far =
      anchorRefusal(world, def.bodyB, anchors[1], `${what} anchor`) ??
      (a === 0 ? null : anchorRefusal(world, a, anchors[0], `${what} anchor`))
    if (far) return refused(far)
  }
  return guarded(what, () => wireJoint(world, world.createJoint(def), def, owner))
}

/** Set the world's gravity (m/s^2) and wake every dynamic body so the change is felt at once. */
export function setWorldGravity(world: World, x: number, y: number): void {
  world.setGravity({ x, y })
  for (const id of world.bodyIds()) if (world.getBodyType(id) === 'dynamic') world.setAwake(id, true)
}
