/*
 * The browser's replay page plays a log of a game loaded with --games DIR: a server serving the
 * client with --games examples/games records a hoops room in which a real client shoots; the
 * page opened at `?replay=NAME` imports the game's module from the server (GET /games/hoops.js,
 * as a lockstep page does), plays the log to its end and shows every recorded hash matching.
 */
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import { listLogNames } from '../../server/replay/replay-files.ts'
import type { RunningServer } from '../../server/server.ts'
import type { ServerMessage } from '../../shared/index.ts'
import { launchBrowser } from '../support/chromium.ts'
import { collectErrors, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/replay-loaded-game/dist'
let server: RunningServer
let browser: Browser
let dir: string

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-replay-game-'))
  await buildClient(DIST)
  ;[server, browser] = await Promise.all([
    serveClient(DIST, { gamesDir: 'examples/games', record: true, replayDir: dir, keyframeTicks: 120 }),
    launchBrowser(),
  ])
}, 120_000)
afterAll(async () => {
  await browser?.close()
  await server?.close()
})

const isGame = (m: ServerMessage): boolean => m.t === 'game'

describe('the replay page and games loaded with --games', { timeout: 300_000 }, () => {
  it('plays a hoops log with every hash matching', async () => {
    const url = `http://127.0.0.1:${server.port}`
    const bot = await BotClient.connect({ url, room: 'court', name: 'shooter', game: 'hoops' })
    for (const [angle, speed] of [
      [0.9, 13],
      [0.7, 12],
    ]) {
      const seen = bot.received.filter(isGame).length
      bot.gameCommand('shoot', { angle, speed })
      await bot.waitFor(() => bot.received.filter(isGame).length > seen, 'a hoops event')
    }
    const at = bot.mirror.tick
    await bot.waitFor(() => bot.mirror.tick >= at + 130, 'two more seconds')
    await bot.close()
    const name = (await listLogNames(dir)).find((n) => n.startsWith('court-'))
    if (!name) throw new Error('no log of room court')

    const context = await browser.newContext({ viewport: { width: 1000, height: 700 } })
    context.setDefaultTimeout(90_000)
    const page = await context.newPage()
    const errors = collectErrors(page)
    await page.goto(`${url}/?replay=${encodeURIComponent(name)}`)
    await page.waitForSelector('#replay-hash')
    expect(await page.evaluate(() => window.concordReplay?.sandbox?.player.log.header.state.game)).toBe(
      'hoops',
    )
    await page.selectOption('#replay-speed', '8')
    await page.click('#replay-play')
    await page.waitForFunction(() => {
      const p = window.concordReplay?.sandbox?.player
      return p !== undefined && p.tick >= p.log.lastTick
    })
    const status = await page.evaluate(() => {
      const p = window.concordReplay!.sandbox!.player
      const hash = document.getElementById('replay-hash')!
      return { checked: p.checked, mismatch: p.mismatch, ok: hash.dataset.ok }
    })
    expect(status.mismatch).toBeNull()
    expect(status.ok).toBe('true')
    expect(status.checked).toBeGreaterThanOrEqual(2)
    expect(errors).toEqual([])

    await context.close()
  })
})
