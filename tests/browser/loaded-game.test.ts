/*
 * A game loaded with --games, played by a lockstep page in headless Chromium: the server loads
 * tests/server/games/loaded/ (the marbles game, written against the SDK only); the page, opened
 * with ?mode=lockstep&game=marbles, does not ship that game, so it imports /games/marbles.js from
 * the server (same origin, under the page's CSP) before it simulates. The page itself sends the
 * game's commands; its simulation must reach the hand-worked state (five marbles dropped, the
 * three dropped at x = -5 resting left of 0) and every hash checkpoint past it must match the
 * server's (the state hash covers the game state), with no page error. Then the game's client
 * module (its `client` export, served in the same module): a lockstep page and a snapshot page of
 * another room both show its panel item and its drawing (a magenta pixel at the world point it
 * marks) and send a drop with M, which the lockstep page's
 * simulation (confirmed by the server's stream) counts: 1, then 2; the snapshot page's panel
 * follows it too (a game without `view` sends snapshot players its whole state).
 */
import type { Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-client/dist-loaded-game'

let server: RunningServer
let browser: Browser

beforeAll(async () => {
  await buildClient(DIST)
  server = await serveClient(DIST, { gamesDir: 'tests/server/games/loaded' })
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

interface GamePage {
  sendGame(kind: string, args: Record<string, unknown>): number
  gameState(): { dropped: number; left: number } | null
  stats(): { tick: number; lockstep: { verifiedTick: number; desyncs: number; resyncs: number } | null }
}

describe('a game loaded from a directory, in a lockstep page', () => {
  it('the page loads the game from the server, plays it, and matches every server hash', async () => {
    const { page, errors, context } = await openSandbox(
      browser,
      `${server.url}/?room=loaded-game&mode=lockstep&game=marbles`,
    )
    try {
      const sandbox = (): Promise<GamePage['stats'] extends () => infer R ? R : never> =>
        page.evaluate(() => (window.concord.sandbox as unknown as GamePage).stats())
      for (const x of [-5, -5, 5, -5, 5])
        await page.evaluate((x) => (window.concord.sandbox as unknown as GamePage).sendGame('drop', { x }), x)
      await page.waitForFunction(() => {
        const s = (window.concord.sandbox as unknown as GamePage).gameState()
        return s !== null && s.dropped === 5 && s.left === 3
      })
      const settled = (await sandbox()).tick
      // Past the settled state by two hash checkpoints, or stopped by a desync (reported below).
      await page.waitForFunction((t) => {
        const l = (window.concord.sandbox as unknown as GamePage).stats().lockstep
        return l !== null && (l.verifiedTick > t + 120 || l.desyncs > 0)
      }, settled)
      const stats = await sandbox()
      expect(stats.lockstep).toMatchObject({ desyncs: 0, resyncs: 0 })
      expect(await page.evaluate(() => window.concord.sandbox.rules()?.game)).toBe('marbles')
      expect(errors).toEqual([])
    } finally {
      await context.close()
    }
  })

  it("the game's client module: both a lockstep and a snapshot page show its panel and send its key's command", async () => {
    const lockstep = await openSandbox(
      browser,
      `${server.url}/?room=loaded-client&mode=lockstep&game=marbles`,
    )
    const snapshot = await openSandbox(browser, `${server.url}/?room=loaded-client`)
    const item = '#game-panel:not([hidden]) .item[data-label="marbles"] b'
    const shows = (page: typeof lockstep.page, text: string) =>
      page.waitForFunction(([item, text]) => document.querySelector(item)?.textContent === text, [
        item,
        text,
      ] as const)
    try {
      // The snapshot page has the state too: marbles has no view, so its view is its state.
      await shows(lockstep.page, '0 dropped, 0 left')
      await shows(snapshot.page, '0 dropped, 0 left')
      // Its drawing, after the world: the canvas pixel at the world point (0, 1) is magenta.
      for (const page of [lockstep.page, snapshot.page])
        await page.waitForFunction(() => {
          const p = window.concord.camera.toScreen(0, 1)
          const canvas = document.getElementById('view') as HTMLCanvasElement
          const scale = canvas.width / canvas.getBoundingClientRect().width
          const ctx = canvas.getContext('2d')
          const [r, g, b] =
            ctx?.getImageData(Math.round(p.x * scale), Math.round(p.y * scale), 1, 1).data ?? []
          return r === 255 && g === 0 && b === 255
        })
      await lockstep.page.keyboard.press('m')
      await shows(lockstep.page, '1 dropped, 0 left')
      await snapshot.page.keyboard.press('m')
      for (const page of [lockstep.page, snapshot.page])
        await page.waitForFunction(
          (item) => document.querySelector(item)?.textContent?.startsWith('2 dropped') === true,
          item,
        )
      expect(lockstep.errors).toEqual([])
      expect(snapshot.errors).toEqual([])
    } finally {
      await lockstep.context.close()
      await snapshot.context.close()
    }
  })
})
