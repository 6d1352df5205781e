/*
 * A game room over real sockets (rooms on worker threads, as `npm start` runs them): a join with
 * `game` opens a room running that game (fixed for the room's life, shown in /rooms and the
 * welcome's rules); `cmd` messages are checked by the protocol (plain data, finite numbers) and
 * then against the game's JSON Schema, and a refusal names the field and echoes the seq before
 * the game sees anything; accepted commands reach a lockstep client through the tick stream
 * (kind 15), and its simulation, game state included, matches every server hash. The oracle for
 * the game's rule is the hand-worked outcome: a ball dropped at x = 0 lands on the target and
 * scores one point for its dropper.
 */
import { encode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { SCENES } from '../../../engine/index.ts'
import type { BallDropState } from '../../../games/index.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage, ServerMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'
import { DocClient } from '../protocol/doc-client.ts'
import { documentedEntryKinds } from '../protocol/doc-tables.ts'

let server: RunningServer
const ws = (): string => server.url

beforeAll(async () => {
  server = await startTestServer({ inputsPerTick: 2, maxRejects: 1000 })
})
afterAll(async () => {
  await server?.close()
})

const isError = (m: ServerMessage): m is ErrorMessage => m.t === 'error'

/** The error answering `seq`. */
async function errorFor(bot: BotClient, seq: number): Promise<ErrorMessage> {
  let found: ErrorMessage | undefined
  await bot.waitFor(() => {
    found = bot.received.find((m): m is ErrorMessage => isError(m) && m.seq === seq)
    return found !== undefined
  }, `the error for seq ${seq}`)
  return found as ErrorMessage
}

describe('a game room over real sockets', { timeout: 60_000 }, () => {
  it('runs the game the join names, refuses bad commands by field, and a lockstep client follows its state', async () => {
    const player = await BotClient.connect({ url: ws(), room: 'bd', name: 'p', game: 'ball-drop' })
    const welcome = player.received.find((m) => m.t === 'welcome')
    expect(welcome?.t === 'welcome' && welcome.rules).toMatchObject({
      game: 'ball-drop',
      commands: ['drop'],
      builtins: [],
      scenes: [],
    })
    // The sandbox lists every built-in command, and its scenes.
    const sandbox = await BotClient.connect({ url: ws(), room: 'bd-sandbox', name: 's' })
    const rules = sandbox.received.find((m) => m.t === 'welcome')
    expect(rules?.t === 'welcome' && rules.rules.builtins).toEqual([
      'delete',
      'grab',
      'gravity',
      'move',
      'pause',
      'pin',
      'release',
      'reset',
      'rope',
      'scene',
      'spawn',
      'step',
      'unjoint',
    ])
    expect(rules?.t === 'welcome' && rules.rules.scenes).toEqual(Object.keys(SCENES))
    await sandbox.close()
    const follower = await LockstepBot.connect({ url: ws(), room: 'bd', name: 'f' })
    await follower.waitFor(() => follower.runner.sim !== null, 'the sync')
    // A lockstep client written from PROTOCOL.md alone reads the game command's entry.
    const raw = await DocClient.open(server.url, 'bd')
    raw.send({ t: 'join', v: 3, room: '', name: 'raw', mode: 'lockstep' })

    // Refused by the protocol or the game's schema, each naming the field, seq echoed.
    const refusals: Array<[Record<string, unknown>, string, string]> = [
      [{ x: 99 }, 'invalid', 'drop refused: x must be <= 8'],
      [{ x: 'left' }, 'invalid', 'drop refused: x must be number'],
      [{}, 'invalid', 'drop refused: x is required'],
      [{ x: 1, y: 2 }, 'invalid', 'drop refused: y is not allowed'],
      [{ x: 'y'.repeat(2000) }, 'invalid', 'a.x must be a string of at most 1024 characters'],
    ]
    for (const [a, code, reason] of refusals) {
      const error = await errorFor(player, player.gameCommand('drop', a))
      expect([error.code, error.reason]).toEqual([code, reason])
    }
    const unknown = await errorFor(player, player.gameCommand('kick', {}))
    expect(unknown.reason).toBe('game ball-drop has no kick command')
    const spawn = await errorFor(
      player,
      player.command({ k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 5 }),
    )
    expect([spawn.code, spawn.reason]).toEqual(['refused', 'game ball-drop has no spawn command'])
    // Sent raw (the bot's encoder writes NaN as 0): a NaN, and arguments that are not a map.
    player.ws.send(encode({ t: 'cmd', seq: 900, k: 'drop', a: { x: Number.NaN } }))
    expect((await errorFor(player, 900)).reason).toBe('a.x must be a finite number')
    player.ws.send(encode({ t: 'cmd', seq: 901, k: 'drop', a: [1] }))
    expect((await errorFor(player, 901)).reason).toBe('cmd a must be a map')

    // One good drop at x = 0: it lands on the target, comes to rest and scores.
    const seq = player.gameCommand('drop', { x: 0 })
    const again = await errorFor(player, player.gameCommand('drop', { x: 1 }))
    expect([again.code, again.reason]).toEqual(['refused', 'one ball a second'])
    const scored = await player.nextMessage((m): m is Extract<ServerMessage, { t: 'game' }> => m.t === 'game')
    expect(scored.events).toEqual([{ scored: player.mirror.clientId, ball: expect.any(Number) }])
    expect(player.received.some((m) => isError(m) && m.seq === seq)).toBe(false)
    await follower.waitFor(() => {
      const state = follower.runner.sim?.gameState as BallDropState | undefined
      return state?.scores[player.mirror.clientId] === 1
    }, 'the score in the lockstep simulation')
    const kind15 = documentedEntryKinds().get(15)
    expect(kind15).toEqual({ name: 'cmd', args: ['kind', 'args'], optional: [] })
    const dropEntry = (): unknown[] | undefined =>
      raw
        .all('ticks')
        .flatMap((m) => m.c as unknown[][])
        .find((e) => e[2] === 15)
    await until(() => dropEntry() !== undefined, 'the drop in the raw stream')
    expect(dropEntry()?.slice(1)).toEqual([player.mirror.clientId, 15, 'drop', { x: 0 }])
    const checked = follower.runner.stats.hashesChecked
    await follower.waitFor(() => follower.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    expect(follower.runner.stats.desyncs, follower.runner.lastProblem).toBe(0)
    expect(follower.runner.stats.refused).toBe(0)

    // The room's game is fixed: a join naming another game is refused; /rooms shows it.
    const other = new BotClient({ url: ws(), room: 'bd', name: 'o', game: 'sandbox' })
    await other.opened
    other.join()
    const refusedJoin = await other.nextMessage(isError)
    expect([refusedJoin.code, refusedJoin.reason]).toEqual([
      'full',
      'room bd runs the game ball-drop, not sandbox',
    ])
    await other.closed
    expect(other.closeCode).toBe(4001)
    const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string; game: string }>
    expect(rooms.find((r) => r.name === 'bd')?.game).toBe('ball-drop')
    await Promise.all([player.close(), follower.close(), other.close()])
  })

  it('refuses a join naming a game the server does not have, by name', async () => {
    const bot = new BotClient({ url: ws(), room: 'nope-room', name: 'x', game: 'nope' })
    await bot.opened
    bot.join()
    const error = await bot.nextMessage(isError)
    expect([error.code, error.reason]).toEqual([
      'invalid',
      'unknown game "nope"; this server has sandbox, ball-drop, goal, tower',
    ])
    await bot.close()
  })

  it('holds game commands to the input budget like any input', async () => {
    const bot = await BotClient.connect({ url: ws(), room: 'bd-budget', name: 'b', game: 'ball-drop' })
    // inputsPerTick 2: 2 this tick and 8 waiting; a burst of 40 leaves at least 30 over budget.
    const seqs: number[] = []
    for (let i = 0; i < 40; i++) seqs.push(bot.gameCommand('drop', { x: 0 }))
    await bot.waitFor(
      () => bot.received.filter((m) => isError(m) && m.code === 'input-budget').length >= 20,
      'budget refusals',
    )
    const over = bot.received.filter((m): m is ErrorMessage => isError(m) && m.code === 'input-budget')
    expect(over[0].reason).toBe('input budget exceeded: at most 2 inputs per tick, 8 more waiting')
    for (const e of over) expect(seqs).toContain(e.seq)
    await bot.close()
  })

  it('refuses a version-2 join with the version error', async () => {
    const bot = new BotClient({ url: ws(), room: 'v2', name: 'old' })
    await bot.opened
    bot.join(2)
    const error = await bot.nextMessage(isError)
    expect([error.code, error.reason]).toEqual(['version', 'protocol version mismatch: client 2, server 3'])
    await bot.close()
  })
})
