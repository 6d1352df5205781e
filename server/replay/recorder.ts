/*
 * One room's recorder: an observer of the room's RoomSimulation that appends every state change
 * to the room's log (format: shared/replay/replay-log.ts). It never blocks the tick loop: records are
 * kept in memory as they happen, and a chain of asynchronous writes appends them, at least once a
 * second (every tick with fsync "always"), and on close. The small records of a flush go out as
 * one deflated block record (compression runs on libuv's pool, like keyframes'). Each flush ends
 * with a hash record for the current tick, so the durable part of a log always ends at a verified
 * checkpoint: crash recovery resumes exactly there.
 *
 * A hash record every 60 ticks; a keyframe (state + saved world, whole or as a delta against the
 * previous one) at multiples of keyframeTicks as keyframe-policy.ts decides: the tick saves the
 * world, the delta is encoded right after the loop tick and deflated on libuv's pool. A log past
 * maxBytes (and holding half of it beyond its header) is closed (reason "rotated") and a new one
 * starts with a header at the current state, written before the old log's close (see rotate()).
 * A write error, a short write the disk does not finish, or the log deleted under it (checked once
 * a second) stops recording for this room (one log line and one count of
 * concord_recorder_failures_total per outage; the room keeps running): the log is cut back to its
 * last whole record and closed "recording failed", or marked given up when even that does not fit
 * (fail, giveUp). Every RETRY_MS (at once after a deletion) it tries again in a new log whose
 * header holds the room's state then.
 */
import { mkdir } from 'node:fs/promises'
import { hostname } from 'node:os'
import { join } from 'node:path'
import { promisify } from 'node:util'
import { deflate } from 'node:zlib'
import type { Logger } from 'pino'
import type { Counter } from 'prom-client'
import { SAVE_FORMAT_VERSION } from '../../engine/index.ts'
import {
  type BlockableRecord,
  type Command,
  encodeBlockEntries,
  encodeByteDelta,
  encodePreamble,
  encodeRecord,
  frameBlock,
  MAX_BLOCK_ENTRIES,
  MAX_BLOCK_TICKS,
  PROTOCOL_VERSION,
  REPLAY_FORMAT_VERSION,
  type ReplayRecord,
  type RoomSimulation,
  type SimulationObserver,
  TICK_RATE,
} from '../../shared/index.ts'
import { KeyframePolicy } from './keyframe-policy.ts'
import { type LogFile, logFileName, type OpenLog, openLogFile } from './replay-files.ts'

const deflateAsync = promisify(deflate)

/** Memory a recorder may hold unwritten before it gives up (a disk far too slow). */
const MAX_PENDING_BYTES = 64 * 1024 * 1024

/** How long a failed recorder waits before it tries a new log (ms): a full disk may have room again. */
export const RETRY_MS = 5000

/** One log file as the recorder writes it. */
interface LogState {
  name: string
  file: Promise<LogFile>
  /** Bytes of the file known to be on disk as whole records (where a cut-back goes). */
  written: number
  /** Room tick of the last record on disk (a close record after a failure is stamped with it). */
  tick: number
  /** Created by this recorder: given up with nothing whole in it, it is removed. */
  created: boolean
  /** Given up after a failure: nothing more is written to it. */
  done: boolean
}

/** Write all of `bytes`, the rest again after a short write; an Error says how much landed. */
async function writeAll(file: LogFile, bytes: Uint8Array): Promise<void> {
  let done = 0
  while (done < bytes.length) {
    let took: number
    try {
      const result = await file.write(bytes.subarray(done))
      const n = (result as { bytesWritten?: unknown } | null)?.bytesWritten
      took = typeof n === 'number' ? n : bytes.length - done
    } catch (error) {
      if (done === 0) throw error
      throw new Error(`${(error as Error).message} (after a short write: ${done} of ${bytes.length} bytes)`)
    }
    if (took <= 0)
      throw new Error(
        `the disk took none of ${bytes.length - done} bytes (${done} of ${bytes.length} written)`,
      )
    done += took
  }
}

