/*
 * The room command `rename` (PROTOCOL.md, "Room commands"; issue 31, People): a player's new name
 * reaches every player's roster, in snapshot and lockstep mode, on the main thread and on a room
 * worker, survives a reconnect with the player's token, and a bad name is refused naming what is
 * wrong. Real server, real sockets.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage, WelcomeMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

let servers: RunningServer[] = []

beforeAll(async () => {
  servers = [await startTestServer({ workers: 0 }), await startTestServer({ workers: 1 })]
})
afterAll(async () => {
  for (const s of servers) await s.close()
})

/** The error answering `seq`. */
async function errorFor(bot: BotClient, seq: number): Promise<ErrorMessage> {
  let found: ErrorMessage | undefined
  await bot.waitFor(() => {
    found = bot.received.find((m): m is ErrorMessage => m.t === 'error' && m.seq === seq)
    return found !== undefined
  }, `the error for seq ${seq}`)
  return found as ErrorMessage
}

const names = (bot: BotClient): string[] => [...bot.mirror.players.values()].map((p) => p.name).sort()

describe('rename', { timeout: 60_000 }, () => {
  for (const [i, where] of ['main thread', 'room worker'].entries()) {
    it(`a new name reaches every roster and survives a reconnect (${where})`, async () => {
      const url = servers[i].url
      const ana = await BotClient.connect({ url, room: 'names', name: 'ana' })
      const bo = await BotClient.connect({ url, room: 'names', name: 'bo' })
      await ana.waitFor(() => names(ana).length === 2, 'both in the roster')
      ana.gameCommand('rename', { name: '  Ana Lima\u0007 ' })
      await bo.waitFor(() => names(bo).includes('Ana Lima'), "bo's roster shows the new name")
      await ana.waitFor(() => names(ana).includes('Ana Lima'), "ana's own roster too")
      expect(names(bo)).toEqual(['Ana Lima', 'bo'])
      // Refusals name what is wrong, and change nothing.
      const blank = await errorFor(ana, ana.gameCommand('rename', { name: ' \t ' }))
      expect(blank).toMatchObject({
        code: 'invalid',
        reason: 'rename refused: name must hold something besides spaces',
      })
      const long = await errorFor(ana, ana.gameCommand('rename', { name: 'x'.repeat(33) }))
      expect(long.reason).toBe('rename refused: name must be a string of at most 32 characters')
      const extra = await errorFor(ana, ana.gameCommand('rename', { name: 'ok', color: 1 }))
      expect(extra.reason).toBe('rename refused: color is not allowed')
      const number = await errorFor(ana, ana.gameCommand('rename', { name: 7 }))
      expect(number.reason).toBe('rename refused: name must be a string of at most 32 characters')
      expect(names(bo)).toEqual(['Ana Lima', 'bo'])
      // A reconnect with the token keeps the new name.
      const token = (ana.received.find((m) => m.t === 'welcome') as WelcomeMessage).token
      const id = ana.mirror.clientId
      await ana.close()
      const back = await BotClient.connect({ url, room: 'names', name: 'someone else', token })
      expect(back.mirror.clientId).toBe(id)
      expect(back.mirror.players.get(id)?.name).toBe('Ana Lima')
      await back.close()
      await bo.close()
    })
  }

  it('a lockstep player renames and a snapshot player sees it', async () => {
    const url = servers[0].url
    const ls = await BotClient.connect({ url, room: 'names-ls', name: 'lock', mode: 'lockstep' })
    const snap = await BotClient.connect({ url, room: 'names-ls', name: 'snap' })
    ls.gameCommand('rename', { name: 'Lockstep Lu' })
    await snap.waitFor(() => names(snap).includes('Lockstep Lu'), 'the new name')
    await ls.close()
    await snap.close()
  })
})
