/*
 * The replay tool's engine in Node: shared/replay/replay-headless.ts with Node's zlib for deflated worlds
 * (the replay CLI, recovery tests and benchmarks use this; a browser page uses the shared module
 * with DecompressionStream). Games come from the server's catalogue: the built-in games and those
 * loaded with --games DIR (the replay CLI's --games loads them as the server does).
 */
import { type ReplayOptions, type ReplayReport, ReplayToolError, replayBytes } from '../../shared/index.ts'
import { findServerGame } from '../games/index.ts'
import { inflateNode } from './recovery.ts'

export {
  type ReplayOptions,
  type ReplayReport,
  ReplayToolError,
} from '../../shared/index.ts'

/** A log whose game is neither built in nor loaded (the CLI says to load it with --games DIR). */
export class UnknownGameError extends ReplayToolError {
  constructor(readonly game: string) {
    super(`the log was recorded with game "${game}", which is neither built in nor loaded`)
  }
}

/** Replay a log held in memory (see shared/replay/replay-headless.ts). */
export async function replayLog(bytes: Uint8Array, options: ReplayOptions = {}): Promise<ReplayReport> {
  let missing: string | null = null
  const games = (name: string) => {
    const game = findServerGame(name)
    if (!game) missing = name
    return game
  }
  try {
    return await replayBytes(bytes, inflateNode, games, options)
  } catch (error) {
    if (missing !== null) throw new UnknownGameError(missing)
    throw error
  }
}
