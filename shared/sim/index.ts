/*
 * The deterministic room simulation and what follows a room on a client: RoomSimulation, the
 * world commands, the lockstep tick stream and sync payload, and the DOM-free followers (the
 * snapshot mirror, the lockstep client with its playout clock, and the predicting client).
 */
export { ClientMirror, type MirrorBody, type MirrorCursor } from './client-mirror.ts'
export {
  BUILTIN_KINDS,
  type BuiltinKind,
  colorsHash,
  copyPlainData,
  type GameCatalog,
  type GameCommand,
  type GameContext,
  hashPlainData,
  NO_EVENTS,
  type PlainData,
  type RoomLimits,
  roomRules,
  type SimCommand,
  type SimCommandDef,
  type SimGame,
  type StepEvents,
  simulationHash,
  stepEvents,
} from './game.ts'
export {
  checkSavedHistory,
  type GameHistory,
  type HistoryBody,
  type HistoryEntry,
  type HistoryItems,
  type HistoryJoint,
  type HistoryList,
  MAX_HISTORY,
  NO_ITEMS,
  type SavedHistory,
} from './history.ts'
export { LockstepClient } from './lockstep-client.ts'
export { PredictClient } from './predict-client.ts'
export {
  DEFAULT_SEED,
  RoomSimulation,
  type SimulationListener,
  type SimulationObserver,
  type SimulationOptions,
  type SimulationState,
  strayBodies,
  worldFromBlueprint,
} from './room-simulation.ts'
export {
  cloneSimulation,
  encodeSyncPayload,
  inflate,
  type RestoreOptions,
  type RestoreResult,
  restoreSyncPayload,
  type SyncPayload,
} from './sync-payload.ts'
export {
  decodeEntries,
  ENTRY_CODES,
  type EntriesResult,
  encodeEntry,
  entryArguments,
  type StreamAction,
  type StreamEntry,
} from './tick-stream.ts'
export {
  addUserJoint,
  anchorRefusal,
  type CreatedGrab,
  clampToWorld,
  createUserJoint,
  deleteBody,
  GRAB_FORCE_PER_KG,
  grabBody,
  grabRefusal,
  isMovable,
  jointRefusal,
  MAX_GRAB_FORCE,
  moveGrab,
  removeJoint,
  setWorldGravity,
  shapeReach,
  spawnBody,
  type WorldResult,
} from './world-commands.ts'
