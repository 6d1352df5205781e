/*
 * The rooms of one process: created on demand by name up to the limit, all driven by one
 * TickClock at 60 Hz, and disposed a while after their last player leaves (the default room
 * stays). Rooms are ticked in creation order; one room's work never depends on another's.
 */
import { performance } from 'node:perf_hooks'
import type { Logger } from 'pino'
import { STEP_SECONDS } from '../../engine/index.ts'
import { CLOSE_CODES, TICK_RATE } from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import { findServerGame } from '../games/index.ts'
import { LogLimiter, type ServerMetrics } from '../hosting/index.ts'
import { Room } from './room.ts'
import { TickClock } from './tick-clock.ts'

/** Every room of the process and the clock that drives them. */
export class RoomManager {
  private readonly rooms = new Map<string, Room>()
  readonly clock: TickClock
  /** Called when a room is created (e.g. to attach a recorder). */
  onRoomCreated: ((room: Room) => void) | null = null
  /** Called when a room is disposed (e.g. to release it in the room directory). */
  onRoomDisposed: ((name: string) => void) | null = null
  /** Called with the room when it is disposed (e.g. to close its recorder). */
  onRoomClosed: ((room: Room) => void) | null = null
  /** Called after every clock tick with the number of ticks run so far (liveness, Agones pings). */
  onTick: ((tick: number) => void) | null = null
  /** Called before each room's tick (a room worker's test faults). */
  beforeRoomTick: ((room: Room) => void) | null = null
  private ticks = 0
  /** Rooms created so far (a room's creation order spreads its snapshot ticks, room.ts). */
  private created = 0

  /** At most 3 overrun warnings per 10 s; the next window's first line counts the rest. */
  private readonly overrunLog: LogLimiter

