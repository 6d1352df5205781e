/*
 * The wire (PROTOCOL.md beside this file is the byte-level contract): message types, the
 * MessagePack codec and exact validation, quantization, quantized frames and the snapshot codec
 * with its encoder and history, shapes and joints as they travel, and a pure zlib inflater.
 */
export { ByteReader, ByteWriter, varintSize, zigzagSize } from './byte-io.ts'
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
  WIRE_JOINT_KINDS,
  type WireJointDef,
  wireJoint,
  withJointSettings,
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
export {
  fromWireShape,
  fromWireShapeDef,
  spawnShapeDefs,
  toWireShape,
  wireShapeOf,
  wireShapesOf,
  wireShapeVertices,
} from './shape-wire.ts'
export { readUpdates, UPDATE_ABSOLUTE, UPDATE_AWAKE, updateSize, writeUpdates } from './snapshot-codec.ts'
export { type EncodeStats, SnapshotEncoder } from './snapshot-encoder.ts'
export { type AppliedSnapshot, SnapshotHistory } from './snapshot-history.ts'
export { validateClientMessage, validateServerMessage } from './validate.ts'
export { InflateError, inflateZlibSync } from './zlib-inflate.ts'
