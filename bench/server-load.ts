/*
 * Shared pieces of the server load benchmarks (bench:capacity, soak): a server in this process
 * with a timed tick loop, bot processes (bots/bots.ts: each bot spawns a few shapes, then grabs
 * and drags bodies in circles), percentiles and memory readings.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { mkdtempSync, rmSync } from 'node:fs'
import { setPriority, tmpdir } from 'node:os'
import { join } from 'node:path'
import { performance } from 'node:perf_hooks'
import pino from 'pino'
import { pileScene, type SceneBlueprint } from '../engine/index.ts'
import { loadConfig, type RunningServer, startServer } from '../server/index.ts'
import { until as waitUntil } from '../tests/support/wait.ts'
import { awakeBlueprint } from './rooms-scene.ts'

/** Durations of clock ticks (ms): wall time, and the process's CPU time over the same span. */
export interface TickTimes {
  wall: number[]
  cpu: number[]
}

/** A server whose every clock tick (all rooms) is timed. */
export interface TimedServer {
  server: RunningServer
  /** Clock tick durations since the last take(). */
  take(): TickTimes
}

/**
 * Start a server in this process for load tests; every loop tick is timed. With `workers` > 0 the
 * rooms run on worker threads and their loops are timed there (WorkerPool.takeLoopStats).
 * Recordings go to `replayDir` when given (its owner removes it), else to a directory of this
 * run's own, removed when the process exits.
 */
export async function startTimedServer(
  workers = 0,
  roomIdleSeconds = 5,
  replayKeep = 200,
  replayDir?: string,
): Promise<TimedServer> {
  // Recordings go to a directory of this run's own (the server records by default). In the
  // repository's replays/ they piled up, and the logs a failed run left unfinished were recovered
  // as rooms by the next run's server: at 20 rooms a Nov 24 run ticked such leftovers beside its
  // own and averaged 74 bodies per room instead of 113.
  if (replayDir === undefined) {
    const own = mkdtempSync(join(tmpdir(), 'concord-bench-replays-'))
    process.on('exit', () => rmSync(own, { recursive: true, force: true }))
    replayDir = own
  }
  const config = loadConfig(
    [],
    {},
    {
      port: 0,
      host: '127.0.0.1',
      logLevel: 'silent',
      defaultScene: 'empty',
      maxRooms: 1000,
      maxBodies: 5000,
      maxConnections: 100000,
      // Every bot connects from 127.0.0.1: no per-address caps.
      maxConnectionsPerIp: 0,
      maxRequestsPerIp: 0,
      maxNewRoomsPerIp: 0,
      roomIdleSeconds,
      // Measure raw capacity: no room is closed for going over the per-room tick budget.
      roomTickBudgetMs: 0,
      workers,
      replayDir,
      replayKeep,
    },
  )
  const server = await startServer(config, { logger: pino({ level: 'silent' }), processMetrics: false })
  let samples: TickTimes = { wall: [], cpu: [] }
  const rooms = server.rooms
  const tickAll = rooms.tickAll.bind(rooms)
  // CPU time is what a tick would take on a core of its own; on a machine shared with other
  // work, wall time also counts the time this process waited for a core.
  rooms.tickAll = () => {
    const start = performance.now()
    const cpu = process.cpuUsage()
    tickAll()
    const used = process.cpuUsage(cpu)
    samples.wall.push(performance.now() - start)
    samples.cpu.push((used.user + used.system) / 1000)
  }
  return {
    server,
    take: () => {
      const out = samples
      samples = { wall: [], cpu: [] }
      return out
    },
  }
}

/** Loop ticks since the last call, of the main thread's loop or of every worker's. */
export interface LoopStats {
  /** Loop tick durations (ms), wall and CPU (the worker thread's own, or the process's on the main thread). */
  wall: number[]
  cpu: number[]
  /** Ticks dropped since the server started, all loops. */
  overruns: number
  /** Each worker's wall p99 (ms) over these ticks; empty without workers. */
  perWorkerP99: number[]
  /** Each worker's V8 heap (MB) as it last reported it; empty without workers. */
  workerHeapMb: number[]
}

