/*
 * Soak (npm run soak): join/leave churn and bot play against one server for a long run (default
 * 10 minutes; --minutes M to change it), printed and saved to bench/results/soak.json.
 * Steady load: 10 rooms, each a pile of 100 never-sleeping bodies, with 3 bots dragging things
 * (a child process running bots/bots.ts). Churn: every 250 ms a client joins one of the rooms
 * or one of 20 short-lived rooms, stays 1-3 s, and leaves, so rooms open and close too.
 * The rooms run as `npm start` runs them: on one worker thread per core (--workers N to change
 * it; 0 puts every room on the main thread).
 * Every 10 s: RSS, the main thread's heap (after a full GC) and each worker's heap (as it last
 * reported it, not collected first), loop tick p50/p99 over those 10 s (wall, and CPU of the
 * loop's thread), dropped ticks, rooms, clients, churn joins so far. Growth of RSS and of the
 * heaps over the run is the leak signal.
 * Recording is on, with --replay-keep K (default 20, so that the churn rooms' logs pass it within
 * a minute): every second the process's open files (/proc/self/fd) are checked, and an open log
 * that was deleted (pruned under its writer) is counted and printed; the run fails if there is one.
 */
import { mkdirSync, readdirSync, readlinkSync, writeFileSync } from 'node:fs'
import { availableParallelism, cpus, loadavg } from 'node:os'
import { BotClient } from '../bots/index.ts'
import { Prng } from '../engine/index.ts'
import {
  awakePile,
  loopStats,
  memoryMb,
  openRoom,
  quantile,
  startBots,
  startTimedServer,
  stopBots,
  until,
  wait,
} from './server-load.ts'

const argv = process.argv.slice(2)
const minutesAt = argv.indexOf('--minutes')
const MINUTES = minutesAt >= 0 ? Number(argv[minutesAt + 1]) : 10
if (!(MINUTES > 0) || !Number.isFinite(MINUTES)) {
  throw new Error(`--minutes takes a number of minutes above 0, got ${JSON.stringify(argv[minutesAt + 1])}`)
}
const workersAt = argv.indexOf('--workers')
const WORKERS = workersAt >= 0 ? Number(argv[workersAt + 1]) : Math.min(256, availableParallelism())
if (!Number.isInteger(WORKERS) || WORKERS < 0) {
  throw new Error(`--workers takes a whole number of 0 or more, got ${JSON.stringify(argv[workersAt + 1])}`)
}
const keepAt = argv.indexOf('--replay-keep')
const KEEP = keepAt >= 0 ? Number(argv[keepAt + 1]) : 20
if (!Number.isInteger(KEEP) || KEEP < 1) {
  throw new Error(`--replay-keep takes a whole number of 1 or more, got ${JSON.stringify(argv[keepAt + 1])}`)
}
const ROOMS = 10
const BOTS_PER_ROOM = 3
const SAMPLE_MS = 10_000

// Rooms close 5 s after their last client leaves, as by default, so the churn rooms come and go.
// The piles are loaded once the bots are in: a room opened before them, empty, would close if
// the bots process took more than 5 s to start, and the bots would then join empty rooms.
const timed = await startTimedServer(WORKERS, 5, KEEP)
const { server } = timed

/** Open logs deleted under their writer, seen in /proc/self/fd once a second (Linux). */
const deletedOpenLogs = new Set<string>()
const watchFds = setInterval(() => {
  const dir = server.config.replayDir
  let fds: string[]
  try {
    fds = readdirSync('/proc/self/fd')
  } catch {
    return
  }
  for (const fd of fds) {
    let target = ''
    try {
      target = readlinkSync(`/proc/self/fd/${fd}`)
    } catch {
      continue
    }
    if (target.startsWith(`${dir}/`) && target.endsWith(' (deleted)') && !deletedOpenLogs.has(target)) {
      deletedOpenLogs.add(target)
      console.log(`soak: an open log was deleted under its writer: ${target}`)
    }
  }
}, 1000)
const take = loopStats(timed)
const bots = startBots(server.url, 'soak', ROOMS, ROOMS * BOTS_PER_ROOM)
await until(() => server.host.playerCount >= ROOMS * BOTS_PER_ROOM, 'the bots to join')
const blueprint = awakePile(100)
for (let k = 1; k <= ROOMS; k++) openRoom(server, `soak-${k}`, blueprint)
const bodiesOf = (name: string): number =>
  server.pool
    ? (server.pool.summaries().find((r) => r.name === name)?.bodies ?? 0)
    : (server.rooms.get(name)?.world.bodyCount ?? 0)
