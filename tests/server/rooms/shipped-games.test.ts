/*
 * The goal and tower games over real sockets: a server on 127.0.0.1 with rooms on worker threads
 * (as `npm start` runs them) and real WebSocket clients joining each game by name (`join.game`).
 * Goal: a striker whose commands are computed from a lockstep replica of the room (the script of
 * tests/games/scripted-players.ts, closed-loop, so the network's delay does not matter) scores
 * against a team that keeps out of the way; the goal reaches the other (snapshot) player as a
 * `game` event with the score 1-0, and the lockstep replica, a player too, holds the same score
 * with every hash checkpoint matched. Tower: five squares dropped on the lane centre measure 5 m
 * (within 5 mm a block, tests/games/tower.test.ts) in the lockstep replica, with no desync; bad
 * block arguments are refused by field before the game sees them.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { DROP_COOLDOWN, type GoalState, type TowerState } from '../../../games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage, GameCommand, RoomSimulation, ServerMessage } from '../../../shared/index.ts'
import { benchCommands, strikerCommands } from '../../games/scripted-players.ts'
import { startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // A striker that misjudges its reach has kicks refused by the game, and each refusal is a strike.
  server = await startTestServer({ maxRejects: 10_000 })
})
afterAll(async () => {
  await server?.close()
})

type GameMessage = Extract<ServerMessage, { t: 'game' }>
const isError = (m: ServerMessage): m is ErrorMessage => m.t === 'error'

/**
 * Every 50 ms, send `bot` the commands `script` computes for it from the replica's simulation
 * (the newest commands of a kind only, as a client would); returns the stop function.
 */
function drive(
  bot: BotClient,
  replica: LockstepBot,
  script: (sim: RoomSimulation, player: number) => GameCommand[],
): () => void {
  const timer = setInterval(() => {
    const sim = replica.runner.sim
    if (!sim) return
    const commands = script(sim, bot.mirror.clientId)
    for (const c of commands) bot.gameCommand(c.kind, c.a as Record<string, unknown>)
  }, 50)
  return () => clearInterval(timer)
}

describe('the shipped games over real sockets', { timeout: 90_000 }, () => {
  it('goal: a striker scores against a team out of the way; the snapshot player and the lockstep replica see 1-0', async () => {
    const red = await BotClient.connect({ url: server.url, room: 'goal-1', name: 'red', game: 'goal' })
    const welcome = red.received.find((m) => m.t === 'welcome')
    expect(welcome?.t === 'welcome' && welcome.rules).toMatchObject({
      game: 'goal',
      commands: ['kick', 'rematch', 'run'],
      builtins: [],
      scenes: [],
    })
    const blue = await BotClient.connect({ url: server.url, room: 'goal-1', name: 'blue', game: 'goal' })
    const replica = await LockstepBot.connect({
      url: server.url,
      room: 'goal-1',
      name: 'replica',
      game: 'goal',
    })
    await replica.waitFor(() => replica.runner.sim !== null, 'the sync')
    const state = () => replica.runner.sim?.gameState as GoalState
    expect(state().players[red.mirror.clientId].team).toBe('red')
    expect(state().players[blue.mirror.clientId].team).toBe('blue')

    const refused = red.gameCommand('kick', { power: 3 })
    const error = await red.nextMessage((m): m is ErrorMessage => isError(m) && m.seq === refused)
    expect([error.code, error.reason]).toEqual(['invalid', 'kick refused: power must be <= 1'])

    const stops = [
      drive(red, replica, (sim, p) => strikerCommands(sim, p, 1)),
      drive(blue, replica, (sim, p) => benchCommands(sim, p, 1)),
    ]
    try {
      const scored = await blue.nextMessage(
        (m): m is GameMessage => m.t === 'game' && m.events.some((e) => (e as { goal?: string }).goal),
      )
      expect(scored.events).toContainEqual({ goal: 'red', score: { red: 1, blue: 0 } })
    } finally {
      for (const stop of stops) stop()
    }
    await replica.waitFor(() => state().score.red === 1, 'the goal in the lockstep replica')
    expect(state().score).toEqual({ red: 1, blue: 0 })
    const checked = replica.runner.stats.hashesChecked
    await replica.waitFor(() => replica.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    expect(replica.runner.stats.desyncs, replica.runner.lastProblem).toBe(0)
    const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string; game: string }>
    expect(rooms.find((r) => r.name === 'goal-1')?.game).toBe('goal')
    await Promise.all([red.close(), blue.close(), replica.close()])
  })

  it('tower: five squares measure 5 m in the lockstep replica, with no desync; bad blocks are refused by field', async () => {
    const builder = await BotClient.connect({ url: server.url, room: 'tower-1', name: 'b', game: 'tower' })
    const replica = await LockstepBot.connect({ url: server.url, room: 'tower-1', name: 'r', game: 'tower' })
    await replica.waitFor(() => replica.runner.sim !== null, 'the sync')
    const state = () => replica.runner.sim?.gameState as TowerState
    const me = builder.mirror.clientId
    expect(state().lanes).toEqual({ [me]: 0, [replica.runner.playerId]: 1 })

    const bad = builder.gameCommand('block', { kind: 'cube', x: 0 })
    const error = await builder.nextMessage((m): m is ErrorMessage => isError(m) && m.seq === bad)
    expect(error.reason).toBe('block refused: kind must be equal to one of the allowed values')

    for (let n = 1; n <= 5; n++) {
      // Drop one and wait until the replica has it; a drop within the cooldown is refused, so try again.
      await replica.waitFor(() => {
        const sim = replica.runner.sim as RoomSimulation
        const last = state().lastDrop[me]
        if (last === undefined || sim.tick - last > DROP_COOLDOWN + 10)
          builder.gameCommand('block', { kind: 'square', x: 0 })
        return Object.values(state().blocks).filter((b) => b.owner === me).length === n
      }, `block ${n}`)
    }
    await replica.waitFor(() => Math.abs(state().height[me] - 5) < 0.025, 'the tower measured 5 m', 30_000)
    expect(state().fallen[me]).toBe(0)
    const checked = replica.runner.stats.hashesChecked
    await replica.waitFor(() => replica.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    expect(replica.runner.stats.desyncs, replica.runner.lastProblem).toBe(0)
    await Promise.all([builder.close(), replica.close()])
  })
})
