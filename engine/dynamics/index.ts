/*
 * Dynamics: bodies, their shapes (body-shape.ts) and their solver state, contacts and their
 * records, the soft-step contact solver with its extra sweeps for pinched and slender bodies and
 * tall columns, islands and sleep, and the continuous stage. Depends on collision/ and the root files.
 */

export { Body, DYNAMIC, STATIC, updateMassData } from './body.ts'
export { BodyShape, shouldFilterCollide } from './body-shape.ts'
export {
  DPX,
  DPY,
  DQC,
  DQS,
  integratePositions,
  integrateVelocities,
  limitBodyVelocity,
  loadSolverStates,
  STATE_STRIDE,
  stateOffset,
  stateToBody,
  VX,
  VY,
  W,
} from './body-state.ts'
export {
  CONTACT_EVENTS,
  CONTACT_POINT_FIELDS,
  Contact,
  clearContact,
  HIT_EVENTS,
  measureApproach,
  mixMaterials,
  updateContact,
} from './contact.ts'
export {
  APPROACH,
  ContactStore,
  HIT_X,
  HIT_Y,
  hitOffset,
  NORMAL_X,
  NORMAL_Y,
  POINT_0,
  POINT_FIELDS,
  ROLLING_IMPULSE,
  TOTAL_NORMAL,
} from './contact-record.ts'
export {
  applyRestitution,
  ContactConstraints,
  prepareContacts,
  solveContacts,
  storeImpulses,
  warmStartContacts,
} from './contact-solver.ts'
export { ContinuousSolver } from './continuous.ts'
export { planExtraSweeps } from './extra-sweeps.ts'
export { IslandBuilder } from './island.ts'
export { Softness, softnessInput } from './softness.ts'
export { StepContext } from './step-context.ts'
