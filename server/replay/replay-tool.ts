/*
 * The replay tool's engine in Node: shared/replay/replay-headless.ts with Node's zlib for deflated worlds
 * (the replay CLI, recovery tests and benchmarks use this; a browser page uses the shared module
 * with DecompressionStream).
 */
import { findGame } from '../../games/index.ts'
import { type ReplayOptions, type ReplayReport, replayBytes } from '../../shared/index.ts'
import { inflateNode } from './recovery.ts'

export {
  type ReplayOptions,
  type ReplayReport,
  ReplayToolError,
} from '../../shared/index.ts'

/** Replay a log held in memory (see shared/replay/replay-headless.ts). */
export function replayLog(bytes: Uint8Array, options: ReplayOptions = {}): Promise<ReplayReport> {
  return replayBytes(bytes, inflateNode, findGame, options)
}
