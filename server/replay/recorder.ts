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
 * maxBytes is closed (reason "rotated") and a new one starts with a header at the current state.
 * Any write error stops recording for this room: one log line, concord_recorder_failures_total,
 * and the room keeps running.
 */
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
import { type LogFile, logFileName, type OpenLog, openLogFile, pruneLogs } from './replay-files.ts'

const deflateAsync = promisify(deflate)

/** Memory a recorder may hold unwritten before it gives up (a disk far too slow). */
const MAX_PENDING_BYTES = 64 * 1024 * 1024

/** Recorder settings (from the server config). */
export interface RecorderOptions {
  dir: string
  fsync: 'none' | 'interval' | 'always'
  keyframeTicks: number
  /** Keyframe bytes allowed per hour of a log (0 or absent: no limit), see keyframe-policy.ts. */
  keyframeBudget?: number
  maxBytes: number
  keep: number
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
  private queue: Array<Uint8Array | Promise<Uint8Array>> = []
  /** Small records not yet sealed into a block. */
  private small: BlockableRecord[] = []
  private pendingBytes = 0
  /** Bumped per file, so a late compression result corrects the right file's size. */
  private generation = 0
  /** The saved world of the last header or keyframe of this file (a delta's base), or null. */
  private base: Uint8Array | null = null
  private readonly keyframes: KeyframePolicy
  private file: Promise<LogFile> | null = null
  private chain: Promise<void> = Promise.resolve()
  /** Records queued since the last hash or keyframe. */
  private dirty = false
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
    this.generation++
    this.base = null
    this.keyframes.reset(this.sim.tick, false, 0)
    this.options.openNames.add(name)
    this.file = this.openLog(join(this.options.dir, name), 'append')
    this.file.catch((error) => this.fail(error))
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
    this.pushWorld(this.sim.world.save(), (z, world) => ({ type: 'world', tick, scene, z, world }))
  }

  ticked(tick: number): void {
    if (this.failed) return
    if (tick % TICK_RATE === 0) this.pushHash()
    const keyframe = this.keyframes.decide(tick)
    if (keyframe !== 'none') this.pushKeyframe(keyframe)
    if (this.bytes >= this.options.maxBytes) this.rotate()
    else if (this.options.fsync === 'always') this.flush()
  }

  /** Write everything queued (ending with a checkpoint); resolves when it is written. */
  flush(): Promise<void> {
    if (this.failed || !this.file) return this.chain
    if (this.dirty) this.pushHash()
    this.sealBlock()
    if (this.queue.length === 0) return this.chain
    const batch = this.queue
    const file = this.file
    this.queue = []
    this.pendingBytes = 0
    const sync = this.options.fsync !== 'none'
    this.chain = this.chain.then(async () => {
      if (this.failed) return
      try {
        const parts = await Promise.all(batch)
        const handle = await file
        await handle.write(Buffer.concat(parts))
        if (sync) await handle.sync()
      } catch (error) {
        this.fail(error)
      }
    })
    return this.chain
  }

  /** Append a clean-close record, write everything, close the file and stop observing. */
  async close(reason: string): Promise<void> {
    if (this.closed) return
    this.closed = true
    this.stopObserving()
    if (!this.failed) this.pushSmall({ type: 'close', tick: this.sim.tick, reason, end: Date.now() })
    await this.closeFile()
  }

  /** Flush and close the current file (its name and handle are taken now: a rotation replaces them). */
  private closeFile(): Promise<void> {
    this.dirty = false
    this.flush()
    const file = this.file
    const name = this.name
    this.file = null
    if (file) {
      this.chain = this.chain.then(async () => {
        try {
          await (await file).close()
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
    this.timer = setInterval(() => this.flush(), 1000)
    this.timer.unref()
  }

  private stopObserving(): void {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    const i = this.sim.observers.indexOf(this)
    if (i >= 0) this.sim.observers.splice(i, 1)
  }

  private newFile(now: number): void {
    const dir = this.options.dir
    const base = logFileName(this.room, now)
    this.name = base
    this.options.openNames.add(base)
    this.bytes = 0
    this.generation++
    this.file = (async () => {
      for (let counter = 0; ; counter++) {
        const name = counter === 0 ? base : logFileName(this.room, now, counter)
        try {
          const file = await this.openLog(join(dir, name), 'create')
          if (name !== base) {
            this.options.openNames.delete(base)
            this.options.openNames.add(name)
            this.name = name
          }
          pruneLogs(dir, this.options.keep, this.options.openNames).catch(() => {})
          return file
        } catch (error) {
          if ((error as NodeJS.ErrnoException).code !== 'EEXIST' || counter >= 50) throw error
        }
      }
    })()
    this.file.catch((error) => this.fail(error))
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
    this.pushWorld(saved, (z, world) => ({
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
    }))
    this.dirty = false
  }

  private rotate(): void {
    this.pushSmall({ type: 'close', tick: this.sim.tick, reason: 'rotated', end: Date.now() })
    this.closeFile().catch(() => {})
    this.newFile(Date.now())
    // The new log's header goes out now, not at the next flush: a crash right after a rotation
    // leaves a log that recovery can start from, not an empty file after a cleanly closed one.
    this.flush()
  }

  private pushHash(): void {
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
  ): void {
    if (this.failed) return
    this.sealBlock()
    if (!this.options.compress) {
      this.queueBytes(count(encodeRecord(make(0, saved))))
      this.dirty = true
      return
    }
    this.queueDeflated(saved, saved.length / 4, (world) => count(encodeRecord(make(1, world))))
  }

  /**
   * Queue a record whose payload is deflated on libuv's pool; `estimate` counts for rotation and
   * the memory bound until the real size is known.
   */
  private queueDeflated(
    raw: Uint8Array | Promise<Uint8Array>,
    estimate: number,
    make: (zlib: Uint8Array) => Uint8Array,
  ): void {
    this.grow(estimate)
    const generation = this.generation
    this.queue.push(
      Promise.resolve(raw)
        .then((bytes) => deflateAsync(bytes))
        .then((z) => {
          const record = make(new Uint8Array(z.buffer, z.byteOffset, z.length))
          if (generation === this.generation) this.bytes += record.length - estimate
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

  private fail(error: unknown): void {
    if (this.failed) return
    this.failed = true
    this.queue = []
    this.small = []
    this.pendingBytes = 0
    this.stopObserving()
    this.options.openNames.delete(this.name)
    this.options.failures.inc()
    this.options.log.error(
      { room: this.room, log: this.name, err: (error as Error).message },
      'recording stopped for this room; the room keeps running',
    )
    const file = this.file
    this.file = null
    file?.then((f) => f.close()).catch(() => {})
  }
}
