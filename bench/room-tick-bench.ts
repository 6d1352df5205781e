/*
 * The room tick on one thread (npm run bench:room-tick): numbers printed and saved to
 * bench/results/room-tick.json, never pass/fail.
 *
 * What one room worker does per loop tick, without sockets, bots processes or other threads: N
 * rooms (default 10, what each of 2 workers holds at 20 rooms) of the capacity benchmark's scene
 * (a pile of 100 bodies that never sleep), each with 5 simulated players on the bots' schedule
 * (bots/bots.ts at 20 Hz: 3 spawns, then grab a random dynamic body, drag it around a circle
 * for 80 steps, release), through the real RoomManager, Room, recorder (on, as the server's
 * default, into a temporary directory) and worker Outbox, whose batch is posted to a
 * MessageChannel each tick. Every snapshot is acknowledged one tick later, as a client on
 * loopback would. Each loop tick is timed in this thread's CPU time (server/workers/thread-cpu.ts) and in wall
 * time; the summary splits the ticks into snapshot ticks of room 1, the other ticks, and the
 * once-a-second checkpoint ticks (hash, sweep, recorder flush), so the cost of each kind of work
 * shows. The inputs are deterministic, so the bytes sent per tick are the same from run to run
 * (a change that should keep the wire bytes must keep that figure).
 *
 * Compare versions in interleaved runs (CPU time still varies with the machine's load).
 * Flags: --rooms N, --ticks N (measured, default 1800), --warmup N (default 300), --no-record.
 *
 * A game's tick cost: --game NAME runs every room with that game (default sandbox; any game in
 * games/index.ts's catalogue) over the same 100-body pile, so the difference
 * from a sandbox run is what the game's rules cost (its tick hook, its state in the hashes);
 * --game-world keeps the game's own world (its setup) instead of the pile. The players' commands
 * that the game does not list are refused, so compare games with --idle (players join and send
 * nothing) unless both list the bots' commands (spawn, grab, move, release). Saved to
 * bench/results/room-tick-GAME[-world][-idle].json unless it is the default run.
 *
 * The same bodies under two games: --world-of OTHER gives every room the world OTHER's setup
 * builds with the room's five players joined (a reference RoomSimulation of OTHER, its world
 * saved and loaded into each room), so `--world-of goal` runs sandbox rooms holding a goal
 * match's bodies (pitch, gates, goals, ball, five discs), to compare with `--game goal
 * --game-world`. --play replaces the bots' schedule by the game's own play at the same 20 Hz: in a
 * goal room each player runs its disc (`run` at 6 m/s, a direction drawn from its PRNG, held for
 * 20 sends); in a sandbox room it grabs one dynamic body (with --world-of goal, its disc) and drags
 * it the same way (`move` to 2 m from the body in that direction), so the same bodies move. Saved as room-tick-GAME[-world][-of-OTHER][-idle|-play].json.
 */
import { mkdirSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs'
import { loadavg, tmpdir } from 'node:os'
import { join } from 'node:path'
import { MessageChannel } from 'node:worker_threads'
import pino from 'pino'
import { botCommand } from '../bots/index.ts'
import { loadWorld, Prng } from '../engine/index.ts'
import { findGame, GAMES, MAX_SPEED } from '../games/index.ts'
import {
  createMetrics,
  handleRoomMessage,
  loadConfig,
  Outbox,
  Recordings,
  RoomManager,
  type RoomPlayer,
  StretchTimer,
  WorkerConnection,
} from '../server/index.ts'
import { type Command, RoomSimulation } from '../shared/index.ts'
import { awakePile, quantile } from './server-load.ts'

const argv = process.argv.slice(2)
const flag = (name: string, fallback: number): number => {
  const i = argv.indexOf(name)
  const value = i >= 0 ? Number(argv[i + 1]) : fallback
  if (!Number.isInteger(value) || value < 1)
    throw new Error(`${name} must be a positive integer, got ${argv[i + 1]}`)
  return value
}
const ROOMS = flag('--rooms', 10)
const TICKS = flag('--ticks', 1800)
const WARMUP = flag('--warmup', 300)
const RECORD = !argv.includes('--no-record')
const PLAYERS = 5
const option = (name: string): string | undefined => {
  const i = argv.indexOf(name)
  return i >= 0 ? argv[i + 1] : undefined
}
const GAME = option('--game') ?? 'sandbox'
const GAME_WORLD = argv.includes('--game-world')
const IDLE = argv.includes('--idle')
const PLAY = argv.includes('--play')
const WORLD_OF = option('--world-of')
for (const name of [GAME, WORLD_OF ?? GAME])
  if (!findGame(name))
    throw new Error(
      `--game/--world-of ${name}: no such game (this build has ${Object.keys(GAMES).join(', ')})`,
    )
if (IDLE && PLAY) throw new Error('--idle and --play exclude each other')

/** The world WORLD_OF's setup builds with PLAYERS players joined, saved (see the file comment). */
function worldOf(name: string): Uint8Array {
  const game = findGame(name)
  if (!game) throw new Error(`no game ${name}`)
  const ref = new RoomSimulation({ game, name: 'reference', scene: 'empty', maxBodies: 5000, controls: true })
  for (let p = 1; p <= PLAYERS; p++) {
    const refused = ref.join(p, `player ${p}`, '#888888')
    if (refused) throw new Error(refused)
  }
  return ref.world.save()
}

const replayDir = mkdtempSync(join(tmpdir(), 'concord-room-tick-'))
const config = loadConfig(
  [],
  {},
  {
    logLevel: 'silent',
    defaultScene: 'empty',
    maxRooms: 1000,
    maxBodies: 5000,
    roomTickBudgetMs: 0,
    record: RECORD,
    replayDir,
  },
)
const log = pino({ level: 'silent' })
const metrics = createMetrics(false)
const rooms = new RoomManager(config, metrics, log, undefined, 'bench')
const recordings = new Recordings(config, metrics, log)
recordings.hook(rooms)
await recordings.prepare()
const outbox = new Outbox()
const channel = new MessageChannel()
channel.port2.on('message', () => {})

/** Snapshots waiting for their ack: the player, the snapshot's tick, the loop tick it is acked at. */
const unacked: Array<{ player: RoomPlayer; tick: number; due: number }> = []
let loopTick = 0

/** Commands the rooms refused (each answered with an error), and the first reason. */
const refused = { count: 0, first: '' }

/** A worker connection that remembers the snapshots it is sent, so they can be acknowledged. */
class AckingConnection extends WorkerConnection {
  override sendError(code: string, reason: string, seq?: number): void {
    super.sendError(code, reason, seq)
    if (refused.count++ === 0) refused.first = `${code}: ${reason}`
  }

  override sendBytes(bytes: Uint8Array, snapshotTick?: number): void {
    super.sendBytes(bytes, snapshotTick)
    if (snapshotTick !== undefined && this.player)
      unacked.push({ player: this.player, tick: snapshotTick, due: loopTick + 1 })
  }
}

interface Player {
  conn: AckingConnection
  room: string
  prng: Prng
  step: number
  seq: number
}

const blueprint = awakePile(100)
/** --world-of's world, built once and loaded into every room. */
const otherWorld = WORLD_OF ? worldOf(WORLD_OF) : null
const players: Player[] = []
for (let r = 1; r <= ROOMS; r++) {
  const room = rooms.getOrCreate(`bench-${r}`, GAME)
  if (!room) throw new Error(`room bench-${r} was refused`)
  if (otherWorld) {
    room.sim.loadWorld(`${WORLD_OF} world`, loadWorld(otherWorld))
    room.touched = true
  } else if (GAME_WORLD) room.touched = true
  else room.loadBlueprint(blueprint.name, blueprint)
  for (let p = 1; p <= PLAYERS; p++) {
    const conn = new AckingConnection(players.length + 1, outbox)
    const joined = room.join(conn, `player ${p}`, undefined)
    if (typeof joined === 'string') throw new Error(joined)
    conn.player = joined
    players.push({ conn, room: room.name, prng: new Prng(players.length + 1), step: 0, seq: 0 })
  }
}

let sent = 0
function send(player: Player, cmd: Command): void {
  const room = rooms.get(player.room)
  const joined = player.conn.player
  if (!room || !joined) throw new Error(`player ${player.conn.id} lost its room`)
  sent++
  handleRoomMessage(room, joined, { t: 'input', seq: ++player.seq, cmd }, 0, () => {})
}

/** One step of the bots' schedule (bots/bots.ts botCommand, with the room's world as the mirror). */
function drive(player: Player): void {
  const world = rooms.get(player.room)?.world
  const cmd = botCommand(player.prng, player.step++, () =>
    world ? world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic') : [],
  )
  if (cmd) send(player, cmd)
}

/** One step of the game's own play (--play, see the file comment): a goal run, else a cursor move. */
function play(player: Player): void {
  const room = rooms.get(player.room)
  const joined = player.conn.player
  if (!room || !joined) throw new Error(`player ${player.conn.id} lost its room`)
  const turn = Math.floor(player.step++ / 20)
  const angle = new Prng(player.conn.id * 1000 + turn).next() * 2 * Math.PI
  const x = Math.round(Math.cos(angle) * MAX_SPEED * 100) / 100
  const y = Math.round(Math.sin(angle) * MAX_SPEED * 100) / 100
  sent++
  if (GAME === 'goal') {
    handleRoomMessage(room, joined, { t: 'cmd', seq: ++player.seq, k: 'run', a: { x, y } }, 0, () => {})
    return
  }
  // The sandbox moves the same bodies its way: each player holds one dynamic body (in a room
  // holding a goal match's world, its disc: the ball comes first) and drags it the same way.
  const world = room.world
  const dynamic = world.bodyIds().filter((id) => world.getBodyType(id) === 'dynamic')
  const body = dynamic[((joined.id - 1) % PLAYERS) + 1] ?? dynamic[0]
  if (body === undefined) return
  if (!room.sim.players.get(joined.id)?.grab) {
    const cmd: Command = { k: 'grab', body, lx: 0, ly: 0 }
    handleRoomMessage(room, joined, { t: 'input', seq: ++player.seq, cmd }, 0, () => {})
    return
  }
  const at = world.getPosition(body)
  const cmd: Command = { k: 'move', x: at.x + x / 3, y: at.y + y / 3 }
  handleRoomMessage(room, joined, { t: 'input', seq: ++player.seq, cmd }, 0, () => {})
}

/** The loop tick's CPU time on this thread (server/workers/thread-cpu.ts). */
const cpuTimer = new StretchTimer()

const cpu: number[] = []
const wall: number[] = []
const kinds: Array<'snapshot' | 'other' | 'checkpoint'> = []
let bytes = 0
const first = rooms.get('bench-1')
if (!first) throw new Error('room bench-1 is missing')
for (loopTick = 0; loopTick < WARMUP + TICKS; loopTick++) {
  // The players' 20 Hz loops, spread over the ticks.
  if (!IDLE)
    for (let i = 0; i < players.length; i++)
      if ((loopTick + i) % 3 === 0) {
        if (PLAY) play(players[i])
        else drive(players[i])
      }
  let kept = 0
  for (const s of unacked) {
    if (s.due <= loopTick) s.player.encoder.ack(s.tick)
    else unacked[kept++] = s
  }
  unacked.length = kept
  cpuTimer.start()
  const w0 = performance.now()
  rooms.tickAll()
  const batch = outbox.take(loopTick, true)
  if (batch) channel.port1.postMessage(batch.message, batch.transfer)
  const tickCpu = cpuTimer.stop()
  const w1 = performance.now()
  if (loopTick >= WARMUP) {
    bytes += outbox.bytesOut
    cpu.push(tickCpu)
    wall.push(w1 - w0)
    const t = first.tick
    kinds.push(t % 60 === 0 ? 'checkpoint' : t % (60 / config.snapshotRate) === 0 ? 'snapshot' : 'other')
  }
  outbox.bytesOut = 0
  // Let the recorders' writes and the channel run, as a worker's event loop would between ticks.
  if (loopTick % 10 === 0) await new Promise((resolve) => setImmediate(resolve))
}
await recordings.closeAll('bench over')
channel.port1.close()
rmSync(replayDir, { recursive: true, force: true })

const round = (x: number): number => Number(x.toFixed(3))
const mean = (xs: number[]): number => xs.reduce((a, b) => a + b, 0) / Math.max(1, xs.length)
const meanOf = (kind: string): number => round(mean(cpu.filter((_, i) => kinds[i] === kind)))
const summary = {
  game: GAME,
  world: WORLD_OF ? `${WORLD_OF}'s setup` : GAME_WORLD ? `${GAME}'s setup` : blueprint.name,
  idle: IDLE,
  play: PLAY,
  commandsSent: sent,
  commandsRefused: refused.count,
  firstRefusal: refused.first,
  rooms: ROOMS,
  playersPerRoom: PLAYERS,
  record: RECORD,
  bodiesPerRoom: first.world.bodyCount,
  cpuMsP50: round(quantile(cpu, 0.5)),
  cpuMsP99: round(quantile(cpu, 0.99)),
  cpuMsMax: round(Math.max(...cpu)),
  cpuMsMean: round(mean(cpu)),
  wallMsP50: round(quantile(wall, 0.5)),
  wallMsP99: round(quantile(wall, 0.99)),
  cpuMsMeanByTick: { snapshot: meanOf('snapshot'), other: meanOf('other'), checkpoint: meanOf('checkpoint') },
  bytesOutPerTick: Math.round(bytes / TICKS),
  load1: loadavg()[0],
}
console.log(
  `room tick, game ${GAME} on ${summary.world}, ${ROOMS} rooms x ${PLAYERS} ${IDLE ? 'idle ' : PLAY ? 'playing ' : ''}players (${summary.bodiesPerRoom} bodies/room), recorder ${RECORD ? 'on' : 'off'}: ` +
    `CPU p50 ${summary.cpuMsP50} ms, p99 ${summary.cpuMsP99} ms, max ${summary.cpuMsMax} ms, mean ${summary.cpuMsMean} ms; ` +
    `mean by tick: room 1's snapshot ticks ${summary.cpuMsMeanByTick.snapshot} ms, others ${summary.cpuMsMeanByTick.other} ms, ` +
    `checkpoints ${summary.cpuMsMeanByTick.checkpoint} ms; wall p50 ${summary.wallMsP50} ms, p99 ${summary.wallMsP99} ms; ` +
    `${summary.bytesOutPerTick} bytes out per tick; ${sent} commands sent, ${refused.count} refused${refused.count ? ` (first: ${refused.first})` : ''}; load ${summary.load1.toFixed(2)}`,
)
mkdirSync('bench/results', { recursive: true })
const file =
  GAME === 'sandbox' && !IDLE && !PLAY && !GAME_WORLD && !WORLD_OF
    ? 'bench/results/room-tick.json'
    : `bench/results/room-tick-${GAME}${GAME_WORLD ? '-world' : ''}${WORLD_OF ? `-of-${WORLD_OF}` : ''}${IDLE ? '-idle' : PLAY ? '-play' : ''}.json`
writeFileSync(
  file,
  `${JSON.stringify({ started: new Date().toISOString(), node: process.version, warmupTicks: WARMUP, ticks: TICKS, summary }, null, 2)}\n`,
)
console.log(`saved ${file}`)
process.exit(0)
