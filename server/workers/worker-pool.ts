/*
 * Rooms on a pool of worker threads (--workers N): each worker (room-worker.ts) runs its own tick
 * clock and whole rooms; a room lives on one worker, placed on the one holding the fewest rooms
 * (then the fewest players) when it opens. This side keeps the sockets: it forwards each joined
 * client's messages to its room's worker (worker-link.ts: inputs and acks in one message before
 * the worker's next tick, anything else at the end of the event-loop turn), delivers the worker's
 * per-tick batches to the sockets, reports each client's unread bytes back (the slow-reader rule),
 * beats the worker's loop in TickHealth on every batch (a silent worker fails /healthz), and
 * merges the workers' metrics into /metrics.
 *
 * A worker that dies (a crash, an exit, an uncaught throw) is reported: one log line naming its
 * rooms and concord_room_workers_failed_total. Its clients get error `room-lost` and close 4008;
 * a fresh worker takes its place, and with recording and recovery on, each of its rooms is rebuilt
 * from its log on a live worker (recovery.ts) before any rejoin reaches it.
 */
import { Worker } from 'node:worker_threads'
import type { Logger } from 'pino'
import { AggregatorRegistry } from 'prom-client'
import type { SceneBlueprint } from '../../engine/index.ts'
import { CLOSE_CODES } from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import type { GameBundle } from '../games/index.ts'
import type { ServerMetrics, TickHealth } from '../hosting/index.ts'
import type { Recordings } from '../replay/index.ts'
import type { JoinRequest, RoomHost, RoomSeat } from '../rooms/index.ts'
import { type Metrics, WorkerLink, WorkerSeat } from './worker-link.ts'
import type { FromWorker, FromWorkerOp, RoomSummary, WorkerFault, WorkerInit } from './worker-protocol.ts'

/** Worker metrics merged into /metrics (the rest, e.g. connections and bytes, are counted here). */
const WORKER_METRICS = new Set([
  'concord_room_tick_seconds',
  'concord_loop_tick_seconds',
  'concord_room_dropped_ticks_total',
  'concord_tick_overruns_total',
  'concord_snapshots_skipped_total',
  'concord_slow_clients_closed_total',
  'concord_desyncs_total',
  'concord_rooms_closed_over_budget_total',
  'concord_recorder_failures_total',
  'concord_rooms_recovered_total',
  'concord_rooms_untouched_closed_total',
  'concord_worker_bytes_out_total',
])

/**
 * Room metrics only rooms count: with every room on a worker, this thread's own copies stay empty
 * and are left out of /metrics. An empty unlabelled series listed first would otherwise read as
 * the total to anything taking the first match (the page's HUD read its tick time as none).
 */
const ROOM_ONLY_METRICS = new Set([
  'concord_room_tick_seconds',
  'concord_snapshots_skipped_total',
  'concord_desyncs_total',
  'concord_rooms_closed_over_budget_total',
])

/** How long shutdown waits for workers to close their logs (ms). */
const SHUTDOWN_WAIT_MS = 3000