/** A function returning the loop ticks since its last call (see LoopStats), for the server's rooms wherever they run. */
export function loopStats(timed: TimedServer): () => LoopStats {
  const { server } = timed
  return () => {
    const pool = server.pool
    if (!pool)
      return { ...timed.take(), overruns: server.rooms.clock.overruns, perWorkerP99: [], workerHeapMb: [] }
    timed.take() // the main thread's own (roomless) loop: dropped, so its samples do not pile up
    const stats = pool.takeLoopStats()
    return {
      wall: stats.flatMap((s) => s.loopMs),
      cpu: stats.flatMap((s) => s.cpuMs),
      overruns: stats.reduce((n, s) => n + s.overruns, 0),
      perWorkerP99: stats.map((s) => Number(quantile(s.loopMs, 0.99).toFixed(2))),
      workerHeapMb: stats.map((s) => Number(s.heapMb.toFixed(1))),
    }
  }
}

/** Open a room holding `blueprint`, on the main thread or on a worker. */
export function openRoom(server: RunningServer, name: string, blueprint: SceneBlueprint): void {
  if (server.pool) server.pool.open(name, { name: blueprint.name, scene: blueprint })
  else server.rooms.getOrCreate(name)?.loadBlueprint(blueprint.name, blueprint)
}

/** A pile of `count` mixed bodies that never sleep (so every one costs a full step). */
export function awakePile(count: number): SceneBlueprint {
  return { ...awakeBlueprint(pileScene(count)), name: `pile-${count}-awake` }
}

/** Start `count` bots over rooms PREFIX-1..PREFIX-rooms in a child process. */
export function startBots(url: string, prefix: string, rooms: number, count: number): ChildProcess {
  const args = ['--import', 'tsx', 'bots/bots.ts', '--url', url, '--room', prefix]
  args.push('--rooms', String(rooms), '--count', String(count), '--seconds', '0')
  const child = spawn(process.execPath, args, { stdio: ['ignore', 'ignore', 'inherit'] })
  // The bots stand in for clients on other machines: on this machine they run at the lowest CPU
  // priority, so they take what the server leaves instead of competing with its loops for a core.
  if (child.pid !== undefined) setPriority(child.pid, 19)
  return child
}

/** Stop bot processes and wait for them. */
export async function stopBots(children: ChildProcess[]): Promise<void> {
  await Promise.all(
    children.map(
      (c) =>
        new Promise<void>((resolve) => {
          if (c.exitCode !== null) return resolve()
          c.once('exit', () => resolve())
          c.kill('SIGTERM')
        }),
    ),
  )
}

/** The p-quantile (0..1) of a list of numbers (nearest rank). */
export function quantile(values: number[], p: number): number {
  if (values.length === 0) return Number.NaN
  const sorted = [...values].sort((a, b) => a - b)
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(p * sorted.length) - 1))]
}

/** Resident set size and V8 heap in MB, after a full GC when the process runs with --expose-gc. */
export function memoryMb(): { rss: number; heap: number } {
  const gc = (globalThis as { gc?: () => void }).gc
  gc?.()
  const m = process.memoryUsage()
  return { rss: m.rss / 1048576, heap: (m.heapUsed + m.external + m.arrayBuffers) / 1048576 }
}

/** Total payload bytes the server has sent. */
export async function bytesSent(server: RunningServer): Promise<number> {
  return (await server.metrics.bytesSent.get()).values[0]?.value ?? 0
}

/** Waits up to two minutes for a load condition (tests/support/wait.ts, polled every 100 ms). */
export function until(condition: () => boolean, what: string, timeoutMs = 120_000): Promise<void> {
  return waitUntil(condition, what, timeoutMs, 100)
}

/** Sleep for the measurement window (benchmarks only; never in tests). */
export function wait(ms: number): Promise<void> {
  return new Promise((resolve) => setTimeout(resolve, ms))
}
