/*
 * Where the physics runs for the page: the Sandbox seam and its modes: online (a server room
 * mirrored from snapshots), lockstep and predict (the room simulated in the page from the tick
 * stream), offline (the room simulated in the page, without a server); what those read from a
 * simulation in the page (simulation-view.ts); plus the smoothing of predicted corrections.
 */
export { findClientGame, findClientGameClient, loadGameModule } from './game-modules.ts'
export { LockstepSandbox } from './lockstep-sandbox.ts'
export { OfflineSandbox } from './offline-sandbox.ts'
export { OnlineSandbox } from './online-sandbox.ts'
export type {
  LabContact,
  LabData,
  LabJointForce,
  PersonRow,
  Sandbox,
  SandboxStats,
  SandboxStatus,
  ViewBody,
  ViewCursor,
  ViewJoint,
} from './sandbox.ts'
export { simulationControl, simulationJoints, simulationLab } from './simulation-view.ts'
