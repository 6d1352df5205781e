/*
 * Input commands applied to a room's world. applyCommand is the single entry point: every command
 * a player's input causes goes through it at a tick, which is what a recorder logs. Inputs are
 * trusted only after validation (shared/validate.ts) and are further clamped here: positions to
 * the world bounds, speeds and grab forces to caps, spawns to the room's body limit. A refused
 * command returns a reason; nothing here throws to the caller.
 */
import { SCENES, type Vec2 } from '../engine/index.ts'
import {
  type Command,
  fromWireShape,
  MAX_ROPE_LENGTH,
  MAX_SPAWN_SPEED,
  type SpawnCommand,
  WORLD_HALF_EXTENT,
} from '../shared/index.ts'
import type { ClientSession } from './client-session.ts'
import type { Room } from './room.ts'
import { wireBody } from './room-wire.ts'

/** Grab force cap per kg of the grabbed body (N/kg): 1000 as in Box2D's samples. */
const GRAB_FORCE_PER_KG = 1000
/** Absolute grab force cap (N). */
const MAX_GRAB_FORCE = 1e7

const clampTo = (v: number, limit: number): number => Math.min(limit, Math.max(-limit, v))
const clampPoint = (x: number, y: number): Vec2 => ({
  x: clampTo(x, WORLD_HALF_EXTENT),
  y: clampTo(y, WORLD_HALF_EXTENT),
})

/** Ticks between scene loads or resets in one room: building a scene is the costliest command. */
const MIN_TICKS_BETWEEN_LOADS = 10

const CONTROLS = new Set(['scene', 'pause', 'step', 'reset', 'gravity'])

/** Apply one command from a player at the current tick; returns a reason when refused. */
export function applyCommand(room: Room, session: ClientSession, cmd: Command): string | null {
  if (CONTROLS.has(cmd.k) && !room.rules.controls) return `room controls are disabled in room ${room.name}`
  // Inspecting only chooses what this player is sent: the world does not change, nothing is recorded.
  if (cmd.k === 'inspect') return inspect(room, session, cmd.body)
  room.onCommand?.(room.tick, session.id, cmd)
  try {
    return dispatch(room, session, cmd)
  } catch (error) {
    // Engine preconditions (a non-convex polygon, a degenerate joint) throw RangeError.
    return `${cmd.k} refused: ${(error as Error).message}`
  }
}

function dispatch(room: Room, session: ClientSession, cmd: Command): string | null {
  const world = room.world
  switch (cmd.k) {
    case 'spawn':
      return spawn(room, cmd)
    case 'grab':
      return grab(room, session, cmd.body, cmd.lx, cmd.ly)
    case 'move': {
      const p = clampPoint(cmd.x, cmd.y)
      session.cursorX = p.x
      session.cursorY = p.y
      session.cursorDirty = true
      if (session.grab && world.hasJoint(session.grab.joint)) world.setJointTarget(session.grab.joint, p)
      return null
    }
    case 'release':
      release(room, session)
      return null
    case 'delete':
      if (!isMovable(room, cmd.body)) return `body ${cmd.body} does not exist or is static`
      room.removeBody(cmd.body)
      return null
    case 'pin':
    case 'rope':
      return joint(room, cmd)
    case 'unjoint':
      if (!room.userJoints.has(cmd.joint)) return `joint ${cmd.joint} is not a pin or rope in this room`
      if (world.hasJoint(cmd.joint)) world.destroyJoint(cmd.joint)
      room.jointRemoved(cmd.joint)
      return null
    case 'scene':
      if (!Object.hasOwn(SCENES, cmd.name)) return `unknown scene "${cmd.name}"`
      if (room.tick - room.lastLoadTick < MIN_TICKS_BETWEEN_LOADS)
        return 'scene loads are limited to 6 per second'
      room.loadScene(cmd.name)
      return null
    case 'reset':
      if (room.tick - room.lastLoadTick < MIN_TICKS_BETWEEN_LOADS)
        return 'scene loads are limited to 6 per second'
      room.loadScene(room.scene)
      return null
    case 'pause':
      room.paused = cmd.paused
      room.markRoomChanged()
      return null
    case 'step':
      room.stepRequested = true
      return null
    case 'inspect':
      return inspect(room, session, cmd.body)
    case 'gravity':
      world.setGravity({ x: cmd.x, y: cmd.y })
      for (const id of world.bodyIds()) if (world.getBodyType(id) === 'dynamic') world.setAwake(id, true)
      room.markRoomChanged()
      return null
  }
}

function inspect(room: Room, session: ClientSession, body: number): string | null {
  if (body !== 0 && !isMovable(room, body)) return `body ${body} does not exist or is static`
  session.inspect = body
  return null
}

