/*
 * Soak (npm run soak): join/leave churn and bot play against one server for a long run (default
 * 10 minutes; --minutes M to change it), printed and saved to bench/results/soak.json.
 * Steady load: 10 rooms, each a pile of 100 never-sleeping bodies, with 3 bots dragging things
 * (a child process running server/bots.ts). Churn: every 250 ms a client joins one of the rooms
 * or one of 20 short-lived rooms, stays 1-3 s, and leaves, so rooms open and close too.
 * Every 10 s: RSS and heap (after a full GC), loop tick p50/p99 over those 10 s, dropped ticks,
 * rooms, clients, churn joins so far. Growth of RSS over the run is the leak signal.
 */
import { mkdirSync, writeFileSync } from 'node:fs'
import { cpus, loadavg } from 'node:os'
import { Prng } from '../engine/index.ts'
import { BotClient } from '../server/bot-client.ts'
import {
  awakePile,
  memoryMb,
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
const ROOMS = 10
const BOTS_PER_ROOM = 3
const SAMPLE_MS = 10_000

const { server, take } = await startTimedServer()
const blueprint = awakePile(100)
for (let k = 1; k <= ROOMS; k++)
  server.rooms.getOrCreate(`soak-${k}`)?.loadBlueprint(blueprint.name, blueprint)
const bots = startBots(server.url, 'soak', ROOMS, ROOMS * BOTS_PER_ROOM)
await until(() => server.rooms.playerCount >= ROOMS * BOTS_PER_ROOM, 'the bots to join')
console.log(`soak: ${MINUTES} min, ${cpus().length} cores, load ${loadavg()[0].toFixed(2)}`)

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
take()
while (performance.now() - started < MINUTES * 60_000) {
  const dropped0 = server.rooms.clock.overruns
  await wait(SAMPLE_MS)
  const ticks = take()
  const mem = memoryMb()
  const row = {
    seconds: Math.round((performance.now() - started) / 1000),
    rssMb: Number(mem.rss.toFixed(1)),
    heapMb: Number(mem.heap.toFixed(1)),
    tickMsP50: Number(quantile(ticks.wall, 0.5).toFixed(3)),
    tickMsP99: Number(quantile(ticks.wall, 0.99).toFixed(3)),
    cpuMsP99: Number(quantile(ticks.cpu, 0.99).toFixed(3)),
    droppedTicks: server.rooms.clock.overruns - dropped0,
    rooms: server.rooms.list().length,
    clients: server.rooms.playerCount,
    churnJoins: joins,
    churnFailures: failures,
    load1: Number(loadavg()[0].toFixed(2)),
  }
  samples.push(row)
  console.log(
    `${row.seconds} s: RSS ${row.rssMb} MB, heap ${row.heapMb} MB, tick p50 ${row.tickMsP50} ms p99 ${row.tickMsP99} ms (CPU p99 ${row.cpuMsP99} ms), ` +
      `dropped ${row.droppedTicks}, rooms ${row.rooms}, clients ${row.clients}, churn joins ${joins} (failed ${failures}), load ${row.load1}`,
  )
}
running = false
await churn
await stopBots([bots])
await server.close()

const first = samples[0]
const last = samples[samples.length - 1]
const results = {
  started: new Date().toISOString(),
  node: process.version,
  cores: cpus().length,
  minutes: MINUTES,
  rooms: ROOMS,
  botsPerRoom: BOTS_PER_ROOM,
  summary: {
    rssMbFirst: first?.rssMb,
    rssMbLast: last?.rssMb,
    heapMbFirst: first?.heapMb,
    heapMbLast: last?.heapMb,
    tickMsP99Max: Math.max(...samples.map((s) => s.tickMsP99)),
    cpuMsP99Max: Math.max(...samples.map((s) => s.cpuMsP99)),
    churnJoins: joins,
    churnFailures: failures,
  },
  samples,
}
mkdirSync('bench/results', { recursive: true })
writeFileSync('bench/results/soak.json', `${JSON.stringify(results, null, 2)}\n`)
console.log(`saved bench/results/soak.json: ${JSON.stringify(results.summary)}`)
process.exit(0)
