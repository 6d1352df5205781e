/*
 * A room worker thread (started by worker-pool.ts): its own RoomManager and tick clock, the rooms
 * the main thread places here (each a whole Room: simulation, snapshots, recorder, lockstep feed),
 * and its own recorders. Clients are WorkerConnections; what the rooms send leaves in one batch per
 * tick (worker-outbox.ts). Once a second it posts its rooms and its metrics (labelled with the
 * worker's id) for /rooms and /metrics. Messages from the main thread are handled in order; a room
 * being rebuilt from its log holds back everything after it until it is open, so a client that
 * rejoins at once finds the recovered room, never a new empty one.
 */
import { parentPort, workerData } from 'node:worker_threads'
import pino from 'pino'
import { Counter } from 'prom-client'
import { TICK_RATE } from '../../shared/index.ts'
import { importGameBundles } from '../games/index.ts'
import { createMetrics } from '../hosting/index.ts'
import { Recordings } from '../replay/index.ts'
import { handleRoomMessage, RoomManager, roomSummary } from '../rooms/index.ts'
import { StretchTimer } from './thread-cpu.ts'
import { Outbox, WorkerConnection } from './worker-outbox.ts'
import type { FromWorker, ToWorker, WorkerFault, WorkerInit } from './worker-protocol.ts'

const port = parentPort
if (!port) throw new Error('room-worker.ts runs only as a worker thread')
const { id, config, phase, games } = workerData as WorkerInit
// The games loaded from --games DIR, before any room can open (the main thread checked them).
await importGameBundles(games ?? [])
const log = pino({ level: config.logLevel }).child({ worker: id })
const metrics = createMetrics(false)
metrics.registry.setDefaultLabels({ worker: String(id) })
const bytesOut = new Counter({
  name: 'concord_worker_bytes_out_total',
  help: 'Bytes the rooms of a worker sent to their clients',
  registers: [metrics.registry],
})
const rooms = new RoomManager(config, metrics, log, undefined, `worker-${id}`)
const recordings = new Recordings(config, metrics, log)
const outbox = new Outbox()
const conns = new Map<number, WorkerConnection>()
/** Test faults: rooms that busy-wait in every tick. */
const busy = new Map<string, number>()

recordings.hook(rooms)
recordings.quiet = true
const recordingsReady = recordings.prepare()
const created = rooms.onRoomCreated
rooms.onRoomCreated = (room) => {
  created?.(room)
  outbox.push({ k: 'opened', room: room.name, summary: roomSummary(room) })
}
rooms.onRoomDisposed = (name) => {
  busy.delete(name)
  outbox.push({ k: 'disposed', room: name })
}
// The main thread prunes the replay directory: it knows every worker's open logs.
recordings.onLogCreated = (name) => outbox.push({ k: 'log-created', name })
recordings.onRecovered = (room, logName, tick, hash) =>
  outbox.push({ k: 'recovered', room, log: logName, tick, hash })
rooms.onTick = (ticks) => {
  flush(ticks, true)
  if (ticks % TICK_RATE === 0) void postStats()
}
rooms.beforeRoomTick = (room) => {
  const ms = busy.get(room.name)
  if (ms === undefined) return
  const until = performance.now() + ms
  while (performance.now() < until) {
    // A pathological room (test fault): holds its worker's thread.
  }
}

/** Loop tick durations since the last stats (ms), and their CPU time on this thread once measured. */
let loopMs: number[] = []
let cpuMs: number[] = []
let measureCpu = false
/** The loop tick's CPU time on this thread (thread-cpu.ts). */
const cpuTimer = new StretchTimer()
process.on('exit', () => cpuTimer.close())
const tickAll = rooms.tickAll.bind(rooms)
rooms.tickAll = () => {
  const start = performance.now()
  if (measureCpu) cpuTimer.start()
  tickAll()
  loopMs.push(performance.now() - start)
  if (measureCpu) cpuMs.push(cpuTimer.stop())
}

let lastTicks = 0
function flush(ticks: number, always: boolean): void {
  lastTicks = ticks
  bytesOut.inc(outbox.bytesOut)
  outbox.bytesOut = 0
  const batch = outbox.take(ticks, always)
  if (batch) port?.postMessage(batch.message, batch.transfer)
}

