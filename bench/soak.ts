/*
 * Soak (npm run soak): join/leave churn and bot play against one server for a long run (default
 * 10 minutes; --minutes M to change it), printed and saved to bench/results/soak.json.
 * Steady load: 10 rooms, each a pile of 100 never-sleeping bodies, with 3 bots dragging things
 * (a child process running bots/bots.ts). Churn: every 250 ms a client joins one of the rooms
 * or one of 20 short-lived rooms (where it drops a ball, so that the room's log is kept when it
 * closes), stays 1-3 s, and leaves, so rooms open and close too.
 * The rooms run as `npm start` runs them: on one worker thread per core (--workers N to change
 * it; 0 puts every room on the main thread).
 * Every 10 s: RSS, the main thread's heap (after a full GC) and each worker's heap (as it last
 * reported it, not collected first), loop tick p50/p99 over those 10 s (wall, and CPU of the
 * loop's thread), dropped ticks, rooms, clients, churn joins so far. Growth of RSS and of the
 * heaps over the run is the leak signal.
 * The server runs in a child process (bench/soak-server.ts: the same in-process server, its loop
 * and memory readings sent over IPC), so RSS and heaps are the server process's.
 * Recording is on, with --replay-keep K (default 20, so that the churn rooms' logs pass it within
 * a minute): every second the server process's open files (/proc/PID/fd) are checked, and an open
 * log that was deleted (pruned under its writer) is counted and printed.
 * At the end the churn stops and its rooms close, every open room is noted with its tick (GET /rooms), the server
 * process is SIGKILLed while the bots play, and a second server (server/main.ts, --recover true)
 * starts on the same replay directory: every noted room must come back ("room recovered from its
 * log") at a tick at most 2 s before its noted one. The summary's `kill` holds the rooms open,
 * recovered and missing; the run exits 1 if an open log was deleted or a room was not recovered.
 */
import { spawn } from 'node:child_process'
import { mkdirSync, mkdtempSync, readdirSync, readlinkSync, rmSync, writeFileSync } from 'node:fs'
import { availableParallelism, cpus, loadavg, tmpdir } from 'node:os'
import { join } from 'node:path'
import { BotClient } from '../bots/index.ts'
import { Prng } from '../engine/index.ts'
import { TICK_RATE } from '../shared/index.ts'
import { startServerProcess } from '../tests/support/server-process.ts'
import { startBots, stopBots, until, wait } from './server-load.ts'

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

// The server runs in a child process (bench/soak-server.ts) so that the soak can SIGKILL it at the
// end; it records to a directory of this run's own, which a second server recovers from.
const replayDir = mkdtempSync(join(tmpdir(), 'concord-soak-replays-'))
process.on('exit', () => rmSync(replayDir, { recursive: true, force: true }))
const child = spawn(
  process.execPath,
  ['--expose-gc', '--import', 'tsx', 'bench/soak-server.ts', String(WORKERS), String(KEEP), replayDir],
  { stdio: ['ignore', 'inherit', 'inherit', 'ipc'] },
)
const childExit = new Promise<NodeJS.Signals | number | null>((resolve) =>
  child.once('exit', (code, signal) => resolve(signal ?? code)),
)
const pending = new Map<number, (value: unknown) => void>()
let nextId = 1
let serverUrl = ''
const ready = new Promise<void>((resolve, reject) => {
  childExit.then((how) => reject(new Error(`the soak's server process ended early (${how})`)))
  child.on('message', (message: { id?: number; value?: unknown; op?: string; url?: string }) => {
    if (message.op === 'ready' && message.url) {
      serverUrl = message.url
      resolve()
    } else if (message.id !== undefined) {
      pending.get(message.id)?.(message.value)
      pending.delete(message.id)
    }
  })
})
/** Ask the server process (soak-server.ts) for something. */
function ask<T>(request: Record<string, unknown>): Promise<T> {
  const id = nextId++
  return new Promise((resolve) => {
    pending.set(id, resolve as (value: unknown) => void)
    child.send({ id, ...request })
  })
}
await ready
const serverPid = child.pid as number

/** Open logs deleted under their writer, seen in /proc/<server pid>/fd once a second (Linux). */
const deletedOpenLogs = new Set<string>()
/**
 * The most files the replay directory held at one check, every log name seen there, and the most
 * file descriptors into the replay directory the server process held at one check (so a run shows
 * that the fd check saw its open logs).
 */
