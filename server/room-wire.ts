/*
 * Turning a room's world into wire data: the quantized frame of moving bodies (built once per
 * snapshot tick and shared by every client), body descriptions with shapes for events and full
 * states. The frame and the full state quantize the same world values with the same functions, so
 * a client's first baseline (built from the full state) equals the server's.
 */
import type { World } from '../engine/index.ts'
import {
  type FullState,
  type QuantizedFrame,
  quantizeAngle,
  quantizePosition,
  toWireShape,
  type WireBody,
  type WireBodyType,
  type WireJoint,
} from '../shared/index.ts'

const KIND: Record<string, WireBodyType> = { static: 0, kinematic: 1, dynamic: 2 }
const scratch = { x: 0, y: 0 }

/** Fill `frame` with the quantized poses of every non-static body, ascending ids. */
export function fillFrame(world: World, frame: QuantizedFrame): void {
  frame.clear()
  for (const id of world.bodyIds()) {
    if (world.getBodyType(id) === 'static') continue
    const p = world.getPosition(id, scratch)
    frame.put(
      id,
      quantizePosition(p.x),
      quantizePosition(p.y),
      quantizeAngle(world.getAngle(id)),
      world.isAwake(id),
    )
  }
}

/** A body as it travels in events and full states. */
export function wireBody(world: World, id: number): WireBody {
  const p = world.getPosition(id, scratch)
  return {
    id,
    kind: KIND[world.getBodyType(id)],
    shape: toWireShape(world.getShape(id)),
    x: quantizePosition(p.x),
    y: quantizePosition(p.y),
    a: quantizeAngle(world.getAngle(id)),
    awake: world.isAwake(id) ? 1 : 0,
  }
}

/** The whole room state at `tick`. */
export function fullState(
  world: World,
  tick: number,
  scene: string,
  paused: boolean,
  joints: Iterable<WireJoint>,
): FullState {
  const g = world.getGravity()
  return {
    tick,
    scene,
    paused,
    gravity: [g.x, g.y],
    bodies: world.bodyIds().map((id) => wireBody(world, id)),
    joints: [...joints],
  }
}
