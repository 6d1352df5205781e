/*
 * Recording for a whole server: a RoomRecorder per room while recording is on (--record), closed
 * when the room is disposed and, cleanly, at shutdown; the replay directory's listing for
 * GET /replays; and, at startup with --recover, the rooms whose newest log has no clean close are
 * rebuilt from it and reopened where it ends (recovery.ts). A directory that cannot be created
 * turns recording off with one log line and a metric; rooms run either way.
 */
import { mkdir } from 'node:fs/promises'
import { hostname } from 'node:os'
import type { Logger } from 'pino'
import type { ServerConfig } from '../config/index.ts'
import type { ServerMetrics } from '../hosting/index.ts'
import type { Room, RoomManager } from '../rooms/index.ts'
import { RoomRecorder } from './recorder.ts'
import { type RecoveredRoom, recoverLog, truncateToCheckpoint } from './recovery.ts'
import {
  isLogName,
  type LogSummary,
  listLogNames,
  listLogs,
  type OpenLog,
  roomOfLog,
  summarize,
} from './replay-files.ts'

/** Whether the process that wrote a log still runs here (a different live process on this host). */
function writerAlive(writer: { host: string; pid: number }): boolean {
  if (writer.host !== hostname() || writer.pid === process.pid) return false
  try {
    process.kill(writer.pid, 0)
    return true
  } catch (error) {
    return (error as NodeJS.ErrnoException).code === 'EPERM'
  }
}

/** The server's recorders (see the file comment). */
export class Recordings {
  readonly recorders = new Map<string, RoomRecorder>()
  /** Names of logs being written. */
  readonly openNames = new Set<string>()
  private enabled: boolean
  private readonly recovered = new Map<string, RecoveredRoom>()
  /** Tests inject failing file operations here. */
  openLog: OpenLog | undefined
  /** Called when a room was rebuilt from its log (room, log, tick and hash of the checkpoint). */
  onRecovered: ((room: string, log: string, tick: number, hash: number) => void) | null = null

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
  ) {
    this.enabled = config.record
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
    rooms.onRoomCreated = (room) => this.attach(room)
    rooms.onRoomClosed = (room) => this.detach(room)
  }

  /** Create the replay directory when recording; false when not recording (off, or it failed). */
  async prepare(): Promise<boolean> {
    if (!this.enabled) return false
    try {
      await mkdir(this.dir, { recursive: true })
      return true
    } catch (error) {
      this.enabled = false
      this.metrics.recorderFailures.inc()
      this.log.error(
        { dir: this.dir, err: (error as Error).message },
        'cannot create the replay directory; not recording',
      )
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

  /** The newest log of each room, when it has no clean close. */
  private async unclosedLogs(): Promise<string[]> {
    const newest = new Map<string, string>()
    for (const name of await listLogNames(this.dir)) newest.set(roomOfLog(name), name)
    const out: string[] = []
    for (const name of newest.values()) {
      const summary = await summarize(this.dir, name, this.openNames).catch(() => null)
      if (
        !summary ||
        summary.status === 'clean' ||
        summary.status === 'invalid' ||
        summary.status === 'empty'
      )
        continue
      if (summary.writer && writerAlive(summary.writer)) {
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
      keep: this.config.replayKeep,
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

  private detach(room: Room): void {
    const recorder = this.recorders.get(room.name)
    if (!recorder) return
    this.recorders.delete(room.name)
    recorder.close('room closed').catch(() => {})
  }

  /** Close every log cleanly (shutdown). */
  async closeAll(reason: string): Promise<void> {
    const all = [...this.recorders.values()]
    this.recorders.clear()
    await Promise.all(all.map((r) => r.close(reason)))
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
