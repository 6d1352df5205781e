/*
 * The online lab's contact data. The protocol streams poses, not contact impulses, and the client
 * cannot replay the room (it never sees the input stream), so the honest local answer is a probe:
 * rebuild the selected body and every body that could touch it at their latest snapshot poses in a
 * small private world (the neighbours held static), let the selected body settle for a short
 * while, and read the engine's own contact impulses. For a body at rest (a box on a ramp, a block
 * in a stack's top row) this is the same static problem the server solves, so the numbers agree;
 * for a body in motion it shows the support forces it would feel if it stopped there, and the lab
 * panel says so. Bodies use the room's defaults (density 1, friction 0.6), which every spawned
 * body and every shipped scene use.
 */
import { type ContactInfo, createWorld } from '../engine/index.ts'
import { fromWireShape } from '../shared/index.ts'
import { wireShapeMass } from './offline-sandbox.ts'
import { shapeRadius } from './picking.ts'
import type { LabData, ViewBody } from './sandbox.ts'

/** Steps the probe runs before reading contacts: half a second, enough for warm starting to settle. */
const PROBE_STEPS = 30
/** Extra distance (m) within which a neighbour is included. */
const MARGIN = 0.2

/** Contact data for `target` by local re-solve among `bodies` (see the file comment). */
export function probeContacts(
  target: ViewBody,
  bodies: readonly ViewBody[],
  gravity: { x: number; y: number },
): LabData {
  const world = createWorld({ gravity, enableSleep: false })
  const reach = shapeRadius(target.shape) + MARGIN
  const make = (b: ViewBody, dynamic: boolean): number =>
    world.createBody({
      type: dynamic ? 'dynamic' : 'static',
      shape: fromWireShape(b.shape),
      position: { x: b.x, y: b.y },
      angle: b.angle,
      friction: 0.6,
    })
  const probeId = make(target, true)
  const realIds = new Map<number, number>([[probeId, target.id]])
  for (const b of bodies) {
    if (b.id === target.id) continue
    const r = shapeRadius(b.shape) + reach
    const dx = b.x - target.x
    const dy = b.y - target.y
    if (dx * dx + dy * dy > r * r) continue
    realIds.set(make(b, false), b.id)
  }
  for (let i = 0; i < PROBE_STEPS; i++) world.step()
  const contacts: ContactInfo[] = world.contacts().map((c) => ({
    ...c,
    bodyA: realIds.get(c.bodyA) ?? 0,
    bodyB: realIds.get(c.bodyB) ?? 0,
  }))
  return { contacts, mass: wireShapeMass(target.shape), gravity, source: 'probe' }
}
