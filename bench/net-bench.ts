/*
 * Network benchmark (npm run bench:net): numbers printed and saved to bench/results/net.json, not
 * pass/fail.
 *
 * Part 1, bandwidth: a real server and real WebSocket clients in this process, but the room clock
 * is stopped and ticks are driven here one by one, each snapshot waited for and acknowledged over
 * the socket before the next tick. So the numbers are the protocol's, independent of this
 * machine's speed, and the run takes as long as the engine needs rather than wall time.
 * Scenes: a pile of 1,000 bodies settling (first 10 s), the same pile at rest, a 20-row pyramid
 * knocked over by a fast ball, each with 1, 10 and 50 clients.
 *
 * Part 2, capacity: the server in this process on its real 60 Hz clock, 10 rooms x 10 bots (a
 * child process running bots/bots.ts), every room tick timed; reports p50/p99 tick time and
 * overruns, once in empty rooms (bots' own shapes only) and once in the default pyramid scene.
 * Part 1 also reports the snapshot encode cost per client.
 * Flags: --quick (shorter runs, fewer clients), --capacity (part 2 only).
 */
import { spawn } from 'node:child_process'
import { mkdirSync, writeFileSync } from 'node:fs'
import { performance } from 'node:perf_hooks'
import pino from 'pino'
import { BotClient } from '../bots/index.ts'
import { pileScene, pyramidScene, type SceneBlueprint } from '../engine/index.ts'
import { loadConfig, type Room, type RunningServer, startServer } from '../server/index.ts'

const silent = pino({ level: 'silent' })
const quick = process.argv.includes('--quick')

async function newServer(overrides = {}): Promise<RunningServer> {
  const config = loadConfig(
    [],
    {},
    {
      port: 0,
      logLevel: 'silent',
      defaultScene: 'empty',
      maxBodies: 5000,
      maxClientsPerRoom: 100,
      inputsPerTick: 1000,
      ...overrides,
    },
  )
  return startServer(config, { logger: silent, processMetrics: false })
}

const turn = (): Promise<void> => new Promise((resolve) => setImmediate(resolve))

interface Measure {
  seconds: number
  /** Most bodies awake at once during the run. */
  peakAwake: number
  bytesPerClient: number
  worstStalenessMs: number
  encodeMicrosPerClient: number
}

/** Drive `ticks` room ticks by hand; every snapshot is delivered and acked before going on. */
async function driveTicks(
  server: RunningServer,
  room: Room,
  bots: BotClient[],
  ticks: number,
): Promise<Measure> {
  const startBytes = bots.map((b) => b.bytesReceived)
  let worst = 0
  let peakAwake = 0
  let encodeMs = 0
  let encodes = 0
  for (const s of room.players.values()) {
    const encoder = s.encoder
    const encode = encoder.encode.bind(encoder)
    encoder.encode = (...args) => {
      const t = performance.now()
      const r = encode(...args)
      encodeMs += performance.now() - t
      encodes++
      return r
    }
  }
  for (let i = 0; i < ticks; i++) {
    room.runTick()
    worst = Math.max(worst, room.lastMaxStaleness)
    peakAwake = Math.max(peakAwake, room.world.awakeBodyCount())
    if (room.tick % (60 / server.config.snapshotRate) === 0) {
      await Promise.all(bots.map((b) => b.waitFor(() => b.mirror.tick >= room.tick)))
      // Let the acks reach the server before the next snapshot.
      await turn()
      await turn()
    }
  }
  const bytes = bots.map((b, i) => b.bytesReceived - startBytes[i])
  const seconds = ticks / 60
  return {
    seconds,
    peakAwake,
    bytesPerClient: bytes.reduce((a, b) => a + b, 0) / bots.length / seconds,
    worstStalenessMs: (worst * 1000) / 60,
    encodeMicrosPerClient: encodes ? (encodeMs * 1000) / encodes : 0,
  }
}

async function withRoom<T>(
  clients: number,
  blueprint: SceneBlueprint,
  run: (server: RunningServer, room: Room, bots: BotClient[]) => Promise<T>,
): Promise<T> {
  const server = await newServer()
  server.rooms.clock.stop()
  const room = server.rooms.getOrCreate('bench')!
  room.loadBlueprint(blueprint.name, blueprint)
  const bots: BotClient[] = []
  for (let i = 0; i < clients; i++)
    bots.push(await BotClient.connect({ url: server.url, room: 'bench', name: `c${i}` }))
  try {
    return await run(server, room, bots)
  } finally {
    await Promise.all(bots.map((b) => b.close()))
    await server.close()
  }
}

