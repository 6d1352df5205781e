/*
 * The default view of a game without `view` (PROTOCOL.md, `view`; docs/games.md, View), over real
 * sockets: a snapshot player of ball drop (a game with state and no view) receives the whole game
 * state in `view` messages, and they follow the game's rules as docs/games.md states them (a drop
 * records the ball's dropper and the drop tick; a ball at rest on the target scores a point and
 * leaves the owners); a lockstep player's computed view() agrees; a spectator gets none. A game
 * whose state passes MAX_VIEW_BYTES (tests/server/games/state-views/notebook) stops sending it and
 * the server logs one line naming the size and the fix.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import type { RunningServer } from '../../../server/server.ts'
import { MAX_VIEW_BYTES, type ServerMessage } from '../../../shared/index.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

const DIR = 'tests/server/games/state-views'
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

interface BallDropView {
  scores: Record<string, number>
  owners: Record<string, number>
  lastDrop: Record<string, number>
}

describe('the default view: the whole state of a game without view', { timeout: 60_000 }, () => {
  it('a ball-drop snapshot player gets the state as it changes; a lockstep player computes the same', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'bd', name: 'a', game: 'ball-drop' })
    const l = await LockstepBot.connect(
      { url: server.url, room: 'bd', name: 'l', game: 'ball-drop' },
      'lockstep',
      16,
    )
    const watcher = await BotClient.connect({ url: server.url, room: 'bd', name: 'w', spectate: true })
    const me = a.mirror.clientId
    const other = l.runner.playerId
    const view = () => a.mirror.view as BallDropView | null

    // Both players joined: scores 0 each (onJoin), nothing dropped.
    await a.waitFor(() => Object.keys(view()?.scores ?? {}).length === 2, 'a view with both players')
    expect(view()).toEqual({ scores: { [me]: 0, [other]: 0 }, owners: {}, lastDrop: {} })

    // A drop: the view names the new ball's dropper and the tick of the drop.
    const beforeDrop = a.mirror.tick
    a.gameCommand('drop', { x: 0 })
    await a.waitFor(() => Object.keys(view()?.owners ?? {}).length === 1, 'the dropped ball in the view')
    const balls = [...a.mirror.bodies.values()].filter((b) => b.kind === 2).map((b) => b.id)
    expect(balls.length).toBe(1)
    const dropped = view() as BallDropView
    expect(dropped.owners).toEqual({ [balls[0]]: me })
    // Commands apply before their tick's step, when ctx.tick is still the tick the page last saw
    // (or later): the drop tick is at least that, and at most the view's tick.
    expect(dropped.lastDrop[me]).toBeGreaterThanOrEqual(beforeDrop)
    expect(dropped.lastDrop[me]).toBeLessThanOrEqual(views(a).at(-1)?.tick ?? 0)

    // The ball comes to rest on the target: a point for its dropper, the ball gone from the owners.
    await a.waitFor(() => view()?.scores[me] === 1, 'the point in the view')
    expect(view()).toEqual({ scores: { [me]: 1, [other]: 0 }, owners: {}, lastDrop: dropped.lastDrop })
    expect(a.mirror.bodies.has(balls[0])).toBe(false)

    // The lockstep player's own view is the same state; the spectator got no view.
    await l.waitFor(
      () => JSON.stringify(l.runner.view()) === JSON.stringify(a.mirror.view),
      "l's view equal to a's",
    )
    expect(watcher.received.some((m) => m.t === 'view')).toBe(false)
    expect(l.bot.received.some((m) => m.t === 'view')).toBe(false)

    // Sent only on change: a quiet second brings no new view.
    const count = views(a).length
    const quiet = a.mirror.tick
    await a.waitFor(() => a.mirror.tick >= quiet + 60, 'a quiet second')
    expect(views(a).length).toBe(count)
    await Promise.all([a.close(), l.close(), watcher.close()])
  })

  it('a state over MAX_VIEW_BYTES is not sent, and logged once with its size and the fix', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'nb', name: 'a', game: 'notebook' })
    const me = a.mirror.clientId
    await a.waitFor(() => views(a).length > 0, 'the first view')
    expect(a.mirror.view).toEqual({ pages: {} })
    a.gameCommand('write', { text: 'hello' })
    await a.waitFor(() => views(a).length > 1, 'the view after a write')
    expect(a.mirror.view).toEqual({ pages: { [me]: 'hello' } })

    // Two long writes: the state passes the limit (1024 bytes), so no view carries them.
    const long = 'x'.repeat(MAX_VIEW_BYTES / 2 + 50)
    a.gameCommand('write', { text: long })
    a.gameCommand('write', { text: long })
    const warned = () => lines.filter((line) => String(line.msg).includes('the view is not sent'))
    await a.waitFor(() => warned().length > 0, 'the log line')
    const after = a.mirror.tick
    await a.waitFor(() => a.mirror.tick >= after + 30, 'half a second more')
    expect(warned().length).toBe(1)
    expect(warned()[0].msg).toMatch(
      /^game notebook: it has no view, so its view is its whole state, and the state is \d+ bytes, over the 1024-byte limit \(give the game a view\(ctx, player\) that returns less\)/,
    )
    expect(((a.mirror.view as { pages: Record<string, string> }).pages[me] ?? '').length).toBeLessThan(
      2 * long.length,
    )
    await a.close()
  })
})