/** Recorder settings (from the server config). */
export interface RecorderOptions {
  dir: string
  fsync: 'none' | 'interval' | 'always'
  keyframeTicks: number
  /** Keyframe bytes allowed per hour of a log (0 or absent: no limit), see keyframe-policy.ts. */
  keyframeBudget?: number
  maxBytes: number
  /** Wait before a failed recorder tries a new log (ms; default RETRY_MS). */
  retryMs?: number
  /**
   * Called with a new log's name once its file exists (the server's one pruner takes it from
   * there: replay-files.ts LogPruner); a recorder never prunes the directory itself.
   */
  created?: (name: string) => void
  /** Deflate saved worlds (header, keyframes, world loads) and write delta keyframes. */
  compress: boolean
  log: Logger
  failures: Counter
  /** Names of logs being written (shared by every recorder; listing and pruning read it). */
  openNames: Set<string>
  openLog?: OpenLog
}

/** Records one room (see the file comment). */
export class RoomRecorder implements SimulationObserver {
  /** The log being written. */
  name = ''
  failed = false
  closed = false
  /** Bytes written or queued in the current log. */
  bytes = 0
  /** Of those, the preamble and header (an estimate until its world is deflated; 0 for a resumed log). */
  private headerBytes = 0
  private queue: Array<Uint8Array | Promise<Uint8Array>> = []
  /** Small records not yet sealed into a block. */
  private small: BlockableRecord[] = []
  private pendingBytes = 0
  /** Bumped per file, so a late compression result corrects the right file's size. */
  private generation = 0
  /** The saved world of the last header or keyframe of this file (a delta's base), or null. */
  private base: Uint8Array | null = null
  private readonly keyframes: KeyframePolicy
  /** The log being written, or null (failed, closed). */
  private log: LogState | null = null
  /** Recording failed and has not written since: further failures are not counted again. */
  private down = false
  private retryTimer: NodeJS.Timeout | null = null
  private chain: Promise<void> = Promise.resolve()
  /** Records queued since the last hash or keyframe. */
  private dirty = false
  /** Room tick of the last hash record queued (-1: none yet). */
  private hashTick = -1
  private timer: NodeJS.Timeout | null = null
  private readonly openLog: OpenLog

  constructor(
    readonly room: string,
    private readonly sim: RoomSimulation,
    private readonly options: RecorderOptions,
  ) {
    this.openLog = options.openLog ?? openLogFile
    this.keyframes = new KeyframePolicy(options.keyframeTicks, options.keyframeBudget ?? 0, TICK_RATE)
  }

  /** Start a new log at the simulation's current state and begin observing. */
  start(now = Date.now()): void {
    this.newFile(now)
    this.sim.observers.push(this)
    this.startTimer()
  }

  /**
   * Continue an existing log after crash recovery (the file already ends at a checkpoint equal to
   * the simulation's state) and begin observing.
   */
  resume(name: string, size: number): void {
    this.name = name
    this.bytes = size
    this.headerBytes = 0
    this.generation++
    this.base = null
    this.keyframes.reset(this.sim.tick, false, 0)
    this.options.openNames.add(name)
    const file = this.openLog(join(this.options.dir, name), 'append')
    this.log = { name, file, written: size, tick: this.sim.tick, created: false, done: false }
    file.catch((error) => this.fail(error))
    this.sim.observers.push(this)
    this.startTimer()
  }

  command(tick: number, playerId: number, cmd: Command): void {
    this.pushSmall({ type: 'command', tick, player: playerId, cmd })
  }

  join(tick: number, playerId: number, name: string, color: string): void {
    this.pushSmall({ type: 'join', tick, player: playerId, name, color })
  }