const fmt = (m: Measure): string =>
  `${m.peakAwake} awake at peak, ${(m.bytesPerClient / 1000).toFixed(2)} kB/s = ${((m.bytesPerClient * 8) / 1000).toFixed(1)} kbit/s per client, worst staleness ${m.worstStalenessMs.toFixed(0)} ms, encode ${m.encodeMicrosPerClient.toFixed(1)} us/client/snapshot`

async function bandwidth(): Promise<Record<string, unknown>> {
  const results: Record<string, unknown> = {}
  const counts = quick ? [1, 10] : [1, 10, 50]
  for (const clients of counts) {
    const pile = await withRoom(clients, pileScene(1000), async (server, room, bots) => {
      const settling = await driveTicks(server, room, bots, quick ? 300 : 600)
      let waited = 0
      while (room.world.awakeBodyCount() > 0 && waited < 60 * 60) {
        await driveTicks(server, room, bots, 60)
        waited += 60
      }
      const atRest = await driveTicks(server, room, bots, 300)
      return { settling, atRest, awakeAtRest: room.world.awakeBodyCount(), settleSeconds: 10 + waited / 60 }
    })
    console.log(`pile 1000 settling, ${clients} clients: ${fmt(pile.settling)}`)
    console.log(
      `pile 1000 at rest (${pile.awakeAtRest} awake after ${pile.settleSeconds} s), ${clients} clients: ${fmt(pile.atRest)}`,
    )
    const pyramid = await withRoom(clients, pyramidScene(20), async (server, room, bots) => {
      let waited = 0
      while (room.world.awakeBodyCount() > 0 && waited < 20 * 60) {
        await driveTicks(server, room, bots, 60)
        waited += 60
      }
      bots[0].command({ k: 'spawn', shape: { type: 'circle', radius: 1.5 }, x: -30, y: 4, vx: 60 })
      return driveTicks(server, room, bots, 600)
    })
    console.log(`pyramid 20 rows knocked over, ${clients} clients: ${fmt(pyramid)}`)
    results[`clients_${clients}`] = { pile, pyramid }
  }
  return results
}

async function capacity(scene: string): Promise<Record<string, unknown>> {
  const server = await newServer({ defaultScene: scene, inputsPerTick: 8, maxClientsPerRoom: 32 })
  const samples: number[] = []
  const roomCount = 10
  const botsPerRoom = 10
  for (let i = 1; i <= roomCount; i++) {
    const room = server.rooms.getOrCreate(`load-${i}`)!
    const runTick = room.runTick.bind(room)
    room.runTick = () => {
      const t = performance.now()
      runTick()
      samples.push(performance.now() - t)
    }
  }
  const seconds = quick ? 8 : 20
  const args = ['--import', 'tsx', 'bots/bots.ts', '--url', server.url, '--room', 'load']
  args.push(
    '--rooms',
    String(roomCount),
    '--count',
    String(roomCount * botsPerRoom),
    '--seconds',
    String(seconds),
  )
  const child = spawn(process.execPath, args, { stdio: ['ignore', 'pipe', 'inherit'] })
  const lines: string[] = []
  child.stdout.on('data', (d: Buffer) => {
    for (const line of d.toString().split('\n'))
      if (line.startsWith(`${roomCount * botsPerRoom} bots:`)) lines.push(line)
  })
  await new Promise((resolve) => child.once('exit', resolve))
  await server.close()
  const sorted = samples.slice(samples.length / 4).sort((a, b) => a - b)
  const q = (p: number): number => sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))]
  const result = {
    scene,
    rooms: roomCount,
    botsPerRoom,
    roomTicks: sorted.length,
    tickMsP50: q(0.5),
    tickMsP99: q(0.99),
    tickMsMax: sorted[sorted.length - 1],
    overruns: server.rooms.clock.overruns,
    bots: lines[Math.floor(lines.length / 2)] ?? '',
  }
  console.log(
    `capacity ${roomCount} rooms x ${botsPerRoom} bots, scene ${scene}: room tick p50 ${result.tickMsP50.toFixed(3)} ms, p99 ${result.tickMsP99.toFixed(3)} ms, max ${result.tickMsMax.toFixed(2)} ms, dropped ticks ${result.overruns}`,
  )
  console.log(`  bots (median second): ${result.bots}`)
  return result
}

const started = new Date().toISOString()
const onlyCapacity = process.argv.includes('--capacity')
const results = {
  started,
  node: process.version,
  quick,
  bandwidth: onlyCapacity ? null : await bandwidth(),
  capacity: [await capacity('empty'), await capacity('pyramid')],
}
const file = `bench/results/net${quick ? '-quick' : ''}${onlyCapacity ? '-capacity' : ''}.json`
mkdirSync('bench/results', { recursive: true })
writeFileSync(file, `${JSON.stringify(results, null, 2)}\n`)
console.log(`saved ${file}`)