  /** Per room: ticks over the tick budget in the current one-second window. */
  private readonly overBudget = new Map<string, number>()

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly log: Logger,
    /** The clock room ticks are timed with (ms); tests pass their own. */
    private readonly now: () => number = () => performance.now(),
    /** The `loop` label of this manager's tick histogram ("main", or "worker-N" in a room worker). */
    private readonly loopName = 'main',
  ) {
    this.overrunLog = new LogLimiter(log, 3, 10_000, Date.now, 'tick loop overrun warnings were suppressed')
    this.clock = new TickClock(
      STEP_SECONDS,
      () => this.tickAll(),
      (n) => {
        metrics.overruns.inc(n)
        for (const name of this.rooms.keys()) metrics.roomDroppedTicks.inc({ room: name }, n)
        this.overrunLog.warn(
          'overrun',
          { dropped: n, rooms: this.rooms.size },
          'tick loop fell behind; dropped ticks',
        )
      },
    )
  }

  /** The open room of that name, or undefined. */
  get(name: string): Room | undefined {
    return this.rooms.get(name)
  }

  /** Every open room, in creation order. */
  list(): Room[] {
    return [...this.rooms.values()]
  }

  /** The room of that name, created if there is room for it; null at the room limit. */
  getOrCreate(name: string, game?: string): Room | null {
    const existing = this.rooms.get(name)
    if (existing) return existing
    if (this.rooms.size >= this.config.maxRooms) return null
    // An unknown name never gets here (the transport refuses the join); the sandbox is the default.
    const room = new Room(
      name,
      this.config,
      this.metrics,
      this.log,
      this.spread(),
      findServerGame(game ?? 'sandbox'),
    )
    this.rooms.set(name, room)
    this.metrics.rooms.set(this.rooms.size)
    this.onRoomCreated?.(room)
    this.log.info({ room: name, scene: room.scene }, 'room created')
    return room
  }

  /**
   * Where a new room's periodic work falls (see Room's constructor). Every room does its
   * once-a-second checkpoint (world hash, sweep, the recorder's hash record and keyframe) on the
   * room ticks that are multiples of 60, so rooms opened in the same tick (a burst of joins, a
   * benchmark, a recovery) would all do it on the same clock tick, and that tick would take the
   * sum of their checkpoints. A room's checkpoint phase is (clock ticks - room tick) mod 60,
   * fixed for its life since both grow by one per tick; the new room gets the phase fewest open
   * rooms have (ties in the order 0, 23, 46, 9, ...: 23 is prime to 60, so consecutive rooms land
   * far apart), by starting its tick at (clock ticks - phase) mod 60. Its snapshot phase takes
   * the clock's snapshot slots in turn, in creation order, as before.
   */
  private spread(): { startTick: number; snapshotPhase: number } {
    const used = new Array<number>(TICK_RATE).fill(0)
    for (const room of this.rooms.values()) used[mod(this.ticks - room.tick, TICK_RATE)]++
    let phase = 0
    for (let k = 1; k < TICK_RATE; k++) {
      const candidate = (k * 23) % TICK_RATE
      if (used[candidate] < used[phase]) phase = candidate
    }
    const startTick = mod(this.ticks - phase, TICK_RATE)
    // Snapshots go out when (tick + snapshotPhase) is a multiple of the interval; the room tick is
    // (clock ticks - phase) mod the interval (which divides 60), so the k-th room created sends
    // when the clock ticks are k mod the interval.
    const interval = TICK_RATE / this.config.snapshotRate
    const snapshotPhase = mod(phase - this.created++, interval)
    return { startTick, snapshotPhase }
  }

  /** Run one tick of every room, measuring each (the measurement is for metrics only). */
  tickAll(): void {
    const loopStart = this.now()
    for (const room of this.rooms.values()) {
      const start = this.now()
      try {
        this.beforeRoomTick?.(room)
        room.runTick()
      } catch (error) {
        // A bug in one room must not take the process down with every other room.
        this.log.error({ room: room.name, err: error }, 'room tick failed; closing the room')
        room.closeAll(1011, 'room failed')
        this.dispose(room)
      }
      const ms = this.now() - start
      this.metrics.tickSeconds.observe(ms / 1000)
      if (this.config.roomTickBudgetMs > 0 && ms > this.config.roomTickBudgetMs) this.overran(room)
    }
    this.metrics.loopTickSeconds.observe({ loop: this.loopName }, (this.now() - loopStart) / 1000)
    if (++this.ticks % TICK_RATE === 0) {
      this.overBudget.clear()
      this.disposeIdle()
    }
    this.onTick?.(this.ticks)
  }

  /**
   * The per-room tick budget: a room over --room-tick-budget-ms in --room-overrun-ticks ticks of
   * one second starves every room on its loop, so it is closed with a notice (error `overloaded`,
   * close 4007) rather than left to make its neighbours drop ticks.
   */
  private overran(room: Room): void {
    const count = (this.overBudget.get(room.name) ?? 0) + 1
    this.overBudget.set(room.name, count)
    if (count < this.config.roomOverrunTicks || this.rooms.get(room.name) !== room) return
    const reason = `room ${room.name} closed: its ticks took over ${this.config.roomTickBudgetMs} ms ${count} times within a second`
    this.log.warn(
      { room: room.name, budgetMs: this.config.roomTickBudgetMs, count },
      'room over its tick budget; closing it',
    )
    this.metrics.roomsClosedOverBudget.inc()
    for (const player of room.players.values()) player.conn.sendError('overloaded', reason)
    this.close(room.name, CLOSE_CODES.overloaded, reason)
  }

  /**
   * Dispose of empty rooms (checked once a second): after --room-idle-seconds, or at once when
   * players came and went and no command was ever applied (Room.touched; a reconnect to one finds
   * a fresh room). A room opened without a player keeps the idle rule.
   */
  private disposeIdle(): void {
    const idleTicks = this.config.roomIdleSeconds * TICK_RATE
    for (const room of this.rooms.values()) {
      if (room.name === this.config.defaultRoom || room.players.size > 0 || room.emptySince < 0) continue
      if (room.visited && !room.touched) {
        this.metrics.roomsUntouchedClosed.inc()
        this.dispose(room)
      } else if (room.tick - room.emptySince >= idleTicks) this.dispose(room)
    }
  }

  /** Close a room's players with a code and reason and dispose of the room now. */
  close(name: string, code: number, reason: string): void {
    const room = this.rooms.get(name)
    if (!room) return
    room.closeAll(code, reason)
    this.dispose(room)
  }

  private dispose(room: Room): void {
    this.rooms.delete(room.name)
    this.metrics.rooms.set(this.rooms.size)
    this.metrics.roomDroppedTicks.remove({ room: room.name })
    this.overBudget.delete(room.name)
    this.log.info({ room: room.name }, 'room disposed')
    this.onRoomClosed?.(room)
    this.onRoomDisposed?.(room.name)
  }

  /** Total joined players. */
  get playerCount(): number {
    let n = 0
    for (const room of this.rooms.values()) n += room.players.size
    return n
  }
}

/** x mod m in [0, m). */
function mod(x: number, m: number): number {
  return ((x % m) + m) % m
}