  leave(tick: number, playerId: number): void {
    this.pushSmall({ type: 'leave', tick, player: playerId })
  }

  worldLoaded(tick: number, scene: string): void {
    const colors = this.sim.colorList()
    const joints = [...this.sim.userJoints.values()].map((j) => ({ ...j }))
    this.pushWorld(this.sim.world.save(), (z, world) => ({
      type: 'world',
      tick,
      scene,
      colors,
      joints,
      z,
      world,
    }))
  }

  ticked(tick: number): void {
    if (this.failed) return
    if (tick % TICK_RATE === 0) this.pushHash()
    const keyframe = this.keyframes.decide(tick)
    if (keyframe !== 'none') this.pushKeyframe(keyframe)
    // A log rotates once past maxBytes and holding half of it beyond its header: a world whose
    // header alone passes the limit must not rotate at every tick (a new header each time).
    if (this.bytes >= this.options.maxBytes && this.bytes - this.headerBytes >= this.options.maxBytes / 2)
      this.rotate()
    else if (this.options.fsync === 'always') this.flush()
  }

  /** Write everything queued (ending with a checkpoint); resolves when it is written. */
  flush(): Promise<void> {
    const log = this.log
    if (this.failed || !log) return this.chain
    if (this.dirty) this.pushHash()
    this.sealBlock()
    if (this.queue.length === 0) return this.chain
    const batch = this.queue
    const tick = this.sim.tick
    this.queue = []
    this.pendingBytes = 0
    const sync = this.options.fsync !== 'none'
    this.chain = this.chain.then(async () => {
      if (this.failed || log.done) return
      try {
        const bytes = Buffer.concat(await Promise.all(batch))
        await writeAll(await log.file, bytes)
        log.written += bytes.length
        log.tick = tick
        if (sync) await (await log.file).sync()
        this.wrote(log)
      } catch (error) {
        this.fail(error, undefined, log)
      }
    })
    return this.chain
  }

  /** A write landed: after a failure, recording is back (one log line). */
  private wrote(log: LogState): void {
    if (this.down) {
      this.down = false
      this.options.log.info({ room: this.room, log: log.name }, 'recording resumed in a new log')
    }
  }

  /**
   * Whether the log being written still has a name: a log deleted under its writer (its directory
   * removed, say) takes writes without an error, so once a second the file is asked; if it has no
   * name, recording fails and starts over in a new log at once.
   */
  private async checkLinked(): Promise<void> {
    const log = this.log
    if (this.failed || !log) return
    try {
      const file = await log.file
      if (!file.linked || (await file.linked())) return
    } catch {
      return
    }
    if (this.log === log) this.fail(new Error('the log file was deleted (or the replay directory)'), 0)
  }

  /** Append a clean-close record, write everything, close the file and stop observing. */
  async close(reason: string): Promise<void> {
    if (this.closed) return
    this.closed = true
    if (this.retryTimer) clearTimeout(this.retryTimer)
    this.retryTimer = null
    this.stopObserving()
    if (!this.failed) this.pushSmall({ type: 'close', tick: this.sim.tick, reason, end: Date.now() })
    await this.closeFile()
  }

  /**
   * Stop for a planned restart: write everything up to a checkpoint at the current tick (a hash
   * record), close the file and stop observing, with no close record. The log is left as a crash
   * leaves one, so the next start reopens the room from it where it ends (crash recovery).
   */
  async leaveOpen(): Promise<void> {
    if (this.closed) return
    this.closed = true
    if (this.retryTimer) clearTimeout(this.retryTimer)
    this.retryTimer = null
    this.stopObserving()
    if (!this.failed && (this.dirty || this.hashTick !== this.sim.tick)) this.pushHash()
    await this.closeFile()
  }