function isMovable(room: Room, id: number): boolean {
  return room.world.hasBody(id) && room.world.getBodyType(id) !== 'static'
}

function spawn(room: Room, cmd: SpawnCommand): string | null {
  if (room.world.bodyCount >= room.config.maxBodies) return `body limit reached (${room.config.maxBodies})`
  const id = room.world.createBody({
    type: 'dynamic',
    shape: fromWireShape(cmd.shape),
    position: clampPoint(cmd.x, cmd.y),
    angle: cmd.angle ?? 0,
    linearVelocity: { x: clampTo(cmd.vx ?? 0, MAX_SPAWN_SPEED), y: clampTo(cmd.vy ?? 0, MAX_SPAWN_SPEED) },
    angularVelocity: clampTo(cmd.w ?? 0, MAX_SPAWN_SPEED),
    friction: 0.6,
  })
  room.bodyAdded(wireBody(room.world, id))
  return null
}

/** Largest distance of the shape's outline from the body origin (m). */
function shapeReach(room: Room, id: number): number {
  const shape = room.world.getShape(id)
  if (shape.type === 'circle') return shape.radius
  let r = 0
  for (const v of shape.vertices) r = Math.max(r, Math.sqrt(v.x * v.x + v.y * v.y))
  return r
}

function grab(room: Room, session: ClientSession, body: number, lx: number, ly: number): string | null {
  const world = room.world
  if (!world.hasBody(body) || world.getBodyType(body) !== 'dynamic') return `body ${body} cannot be grabbed`
  release(room, session)
  const reach = shapeReach(room, body)
  const length = Math.sqrt(lx * lx + ly * ly)
  const scale = length > reach ? reach / length : 1
  const localAnchor = { x: lx * scale, y: ly * scale }
  const target = world.getWorldPoint(body, localAnchor)
  const maxForce = Math.min(MAX_GRAB_FORCE, GRAB_FORCE_PER_KG * world.getMass(body))
  const joint = world.createJoint({ type: 'mouse', body, target, localAnchor, maxForce })
  session.grab = { joint, body }
  session.cursorX = target.x
  session.cursorY = target.y
  session.cursorDirty = true
  room.grabCounts.set(body, (room.grabCounts.get(body) ?? 0) + 1)
  return null
}

/** Release a player's grab, if any. */
export function release(room: Room, session: ClientSession): void {
  const g = session.grab
  if (!g) return
  if (room.world.hasJoint(g.joint)) room.world.destroyJoint(g.joint)
  const n = (room.grabCounts.get(g.body) ?? 1) - 1
  if (n > 0) room.grabCounts.set(g.body, n)
  else room.grabCounts.delete(g.body)
  session.grab = null
  session.cursorDirty = true
}

function joint(room: Room, cmd: Extract<Command, { k: 'pin' | 'rope' }>): string | null {
  const world = room.world
  if (!isMovable(room, cmd.b)) return `body ${cmd.b} does not exist or is static`
  if (cmd.a !== 0 && !world.hasBody(cmd.a)) return `body ${cmd.a} does not exist`
  if (cmd.a === cmd.b) return 'a joint needs two different bodies'
  if (room.userJoints.size >= room.config.maxBodies) return 'joint limit reached'
  const bodyA = cmd.a === 0 ? null : cmd.a
  const local = (body: number | null, p: Vec2): Vec2 => (body === null ? p : world.getLocalPoint(body, p))
  if (cmd.k === 'pin') {
    const anchor = clampPoint(cmd.x, cmd.y)
    const id = world.createJoint({ type: 'revolute', bodyA, bodyB: cmd.b, anchor })
    const la = local(bodyA, anchor)
    const lb = local(cmd.b, anchor)
    room.jointAdded({
      id,
      kind: 'pin',
      a: cmd.a,
      b: cmd.b,
      ax: la.x,
      ay: la.y,
      bx: lb.x,
      by: lb.y,
      length: 0,
    })
    return null
  }
  const anchorA = clampPoint(cmd.ax, cmd.ay)
  const anchorB = clampPoint(cmd.bx, cmd.by)
  const length = Math.sqrt((anchorB.x - anchorA.x) ** 2 + (anchorB.y - anchorA.y) ** 2)
  if (length > MAX_ROPE_LENGTH) return `rope longer than ${MAX_ROPE_LENGTH} m`
  const id = world.createJoint({
    type: 'distance',
    bodyA,
    bodyB: cmd.b,
    anchorA,
    anchorB,
    length,
    minLength: 0,
    maxLength: length,
  })
  const la = local(bodyA, anchorA)
  const lb = local(cmd.b, anchorB)
  room.jointAdded({ id, kind: 'rope', a: cmd.a, b: cmd.b, ax: la.x, ay: la.y, bx: lb.x, by: lb.y, length })
  return null
}
