/*
 * The main thread's side of one room worker (worker-pool.ts): what it knows of the worker (its
 * rooms, the clients seated there, its last stats) and the queue of ops going to it. Ops that can
 * wait (a client's inputs and acks, the unread-bytes reports) go in one message FLUSH_LEAD_MS
 * before the worker's next tick; anything else goes at the end of the event-loop turn, with
 * everything queued before it, in order.
 */
import { performance } from 'node:perf_hooks'
import type { Worker } from 'node:worker_threads'
import type { MetricObjectWithValues, MetricValue } from 'prom-client'
import { TICK_RATE } from '../../shared/index.ts'
import type { ClientSession } from '../net/index.ts'
import { phaseAccumulator, type RoomMessage, type RoomSeat, type Strike } from '../rooms/index.ts'
import type { RoomSummary, ToWorker } from './worker-protocol.ts'

/**
 * Ops that can wait go to a worker this long before its next tick falls due (ms): a client's
 * inputs and acks reach their room in time for the same tick as before, in one message per tick
 * instead of one per event-loop turn (about 20 a tick per worker at 10 rooms of 5 bots).
 */
export const FLUSH_LEAD_MS = 3

/** A worker's metrics, as its last stats reported them. */
export type Metrics = MetricObjectWithValues<MetricValue<string>>[]

/** A client's seat in a room on a worker. */
export class WorkerSeat implements RoomSeat {
  playerId = 0
  open = true
  /** A spectator's seat (join.spectate): not counted as a player in /rooms. */
  spectator = false

  constructor(
    readonly conn: number,
    readonly room: string,
    readonly session: ClientSession,
    readonly link: WorkerLink,
    readonly strike: Strike,
    readonly refused: (error: string, reason: string) => void,
  ) {}

  deliver(message: RoomMessage): void {
    if (this.open) this.link.post({ op: 'msg', conn: this.conn, message })
  }

  leave(): void {
    if (!this.link.seats.delete(this.conn)) return
    this.open = false
    this.link.post({ op: 'leave', conn: this.conn })
  }
}

/** One worker thread and what this side knows of it. */
export class WorkerLink {
  readonly rooms = new Set<string>()
  readonly seats = new Map<number, WorkerSeat>()
  /** Joins sent and not yet answered, by room (a room disposed meanwhile is reopened by them). */
  readonly pendingJoins = new Map<string, number>()
  /**
   * The room of each join not yet answered, by connection: kept apart from `seats`, which a client
   * that leaves before the answer has already left, so that its answer still settles the count.
   */
  readonly unanswered = new Map<number, string>()
  summaries: RoomSummary[] = []
  metrics: Metrics = []
  /** Loop tick times (ms) collected while sampling, dropped ticks and heap from the last stats. */
  loopMs: number[] = []
  cpuMs: number[] = []
  overruns = 0
  heapMb = 0
  openLogs: string[] = []
  exited = false
  /** Set by the worker's first message: its code loaded and its loop runs. */
  started = false
  /** The last error the thread threw (named when it dies before starting). */
  lastError = ''
  private pending: ToWorker[] = []
  private scheduled = false
  /** Holds ops that can wait until FLUSH_LEAD_MS before the worker's next tick. */
  private timer: NodeJS.Timeout | null = null

  constructor(
    readonly id: number,
    /** Its place in the pool, 0..size-1: its clock ticks slot / size of a tick after slot 0's. */
    readonly slot: number,
    /** Its clock's phase (TickClock.start), slot / size. */
    readonly phase: number,
    readonly worker: Worker,
  ) {}

  /** The loop's name in TickHealth and the `loop` metric label. */
  get loop(): string {
    return `worker-${this.id}`
  }

  /**
   * Queue an op. Inputs, acks and unread-bytes reports wait until FLUSH_LEAD_MS before the worker's
   * next tick; anything else (a join, a leave, a ping) sends the queue, in order, at the end of
   * this event-loop turn.
   */
  post(op: ToWorker): void {
    if (this.exited) return
    this.pending.push(op)
    if (this.scheduled || this.timer) {
      if (this.timer && !canWait(op)) this.flushSoon()
      return
    }
    const wait = canWait(op) ? flushDelay(performance.timeOrigin + performance.now(), this.phase) : 0
    if (wait > 0) this.timer = setTimeout(this.flush, wait)
    else this.flushSoon()
  }

  /** Send the queue at the end of this event-loop turn. */
  private flushSoon(): void {
    if (this.scheduled) return
    this.scheduled = true
    setImmediate(this.flush)
  }

  private readonly flush = (): void => {
    this.scheduled = false
    if (this.timer) clearTimeout(this.timer)
    this.timer = null
    const ops = this.pending
    this.pending = []
    if (!this.exited && ops.length > 0) this.worker.postMessage(ops)
  }
}

/** Ops that may wait for the worker's next tick: a client's inputs and acks (not pings), unread-bytes reports. */
function canWait(op: ToWorker): boolean {
  return op.op === 'buffered' || (op.op === 'msg' && op.message.t !== 'ping')
}

/**
 * How long ops that can wait are held before going to a worker whose clock has phase `phase`
 * (ms; 0 or less: send now), at time `nowMs` since the epoch: until FLUSH_LEAD_MS before its next
 * tick, so they reach it in time for that tick, as they would have one by one.
 */
export function flushDelay(nowMs: number, phase: number): number {
  const stepMs = 1000 / TICK_RATE
  return stepMs - FLUSH_LEAD_MS - phaseAccumulator(1 / TICK_RATE, phase, nowMs) * 1000
}
