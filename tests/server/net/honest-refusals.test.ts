/*
 * A game's own refusals are not strikes (PROTOCOL.md, Refusals and errors: `refused`, strike
 * "no"); malformed input is. Over real sockets, a server with --max-rejects 20 and a heartbeat
 * (which forgives strikes) far longer than the test: a goal-game player sends 1,000 commands the
 * rules refuse (a kick with the ball out of reach, a rematch while the match is not over), 8 per
 * tick (the input budget), and stays connected with 1,000 `refused` errors; another sends
 * malformed commands (an unknown kind, a wrong type, a number out of range, a missing field) and
 * gets exactly 20 `invalid` errors, then the 21st closes its socket with 1008.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ServerMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

const MAX_REJECTS = 20
let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ maxRejects: MAX_REJECTS, heartbeatMs: 600_000 })
})
afterAll(async () => {
  await server?.close()
})

type ErrorMessage = Extract<ServerMessage, { t: 'error' }>
const errors = (bot: BotClient): ErrorMessage[] =>
  bot.received.filter((m): m is ErrorMessage => m.t === 'error')

describe('honest refusals and --max-rejects', { timeout: 120_000 }, () => {
  it('1,000 commands the game refuses cost no strikes: the player stays connected', async () => {
    const player = await BotClient.connect({ url: server.url, room: 'r1', name: 'p', game: 'goal' })
    // Alone, the player's disc waits on its kickoff spot (-4, 0) and the ball on the centre spot:
    // 3.2 m between their edges, far beyond the kick's reach.
    for (let sent = 0; sent < 1000; ) {
      const batch = Math.min(8, 1000 - sent)
      for (let i = 0; i < batch; i++, sent++)
        if (sent % 2 === 0) player.gameCommand('kick', { power: 1 })
        else player.gameCommand('rematch', {})
      await player.waitFor(() => errors(player).length >= sent, `${sent} refusals`)
    }
    const all = errors(player)
    expect(all.length).toBe(1000)
    expect(new Set(all.map((e) => `${e.code}: ${e.reason}`))).toEqual(
      new Set(['refused: the ball is out of reach', 'refused: the match is not over']),
    )
    expect(all.map((e) => e.seq)).toEqual(Array.from({ length: 1000 }, (_, i) => i + 1))
    // Still connected and served: a ping is answered.
    player.ping()
    await player.waitFor(() => player.received.some((m) => m.t === 'pong'), 'a pong')
    expect(player.ws.readyState).toBe(player.ws.OPEN)
    await player.close()
  })

  it(`malformed commands are strikes: ${MAX_REJECTS} are answered, the next closes the socket with 1008`, async () => {
    const player = await BotClient.connect({ url: server.url, room: 'r2', name: 'p', game: 'goal' })
    const bad: Array<[string, Record<string, unknown>]> = [
      ['fly', {}],
      ['kick', { power: 'hard' }],
      ['kick', { power: 5 }],
      ['kick', {}],
    ]
    for (let i = 0; i <= MAX_REJECTS; i++) player.gameCommand(...bad[i % bad.length])
    await player.closed
    const all = errors(player)
    expect(all.length).toBe(MAX_REJECTS)
    expect(all.every((e) => e.code === 'invalid')).toBe(true)
    expect(all.slice(0, 4).map((e) => e.reason)).toEqual([
      'game goal has no fly command',
      expect.stringMatching(/^kick refused: .*power/),
      expect.stringMatching(/^kick refused: .*power/),
      expect.stringMatching(/^kick refused: .*power/),
    ])
    expect(player.closeCode).toBe(1008)
    expect(player.closeReason).toMatch(/^too many invalid messages; last: game goal has no fly command/)
  })
})
