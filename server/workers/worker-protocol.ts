/*
 * The messages between the main thread and a room worker (worker-pool.ts, room-worker.ts). The
 * main thread owns the sockets: it validates every client message and forwards those of joined
 * players to the worker that holds their room, with each client's unread-bytes figure for the
 * slow-reader rule. A worker runs its rooms and posts, once per tick, everything its rooms sent:
 * the bytes of every send packed into one transferred buffer, and the operations that say which
 * client each slice goes to, in order. Both directions are batched; order within a batch matters.
 */
import type { MetricObjectWithValues, MetricValue } from 'prom-client'
import type { SceneBlueprint } from '../../engine/index.ts'
import type { JoinMode } from '../../shared/index.ts'
import type { ServerConfig } from '../config/index.ts'
import type { GameBundle } from '../games/index.ts'
import type { RoomMessage } from '../rooms/index.ts'

/** What a worker starts with. */
export interface WorkerInit {
  id: number
  config: ServerConfig
  /** The worker's tick phase, a fraction of a tick (TickClock.start): workers take turns on the cores. */
  phase: number
  /** The games loaded from --games DIR (their bundles): the worker imports them before any room opens. */
  games: GameBundle[]
}

/** A test-only fault to inject into a worker (never reachable from the network). */
export type WorkerFault =
  /** Busy-wait this long in every tick of the named room (a pathological room). */
  | { kind: 'busy'; room: string; ms: number }
  /** End the worker's thread at once, as a crash would. */
  | { kind: 'exit' }

/** Main thread to worker, in order. */
export type ToWorker =
  | {
      op: 'join'
      conn: number
      room: string
      name: string
      token: string | undefined
      mode: JoinMode
      /** Whether the connection may use room controls (its key). */
      controls: boolean
      /** The game the join asks for (a new room runs it; an open room must already). */
      game: string | undefined
      /** A spectator's join. */
      spectate: boolean
    }
  | { op: 'msg'; conn: number; message: RoomMessage }
  | { op: 'leave'; conn: number }
  /** Unread bytes per connection: pairs (conn, bytes). */
  | { op: 'buffered'; values: number[] }
  /** Open a room: rebuilt from its log (`log`, or its newest unclosed one with `recover`), or with a blueprint. */
  | {
      op: 'open'
      room: string
      log?: string
      recover?: boolean
      blueprint?: { name: string; scene: SceneBlueprint }
    }
  | { op: 'close-room'; room: string; code: number; reason: string }
  | { op: 'fault'; fault: WorkerFault }
  /** Benchmarks: time each loop tick's CPU on the worker's own thread too (Linux). */
  | { op: 'measure-cpu' }
  | { op: 'shutdown'; reason: string; keep: boolean }

/** Worker to main thread, in order; `at`/`len` locate a send's bytes in the batch buffer. */
export type FromWorkerOp =
  | { k: 'send'; conn: number; at: number; len: number; snap: number }
  | { k: 'error'; conn: number; code: string; reason: string; seq: number | undefined }
  | { k: 'close'; conn: number; code: number; reason: string }
  | { k: 'joined'; conn: number; player: number }
  | { k: 'refused'; conn: number; error: string; reason: string }
  | {
      k: 'strike'
      conn: number
      code: 'input-budget' | 'invalid'
      reason: string
      tick: number
      seq: number | undefined
    }
  /** A room opened here, as /rooms lists it at that moment (later once a second with the stats). */
  | { k: 'opened'; room: string; summary: RoomSummary }
  | { k: 'disposed'; room: string }
  | { k: 'recovered'; room: string; log: string; tick: number; hash: number }
  | { k: 'recover-failed'; room: string; reason: string }
  /** A recorder here created log `name` (the main thread, the one pruner, counts it as open). */
  | { k: 'log-created'; name: string }

/** One room as /rooms lists it. */
export interface RoomSummary {
  name: string
  players: number
  bodies: number
  scene: string
  tick: number
  /** The game the room runs. */
  game: string
  /** Spectators watching (join.spectate), not counted in `players`. */
  spectators: number
}

/** Worker to main thread. */
export type FromWorker =
  /** A tick ran (ticks = the worker's tick count) or a batch was answered; `buf` holds the sends' bytes. */
  | { t: 'batch'; ticks: number; buf: ArrayBuffer; ops: FromWorkerOp[] }
  /** Once a second: the rooms, the worker's metrics and the logs it writes. */
  | {
      t: 'stats'
      rooms: RoomSummary[]
      metrics: MetricObjectWithValues<MetricValue<string>>[]
      openLogs: string[]
      /** Wall time of each loop tick since the last stats (ms; for benchmarks). */
      loopMs: number[]
      /** CPU time of the worker's thread in each of those ticks (ms), once asked to measure it. */
      cpuMs: number[]
      /** Ticks the worker's clock has dropped since it started. */
      overruns: number
      /** The worker's JavaScript heap (MB). */
      heapMb: number
    }
  /** Shutdown finished: every log is closed. */
  | { t: 'closed' }
