/*
 * Dynamics: bodies and their solver state, contacts and their records, the soft-step contact
 * solver with its extra sweeps for pinched bodies and tall columns, islands and sleep, and the
 * continuous stage. Depends on collision/ and the root files.
 */

export { Body, DYNAMIC, STATIC, updateMassData } from './body.ts'
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
export { CONTACT_POINT_FIELDS, Contact, clearContact, updateContact } from './contact.ts'
export { ContactStore, NORMAL_X, POINT_0, POINT_FIELDS } from './contact-record.ts'
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
