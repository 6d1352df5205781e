/*
 * Turning a room's world into wire data: the quantized frame of moving bodies (built once per
 * snapshot tick and shared by every client), body descriptions with shapes for events and full
 * states, and the contacts of inspected bodies (one world.contacts() per snapshot tick, and only
 * when someone inspects, shared by every inspector; one encoded message per inspected body). The frame and the full state quantize the same world values with the same functions, so
 * a client's first baseline (built from the full state) equals the server's.
 */
import {
  type ContactInfo,
  POSE_ANGLE,
  POSE_AWAKE,
  POSE_ID,
  POSE_STATIC,
  POSE_STRIDE,
  POSE_TYPE,
  POSE_X,
  POSE_Y,
  type World,
} from '../../engine/index.ts'
import {
  type ContactsMessage,
  encodeMessage,
  type FullState,
  jointForceOn,
  MAX_INSPECT_CONTACTS,
  type QuantizedFrame,
  quantizeAngle,
  quantizePosition,
  type WireBody,
  type WireBodyType,
  type WireJoint,
  type WireJointForce,
  type WireJointForceKind,
  wireShapesOf,
} from '../../shared/index.ts'

const KIND: Record<string, WireBodyType> = { static: 0, kinematic: 1, dynamic: 2 }
const scratch = { x: 0, y: 0 }

/** Scratch for world.writePoses, grown as worlds grow (one per thread: rooms tick one at a time). */
let poses = new Float64Array(128 * POSE_STRIDE)

/** Fill `frame` with the quantized poses of every non-static body, ascending ids; allocates nothing once warm. */
export function fillFrame(world: World, frame: QuantizedFrame): void {
  if (poses.length < world.bodyCount * POSE_STRIDE)
    poses = new Float64Array(2 * world.bodyCount * POSE_STRIDE)
  const n = world.writePoses(poses)
  frame.clear()
  for (let i = 0, o = 0; i < n; i++, o += POSE_STRIDE) {
    if (poses[o + POSE_TYPE] === POSE_STATIC) continue
    frame.put(
      poses[o + POSE_ID],
      quantizePosition(poses[o + POSE_X]),
      quantizePosition(poses[o + POSE_Y]),
      quantizeAngle(poses[o + POSE_ANGLE]),
      poses[o + POSE_AWAKE] !== 0,
    )
  }
}

/** A body as it travels in events and full states, with its colour from `colors` when it has one. */
export function wireBody(world: World, id: number, colors?: ReadonlyMap<number, number>): WireBody {
  const p = world.getPosition(id, scratch)
  const body: WireBody = {
    id,
    kind: KIND[world.getBodyType(id)],
    shapes: wireShapesOf(world, id),
    x: quantizePosition(p.x),
    y: quantizePosition(p.y),
    a: quantizeAngle(world.getAngle(id)),
    awake: world.isAwake(id) ? 1 : 0,
  }
  const color = colors?.get(id)
  if (color !== undefined) body.color = color
  return body
}

/**
 * Bring a body description up to the world's current pose (quantized x, y, angle and awake), so
 * an `events` message shows each new body at the tick it carries, after that tick's step.
 */
export function refreshPose(world: World, body: WireBody): void {
  if (!world.hasBody(body.id)) return
  const p = world.getPosition(body.id, scratch)
  body.x = quantizePosition(p.x)
  body.y = quantizePosition(p.y)
  body.a = quantizeAngle(world.getAngle(body.id))
  body.awake = world.isAwake(body.id) ? 1 : 0
}

/** The whole room state at `tick`. */
export function fullState(
  world: World,
  tick: number,
  scene: string,
  paused: boolean,
  joints: Iterable<WireJoint>,
  colors?: ReadonlyMap<number, number>,
  control: { slow: number; creator: number; locked: boolean } = { slow: 1, creator: 0, locked: false },
): FullState {
  const g = world.getGravity()
  return {
    tick,
    scene,
    paused,
    gravity: [g.x, g.y],
    slow: control.slow,
    creator: control.creator,
    locked: control.locked,
    bodies: world.bodyIds().map((id) => wireBody(world, id, colors)),
    joints: [...joints],
  }
}

/** Total normal impulse of a contact (N s). */
const normalImpulse = (c: ContactInfo): number => c.points.reduce((sum, p) => sum + p.normalImpulse, 0)

const forceSize = (f: WireJointForce): number => Math.abs(f.fx) + Math.abs(f.fy)

/**
 * The `contacts` message for `body` from its touching contacts (the largest by normal impulse)
 * and the joints acting on it (the largest forces), with its velocity and inertia for the lab.
 */
export function contactsMessage(
  world: World,
  tick: number,
  body: number,
  touching: ContactInfo[],
  joints: WireJointForce[],
): ContactsMessage {
  const kept =
    touching.length > MAX_INSPECT_CONTACTS
      ? [...touching].sort((a, b) => normalImpulse(b) - normalImpulse(a)).slice(0, MAX_INSPECT_CONTACTS)
      : touching
  const pulls =
    joints.length > MAX_INSPECT_CONTACTS
      ? [...joints].sort((a, b) => forceSize(b) - forceSize(a)).slice(0, MAX_INSPECT_CONTACTS)
      : joints
  const v = world.getLinearVelocity(body, scratch)
  return {
    t: 'contacts',
    tick,
    body,
    mass: world.getMass(body),
    total: touching.length,
    contacts: kept.map((c) => ({
      a: c.bodyA,
      b: c.bodyB,
      nx: c.normal.x,
      ny: c.normal.y,
      points: c.points.map((p) => ({ x: p.point.x, y: p.point.y, n: p.normalImpulse, t: p.tangentImpulse })),
    })),
    inertia: world.getInertia(body),
    vx: v.x,
    vy: v.y,
    w: world.getAngularVelocity(body),
    joints: pulls,
  }
}

/**
 * Encoded `contacts` messages for the bodies in `inspected` (body id -> bytes), from one
 * world.contacts() and one world.joints() call; empty without reading either when nobody inspects.
 * `wireJoints` names the kind of every joint that travels; the rest (mouse joints) are grabs.
 */
export function encodeInspections(
  world: World,
  tick: number,
  inspected: ReadonlySet<number>,
  wireJoints: ReadonlyMap<number, WireJoint>,
): Map<number, Uint8Array> {
  const out = new Map<number, Uint8Array>()
  if (inspected.size === 0) return out
  const touching = new Map<number, ContactInfo[]>()
  const pulls = new Map<number, WireJointForce[]>()
  for (const id of inspected) {
    if (!world.hasBody(id)) continue
    touching.set(id, [])
    pulls.set(id, [])
  }
  for (const c of world.contacts()) {
    touching.get(c.bodyA)?.push(c)
    touching.get(c.bodyB)?.push(c)
  }
  for (const j of world.joints()) {
    const kind: WireJointForceKind = j.type === 'mouse' ? 'grab' : (wireJoints.get(j.id)?.kind ?? 'pin')
    if (j.bodyA !== null) pulls.get(j.bodyA)?.push(jointForceOn(j.bodyA, j, kind))
    pulls.get(j.bodyB)?.push(jointForceOn(j.bodyB, j, kind))
  }
  for (const [id, list] of touching) {
    out.set(id, encodeMessage(contactsMessage(world, tick, id, list, pulls.get(id) ?? [])))
  }
  return out
}
