/*
 * The rough edges a newcomer hit in the sandbox page (issue 31, "Fix"), each checked in headless
 * Chromium against a real server on 127.0.0.1 serving a client built for this file: a late
 * joiner's camera frames the other players' cursors and what they hold, not only the bodies.
 */
import { mkdir } from 'node:fs/promises'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { ARTIFACTS, openSandbox, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-newcomer/dist'
let browser: Browser
let server: RunningServer

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await mkdir(ARTIFACTS, { recursive: true })
  await buildClient(DIST)
  ;[server, browser] = await Promise.all([serveClient(DIST), launchBrowser()])
}, 120_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** Where world point (x, y) is on the page's canvas (CSS px), and the band the toolbar leaves free. */
function onScreen(page: Page, x: number, y: number) {
  return page.evaluate(
    ([wx, wy]) => {
      const c = window.concord.camera
      const p = c.toScreen(wx, wy)
      const top = document.getElementById('toolbar')!.getBoundingClientRect().bottom
      return { x: p.x, y: p.y, top, width: c.width, height: c.height }
    },
    [x, y],
  )
}

describe('a late joiner', () => {
  it("frames the other player's cursor and the box it holds high above the pyramid", async () => {
    const room = 'late-joiner'
    const bot = await BotClient.connect({ url: server.url, room, name: 'holder' })
    try {
      await bot.waitFor(() => bot.mirror.bodies.size > 1, 'the pyramid')
      // The pyramid's top box, lifted 20 m above the pyramid and 14 m to the right.
      const [top] = [...bot.mirror.bodies].sort((a, b) => b[1].y - a[1].y)[0]
      const lift = { x: 14, y: 40 }
      bot.command({ k: 'grab', body: top, lx: 0, ly: 0 })
      bot.command({ k: 'move', x: lift.x, y: lift.y })
      await bot.waitFor(() => (bot.mirror.bodies.get(top)?.y ?? 0) > lift.y - 3, 'the box lifted')

      const { page, context } = await openSandbox(browser, `${server.url}/?room=${room}&name=late`, {
        size: { width: 1280, height: 800 },
      })
      // Both the cursor and the held box end up in the free band below the toolbar.
      await page.waitForFunction(
        ([id, x, y]) => {
          const c = window.concord.camera
          const top = document.getElementById('toolbar')!.getBoundingClientRect().bottom
          const box = window.concord.sandbox.bodies().find((b) => b.id === id)
          const cursor = window.concord.sandbox.cursors().find((k) => k.x === x && k.y === y)
          if (!box || !cursor) return false
          return [box, cursor].every((p) => {
            const s = c.toScreen(p.x, p.y)
            return s.x > 0 && s.x < c.width && s.y > top && s.y < c.height
          })
        },
        [top, lift.x, lift.y],
      )
      // The pyramid's bottom row stays in view as well.
      const ground = await onScreen(page, 0, 0.5)
      expect(ground.y).toBeGreaterThan(ground.top)
      expect(ground.y).toBeLessThan(ground.height)
      await page.screenshot({ path: `${ARTIFACTS}/late-joiner.png` })
      await context.close()
    } finally {
      await bot.close()
    }
  })
})
