/*
 * What a page reads from a room simulation that runs in the page (the lockstep and predicting
 * sandboxes, the offline sandbox, the replay player): the user joints placed on the drawn bodies
 * with their last reaction forces, the lab's free-body data of one body, and the room's slow
 * motion and control lock. Each mode draws its bodies its own way (straight from the world, or
 * between the last two steps); these read the rest the same way in every mode.
 */
import type { ContactInfo, Vec2 } from '../../engine/index.ts'
import type { RoomSimulation } from '../../shared/index.ts'
import { labFromWorld, viewJoints } from '../draw/index.ts'
import type { LabData, RoomControl, ViewBody, ViewJoint } from './sandbox.ts'

/** The simulation's user joints on the drawn bodies (`bodyOf`), each with its force of the last step. */
export function simulationJoints(
  sim: RoomSimulation,
  bodyOf: (id: number) => ViewBody | undefined,
): ViewJoint[] {
  const forces = new Map<number, Vec2>()
  for (const info of sim.world.joints()) forces.set(info.id, info.force)
  return viewJoints(sim.userJoints.values(), bodyOf, (id) => forces.get(id) ?? null)
}

/**
 * The lab's data for body `bodyId` from the simulation's world and its touching `contacts`; null
 * when the body is gone or not dynamic (only a dynamic body has a free-body diagram).
 */
export function simulationLab(
  sim: RoomSimulation,
  bodyId: number,
  contacts: readonly ContactInfo[],
): LabData | null {
  const world = sim.world
  if (!world.hasBody(bodyId) || world.getBodyType(bodyId) !== 'dynamic') return null
  return labFromWorld(world, bodyId, contacts, (id) => sim.userJoints.get(id)?.kind)
}

/** The room's slow motion, creator and control lock as the simulation has them, for player `self`. */
export function simulationControl(sim: RoomSimulation | null, self: number): RoomControl {
  return {
    slow: sim?.slowMotion ?? 1,
    creator: sim?.creator ?? 0,
    locked: sim?.controlsLocked ?? false,
    self,
  }
}
