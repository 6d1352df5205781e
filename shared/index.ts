/*
 * The wire protocol's public entry: everything the server, the browser client and the bots use.
 * See PROTOCOL.md for the byte-level description.
 */
export { ByteReader, ByteWriter, varintSize, zigzagSize } from './byte-io.ts'
export { ClientMirror, type MirrorBody, type MirrorCursor } from './client-mirror.ts'
export {
  type DecodeResult,
  decodeClientMessage,
  decodeServerMessage,
  decodeValue,
  encodeMessage,
  encodeValue,
} from './codec.ts'
export * from './constants.ts'
export {
  buildSceneJoints,
  defaultCollide,
  distanceKind,
  jointForceOn,
  type WireJointDef,
  wireJoint,
} from './joint-wire.ts'
export type * from './messages.ts'
export {
  addAngle,
  angleDelta,
  dequantizeAngle,
  dequantizePosition,
  MAX_ANGLE_ERROR,
  MAX_POSITION_ERROR,
  quantizeAngle,
  quantizePosition,
} from './quantize.ts'
export { FRAME_AWAKE, FRAME_PRESENT, QuantizedFrame } from './quantized-frame.ts'
export { RoomSimulation, strayBodies } from './room-simulation.ts'
export { fromWireShape, toWireShape, wireShapeVertices } from './shape-wire.ts'
export { readUpdates, UPDATE_ABSOLUTE, UPDATE_AWAKE, updateSize, writeUpdates } from './snapshot-codec.ts'
export { type EncodeStats, SnapshotEncoder } from './snapshot-encoder.ts'
export { type AppliedSnapshot, SnapshotHistory } from './snapshot-history.ts'
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
export { validateClientMessage, validateServerMessage } from './validate.ts'
export {
  addUserJoint,
  type CreatedGrab,
  clampToWorld,
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
  spawnBody,
  type WorldResult,
} from './world-commands.ts'
