/*
 * Replaying a whole log headless (the replay CLI through server/replay/replay-tool.ts, recovery tests,
 * benchmarks, and the same code in a browser page for the Node-versus-Chromium check): read it through the
 * streaming reader, start from the header, apply every record at its tick, optionally up to a
 * tick only, and report what was replayed: ticks, players, commands, steps per second, the hashes
 * checked and the first divergence. A file that is not a readable log (bad magic, wrong version,
 * no header) is a ReplayToolError with one line naming the problem; a torn or corrupt tail is
 * reported (the intact prefix is replayed).
 */
import type { GameCatalog } from '../sim/index.ts'
import { type ReadStatus, ReplayLogReader } from './replay-log-reader.ts'
import { type Divergence, type HeaderRecord, type Inflate, ReplayRunner } from './replay-runner.ts'

/** A log that cannot be replayed at all; the message is one line for the user. */
export class ReplayToolError extends Error {}

/** What to do. */
export interface ReplayOptions {
  /** Also check every keyframe against the replayed state. */
  verify?: boolean
  /** Stop at this room tick. */
  to?: number
  /** Also collect the world hash every N ticks. */
  hashEvery?: number
  /** Called every `progressEvery` room ticks replayed (counted from the header's tick) with the tick reached and the log's last. */
  onProgress?: (tick: number, lastTick: number) => void
  progressEvery?: number
}

/** What a replay found. */
export interface ReplayReport {
  room: string
  scene: string
  start: string
  firstTick: number
  lastTick: number
  ticks: number
  seconds: number
  players: number
  commands: number
  steps: number
  hashesChecked: number
  keyframesChecked: number
  divergence: Divergence | null
  /** How reading ended: clean close, or where a torn or corrupt tail was cut. */
  read: ReadStatus
  replaySeconds: number
  stepsPerSecond: number
  ticksPerSecond: number
  finalHash: number
  hashes: Array<{ tick: number; hash: number }>
}

/** Replay a log held in memory with the platform's `inflate` (see the file comment). */
export async function replayBytes(
  bytes: Uint8Array,
  inflate: Inflate,
  games: GameCatalog,
  options: ReplayOptions = {},
): Promise<ReplayReport> {
  const reader = new ReplayLogReader()
  const records = reader.push(bytes)
  const read = reader.finish()
  if (read.state === 'invalid') throw new ReplayToolError(read.reason)
  const header = records[0] as HeaderRecord | undefined
  if (!header || !reader.preamble) throw new ReplayToolError(read.reason || 'the log has no header record')
  const began = performance.now()
  let runner: ReplayRunner
  try {
    runner = await ReplayRunner.start(reader.preamble, header, {
      inflate,
      games,
      verify: options.verify,
    })
  } catch (error) {
    throw new ReplayToolError(`cannot start from the header: ${(error as Error).message}`)
  }
  const hashes: ReplayReport['hashes'] = []
  const every = options.hashEvery ?? 0
  const progressEvery = options.progressEvery ?? 0
  const onProgress = options.onProgress
  const end = Math.min(options.to ?? Number.POSITIVE_INFINITY, read.lastTick)
  if (every > 0 || (progressEvery > 0 && onProgress)) {
    runner.onTick = (sim) => {
      if (every > 0 && sim.tick % every === 0) hashes.push({ tick: sim.tick, hash: sim.hash() })
      if (progressEvery > 0 && (sim.tick - header.tick) % progressEvery === 0) onProgress?.(sim.tick, end)
    }
  }
  const players = new Set<number>()
  const to = options.to ?? Number.POSITIVE_INFINITY
  for (let i = 1; i < records.length; i++) {
    const r = records[i]
    if (r.tick > to) break
    if (r.type === 'join') players.add(r.player)
    try {
      await runner.apply(r)
    } catch (error) {
      throw new ReplayToolError(
        `record ${i + 1} at tick ${r.tick} cannot be replayed: ${(error as Error).message}`,
      )
    }
  }
  if (Number.isFinite(to) && runner.sim.tick < to) runner.advanceTo(Math.min(to, read.lastTick))
  const replaySeconds = (performance.now() - began) / 1000
  const lastTick = runner.sim.tick
  const ticks = lastTick - header.tick
  return {
    room: header.room,
    scene: header.scene,
    start: new Date(header.start).toISOString(),
    firstTick: header.tick,
    lastTick,
    ticks,
    seconds: ticks / reader.preamble.tickRate,
    players: players.size,
    commands: runner.commands,
    steps: runner.steps,
    hashesChecked: runner.hashesChecked,
    keyframesChecked: runner.keyframesChecked,
    divergence: runner.divergence,
    read,
    replaySeconds,
    stepsPerSecond: replaySeconds > 0 ? runner.steps / replaySeconds : 0,
    ticksPerSecond: replaySeconds > 0 ? ticks / replaySeconds : 0,
    finalHash: runner.sim.hash(),
    hashes,
  }
}