let logsMax = 0
let openLogFdsMax = 0
const logsSeen = new Set<string>()
const checkFds = (): void => {
  const logs = readdirSync(replayDir)
  logsMax = Math.max(logsMax, logs.length)
  for (const name of logs) logsSeen.add(name)
  let fds: string[]
  let open = 0
  try {
    fds = readdirSync(`/proc/${serverPid}/fd`)
  } catch {
    return
  }
  for (const fd of fds) {
    let target = ''
    try {
      target = readlinkSync(`/proc/${serverPid}/fd/${fd}`)
    } catch {
      continue
    }
    if (target.startsWith(`${replayDir}/`)) open++
    if (target.startsWith(`${replayDir}/`) && target.endsWith(' (deleted)') && !deletedOpenLogs.has(target)) {
      deletedOpenLogs.add(target)
      console.log(`soak: an open log was deleted under its writer: ${target}`)
    }
  }
  openLogFdsMax = Math.max(openLogFdsMax, open)
}
const watchFds = setInterval(checkFds, 1000)
// The piles are loaded once the bots are in: a room opened before them, empty, would close if
// the bots process took more than 5 s to start, and the bots would then join empty rooms.
const bots = startBots(serverUrl, 'soak', ROOMS, ROOMS * BOTS_PER_ROOM)
let players = 0
await until(() => {
  void ask<number>({ op: 'players' }).then((n) => {
    players = n
  })
  return players >= ROOMS * BOTS_PER_ROOM
}, 'the bots to join')
const soakRooms = Array.from({ length: ROOMS }, (_, k) => `soak-${k + 1}`)
await ask({ op: 'open', names: soakRooms })
let bodies: number[] = []
await until(() => {
  void ask<number[]>({ op: 'bodies', names: soakRooms }).then((n) => {
    bodies = n
  })
  return bodies.length === ROOMS && bodies.every((n) => n >= 100)
}, 'the soak rooms to hold their piles')
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
      BotClient.connect({ url: serverUrl, room, name: `churn ${joins}` }).then(
        async (bot) => {
          joins++
          // A command in a churn room, so that its log stays when it closes (the log of a room
          // where no command was applied is removed) and the logs pass --replay-keep.
          if (room.startsWith('churn-'))
            bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.3 }, x: (joins % 10) - 5, y: 8 })
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

interface ServerSample {
  rssMb: number
  heapMb: number
  workerHeapMb: number
  tickMsP50: number
  tickMsP99: number
  cpuMsP99: number
  overruns: number
  rooms: number
  clients: number
}
const samples: Record<string, number>[] = []
const started = performance.now()
let dropped = (await ask<ServerSample>({ op: 'sample' })).overruns
while (performance.now() - started < MINUTES * 60_000) {
  await wait(SAMPLE_MS)
  const at = await ask<ServerSample>({ op: 'sample' })
  const row = {
    seconds: Math.round((performance.now() - started) / 1000),
    rssMb: Number(at.rssMb.toFixed(1)),
    heapMb: Number(at.heapMb.toFixed(1)),
    workerHeapMb: Number(at.workerHeapMb.toFixed(1)),
    tickMsP50: Number(at.tickMsP50.toFixed(3)),
    tickMsP99: Number(at.tickMsP99.toFixed(3)),
    cpuMsP99: Number(at.cpuMsP99.toFixed(3)),
    droppedTicks: at.overruns - dropped,
    rooms: at.rooms,
    clients: at.clients,
    churnJoins: joins,
    churnFailures: failures,
    load1: Number(loadavg()[0].toFixed(2)),
  }
  dropped = at.overruns
  samples.push(row)
  console.log(
    `${row.seconds} s: RSS ${row.rssMb} MB, heap ${row.heapMb} MB (workers ${row.workerHeapMb.toFixed(1)} MB), tick p50 ${row.tickMsP50} ms p99 ${row.tickMsP99} ms (CPU p99 ${row.cpuMsP99} ms), ` +
      `dropped ${row.droppedTicks}, rooms ${row.rooms}, clients ${row.clients}, churn joins ${joins} (failed ${failures}), load ${row.load1}`,
  )
}
running = false
await churn