  /** Flush and close the current file (its name and handle are taken now: a rotation replaces them). */
  private closeFile(): Promise<void> {
    this.dirty = false
    this.flush()
    const log = this.log
    const name = this.name
    this.log = null
    if (log) {
      this.chain = this.chain.then(async () => {
        try {
          await (await log.file).close()
        } catch {
          // Already failed or closed: nothing more to do.
        }
      })
    }
    this.chain = this.chain.then(() => {
      this.options.openNames.delete(name)
    })
    return this.chain
  }

  private startTimer(): void {
    this.timer = setInterval(() => {
      this.flush()
      this.chain = this.chain.then(() => this.checkLinked())
    }, 1000)
    this.timer.unref()
  }

  private stopObserving(): void {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    const i = this.sim.observers.indexOf(this)
    if (i >= 0) this.sim.observers.splice(i, 1)
  }

  private newFile(now: number): void {
    const base = logFileName(this.room, now)
    this.name = base
    this.options.openNames.add(base)
    this.bytes = 0
    this.generation++
    // The file is opened below; until then `file` is the promise of it.
    const log = { name: base, written: 0, tick: this.sim.tick, created: true, done: false } as LogState
    log.file = this.createFile(log, now)
    this.log = log
    log.file.catch((error) => {
      if (this.log === log) this.fail(error)
    })
    this.queueBytes(
      encodePreamble({
        format: REPLAY_FORMAT_VERSION,
        engine: SAVE_FORMAT_VERSION,
        protocol: PROTOCOL_VERSION,
        tickRate: TICK_RATE,
      }),
    )
    const sim = this.sim
    const state = sim.saveState()
    const tick = sim.tick
    const scene = sim.scene
    const saved = sim.world.save()
    this.base = this.options.compress ? saved : null
    this.keyframes.reset(tick, this.base !== null, saved.length * 0.63)
    this.pushWorld(
      saved,
      (z, world) => ({
        type: 'header',
        tick,
        room: this.room,
        scene,
        start: now,
        maxBodies: sim.maxBodies,
        controls: sim.controls,
        state,
        host: hostname(),
        pid: process.pid,
        z,
        world,
      }),
      undefined,
      true,
    )
    this.headerBytes = this.bytes
    this.dirty = false
  }

  /** Create a new log file for `log` (a counter in its name when the name is taken). */
  private async createFile(log: LogState, now: number): Promise<LogFile> {
    const base = log.name
    for (let counter = 0; ; counter++) {
      const name = counter === 0 ? base : logFileName(this.room, now, counter)
      try {
        const file = await this.openLog(join(this.options.dir, name), 'create')
        if (name !== base) {
          this.options.openNames.delete(base)
          this.options.openNames.add(name)
          if (this.log === log) this.name = name
          log.name = name
        }
        this.options.created?.(name)
        return file
      } catch (error) {
        if ((error as NodeJS.ErrnoException).code !== 'EEXIST' || counter >= 50) throw error
      }
    }
  }

  /**
   * Close this log (reason "rotated") and go on in a new one. In this order, one after the other:
   * this log's records, the new log's header (at once, not at the next timed flush), then this log's
   * close record. A crash anywhere in between leaves a log recovery starts from: this one unclosed
   * (the new one empty or cut before its header is whole, which recovery passes over), or the new
   * one with its header. Closing first left, after a crash, a closed log and an empty one: the room
   * was lost.
   */
  private rotate(): void {
    this.flush()
    const old = this.log as LogState
    const name = this.name
    const close = encodeRecord({ type: 'close', tick: this.sim.tick, reason: 'rotated', end: Date.now() })
    const sync = this.options.fsync !== 'none'
    this.newFile(Date.now())
    this.flush()
    this.chain = this.chain.then(async () => {
      // A failed write to it gave it up already (cut back, closed "recording failed").
      if (old.done) return
      let handle: LogFile | null = null
      try {
        handle = await old.file
        await writeAll(handle, close)
        if (sync) await handle.sync()
      } catch (error) {
        // It stays unclosed and cut back to its last record; the new log (a header) supersedes it.
        await handle?.truncate?.(old.written).catch(() => {})
        this.options.log.warn(
          { room: this.room, log: name, err: (error as Error).message },
          'cannot close a rotated log',
        )
      }
      await handle?.close().catch(() => {})
      this.options.openNames.delete(name)
    })
  }

