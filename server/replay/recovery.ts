/*
 * Crash recovery: rebuild a room from a log that has no clean-close record. The durable part of a
 * log ends at a checkpoint (every recorder flush ends with a hash record), so the room is rebuilt
 * from the last keyframe before that checkpoint plus the records after it, up to the checkpoint
 * and no further; every hash on the way must match. A torn or corrupt tail after the checkpoint is
 * cut off (the file is truncated there) and recording continues in the same file.
 */
import { truncate } from 'node:fs/promises'
import { join } from 'node:path'
import { inflateSync } from 'node:zlib'
import { hex, type KeyframeRecord, type ReplayRecord, ReplayRunner } from '../../shared/index.ts'
import { findServerGame } from '../games/index.ts'
import { scanLog } from './replay-files.ts'

/** A room rebuilt from its log. */
export interface RecoveredRoom {
  room: string
  /** The log to continue, truncated to `size` bytes (its last checkpoint). */
  name: string
  size: number
  runner: ReplayRunner
  /** Room tick and world hash of the checkpoint reached. */
  tick: number
  hash: number
  /** Largest player id in the log. */
  maxPlayerId: number
}

/** Node's inflate for stored worlds. */
export const inflateNode = (bytes: Uint8Array): Uint8Array => new Uint8Array(inflateSync(bytes))

/**
 * Rebuild the room of one log up to its last checkpoint; throws an Error naming the problem when
 * the log cannot be recovered (no header, versions, a hash that does not match). Does not modify
 * the file; call truncateToCheckpoint before appending.
 */
export async function recoverLog(dir: string, name: string): Promise<RecoveredRoom> {
  /** Keyframes from the last whole one (a delta chain decodes from there). */
  let chain: KeyframeRecord[] = []
  let since: ReplayRecord[] = []
  let pending: ReplayRecord[] = []
  let maxPlayerId = 0
  let checkpointHash: number | null = null
  const scan = await scanLog(join(dir, name), (r) => {
    if (r.type === 'join' && r.player > maxPlayerId) maxPlayerId = r.player
    if (r.type === 'header') return
    if (r.type === 'keyframe') {
      chain = r.z === 2 ? [...chain, r] : [r]
      since = []
      pending = []
      checkpointHash = null
      return
    }
    pending.push(r)
    if (r.type === 'hash') {
      since.push(...pending)
      pending = []
      checkpointHash = r.hash
    }
  })
  if (!scan.header || !scan.preamble) throw new Error(`${name}: ${scan.status.reason || 'no header'}`)
  if (scan.status.closed) throw new Error(`${name} was closed cleanly; nothing to recover`)
  const runner = await ReplayRunner.start(scan.preamble, scan.header, {
    inflate: inflateNode,
    games: findServerGame,
  })
  if (chain.length > 0) await runner.restore(chain[0].z === 2 ? [scan.header, ...chain] : chain)
  for (const r of since) await runner.apply(r)
  if (runner.divergence)
    throw new Error(`${name}: replay diverges at tick ${runner.divergence.tick}: ${runner.divergence.reason}`)
  const hash = runner.sim.hash()
  if (checkpointHash !== null && hash !== checkpointHash)
    throw new Error(`${name}: rebuilt hash ${hex(hash)} differs from the checkpoint's ${hex(checkpointHash)}`)
  return {
    room: scan.header.room,
    name,
    size: scan.checkpointBytes,
    runner,
    tick: runner.sim.tick,
    hash,
    maxPlayerId,
  }
}

/** Cut a log back to its last checkpoint (drops a torn or corrupt tail). */
export async function truncateToCheckpoint(dir: string, recovered: RecoveredRoom): Promise<void> {
  await truncate(join(dir, recovered.name), recovered.size)
}
