/*
 * Recording for a whole server: a RoomRecorder per room while recording is on (--record), closed
 * when the room is disposed and, cleanly, at shutdown; the replay directory's listing for
 * GET /replays; and, at startup with --recover, the rooms whose newest log has no clean close are
 * rebuilt from it and reopened where it ends (recovery.ts): the newest log that is not empty, not
 * given up by its writer (read-only) and not written by a live process (log-writer.ts). It owns
 * the process's one pruner of the directory (--replay-keep; with room workers the main thread's).
 * A directory that cannot be created or written turns recording off with one loud log line (error
 * level, naming the directory, the cause and the consequence) and a metric, and sets `problem`,
 * which /readyz reports with --require-recording; rooms run either way. Room workers check the
 * directory too, quietly.
 */
import { constants } from 'node:fs'
import { access, mkdir, unlink } from 'node:fs/promises'
import { join, resolve } from 'node:path'
import type { Logger } from 'pino'
import type { ServerConfig } from '../config/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import type { Room, RoomManager } from '../rooms/index.ts'
import { writerAlive } from './log-writer.ts'
import { RoomRecorder } from './recorder.ts'
import { type RecoveredRoom, recoverLog, truncateToCheckpoint } from './recovery.ts'
import {
  givenUp,
  hasHeader,
  isLogName,
  LogPruner,
  type LogSummary,
  listLogNames,
  listLogs,
  type OpenLog,
  recoveryPick,
  roomOfLog,
  summarize,
} from './replay-files.ts'

/** What a player joining a room rebuilt from its log is told (welcome.notice, PROTOCOL.md). */
export const RESTORED_NOTICE = 'This room was restored after a server restart: what was built here is back.'

