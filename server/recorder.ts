/*
 * One room's recorder: an observer of the room's RoomSimulation that appends every state change
 * to the room's log (format: shared/replay-log.ts). It never blocks the tick loop: records are
 * encoded into memory as they happen (keyframe compression runs on libuv's pool), and a chain of
 * asynchronous writes appends them, at least once a second (every tick with fsync "always"), and
 * on close. Each flush ends with a hash record for the current tick, so the durable part of a log
 * always ends at a verified checkpoint: crash recovery resumes exactly there.
 *
 * A hash record every 60 ticks, a keyframe (state + saved world) every keyframeTicks. A log past
 * maxBytes is closed (reason "rotated") and a new one starts with a header at the current state.
 * Any write error stops recording for this room: one log line, concord_recorder_failures_total,
 * and the room keeps running.
 */
import { open as openFile } from 'node:fs/promises'
import { hostname } from 'node:os'
import { join } from 'node:path'
import { promisify } from 'node:util'
import { deflate } from 'node:zlib'
import type { Logger } from 'pino'
import type { Counter } from 'prom-client'
import { SAVE_FORMAT_VERSION } from '../engine/index.ts'
import { type Command, PROTOCOL_VERSION, TICK_RATE } from '../shared/index.ts'
import {
  encodePreamble,
  encodeRecord,
  REPLAY_FORMAT_VERSION,
  type ReplayRecord,
} from '../shared/replay-log.ts'
import type { RoomSimulation, SimulationObserver } from '../shared/room-simulation.ts'
import { logFileName, pruneLogs } from './replay-files.ts'

const deflateAsync = promisify(deflate)

/** Memory a recorder may hold unwritten before it gives up (a disk far too slow). */
const MAX_PENDING_BYTES = 64 * 1024 * 1024

/** The file operations a recorder uses (tests inject failing ones). */
export interface LogFile {
  write(bytes: Uint8Array): Promise<unknown>
  sync(): Promise<void>
  close(): Promise<void>
}

/** Open a log file: 'create' fails if it exists; 'append' continues one (recovery). */
export type OpenLog = (path: string, mode: 'create' | 'append') => Promise<LogFile>

/** Node's filesystem. */
export const openLogFile: OpenLog = async (path, mode) => {
  const handle = await openFile(path, mode === 'create' ? 'wx' : 'a')
  return {
    write: (bytes) => handle.write(bytes),
    sync: () => handle.sync(),
    close: () => handle.close(),
  }
}

/** Recorder settings (from the server config). */
export interface RecorderOptions {
  dir: string
  fsync: 'none' | 'interval' | 'always'
  keyframeTicks: number
  maxBytes: number
  keep: number
  /** Deflate saved worlds (header, keyframes, world loads). */
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
  private pendingBytes = 0
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
    this.options.openNames.add(name)
    this.file = this.openLog(join(this.options.dir, name), 'append')
    this.file.catch((error) => this.fail(error))
    this.sim.observers.push(this)
    this.startTimer()
  }

  command(tick: number, playerId: number, cmd: Command): void {
    this.push({ type: 'command', tick, player: playerId, cmd })
  }

  join(tick: number, playerId: number, name: string, color: string): void {
    this.push({ type: 'join', tick, player: playerId, name, color })
  }

  leave(tick: number, playerId: number): void {
    this.push({ type: 'leave', tick, player: playerId })
  }

  worldLoaded(tick: number, scene: string): void {
    this.pushWorld(this.sim.world.save(), (z, world) => ({ type: 'world', tick, scene, z, world }))
  }

  ticked(tick: number): void {
    if (this.failed) return
    if (tick % TICK_RATE === 0) this.pushHash()
    if (tick % this.options.keyframeTicks === 0) this.pushKeyframe()
    if (this.bytes >= this.options.maxBytes) this.rotate()
    else if (this.options.fsync === 'always') this.flush()
  }

  /** Write everything queued (ending with a checkpoint); resolves when it is written. */
  flush(): Promise<void> {
    if (this.failed || !this.file) return this.chain
    if (this.dirty) this.pushHash()
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
    if (!this.failed) this.push({ type: 'close', tick: this.sim.tick, reason, end: Date.now() })
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
    this.pushWorld(sim.world.save(), (z, world) => ({
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
    this.push({ type: 'close', tick: this.sim.tick, reason: 'rotated', end: Date.now() })
    this.closeFile().catch(() => {})
    this.newFile(Date.now())
  }

  private pushHash(): void {
    this.push({ type: 'hash', tick: this.sim.tick, hash: this.sim.world.hash(), step: this.sim.world.tick })
    this.dirty = false
  }

  private pushKeyframe(): void {
    const state = this.sim.saveState()
    const tick = this.sim.tick
    this.pushWorld(this.sim.world.save(), (z, world) => ({ type: 'keyframe', tick, state, z, world }))
    this.dirty = false
  }

  private pushWorld(saved: Uint8Array, make: (z: 0 | 1, world: Uint8Array) => ReplayRecord): void {
    if (this.failed) return
    if (!this.options.compress) {
      this.push(make(0, saved))
      return
    }
    // Estimated size until compressed (for rotation and the memory bound): a quarter.
    const estimate = saved.length / 4
    this.bytes += estimate
    this.pendingBytes += estimate
    this.queue.push(
      deflateAsync(saved).then((z) =>
        encodeRecord(make(1, new Uint8Array(z.buffer, z.byteOffset, z.length))),
      ),
    )
  }

  private push(r: ReplayRecord): void {
    if (this.failed) return
    this.queueBytes(encodeRecord(r))
    this.dirty = true
  }

  private queueBytes(bytes: Uint8Array): void {
    this.queue.push(bytes)
    this.bytes += bytes.length
    this.pendingBytes += bytes.length
    if (this.pendingBytes > MAX_PENDING_BYTES)
      this.fail(new Error(`${this.pendingBytes} bytes waiting for a disk that does not keep up`))
  }

  private fail(error: unknown): void {
    if (this.failed) return
    this.failed = true
    this.queue = []
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