async function postStats(): Promise<void> {
  const message: FromWorker = {
    t: 'stats',
    rooms: rooms.list().map(roomSummary),
    metrics: await metrics.registry.getMetricsAsJSON(),
    openLogs: [...recordings.openNames],
    loopMs,
    cpuMs,
    overruns: rooms.clock.overruns,
    heapMb: process.memoryUsage().heapUsed / 2 ** 20,
  }
  loopMs = []
  cpuMs = []
  port?.postMessage(message)
}

/** Ops waiting behind a room being rebuilt from its log. */
const waiting: ToWorker[] = []
let blocked = false

port.on('message', (ops: ToWorker[]) => {
  waiting.push(...ops)
  drain()
})

function drain(): void {
  while (!blocked && waiting.length > 0) {
    const op = waiting.shift() as ToWorker
    try {
      handle(op)
    } catch (error) {
      log.error({ err: error, op: op.op }, 'room worker failed handling a message')
    }
  }
  flush(lastTicks, false)
}

function handle(op: ToWorker): void {
  switch (op.op) {
    case 'join': {
      const conn = new WorkerConnection(op.conn, outbox)
      const room = rooms.getOrCreate(op.room, op.game)
      if (!room) {
        const error = `the server has reached its limit of ${config.maxRooms} rooms`
        outbox.push({ k: 'refused', conn: op.conn, error, reason: 'too many rooms' })
        return
      }
      const joined = room.join(conn, op.name, op.token, op.mode, op.controls, op.game, op.spectate)
      if (typeof joined === 'string') {
        outbox.push({ k: 'refused', conn: op.conn, error: joined, reason: joined })
        return
      }
      conn.player = joined
      conns.set(op.conn, conn)
      outbox.push({ k: 'joined', conn: op.conn, player: joined.id })
      return
    }
    case 'msg': {
      const player = conns.get(op.conn)?.player
      const room = player ? rooms.get(player.room) : undefined
      if (!player || !room || !player.joined) return
      handleRoomMessage(room, player, op.message, rooms.clock.fraction, (code, reason, tick, seq) =>
        outbox.push({ k: 'strike', conn: op.conn, code, reason, tick, seq }),
      )
      return
    }
    case 'leave': {
      const player = conns.get(op.conn)?.player
      conns.delete(op.conn)
      if (player) rooms.get(player.room)?.leave(player)
      return
    }
    case 'buffered':
      for (let i = 0; i < op.values.length; i += 2) {
        const conn = conns.get(op.values[i])
        if (conn) conn.unread = op.values[i + 1]
      }
      return
    case 'open':
      open(op)
      return
    case 'close-room':
      rooms.close(op.room, op.code, op.reason)
      return
    case 'fault':
      fault(op.fault)
      return
    case 'measure-cpu':
      if (StretchTimer.available()) measureCpu = true
      else
        log.warn(
          'no per-thread CPU time here (no /proc/thread-self/schedstat); loop ticks are timed in wall time only',
        )
      return
    case 'shutdown':
      void shutdown(op.reason, op.keep)
      return
  }
}

/** Open a room; one rebuilt from a log holds back the ops after it until it is open. */
function open(op: Extract<ToWorker, { op: 'open' }>): void {
  if (!op.log && !op.recover) {
    const room = rooms.getOrCreate(op.room)
    if (room && op.blueprint) room.loadBlueprint(op.blueprint.name, op.blueprint.scene)
    return
  }
  blocked = true
  const rebuild = async (): Promise<void> => {
    if (!(await recordingsReady)) return
    const name = op.log ?? (await recordings.unclosedLogOf(op.room))
    if (name) await recordings.reopen(rooms, name)
  }
  rebuild()
    .catch((error: Error) => {
      log.error({ room: op.room, err: error.message }, 'cannot recover a room from its log')
      outbox.push({ k: 'recover-failed', room: op.room, reason: error.message })
    })
    .finally(() => {
      // Not recovered (no log, or it failed): the room opens empty, as a new room would.
      rooms.getOrCreate(op.room)
      blocked = false
      drain()
    })
}

function fault(f: WorkerFault): void {
  if (f.kind === 'exit') process.exit(70)
  busy.set(f.room, f.ms)
}

async function shutdown(reason: string, keep: boolean): Promise<void> {
  rooms.clock.stop()
  await recordings.closeAll(reason, keep)
  flush(lastTicks, true)
  port?.postMessage({ t: 'closed' } satisfies FromWorker)
}

rooms.clock.start(phase)
