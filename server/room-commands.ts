/*
 * Input commands applied to a room's world. applyCommand is the single entry point: every command
 * a player's input causes goes through it at a tick, which is what a recorder logs. Inputs are
 * trusted only after validation (shared/validate.ts); what a command does to the world, with its
 * clamps and caps (world bounds, spawn speed, grab force, rope length), is shared/world-commands.ts,
 * which the offline sandbox calls too. This file keeps what is the room's: sessions and their
 * cursors and grabs, the body and joint limits, events, the scene-load rate limit and inspect.
 * A refused command returns a reason; nothing here throws to the caller.
 */
import { SCENES } from '../engine/index.ts'
import {
  addUserJoint,
  type Command,
  grabBody,
  grabRefusal,
  isMovable,
  jointRefusal,
  moveGrab,
  removeJoint,
  type SpawnCommand,
  setWorldGravity,
  spawnBody,
} from '../shared/index.ts'
import type { ClientSession } from './client-session.ts'
import type { Room } from './room.ts'
import { wireBody } from './room-wire.ts'

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
      const p = moveGrab(world, session.grab?.joint ?? null, cmd.x, cmd.y)
      session.cursorX = p.x
      session.cursorY = p.y
      session.cursorDirty = true
      return null
    }
    case 'release':
      release(room, session)
      return null
    case 'delete':
      if (!isMovable(world, cmd.body)) return `body ${cmd.body} does not exist or is static`
      room.removeBody(cmd.body)
      return null
    case 'pin':
    case 'rope':
      return joint(room, cmd)
    case 'unjoint':
      if (!room.userJoints.has(cmd.joint)) return `joint ${cmd.joint} is not a pin or rope in this room`
      removeJoint(world, cmd.joint)
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
      setWorldGravity(world, cmd.x, cmd.y)
      room.markRoomChanged()
      return null
  }
}

function inspect(room: Room, session: ClientSession, body: number): string | null {
  if (body !== 0 && !isMovable(room.world, body)) return `body ${body} does not exist or is static`
  session.inspect = body
  return null
}

function spawn(room: Room, cmd: SpawnCommand): string | null {
  if (room.world.bodyCount >= room.config.maxBodies) return `body limit reached (${room.config.maxBodies})`
  const spawned = spawnBody(room.world, cmd)
  if (!spawned.ok) return spawned.reason
  room.bodyAdded(wireBody(room.world, spawned.value))
  return null
}

function grab(room: Room, session: ClientSession, body: number, lx: number, ly: number): string | null {
  const refusal = grabRefusal(room.world, body)
  if (refusal) return refusal
  release(room, session)
  const grabbed = grabBody(room.world, body, lx, ly)
  if (!grabbed.ok) return grabbed.reason
  const { joint, target } = grabbed.value
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
  removeJoint(room.world, g.joint)
  const n = (room.grabCounts.get(g.body) ?? 1) - 1
  if (n > 0) room.grabCounts.set(g.body, n)
  else room.grabCounts.delete(g.body)
  session.grab = null
  session.cursorDirty = true
}

function joint(room: Room, cmd: Extract<Command, { k: 'pin' | 'rope' }>): string | null {
  const refusal = jointRefusal(room.world, cmd)
  if (refusal) return refusal
  if (room.userJoints.size >= room.config.maxBodies) return 'joint limit reached'
  const added = addUserJoint(room.world, cmd)
  if (!added.ok) return added.reason
  room.jointAdded(added.value)
  return null
}
