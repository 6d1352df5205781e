/*
 * A SIGKILLed server recovers game rooms mid-match (issue 29), as real processes: a server with
 * recording, recovery and --replay-fsync always, rooms on a worker thread, runs a goal-game room
 * (games/goal) with two real WebSocket players and a hoops room (examples/games, loaded with
 * --games) with one. Red dribbles the ball into the right goal with `run` commands (blue steps out
 * of the way), a goal is scored, and hoops shots fly. The server is SIGKILLed and restarted on the
 * same replay directory: each room comes back at the last hash checkpoint its log holds (one a
 * second, 60 ticks, and at every flush), no earlier than the last one read from the file before
 * the kill, with the hash the killed server recorded there (the state hash mixes the
 * game's state and PRNG in: PROTOCOL.md, Lockstep and predict), and a lockstep spectator joining
 * the recovered goal room receives the score, the match's start tick (so the match clock, tick -
 * startTick, is the live one at that tick) and the phase.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { findGame, type GoalState } from '../../../games/index.ts'
import { loadGameDirectory } from '../../../server/games/game-loader.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import type { PlainData, ServerMessage } from '../../../shared/index.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children)
    if (c.process.exitCode === null && c.process.signalCode === null) c.process.kill('SIGKILL')
})

async function start(dir: string): Promise<ServerProcess> {
  const server = await startServerProcess([
    ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--replay-fsync', 'always'],
    ...['--games', 'examples/games', '--workers', '1', '--room-idle-seconds', '600'],
  ])
  children.push(server)
  return server
}

/** The hash checkpoints (tick, hash) the killed server wrote to a room's log. */
async function hashRecords(dir: string, room: string): Promise<Map<number, number>> {
  const name = (await listLogNames(dir)).filter((n) => n.startsWith(`${room}-`)).pop()
  if (!name) throw new Error(`no log of room ${room}`)
  const out = new Map<number, number>()
  const reader = new ReplayLogReader()
  reader.push(new Uint8Array(await readFile(join(dir, name))), (r) => {
    if (r.type === 'hash') out.set(r.tick, r.hash)
  })
  expect(reader.finish().closed).toBe(false)
  return out
}

type GameMessage = Extract<ServerMessage, { t: 'game' }>
const gameEvents = (bot: BotClient): Array<{ tick: number; event: Record<string, PlainData> }> =>
  bot.received
    .filter((m): m is GameMessage => m.t === 'game')
    .flatMap((m) => m.events.map((event) => ({ tick: m.tick, event: event as Record<string, PlainData> })))

describe('SIGKILL mid-match', { timeout: 180_000 }, () => {
  it('recovers a goal room with its score, clock and state, and a hoops room loaded with --games', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-game-kill-'))
    let server = await start(dir)
    const red = await BotClient.connect({ url: server.url, room: 'pitch', name: 'red', game: 'goal' })
    const blue = await BotClient.connect({ url: server.url, room: 'pitch', name: 'blue', game: 'goal' })
    const shooter = await BotClient.connect({ url: server.url, room: 'court', name: 'ann', game: 'hoops' })
    await red.waitFor(() => gameEvents(red).some((e) => e.event.kickoff !== undefined), 'kickoff')
    const kickoff = gameEvents(red).find((e) => e.event.kickoff !== undefined)!.event.kickoff as number

    // Blue runs up out of the way; red runs right along y = 0 through the ball on the centre
    // spot and pushes it, exactly on the x axis, into the right goal (blue defends it).
    blue.gameCommand('run', { x: 0, y: 6 })
    red.gameCommand('run', { x: 6, y: 0 })
    shooter.gameCommand('shoot', { angle: 0.9, speed: 13 })
    await red.waitFor(() => gameEvents(red).some((e) => e.event.goal !== undefined), 'a goal')
    const scored = gameEvents(red).find((e) => e.event.goal !== undefined)!
    expect(scored.event).toEqual({ goal: 'red', score: { red: 1, blue: 0 } })
    red.gameCommand('run', { x: 0, y: 0 })
    // Two more seconds of play: the log holds checkpoints after the goal (fsync always), read
    // from the file before the kill.
    let durable = 0
    await until(async () => {
      durable = Math.max(...(await hashRecords(dir, 'pitch')).keys())
      return durable >= scored.tick + 120
    }, 'a checkpoint two seconds after the goal in the log')
    const lastSeen = red.mirror.tick
    server.process.kill('SIGKILL')
    await server.exited
    await Promise.all([red.closed, blue.closed, shooter.closed])

    const goalHashes = await hashRecords(dir, 'pitch')
    const hoopsHashes = await hashRecords(dir, 'court')
    server = await start(dir)
    const recovered = new Map<string, { tick: number; hash: number }>()
    const readRecovered = () => {
      for (const l of server.lines)
        if (l.msg === 'room recovered from its log')
          recovered.set(l.room as string, { tick: l.tick as number, hash: l.hash as number })
      return recovered.has('pitch') && recovered.has('court')
    }
    // A room rebuilt on a worker logs its recovery from the worker's thread, whose output can
    // reach stdout after the main thread's "listening" (as in recovery.test.ts): wait for both.
    await until(readRecovered, 'both rooms to log their recovery').catch(() => {})
    const pitch = recovered.get('pitch')
    const court = recovered.get('court')
    if (!pitch || !court) throw new Error(`rooms recovered: ${[...recovered.keys()].join(', ')}`)
    // At the log's last checkpoint, with the hash the killed server recorded there.
    expect(pitch.tick).toBe(Math.max(...goalHashes.keys()))
    expect(pitch.hash).toBe(goalHashes.get(pitch.tick))
    expect(court.tick).toBe(Math.max(...hoopsHashes.keys()))
    expect(court.hash).toBe(hoopsHashes.get(court.tick))
    // At or after the last checkpoint read from the file just before the kill: the room lost at
    // most the ticks since (one checkpoint interval, 60 ticks, plus the last write's latency).
    expect(pitch.tick).toBeGreaterThanOrEqual(durable)
    console.log(
      `goal room: kickoff ${kickoff}, goal at ${scored.tick}, durable checkpoint ${durable} before the kill, last tick a player saw ${lastSeen}, recovered at ${pitch.tick}`,
    )

    // The recovered goal room, as a lockstep spectator receives it: score, start tick, phase;
    // the killed process's players left (their discs are gone).
    const watcher = await LockstepBot.connect({ url: server.url, room: 'pitch', name: 'w', spectate: true })
    await watcher.waitFor(() => watcher.runner.sim !== null, 'sync')
    const state = watcher.runner.sim!.gameState as GoalState
    expect(state).toMatchObject({
      phase: 'playing',
      startTick: kickoff,
      score: { red: 1, blue: 0 },
      players: {},
    })
    expect(watcher.runner.sim!.tick).toBeGreaterThanOrEqual(pitch.tick)
    await watcher.close()

    // The hoops room runs hoops again, and a lockstep spectator running the same module follows it.
    const hoops = (await loadGameDirectory('examples/games'))[0].game
    const games = (name: string) => findGame(name) ?? (name === 'hoops' ? hoops : undefined)
    const fan = await LockstepBot.connect(
      { url: server.url, room: 'court', name: 'f', spectate: true },
      'lockstep',
      16,
      games,
    )
    await fan.waitFor(() => fan.runner.stats.hashesChecked >= 2, 'two hash checkpoints')
    expect(fan.runner.sim!.game.name).toBe('hoops')
    expect(fan.runner.stats.desyncs).toBe(0)
    await fan.close()
    server.process.kill('SIGTERM')
    await until(() => server.process.exitCode !== null, 'the server to exit')
  })
})
