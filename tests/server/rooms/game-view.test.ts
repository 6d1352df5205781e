/*
 * A game's per-player view (PROTOCOL.md, `view`; docs/games.md), over real sockets: a server
 * (rooms on the main thread, to read its log lines) loads tests/server/games/views/ with --games;
 * its `secret` game keeps every player's secret number and note in its state and shows each player
 * only its own. Two snapshot players each receive their own view and never the other's secret (the
 * raw frames are searched for its MessagePack bytes), a view is sent only when it changed, a
 * lockstep player computes its own view and receives none, and a view over MAX_VIEW_BYTES is not
 * sent (logged once) while the other player's still is. The message's fields are PROTOCOL.md's.
 */
import { decode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import { findGame } from '../../../games/index.ts'
import { loadGameDirectory } from '../../../server/games/game-loader.ts'
import type { RunningServer } from '../../../server/server.ts'
import { encodeValue, MAX_VIEW_BYTES, type ServerMessage } from '../../../shared/index.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'
import { documentedFields } from '../protocol/doc-tables.ts'

const DIR = 'tests/server/games/views'
let server: RunningServer
const { logger, lines } = capturingLogger('warn')

beforeAll(async () => {
  server = await startTestServer({ ...inProcessRooms, gamesDir: DIR }, logger)
})
afterAll(async () => {
  await server?.close()
})

type ViewMessage = Extract<ServerMessage, { t: 'view' }>
const views = (bot: BotClient): ViewMessage[] => bot.received.filter((m): m is ViewMessage => m.t === 'view')

/** Whether any frame the bot received holds these bytes. */
function framesHold(bot: BotClient, bytes: Uint8Array): boolean {
  return bot.frames.some((f) => Buffer.from(f).includes(Buffer.from(bytes)))
}

describe('a game view per player', { timeout: 60_000 }, () => {
  it('each player sees only its own view; a lockstep player computes its own; too big a view is not sent', async () => {
    const secret = (await loadGameDirectory(DIR))[0].game
    const games = (name: string) => findGame(name) ?? (name === 'secret' ? secret : undefined)
    const a = new BotClient({ url: server.url, room: 'v', name: 'a', game: 'secret' })
    a.keepFrames = true
    await a.opened
    a.join()
    await a.waitFor(() => a.mirror.clientId !== 0, 'the welcome')
    const b = new BotClient({ url: server.url, room: 'v', name: 'b', game: 'secret' })
    b.keepFrames = true
    await b.opened
    b.join()
    await b.waitFor(() => b.mirror.clientId !== 0, 'the welcome')
    const l = await LockstepBot.connect(
      { url: server.url, room: 'v', name: 'l', game: 'secret' },
      'lockstep',
      16,
      games,
    )
    const watcher = await BotClient.connect({ url: server.url, room: 'v', name: 'w', spectate: true })

    // Each player's first view comes at its first snapshot tick.
    await a.waitFor(() => views(a).length > 0, "a's first view")
    expect(a.mirror.view).toEqual({ secret: null, note: '', picked: 0 })

    a.gameCommand('pick', { n: 111111 })
    b.gameCommand('pick', { n: 222222 })
    l.bot.gameCommand('pick', { n: 333333 })
    // A player's view is null until its first view message arrives (b's may come after a's picks).
    await a.waitFor(
      () => (a.mirror.view as { picked: number } | null)?.picked === 3,
      "a's view after three picks",
    )
    await b.waitFor(
      () => (b.mirror.view as { picked: number } | null)?.picked === 3,
      "b's view after three picks",
    )
    expect(a.mirror.view).toEqual({ secret: 111111, note: '', picked: 3 })
    expect(b.mirror.view).toEqual({ secret: 222222, note: '', picked: 3 })
    await l.waitFor(() => (l.runner.view() as { picked: number } | undefined)?.picked === 3, "l's view")
    expect(l.runner.view()).toEqual({ secret: 333333, note: '', picked: 3 })

    // Nobody else's secret in any frame a player received; no view to the lockstep player or the
    // spectator.
    expect(framesHold(a, encodeValue(111111))).toBe(true)
    for (const n of [222222, 333333]) expect(framesHold(a, encodeValue(n)), `a got ${n}`).toBe(false)
    for (const n of [111111, 333333]) expect(framesHold(b, encodeValue(n)), `b got ${n}`).toBe(false)
    expect(l.bot.received.some((m) => m.t === 'view')).toBe(false)
    expect(watcher.received.some((m) => m.t === 'view')).toBe(false)

    // Sent only on change: a second of quiet ticks brings no new view. Every view is a new value.
    const count = views(a).length
    const quiet = a.mirror.tick
    await a.waitFor(() => a.mirror.tick >= quiet + 60, 'a quiet second')
    expect(views(a).length).toBe(count)
    const sent = views(a).map((v) => JSON.stringify(v.view))
    expect(new Set(sent).size).toBe(sent.length)

    // The message's fields are PROTOCOL.md's `view` table, read with an independent decoder.
    const documented = documentedFields().get('view')
    const frame = a.frames.map((f) => decode(f) as Record<string, unknown>).find((m) => m.t === 'view')
    expect(Object.keys(frame ?? {}).sort()).toEqual([...(documented?.all ?? [])].sort())

    // A note that makes a's view pass MAX_VIEW_BYTES: a's view is not sent (logged once), b's
    // still is.
    const long = 'x'.repeat(MAX_VIEW_BYTES / 2 + 50)
    a.gameCommand('note', { text: long })
    a.gameCommand('note', { text: long })
    b.gameCommand('note', { text: 'hello' })
    await b.waitFor(() => (b.mirror.view as { note: string }).note === 'hello', "b's note in its view")
    const after = a.mirror.tick
    await a.waitFor(() => a.mirror.tick >= after + 10, 'ten more ticks')
    // (The two notes may land in different snapshot intervals: the half-long one may be shown.)
    expect(a.mirror.view).toMatchObject({ secret: 111111, picked: 3 })
    expect((a.mirror.view as { note: string }).note.length).toBeLessThan(2 * long.length)
    expect(framesHold(a, Buffer.from(long + long))).toBe(false)
    const warned = lines.filter((line) => String(line.msg).includes('the view is not sent'))
    expect(warned.length).toBe(1)
    expect(warned[0].msg).toMatch(/^game secret: its view is \d+ bytes, over the 1024-byte limit/)
    await Promise.all([a.close(), b.close(), l.close(), watcher.close()])
  })
})