await until(
  () => Array.from({ length: ROOMS }, (_, k) => bodiesOf(`soak-${k + 1}`)).every((n) => n >= 100),
  'the soak rooms to hold their piles',
)
console.log(
  `soak: ${MINUTES} min, ${WORKERS} worker(s), ${cpus().length} cores, load ${loadavg()[0].toFixed(2)}`,
)

const prng = new Prng(7)
let joins = 0
let failures = 0
let running = true
const churn = (async () => {
  const live: Promise<void>[] = []
  while (running) {
    const room = prng.int(2) === 0 ? `soak-${1 + prng.int(ROOMS)}` : `churn-${1 + prng.int(20)}`
    const stay = 1000 + prng.int(2000)
    live.push(
      BotClient.connect({ url: server.url, room, name: `churn ${joins}` }).then(
        async (bot) => {
          joins++
          await wait(stay)
          await bot.close()
        },
        () => {
          failures++
        },
      ),
    )
    if (live.length > 64) await Promise.all(live.splice(0, 32))
    await wait(250)
  }
  await Promise.all(live)
})()

const samples: Record<string, number>[] = []
const started = performance.now()
let dropped = take().overruns
while (performance.now() - started < MINUTES * 60_000) {
  await wait(SAMPLE_MS)
  const ticks = take()
  const mem = memoryMb()
  const rooms = server.pool ? server.pool.summaries().length : server.rooms.list().length
  const row = {
    seconds: Math.round((performance.now() - started) / 1000),
    rssMb: Number(mem.rss.toFixed(1)),
    heapMb: Number(mem.heap.toFixed(1)),
    workerHeapMb: Number(ticks.workerHeapMb.reduce((a, b) => a + b, 0).toFixed(1)),
    tickMsP50: Number(quantile(ticks.wall, 0.5).toFixed(3)),
    tickMsP99: Number(quantile(ticks.wall, 0.99).toFixed(3)),
    cpuMsP99: Number(quantile(ticks.cpu, 0.99).toFixed(3)),
    droppedTicks: ticks.overruns - dropped,
    rooms,
    clients: server.host.playerCount,
    churnJoins: joins,
    churnFailures: failures,
    load1: Number(loadavg()[0].toFixed(2)),
  }
  dropped = ticks.overruns
  samples.push(row)
  console.log(
    `${row.seconds} s: RSS ${row.rssMb} MB, heap ${row.heapMb} MB (workers ${row.workerHeapMb.toFixed(1)} MB), tick p50 ${row.tickMsP50} ms p99 ${row.tickMsP99} ms (CPU p99 ${row.cpuMsP99} ms), ` +
      `dropped ${row.droppedTicks}, rooms ${row.rooms}, clients ${row.clients}, churn joins ${joins} (failed ${failures}), load ${row.load1}`,
  )
}
running = false
await churn
await stopBots([bots])
clearInterval(watchFds)
const logsAtEnd = readdirSync(server.config.replayDir).length
await server.close()

const first = samples[0]
const last = samples[samples.length - 1]
const results = {
  started: new Date().toISOString(),
  node: process.version,
  cores: cpus().length,
  minutes: MINUTES,
  workers: WORKERS,
  rooms: ROOMS,
  botsPerRoom: BOTS_PER_ROOM,
  summary: {
    rssMbFirst: first?.rssMb,
    rssMbLast: last?.rssMb,
    heapMbFirst: first?.heapMb,
    heapMbLast: last?.heapMb,
    workerHeapMbFirst: first?.workerHeapMb,
    workerHeapMbLast: last?.workerHeapMb,
    droppedTicks: samples.reduce((n, s) => n + s.droppedTicks, 0),
    tickMsP99Max: Math.max(...samples.map((s) => s.tickMsP99)),
    cpuMsP99Max: Math.max(...samples.map((s) => s.cpuMsP99)),
    churnJoins: joins,
    churnFailures: failures,
    replayKeep: KEEP,
    logsAtEnd,
    openLogsDeleted: deletedOpenLogs.size,
  },
  samples,
}
mkdirSync('bench/results', { recursive: true })
writeFileSync('bench/results/soak.json', `${JSON.stringify(results, null, 2)}\n`)
console.log(`saved bench/results/soak.json: ${JSON.stringify(results.summary)}`)
process.exit(deletedOpenLogs.size > 0 ? 1 : 0)
