/*
 * Lockstep benchmark (npm run bench:lockstep): numbers printed and saved to
 * bench/results/lockstep.json, not pass/fail.
 *
 * Part 1, bandwidth: a real server in this process on its 60 Hz clock, a room holding a pile of
 * 1,000 bodies, 5 snapshot-mode bots dragging bodies (bots/bots.ts driveBot, 20 Hz), one
 * snapshot-mode observer and one lockstep client (LockstepBot). Reported per room second (60
 * ticks, so a loaded machine that drops ticks does not flatter either mode): bytes received by the
 * lockstep client after its first sync against the snapshot observer's, and the first sync's size
 * on the wire and uncompressed. Then bytes and messages per room second, busy (the bots dragging)
 * and idle (the bots silent), for every client: the snapshot observer, the lockstep client (join
 * hold 2, its default) and stream-only followers joined with hold 2 (the stream before join.hold
 * existed), 30 (the predicting client's) and 60 (the largest).
 *
 * Part 2, rollback cost: what a predicting client pays per rollback, in Node: copy the confirmed
 * simulation (cloneSimulation: world save + load) and re-simulate 4, 8 or 16 ticks, in a 20-row
 * pyramid (210 boxes) and a 1,000-body pile, both awake (rollback-cost.ts; median of REPS runs
 * each). The same in Chromium: npm run bench:lockstep-browser.
 * Flags: --quick (10 s of bandwidth instead of 30).
 */
import { mkdirSync, writeFileSync } from 'node:fs'
import pino from 'pino'
import { BotClient, driveBot, LockstepBot } from '../bots/index.ts'
import { Prng, pileScene } from '../engine/index.ts'
import { loadConfig, startServer } from '../server/index.ts'
import { formatRollbackCost, measureRollbackScenes } from './rollback-cost.ts'

const quick = process.argv.includes('--quick')
const REPS = 15

/** Bytes and messages one client received in a phase, per room second. */
interface Stream {
  bytesPerSecond: number
  messagesPerSecond: number
}

/** The clients measured: counters read at the start and end of a phase. */
type Counted = Record<string, BotClient>

/** Measure every client over `seconds` of wall time; rates per room second. */
async function phase(room: { tick: number }, clients: Counted, seconds: number) {
  const start = room.tick
  const before = Object.fromEntries(
    Object.entries(clients).map(([k, c]) => [k, { bytes: c.bytesReceived, messages: c.received.length }]),
  )
  await new Promise((resolve) => setTimeout(resolve, seconds * 1000))
  const roomSeconds = (room.tick - start) / 60
  const streams: Record<string, Stream> = {}
  for (const [k, c] of Object.entries(clients)) {
    streams[k] = {
      bytesPerSecond: (c.bytesReceived - before[k].bytes) / roomSeconds,
      messagesPerSecond: (c.received.length - before[k].messages) / roomSeconds,
    }
  }
  return { roomSeconds, streams }
}

const HOLDS = [2, 30, 60]

