/*
 * The online lab's contact data. The protocol streams poses, not contact impulses, and the client
 * cannot replay the room (it never sees the input stream), so the honest local answer is a probe:
 * rebuild the selected body and its neighbourhood at their latest snapshot poses in a small
 * private world, let it settle for half a second, and read the engine's own contact impulses.
 * What supports the body (bodies whose centre is lower along gravity, and the room's static
 * bodies) is held fixed; what rests on it (bodies at its height or above, within LOAD_RADIUS) stays
 * dynamic, so their weight reaches it. For a body at rest (a box on a ramp, a block in a tower)
 * this is the same static problem the server solves, so the numbers agree; for a body in motion
 * it shows the support forces it would feel if it stopped there, and the lab panel says so.
 * Bodies use the room's defaults (density 1, friction 0.6), which every spawned body and every
 * shipped scene use.
 */
import { type ContactInfo, createWorld } from '../engine/index.ts'
import { fromWireShape } from '../shared/index.ts'
import { wireShapeMass } from './offline-sandbox.ts'
import { shapeRadius } from './picking.ts'
import type { LabData, ViewBody } from './sandbox.ts'

/** Steps the probe runs before reading contacts: half a second, enough for warm starting to settle. */
const PROBE_STEPS = 30
/** Extra distance (m) within which a supporting neighbour is included. */
const MARGIN = 0.2
/** Distance (m) within which bodies at the body's height or above are included as load. */
const LOAD_RADIUS = 40
/** Most bodies a probe simulates. */
const MAX_BODIES = 120

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
  const g = Math.hypot(gravity.x, gravity.y)
  const down = g > 0 ? { x: gravity.x / g, y: gravity.y / g } : { x: 0, y: -1 }
  const chosen: Array<{ body: ViewBody; dynamic: boolean; distance: number }> = []
  for (const b of bodies) {
    if (b.id === target.id) continue
    const r = shapeRadius(b.shape)
    const dx = b.x - target.x
    const dy = b.y - target.y
    const distance = Math.sqrt(dx * dx + dy * dy)
    const below = dx * down.x + dy * down.y > 0.05
    if (b.kind === 0 || below) {
      if (distance <= r + reach) chosen.push({ body: b, dynamic: false, distance })
    } else if (distance <= LOAD_RADIUS + r) chosen.push({ body: b, dynamic: true, distance })
  }
  chosen.sort((a, b) => a.distance - b.distance)
  for (const c of chosen.slice(0, MAX_BODIES)) realIds.set(make(c.body, c.dynamic), c.body.id)
  for (let i = 0; i < PROBE_STEPS; i++) world.step()
  const contacts: ContactInfo[] = world.contacts().map((c) => ({
    ...c,
    bodyA: realIds.get(c.bodyA) ?? 0,
    bodyB: realIds.get(c.bodyB) ?? 0,
  }))
  return { contacts, mass: wireShapeMass(target.shape), gravity, source: 'probe' }
}