/** The worker threads and the rooms on them (see the file comment). */
export class WorkerPool implements RoomHost {
  private readonly links: WorkerLink[] = []
  private readonly roomLinks = new Map<string, WorkerLink>()
  private nextConn = 1
  private nextId = 1
  private closing = false
  /** Rooms being rebuilt from their logs at startup: called when the worker has answered. */
  private readonly reopening = new Map<string, () => void>()
  /** Whether loop tick times are being collected (benchmarks). */
  private sampling = false
  /** Called when a room is gone for good (e.g. to release it in the room directory). */
  onRoomDisposed: ((name: string) => void) | null = null
  /**
   * Resolves once every worker has started its loop (its first message); rejects, naming the
   * worker and its error, when one ends before that (e.g. dist/room-worker.js missing).
   */
  readonly ready: Promise<void>
  private startup: { resolve: () => void; reject: (error: Error) => void } | null = null

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
    private readonly health: TickHealth,
    private readonly recordings: Recordings,
    readonly size: number,
    /** Games loaded from --games DIR: each worker imports the same bundles at boot. */
    private readonly games: readonly GameBundle[] = [],
  ) {
    this.ready = new Promise((resolve, reject) => {
      this.startup = { resolve, reject }
    })
    // Nobody may be waiting yet when a worker fails (startServer awaits soon after): no unhandled rejection.
    this.ready.catch(() => {})
    for (let slot = 0; slot < size; slot++) this.spawn(slot)
  }

  has(name: string): boolean {
    return this.roomLinks.has(name)
  }

  join(request: JoinRequest): RoomSeat | null {
    const link = this.place(request.room)
    if (!link) {
      request.refused(`the server has reached its limit of ${this.config.maxRooms} rooms`, 'too many rooms')
      return null
    }
    const conn = this.nextConn++
    const seat = new WorkerSeat(conn, request.room, request.conn, link, request.strike, request.refused)
    seat.spectator = request.spectate
    link.seats.set(conn, seat)
    link.pendingJoins.set(request.room, (link.pendingJoins.get(request.room) ?? 0) + 1)
    link.unanswered.set(conn, request.room)
    const { room, name, token, mode, controls, game, spectate } = request
    link.post({ op: 'join', conn, room, name, token, mode, controls, game, spectate })
    return seat
  }

  open(name: string, blueprint?: { name: string; scene: SceneBlueprint }): void {
    this.place(name)?.post({ op: 'open', room: name, blueprint })
  }

  close(name: string, code: number, reason: string): void {
    this.roomLinks.get(name)?.post({ op: 'close-room', room: name, code, reason })
  }

  /** Rebuild a room from log `log` on a worker (startup recovery); resolves once the worker has answered. */
  reopen(room: string, log: string): Promise<void> {
    const link = this.place(room)
    if (!link) return Promise.resolve()
    return new Promise((resolve) => {
      this.reopening.set(room, resolve)
      link.post({ op: 'open', room, log })
    })
  }

  summaries(): RoomSummary[] {
    const out: RoomSummary[] = []
    for (const [name, link] of this.roomLinks) {
      const known = link.summaries.find((s) => s.name === name)
      let players = 0
      let spectators = 0
      for (const seat of link.seats.values())
        if (seat.room === name && seat.playerId > 0) seat.spectator ? spectators++ : players++
      out.push({
        name,
        players,
        bodies: known?.bodies ?? 0,
        scene: known?.scene ?? '',
        tick: known?.tick ?? 0,
        game: known?.game ?? '',
        spectators,
      })
    }
    return out
  }

  get playerCount(): number {
    let n = 0
    for (const link of this.links) n += link.seats.size
    return n
  }

  /** The worker holding a room, by id (tests and logs), or undefined. */
  workerOf(room: string): number | undefined {
    return this.roomLinks.get(room)?.id
  }

  /** The live workers' ids. */
  get workerIds(): number[] {
    return this.links.map((l) => l.id)
  }

  /** The live workers' tick phases (fractions of a tick, in slot order): k / size for slot k. */
  get workerPhases(): number[] {
    return this.links.map((l) => l.phase).sort((a, b) => a - b)
  }

  /** Inject a test fault into the worker holding `room` (never reachable from the network). */
  fault(room: string, fault: WorkerFault): void {
    this.roomLinks.get(room)?.post({ op: 'fault', fault })
  }

  /**
   * Benchmarks: each worker's loop tick times since the last call (wall ms, and CPU ms on the
   * worker's thread where Linux reports it), from its once-a-second stats (collection starts with
   * the first call), its dropped ticks so far and its heap (MB).
   */
  takeLoopStats(): Array<{
    worker: number
    loopMs: number[]
    cpuMs: number[]
    overruns: number
    heapMb: number
  }> {
    if (!this.sampling) for (const link of this.links) link.post({ op: 'measure-cpu' })
    this.sampling = true
    return this.links.map((link) => {
      const { loopMs, cpuMs } = link
      link.loopMs = []
      link.cpuMs = []
      return { worker: link.id, loopMs, cpuMs, overruns: link.overruns, heapMb: link.heapMb }
    })
  }

  /** /metrics: this process's metrics with every worker's merged in (worker label). */
  async metricsText(): Promise<string> {
    const own = ((await this.metrics.registry.getMetricsAsJSON()) as Metrics).filter(
      (m) => !ROOM_ONLY_METRICS.has(m.name),
    )
    const parts = [own, ...this.links.map((l) => l.metrics.filter((m) => WORKER_METRICS.has(m.name)))]
    return AggregatorRegistry.aggregate(parts).metrics()
  }

  /** Stop every worker after it has closed its logs (or after a few seconds); `keep`: see Recordings.closeAll. */
  async stop(reason: string, keep = false): Promise<void> {
    this.closing = true
    const links = [...this.links]
    await Promise.all(
      links.map(
        (link) =>
          new Promise<void>((resolve) => {
            const timer = setTimeout(resolve, SHUTDOWN_WAIT_MS)
            const done = (): void => {
              clearTimeout(timer)
              resolve()
            }
            link.worker.on('message', (m: FromWorker) => m.t === 'closed' && done())
            link.worker.once('exit', done)
            link.post({ op: 'shutdown', reason, keep })
          }),
      ),
    )
    await Promise.all(links.map((l) => l.worker.terminate()))
  }

  /** The worker holding `room`, or the least loaded one for a new room; null at the room limit. */
  private place(room: string): WorkerLink | null {
    const held = this.roomLinks.get(room)
    if (held) return held
    if (this.roomLinks.size >= this.config.maxRooms || this.links.length === 0) return null
    let best = this.links[0]
    for (const link of this.links) {
      const fewer = link.rooms.size - best.rooms.size || link.seats.size - best.seats.size
      if (fewer < 0) best = link
    }
    this.roomLinks.set(room, best)
    best.rooms.add(room)
    this.metrics.rooms.set(this.roomLinks.size)
    return best
  }

  private spawn(slot: number): WorkerLink {
    const id = this.nextId++
    const phase = slot / this.size
    const init: WorkerInit = { id, config: this.config, phase, games: [...this.games] }
    const here = import.meta.url
    // From source (tests, tsx) the worker loads TypeScript through tsx; the build ships dist/room-worker.js.
    const worker = here.endsWith('.ts')
      ? new Worker(new URL('./worker-boot.mjs', here), {
          workerData: { ...init, entry: new URL('./room-worker.ts', here).href },
        })
      : new Worker(new URL('./room-worker.js', here), { workerData: init })
    const link = new WorkerLink(id, slot, phase, worker)
    this.links.push(link)
    this.health.beat(link.loop)
    worker.on('message', (message: FromWorker) => {
      try {
        this.receive(link, message)
      } catch (error) {
        this.log.error({ worker: id, err: error }, 'handling a room worker message failed')
      }
    })
    worker.on('error', (error) => {
      link.lastError = error.message
      this.log.error({ worker: id, err: error }, 'room worker threw')
    })
    worker.on('exit', (code) => this.lost(link, code))
    return link
  }

  private receive(link: WorkerLink, message: FromWorker): void {
    if (!link.started) {
      link.started = true
      this.health.beat(link.loop)
      if (this.startup && this.links.every((l) => l.started)) {
        this.startup.resolve()
        this.startup = null
      }
    }
    if (message.t === 'stats') {
      link.summaries = message.rooms
      link.metrics = message.metrics
      link.overruns = message.overruns
      link.heapMb = message.heapMb
      if (this.sampling) {
        link.loopMs.push(...message.loopMs)
        link.cpuMs.push(...message.cpuMs)
      }
      for (const name of link.openLogs) this.recordings.openNames.delete(name)
      link.openLogs = message.openLogs
      for (const name of link.openLogs) this.recordings.openNames.add(name)
      return
    }
    if (message.t !== 'batch') return
    this.health.beat(link.loop)
    const bytes = new Uint8Array(message.buf)
    for (const op of message.ops) this.apply(link, op, bytes)
    const values: number[] = []
    for (const [conn, seat] of link.seats) values.push(conn, seat.session.buffered())
    if (values.length > 0 && message.ops.length > 0) link.post({ op: 'buffered', values })
  }

  private apply(link: WorkerLink, op: FromWorkerOp, bytes: Uint8Array): void {
    switch (op.k) {
      case 'send':
        link.seats
          .get(op.conn)
          ?.session.sendBytes(bytes.subarray(op.at, op.at + op.len), op.snap >= 0 ? op.snap : undefined)
        return
      case 'error':
        link.seats.get(op.conn)?.session.sendError(op.code, op.reason, op.seq)
        return
      case 'close':
        link.seats.get(op.conn)?.session.close(op.code, op.reason)
        return
      case 'strike': {
        const seat = link.seats.get(op.conn)
        seat?.strike(op.code, op.reason, op.tick, op.seq)
        return
      }
      case 'joined': {
        this.answered(link, op.conn)
        const seat = link.seats.get(op.conn)
        if (seat) seat.playerId = op.player
        this.metrics.clients.set(this.playerCount)
        return
      }
      case 'refused': {
        const seat = this.answered(link, op.conn)
        if (!seat) return
        link.seats.delete(op.conn)
        seat.open = false
        seat.refused(op.error, op.reason)
        return
      }
      case 'opened':
        if (this.roomLinks.get(op.room) !== link) {
          this.roomLinks.set(op.room, link)
          this.metrics.rooms.set(this.roomLinks.size)
        }
        link.rooms.add(op.room)
        // /rooms shows its scene and bodies at once, not after the worker's next stats.
        link.summaries = [...link.summaries.filter((s) => s.name !== op.room), op.summary]
        return
      case 'disposed':
        // A join already on its way reopens the room on the same worker: keep it placed there.
        if ((link.pendingJoins.get(op.room) ?? 0) > 0) return
        link.rooms.delete(op.room)
        if (this.roomLinks.get(op.room) === link) this.roomLinks.delete(op.room)
        this.metrics.rooms.set(this.roomLinks.size)
        this.onRoomDisposed?.(op.room)
        return
      case 'recovered':
        this.reopened(op.room)
        this.log.info(
          { room: op.room, log: op.log, tick: op.tick, hash: op.hash, worker: link.id },
          'room rebuilt from its log on a worker',
        )
        return
      case 'log-created':
        if (!link.openLogs.includes(op.name)) link.openLogs.push(op.name)
        this.recordings.logCreated(op.name)
        return
      case 'recover-failed':
        this.reopened(op.room)
        this.log.error(
          { room: op.room, err: op.reason, worker: link.id },
          'cannot rebuild a room from its log',
        )
        return
    }
  }

  /** A startup rebuild was answered (done or failed). */
  private reopened(room: string): void {
    this.reopening.get(room)?.()
    this.reopening.delete(room)
  }

  /**
   * A join was answered: one fewer pending for its room, whether or not the client is still
   * there (one that left first must not keep its room's `disposed` ignored, and the room counted
   * against --max-rooms, for good). Returns the seat if the client is still there.
   */
  private answered(link: WorkerLink, conn: number): WorkerSeat | undefined {
    const room = link.unanswered.get(conn)
    if (room !== undefined) {
      link.unanswered.delete(conn)
      const left = (link.pendingJoins.get(room) ?? 1) - 1
      if (left > 0) link.pendingJoins.set(room, left)
      else link.pendingJoins.delete(room)
    }
    return link.seats.get(conn)
  }

  /** A worker ended: report it, close its clients, replace it, rebuild its rooms from their logs. */
  private lost(link: WorkerLink, code: number): void {
    link.exited = true
    this.health.remove(link.loop)
    this.links.splice(this.links.indexOf(link), 1)
    for (const name of link.openLogs) this.recordings.openNames.delete(name)
    if (this.closing) return
    if (!link.started) {
      // It never ran: replacing it would fail the same way, over and over.
      const error = `room worker ${link.id} ended before starting (exit code ${code}): ${link.lastError || 'no error reported'}`
      this.log.error({ worker: link.id, exitCode: code, err: link.lastError }, 'room worker failed to start')
      this.startup?.reject(new Error(error))
      this.startup = null
      return
    }
    const rooms = [...link.rooms].filter((room) => this.roomLinks.get(room) === link)
    this.metrics.workersFailed.inc()
    this.log.error({ worker: link.id, exitCode: code, rooms }, 'room worker died; its rooms are lost')
    const reason = 'room lost: the thread running it failed; rejoin'
    for (const seat of link.seats.values()) {
      seat.open = false
      seat.session.sendError('room-lost', reason)
      seat.session.close(CLOSE_CODES.roomLost, reason)
    }
    link.seats.clear()
    for (const room of rooms) {
      this.roomLinks.delete(room)
      this.reopened(room)
    }
    this.metrics.rooms.set(this.roomLinks.size)
    this.spawn(link.slot)
    for (const room of rooms) {
      if (this.config.record && this.config.recover)
        this.place(room)?.post({ op: 'open', room, recover: true })
      else if (room === this.config.defaultRoom) this.open(room)
      else this.onRoomDisposed?.(room)
    }
  }
}