  private pushHash(): void {
    this.hashTick = this.sim.tick
    this.pushSmall({
      type: 'hash',
      tick: this.sim.tick,
      hash: this.sim.hash(),
      step: this.sim.world.tick,
    })
    this.dirty = false
  }

  private pushKeyframe(kind: 'full' | 'delta'): void {
    this.sealBlock()
    const state = this.sim.saveState()
    const tick = this.sim.tick
    const saved = this.sim.world.save()
    const policy = this.keyframes
    const generation = this.generation
    const base = this.options.compress ? this.base : null
    const written = kind === 'delta' && base ? 'delta' : 'full'
    // Measured: a saved world deflates about 1.6x; a delta's size is known only once it is
    // encoded, so it is estimated (an awake room's delta deflates to about 0.4 of its saved world,
    // a resting room's to almost nothing) and settled once written, long before the next keyframe.
    const estimate = saved.length * (written === 'delta' ? 0.4 : 0.63)
    policy.record(written, estimate)
    const count = (bytes: Uint8Array): Uint8Array => {
      if (generation === this.generation) policy.settle(written, estimate, bytes.length)
      return bytes
    }
    if (written === 'delta' && base) {
      this.base = saved
      // The delta is encoded after the loop tick (setImmediate), in the frame's idle time, not
      // inside the tick that every room on this thread shares (1.2 ms for a 100-body awake pile,
      // 17 ms for 1,000 bodies); the queue keeps the record in its place.
      const delta = new Promise<Uint8Array>((resolve) =>
        setImmediate(() => resolve(encodeByteDelta(base, saved))),
      )
      this.queueDeflated(delta, saved.length / 4, (world) =>
        count(encodeRecord({ type: 'keyframe', tick, state, z: 2, world })),
      )
    } else {
      if (this.options.compress) this.base = saved
      this.pushWorld(saved, (z, world) => ({ type: 'keyframe', tick, state, z, world }), count)
    }
    this.dirty = false
  }

  private pushWorld(
    saved: Uint8Array,
    make: (z: 0 | 1, world: Uint8Array) => ReplayRecord,
    count: (bytes: Uint8Array) => Uint8Array = (bytes) => bytes,
    header = false,
  ): void {
    if (this.failed) return
    this.sealBlock()
    if (!this.options.compress) {
      this.queueBytes(count(encodeRecord(make(0, saved))))
      this.dirty = true
      return
    }
    this.queueDeflated(saved, saved.length / 4, (world) => count(encodeRecord(make(1, world))), header)
  }

  /**
   * Queue a record whose payload is deflated on libuv's pool; `estimate` counts for rotation and
   * the memory bound until the real size is known (in headerBytes too for the log's header).
   */
  private queueDeflated(
    raw: Uint8Array | Promise<Uint8Array>,
    estimate: number,
    make: (zlib: Uint8Array) => Uint8Array,
    header = false,
  ): void {
    this.grow(estimate)
    const generation = this.generation
    this.queue.push(
      Promise.resolve(raw)
        .then((bytes) => deflateAsync(bytes))
        .then((z) => {
          const record = make(new Uint8Array(z.buffer, z.byteOffset, z.length))
          if (generation === this.generation) {
            this.bytes += record.length - estimate
            if (header) this.headerBytes += record.length - estimate
          }
          return record
        }),
    )
  }

  private pushSmall(r: BlockableRecord): void {
    if (this.failed) return
    const small = this.small
    if (small.length === MAX_BLOCK_ENTRIES || (small.length > 0 && r.tick - small[0].tick > MAX_BLOCK_TICKS))
      this.sealBlock()
    this.small.push(r)
    this.dirty = true
  }