async function bandwidth() {
  // Rooms on the main thread: the bench loads a blueprint into its room and reads its tick.
  const config = loadConfig(
    [],
    {},
    { port: 0, logLevel: 'silent', defaultScene: 'empty', maxBodies: 5000, workers: 0 },
  )
  const server = await startServer(config, { logger: pino({ level: 'silent' }), processMetrics: false })
  const url = server.url
  const room = server.rooms.getOrCreate('bw')
  if (!room) throw new Error('no room')
  room.loadBlueprint('pile-1000', pileScene(1000))
  const bots: BotClient[] = []
  for (let i = 0; i < 5; i++) bots.push(await BotClient.connect({ url, room: 'bw', name: `bot ${i + 1}` }))
  const prngs = bots.map((_, i) => new Prng(i + 1))
  let step = 0
  const drive = setInterval(() => {
    step++
    bots.forEach((b, i) => {
      driveBot(b, prngs[i], step)
    })
  }, 50)
  const observer = await BotClient.connect({ url, room: 'bw', name: 'observer' })
  // Followers that only count the stream (no simulation), one per join.hold; hold 2 is the
  // server's default, the stream every follower had before join.hold.
  const held: Counted = {}
  for (const hold of HOLDS) {
    const f = await BotClient.connect({ url, room: 'bw', name: `hold ${hold}`, mode: 'lockstep', hold })
    held[`hold${hold}`] = f
  }
  const lockstep = await LockstepBot.connect({ url, room: 'bw', name: 'lockstep' })
  await lockstep.waitFor(() => lockstep.runner.state === 'running', 'first sync', 300_000)
  const syncWire = lockstep.runner.stats.syncWireBytes
  const syncRaw = lockstep.runner.stats.syncBytes
  // Measure after a settling second.
  await new Promise((resolve) => setTimeout(resolve, 1000))
  const clients: Counted = { snapshot: observer, lockstep: lockstep.bot, ...held }
  const busy = await phase(room, clients, quick ? 10 : 30)
  clearInterval(drive)
  // Idle: the bots stay but send nothing; a second for the last commands to pass.
  await new Promise((resolve) => setTimeout(resolve, 1000))
  const idle = await phase(room, clients, quick ? 8 : 20)
  const result = {
    roomSeconds: busy.roomSeconds,
    bodies: room.world.bodyCount,
    lockstepBytesPerSecond: busy.streams.lockstep.bytesPerSecond,
    snapshotBytesPerSecond: busy.streams.snapshot.bytesPerSecond,
    busy: busy.streams,
    idleRoomSeconds: idle.roomSeconds,
    idle: idle.streams,
    syncWireBytes: syncWire,
    syncUncompressedBytes: syncRaw,
    lockstepDesyncs: lockstep.runner.stats.desyncs,
    lockstepVerifiedTick: lockstep.runner.stats.verifiedTick,
    roomTick: room.tick,
  }
  await Promise.all([...bots.map((b) => b.close()), observer.close(), lockstep.close()])
  await Promise.all(Object.values(held).map((b) => b.close()))
  await server.close()
  return result
}

const loadAverage = async (): Promise<number[]> => (await import('node:os')).loadavg()

const results: Record<string, unknown> = { date: new Date().toISOString(), loadBefore: await loadAverage() }
const rollback = measureRollbackScenes(REPS)
results.rollbackNode = rollback
for (const [name, r] of Object.entries(rollback)) console.log(formatRollbackCost('Node', name, r))
const bw = await bandwidth()
results.bandwidth = bw
console.log(
  `bandwidth, pile of ${bw.bodies} bodies, 5 bots dragging, over ${bw.roomSeconds.toFixed(1)} room seconds: ` +
    `lockstep ${(bw.lockstepBytesPerSecond / 1000).toFixed(2)} kB/s, snapshot ${(bw.snapshotBytesPerSecond / 1000).toFixed(2)} kB/s; ` +
    `first sync ${(bw.syncWireBytes / 1000).toFixed(1)} kB on the wire (${(bw.syncUncompressedBytes / 1000).toFixed(1)} kB uncompressed); ` +
    `lockstep desyncs ${bw.lockstepDesyncs}`,
)
const rates = (streams: Record<string, Stream>): string =>
  Object.entries(streams)
    .map(
      ([k, v]) => `${k} ${(v.bytesPerSecond / 1000).toFixed(2)} kB/s ${v.messagesPerSecond.toFixed(1)} msg/s`,
    )
    .join(', ')
console.log(`busy (${bw.roomSeconds.toFixed(1)} room s): ${rates(bw.busy)}`)
console.log(`idle (${bw.idleRoomSeconds.toFixed(1)} room s): ${rates(bw.idle)}`)
results.loadAfter = await loadAverage()
const file = `bench/results/lockstep${quick ? '-quick' : ''}.json`
mkdirSync('bench/results', { recursive: true })
writeFileSync(file, `${JSON.stringify(results, null, 2)}\n`)
console.log(`saved ${file}`)
process.exit(0)
