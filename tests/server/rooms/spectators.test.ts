/*
 * Spectators (join.spectate, PROTOCOL.md "Spectators") over real sockets, rooms on a worker
 * thread as `npm start` runs them. A room of the ball-drop game with two player slots, both
 * taken, still admits spectators up to --max-spectators (2 here) and refuses the next one with
 * `full` (4001) naming the limit; spectators are in no roster and have no cursor; every input and
 * game command of theirs is refused (`refused`, with its seq) and changes nothing; a snapshot
 * spectator sees the players' bodies and the game's events; a lockstep spectator simulates the
 * room (the game state included) with every hash matching and is no player of the simulation;
 * /rooms counts players and spectators apart. The oracle for the game is the one the game-room
 * test uses: a ball dropped at x = 0 comes to rest on the target and scores for its dropper.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import type { BallDropState } from '../../../games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage, ServerMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ maxClientsPerRoom: 2, maxSpectatorsPerRoom: 2, workers: 1 })
})
afterAll(async () => {
  await server?.close()
})

const isError = (m: ServerMessage): m is ErrorMessage => m.t === 'error'
type Players = Extract<ServerMessage, { t: 'players' }>

async function errorFor(bot: BotClient, seq: number): Promise<ErrorMessage> {
  let found: ErrorMessage | undefined
  await bot.waitFor(() => {
    found = bot.received.find((m): m is ErrorMessage => isError(m) && m.seq === seq)
    return found !== undefined
  }, `the error for seq ${seq}`)
  return found as ErrorMessage
}

describe('spectators', { timeout: 90_000 }, () => {
  it('watch a full room in snapshot and lockstep modes without a slot, a cursor or a command', async () => {
    const room = 'watched'
    const a = await BotClient.connect({ url: server.url, room, name: 'a', game: 'ball-drop' })
    const b = await BotClient.connect({ url: server.url, room, name: 'b' })
    // The room is full for players...
    const third = new BotClient({ url: server.url, room, name: 'c' })
    await third.opened
    third.join()
    expect((await third.nextMessage(isError)).code).toBe('full')
    await third.closed

    // ...but not for spectators, up to --max-spectators.
    const watcher = await BotClient.connect({ url: server.url, room, name: 'w', spectate: true })
    const follower = await LockstepBot.connect({ url: server.url, room, name: 'f', spectate: true })
    await follower.waitFor(() => follower.runner.sim !== null, 'the sync')
    const welcome = watcher.received.find((m) => m.t === 'welcome')
    expect(welcome?.t === 'welcome' && welcome.rules.maxSpectators).toBe(2)
    expect(welcome?.t === 'welcome' && welcome.players.map((p) => p.name)).toEqual(['a', 'b'])
    const extra = new BotClient({ url: server.url, room, name: 'x', spectate: true })
    await extra.opened
    extra.join()
    const full = await extra.nextMessage(isError)
    expect([full.code, full.reason]).toEqual(['full', `room ${room} has its 2 spectators (--max-spectators)`])
    await extra.closed
    expect(extra.closeCode).toBe(4001)

    // Every command of a spectator is refused with its seq, and nothing changes.
    const bodies = watcher.mirror.bodies.size
    for (const seq of [
      watcher.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 5 }),
      watcher.command({ k: 'move', x: 1, y: 1 }),
      watcher.command({ k: 'inspect', body: 1 }),
      watcher.gameCommand('drop', { x: 0 }),
    ]) {
      const error = await errorFor(watcher, seq)
      expect([error.code, error.reason]).toEqual(['refused', 'spectators send no commands'])
    }

    // A player's drop: the snapshot spectator sees the ball and the score event, the lockstep
    // spectator computes the score, and every hash matches.
    const seq = a.gameCommand('drop', { x: 0 })
    await watcher.waitFor(() => watcher.mirror.bodies.size === bodies + 1, 'the ball in the snapshots')
    const scored = await watcher.nextMessage(
      (m): m is Extract<ServerMessage, { t: 'game' }> => m.t === 'game',
    )
    expect(scored.events).toEqual([{ scored: a.mirror.clientId, ball: expect.any(Number) }])
    expect(a.received.some((m) => isError(m) && m.seq === seq)).toBe(false)
    await follower.waitFor(() => {
      const state = follower.runner.sim?.gameState as BallDropState | undefined
      return state?.scores[a.mirror.clientId] === 1
    }, 'the score in the lockstep simulation')
    const checked = follower.runner.stats.hashesChecked
    await follower.waitFor(() => follower.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    expect(follower.runner.stats.desyncs, follower.runner.lastProblem).toBe(0)
    const sim = follower.runner.sim
    if (!sim) throw new Error('the lockstep spectator has no simulation')
    const ids = [a.mirror.clientId, b.mirror.clientId].sort((x, y) => x - y)
    expect([...sim.players.keys()].sort((x, y) => x - y)).toEqual(ids)
    const scores = (sim.gameState as BallDropState).scores
    expect(Object.keys(scores).map(Number)).toEqual(ids)

    // No roster entry, no cursor; /rooms counts them apart.
    const lastRoster = (bot: BotClient): string[] =>
      (bot.received.filter((m): m is Players => m.t === 'players').at(-1)?.players ?? []).map((p) => p.name)
    expect(lastRoster(a)).toEqual(['a', 'b'])
    expect(a.mirror.cursors.has(watcher.mirror.clientId)).toBe(false)
    const listed = async () =>
      ((await (await fetch(`${server.url}/rooms`)).json()) as Array<Record<string, unknown>>).find(
        (r) => r.name === room,
      )
    await until(async () => (await listed())?.spectators === 2, '/rooms to count 2 spectators')
    expect(await listed()).toMatchObject({ players: 2, spectators: 2, game: 'ball-drop' })

    // A spectator's leave frees a spectator place and tells the players nothing.
    const rosters = a.received.filter((m) => m.t === 'players').length
    await watcher.close()
    const again = await BotClient.connect({ url: server.url, room, name: 'w2', spectate: true })
    expect(again.mirror.clientId).toBeGreaterThan(0)
    expect(a.received.filter((m) => m.t === 'players').length).toBe(rosters)
    await Promise.all([a.close(), b.close(), follower.close(), again.close()])
  })
})