  /** Queue the small records gathered since the last block or big record as one block. */
  private sealBlock(): void {
    if (this.small.length === 0) return
    const records = this.small
    this.small = []
    const entries = encodeBlockEntries(records)
    this.queueDeflated(entries, entries.length / 2, (zlib) => frameBlock(records[0].tick, zlib))
  }

  private queueBytes(bytes: Uint8Array): void {
    this.queue.push(bytes)
    this.grow(bytes.length)
  }

  private grow(bytes: number): void {
    this.bytes += bytes
    this.pendingBytes += bytes
    if (this.pendingBytes > MAX_PENDING_BYTES)
      this.fail(new Error(`${this.pendingBytes} bytes waiting for a disk that does not keep up`))
  }

  /**
   * Recording failed (a write error, a short write the disk would not finish, a deleted log, a
   * disk too slow): stop observing, count it and say so once per outage, give the log up (giveUp),
   * and after `retryMs` try again in a new log that starts with a header at the room's state then.
   * `failed` is the log a failed write went to when it may not be the current one (a rotation's
   * old log): it is given up too, and marked at once, so that no later write (a rotation's close
   * record) lands after the part of a record it holds.
   */
  private fail(error: unknown, retryMs = this.options.retryMs ?? RETRY_MS, failed?: LogState): void {
    const current = this.failed ? null : this.log
    for (const log of new Set([failed, current])) {
      if (!log || log.done) continue
      log.done = true
      this.chain = this.chain.then(() => this.giveUp(log))
    }
    if (this.failed) return
    this.failed = true
    this.queue = []
    this.small = []
    this.pendingBytes = 0
    this.stopObserving()
    this.log = null
    const details = { room: this.room, log: failed?.name ?? this.name, err: (error as Error).message }
    if (!this.down) {
      this.down = true
      this.options.failures.inc()
      this.options.log.error(details, 'recording stopped for this room; the room keeps running')
    } else this.options.log.warn(details, 'recording is still failing for this room')
    if (!this.closed) {
      this.retryTimer = setTimeout(() => this.retry(), retryMs)
      this.retryTimer.unref()
    }
  }

  /**
   * Leave a failed log so that crash recovery never reopens it at the tick where recording
   * stopped: cut back to its last whole record, then a close record (reason "recording failed");
   * when even that cannot be written (the disk is full), mark it given up (read-only, which needs
   * no space). A log with nothing whole in it that this recorder created is removed.
   */
  private async giveUp(log: LogState): Promise<void> {
    let file: LogFile
    try {
      file = await log.file
    } catch {
      this.options.openNames.delete(log.name)
      return
    }
    try {
      if (log.created && log.written === 0) {
        await file.close()
        await file.remove?.().catch(() => {})
        return
      }
      await file.truncate?.(log.written)
      try {
        await writeAll(
          file,
          encodeRecord({ type: 'close', tick: log.tick, reason: 'recording failed', end: Date.now() }),
        )
        await file.sync()
      } catch {
        await file.truncate?.(log.written)
        await file.giveUp?.()
      }
    } catch (error) {
      this.options.log.error(
        { room: this.room, log: log.name, err: (error as Error).message },
        'cannot close or mark a failed log',
      )
    } finally {
      await file.close().catch(() => {})
      this.options.openNames.delete(log.name)
    }
  }

  /** After a failure: a new log at the room's current state (the directory made again if it is gone). */
  private retry(): void {
    this.retryTimer = null
    if (this.closed) return
    this.chain = this.chain.then(async () => {
      if (this.closed) return
      await mkdir(this.options.dir, { recursive: true }).catch(() => {})
      this.failed = false
      this.small = []
      this.dirty = false
      this.start()
      // The new log's header goes out now, not at the next timed flush.
      this.flush()
    })
  }
}
