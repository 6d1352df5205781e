/*
 * The example game directory runs as README says (`npm start -- --games examples/games`; here the
 * same command line from source, server/main.ts through tsx, in its own process with rooms on a
 * worker thread): the hoops game is in the catalogue, and a shot aimed by the closed form of a
 * projectile scores while one too slow to reach the hoop is a miss. The oracle is the textbook
 * trajectory under g = 10 m/s^2 without drag, from the launcher (-8, 1) through the rim's centre
 * (4, 4): at angle a the speed is v = sqrt(g d^2 / (2 cos^2 a (d tan a - h))) with d = 12 m and
 * h = 3 m. The engine's semi-implicit Euler steps fall about g t dt / 2 = 0.13 m below that curve
 * by the rim, well inside the opening (1.2 m less the ball's 0.4 m).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import type { ServerMessage } from '../../shared/index.ts'
import { type ServerProcess, startServerProcess } from '../support/server-process.ts'

let server: ServerProcess

beforeAll(async () => {
  server = await startServerProcess(['--games', 'examples/games', '--workers', '1', '--record', 'false'])
}, 60_000)
afterAll(async () => {
  server?.process.kill('SIGTERM')
  await server?.exited
})

type GameMessage = Extract<ServerMessage, { t: 'game' }>
const isGame = (m: ServerMessage): m is GameMessage => m.t === 'game'

describe('examples/games, loaded with --games', { timeout: 60_000 }, () => {
  it('runs hoops: a shot aimed by the projectile formula scores, a slow one misses', async () => {
    expect(server.lines.find((l) => l.msg === 'games loaded')).toMatchObject({ games: ['hoops'] })
    const bot = await BotClient.connect({ url: server.url, room: 'court', name: 'shooter', game: 'hoops' })
    const welcome = bot.received.find((m) => m.t === 'welcome')
    expect(welcome?.t === 'welcome' && welcome.rules).toMatchObject({ game: 'hoops', commands: ['shoot'] })

    const g = 10
    const d = 12
    const h = 3
    const angle = 0.9
    const speed = Math.sqrt((g * d * d) / (2 * Math.cos(angle) ** 2 * (d * Math.tan(angle) - h)))
    bot.gameCommand('shoot', { angle, speed })
    const scored = await bot.nextMessage(isGame)
    expect(scored.events).toEqual([{ scored: bot.mirror.clientId, ball: expect.any(Number) }])

    bot.gameCommand('shoot', { angle, speed: speed * 0.6 })
    const missed = await bot.nextMessage(isGame)
    expect(missed.events).toEqual([{ missed: bot.mirror.clientId, ball: expect.any(Number) }])
    await bot.close()
  })
})