/** The server's recorders (see the file comment). */
export class Recordings {
  readonly recorders = new Map<string, RoomRecorder>()
  /** Names of logs being written. */
  readonly openNames = new Set<string>()
  private enabled: boolean
  private readonly recovered = new Map<string, RecoveredRoom>()
  /** The rooms recorded here (hook()): closeAll asks them whether they were ever touched. */
  private rooms: RoomManager | null = null
  /** Tests inject failing file operations here. */
  openLog: OpenLog | undefined
  /** Why recording is configured but impossible (the replay directory cannot be written), else null. */
  problem: string | null = null
  /** Log a failed prepare() at debug level only (a room worker: the main thread has said it). */
  quiet = false
  /** Called when a room was rebuilt from its log (room, log, tick and hash of the checkpoint). */
  onRecovered: ((room: string, log: string, tick: number, hash: number) => void) | null = null
  /**
   * The process's one pruner of the replay directory (--replay-keep). With room workers only the
   * main thread's prunes: it knows every worker's open logs (each reports the logs it creates).
   */
  readonly pruner: LogPruner
  /** Called when one of these recorders has created a new log: here, prune; a room worker reports it instead. */
  onLogCreated: (name: string) => void = () => this.pruner.request()

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.enabled = config.record
    this.pruner = new LogPruner(config.replayDir, config.replayKeep, this.openNames, (error) =>
      log.error({ dir: config.replayDir, err: error.message }, 'pruning the replay directory failed'),
    )
  }

  /** A log was created (here or, reported by its worker, on a room worker): record it as open and prune. */
  logCreated(name: string): void {
    this.openNames.add(name)
    this.pruner.request()
  }

  /** The replay directory. */
  get dir(): string {
    return this.config.replayDir
  }

  /**
   * Create the directory and, with --recover, rebuild the rooms of logs without a clean close
   * (they are reopened when `rooms` creates them, which this does). Call before opening any room.
   * With room workers, `reopen` is called with each room and log instead: the worker that will hold
   * the room rebuilds it (reopen() there); this resolves once every one has answered.
   */
  async start(rooms: RoomManager, reopen?: (room: string, log: string) => Promise<void>): Promise<void> {
    this.hook(rooms)
    if (!(await this.prepare())) return
    if (!this.config.recover) return
    if (this.config.redisUrl) {
      // Rooms belong to whichever server claims them in the directory; reopening one here could
      // run it twice.
      this.log.info('room directory in use: rooms are not reopened from logs')
      return
    }
    const rebuilt: Promise<void>[] = []
    for (const name of await this.unclosedLogs()) {
      if (reopen) {
        rebuilt.push(reopen(roomOfLog(name), name))
        continue
      }
      await this.reopen(rooms, name).catch((error: Error) =>
        this.log.error({ log: name, err: error.message }, 'cannot recover a room from its log'),
      )
    }
    await Promise.all(rebuilt)
  }

  /** Record the rooms `rooms` creates (a recorder each) and close their logs when they go. */
  hook(rooms: RoomManager): void {
    this.rooms = rooms
    rooms.onRoomCreated = (room) => this.attach(room)
    rooms.onRoomClosed = (room) => this.detach(room)
  }

  /**
   * Create the replay directory when recording and check that this process may write in it (an
   * existing directory of another user, a read-only mount); false when not recording (off, or it
   * failed: see the file comment).
   */
  async prepare(): Promise<boolean> {
    if (!this.enabled) return false
    try {
      await mkdir(this.dir, { recursive: true })
      await access(this.dir, constants.W_OK | constants.X_OK)
      return true
    } catch (error) {
      this.enabled = false
      this.metrics.recorderFailures.inc()
      const cause = (error as NodeJS.ErrnoException).code ?? (error as Error).message
      this.problem = `recording is configured but impossible: the replay directory ${resolve(this.dir)} cannot be written (${cause})`
      const line = `${this.problem}; rooms run unrecorded and crash recovery is off (mount a writable volume there or set --replay-dir)`
      if (this.quiet) this.log.debug({ dir: this.dir, err: (error as Error).message }, line)
      else this.log.error({ dir: this.dir, err: (error as Error).message }, line)
      return false
    }
  }

  /**
   * Rebuild the room of log `name` (truncated to its last checkpoint) and open it in `rooms`,
   * which continues the log; throws an Error naming the problem when the log cannot be recovered.
   */
  async reopen(rooms: RoomManager, name: string): Promise<RecoveredRoom> {
    const recovered = await recoverLog(this.dir, name)
    // Whoever asked for this log's room (a worker reopening it) waits for that room by name.
    if (recovered.room !== roomOfLog(name))
      throw new Error(`${name} holds room "${recovered.room}", not the room its name gives`)
    await truncateToCheckpoint(this.dir, recovered)
    this.recovered.set(recovered.room, recovered)
    // The room reopens running the log's game (a game room recovers with its score and clock).
    if (!rooms.getOrCreate(recovered.room, recovered.runner.sim.game.name))
      this.recovered.delete(recovered.room)
    return recovered
  }

  /** The newest log of `room` when it has no clean close (its writer died), else null. */
  async unclosedLogOf(room: string): Promise<string | null> {
    return (await this.unclosedLogs()).find((name) => roomOfLog(name) === room) ?? null
  }

  /**
   * Per room, the log recovery reopens: its newest log that is not empty (recoveryPick), when that
   * log has a header, no clean close, was not given up and has no live writer. Newer logs cut
   * before their header is whole (a crash right after a rotation created one) are passed over: a
   * 0-byte newest log once hid the older, unclosed one, and the room was lost.
   */
  private async unclosedLogs(): Promise<string[]> {
    const byRoom = new Map<string, string[]>()
    for (const name of await listLogNames(this.dir)) {
      const room = roomOfLog(name)
      byRoom.set(room, [...(byRoom.get(room) ?? []), name])
    }
    const out: string[] = []
    for (const names of byRoom.values()) {
      const name = await recoveryPick(this.dir, names, this.openNames)
      if (!name) continue
      const summary = await summarize(this.dir, name, this.openNames).catch(() => null)
      if (!summary || summary.status === 'clean' || !hasHeader(summary)) continue
      if (await givenUp(this.dir, name)) {
        this.log.info({ log: name }, 'not recovering a log whose recording failed (given up by its writer)')
        continue
      }
      if (summary.writer && writerAlive(summary.writer, Date.parse(summary.start))) {
        this.log.warn(
          { log: name, writer: summary.writer },
          'not recovering a log another live process writes',
        )
        continue
      }
      out.push(name)
    }
    return out
  }

  private attach(room: Room): void {
    if (!this.enabled) return
    const options = {
      dir: this.dir,
      fsync: this.config.replayFsync as 'none' | 'interval' | 'always',
      keyframeTicks: this.config.keyframeTicks,
      keyframeBudget: this.config.keyframeBudget * 1_000_000,
      maxBytes: this.config.replayMaxBytes,
      created: (name: string) => this.onLogCreated(name),
      compress: true,
      log: this.log,
      failures: this.metrics.recorderFailures,
      openNames: this.openNames,
      openLog: this.openLog,
    }
    const recorder = new RoomRecorder(room.name, room.sim, options)
    this.recorders.set(room.name, recorder)
    const recovered = this.recovered.get(room.name)
    if (!recovered) {
      recorder.start()
      return
    }
    this.recovered.delete(room.name)
    room.touched = true // a session that was recorded: never closed early, its log never removed
    room.notice = RESTORED_NOTICE
    const sim = recovered.runner.sim
    room.sim.restoreState(sim.saveState(), sim.world)
    room.nextPlayerId = recovered.maxPlayerId + 1
    room.emptySince = room.tick
    // Read back from the room itself (before the departed players leave, which releases grabs).
    const tick = room.tick
    const hash = room.sim.hash()
    recorder.resume(recovered.name, recovered.size)
    // The players of the crashed process are gone; they come back as new joins.
    for (const id of [...room.sim.players.keys()]) room.sim.leave(id)
    this.metrics.roomsRecovered.inc()
    this.log.info(
      { room: room.name, log: recovered.name, tick, hash, logHash: recovered.hash },
      'room recovered from its log',
    )
    this.onRecovered?.(room.name, recovered.name, recovered.tick, recovered.hash)
  }

  /**
   * Close a disposed room's log; the log of a room where no command was ever applied is removed
   * (Room.touched: it holds a scene and joins, nothing to replay), so junk rooms leave no file for
   * pruning to weigh against real recordings.
   */
  private detach(room: Room): void {
    const recorder = this.recorders.get(room.name)
    if (!recorder) return
    this.recorders.delete(room.name)
    const closed = recorder.close('room closed')
    if (room.touched) {
      closed.catch(() => {})
      return
    }
    closed
      .then(() => (recorder.name ? unlink(join(this.dir, recorder.name)) : undefined))
      .catch((error: Error) =>
        this.log.warn(
          { room: room.name, log: recorder.name, err: error.message },
          'cannot remove the log of an untouched room',
        ),
      )
  }

  /**
   * Whether a shutdown here keeps rooms for the next start: --keep-rooms, recording works and
   * --recover is on, without a room directory (whose rooms any server may claim).
   */
  get keepsRooms(): boolean {
    return this.enabled && this.config.keepRooms && this.config.recover && !this.config.redisUrl
  }

  /**
   * Close every log (shutdown). With `keep` (a planned restart), the log of every room where a
   * command was ever applied (Room.touched) is left open at a checkpoint at its last tick
   * (RoomRecorder.leaveOpen), so the next start reopens that room where it stopped, as after a
   * crash; the others are closed cleanly with `reason`.
   */
  async closeAll(reason: string, keep = false): Promise<void> {
    const all = [...this.recorders]
    this.recorders.clear()
    await Promise.all(
      all.map(([name, r]) => (keep && this.rooms?.get(name)?.touched ? r.leaveOpen() : r.close(reason))),
    )
  }

  /** Logs in the directory for GET /replays, newest first. */
  async list(): Promise<LogSummary[]> {
    // The writer (host name, process id) stays internal.
    return (await listLogs(this.dir, this.openNames)).map(({ writer: _, ...summary }) => summary)
  }

  /** Whether `name` is a log name (so it can only name a file directly inside the directory). */
  isLogName(name: string): boolean {
    return isLogName(name)
  }
}