// The kill. The churn is over and its rooms close 5 s after their last client left; once none is
// open (the bots still play in theirs), the open rooms are noted with their ticks (GET /rooms) and
// the server process is SIGKILLed at once. (Killing mid-churn would race a room's idle close
// between the listing and the kill.)
type Listed = { name: string; tick: number }
const listRooms = async (): Promise<Listed[]> =>
  ((await (await fetch(`${serverUrl}/rooms`)).json()) as Listed[]).sort((a, b) =>
    a.name.localeCompare(b.name),
  )
for (let waited = 0; waited < 60; waited++) {
  if (!(await listRooms()).some((r) => r.name.startsWith('churn-'))) break
  await wait(500)
}
checkFds()
const openAtKill = await listRooms()
child.kill('SIGKILL')
const killedBy = await childExit
clearInterval(watchFds)
await stopBots([bots])
const logsAtEnd = readdirSync(replayDir).length

// A second server on the same directory recovers the rooms: each must come back at a tick no more
// than RECOVERY_SLACK_S before its noted one (logs are fsynced once a second; with workers the
// noted tick is the worker's last once-a-second report, so it is itself up to a second old).
const RECOVERY_SLACK_S = 2
const recovering = await startServerProcess([
  '--replay-dir',
  replayDir,
  '--recover',
  'true',
  '--workers',
  String(WORKERS),
  '--replay-keep',
  String(KEEP),
  '--default-scene',
  'empty',
  '--max-rooms',
  '1000',
  '--max-bodies',
  '5000',
])
const recoveredTicks = new Map<string, number>()
const readRecovered = (): void => {
  for (const line of recovering.lines)
    if (
      line.msg === 'room recovered from its log' &&
      typeof line.room === 'string' &&
      typeof line.tick === 'number'
    )
      recoveredTicks.set(line.room, line.tick)
}
// The rooms are rebuilt before the server listens; their workers' log lines may come a moment later.
await until(
  () => {
    readRecovered()
    return openAtKill.every((r) => recoveredTicks.has(r.name))
  },
  'every room open at the kill to be recovered',
  30_000,
).catch(() => readRecovered())
recovering.process.kill('SIGTERM')
await recovering.exited
const missing: string[] = []
const late: { room: string; noted: number; recovered: number }[] = []
for (const room of openAtKill) {
  const tick = recoveredTicks.get(room.name)
  if (tick === undefined) missing.push(room.name)
  else if (tick < room.tick - RECOVERY_SLACK_S * TICK_RATE)
    late.push({ room: room.name, noted: room.tick, recovered: tick })
}
const lags = openAtKill
  .filter((r) => recoveredTicks.has(r.name))
  .map((r) => r.tick - (recoveredTicks.get(r.name) ?? 0))
const kill = {
  killedBy,
  roomsOpen: openAtKill.length,
  roomsRecovered: openAtKill.length - missing.length,
  missing,
  recoveredTooEarly: late,
  maxTicksBehindNoted: lags.length > 0 ? Math.max(...lags) : null,
  slackTicks: RECOVERY_SLACK_S * TICK_RATE,
  rooms: openAtKill.map((r) => ({
    room: r.name,
    noted: r.tick,
    recovered: recoveredTicks.get(r.name) ?? null,
  })),
  recoveredNotNoted: [...recoveredTicks.keys()].filter((name) => !openAtKill.some((r) => r.name === name)),
}
console.log(
  `soak: SIGKILL (${killedBy}) with ${kill.roomsOpen} rooms open; ${kill.roomsRecovered} recovered` +
    (missing.length > 0 ? `; MISSING ${missing.join(', ')}` : '') +
    (late.length > 0 ? `; recovered more than ${RECOVERY_SLACK_S} s back: ${JSON.stringify(late)}` : '') +
    `; ticks noted -> recovered: ${kill.rooms.map((r) => `${r.room} ${r.noted} -> ${r.recovered}`).join(', ')}`,
)

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
    logsMax,
    logsSeen: logsSeen.size,
    openLogFdsMax,
    openLogsDeleted: deletedOpenLogs.size,
    kill,
  },
  samples,
}
mkdirSync('bench/results', { recursive: true })
writeFileSync('bench/results/soak.json', `${JSON.stringify(results, null, 2)}\n`)
console.log(`saved bench/results/soak.json: ${JSON.stringify(results.summary)}`)
process.exit(deletedOpenLogs.size > 0 || missing.length > 0 || late.length > 0 ? 1 : 0)
