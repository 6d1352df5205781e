/*
 * Replay logs (docs/replay-format.md is the byte-level contract): the log format and its records,
 * the streaming reader, byte deltas between keyframes, CRC-32, the runner that replays a log
 * through a RoomSimulation, and headless verification.
 */
export { encodeByteDelta } from './byte-delta.ts'
export { type ReplayOptions, type ReplayReport, ReplayToolError, replayBytes } from './replay-headless.ts'
export {
  type BlockableRecord,
  encodeBlockEntries,
  encodePreamble,
  encodeRecord,
  frameBlock,
  MAX_BLOCK_ENTRIES,
  MAX_BLOCK_TICKS,
  PREAMBLE_BYTES,
  type Preamble,
  REPLAY_FORMAT_VERSION,
  REPLAY_MAGIC,
  type ReplayRecord,
} from './replay-log.ts'
export { type ReadStatus, ReplayLogReader } from './replay-log-reader.ts'
export {
  type Divergence,
  deltaChain,
  type HeaderRecord,
  hex,
  type Inflate,
  incompatibility,
  type KeyframeRecord,
  ReplayRunner,
  type RunnerSnapshot,
} from './replay-runner.ts'
