/*
 * The rough edges a newcomer hit in the sandbox page (issue 31, "Fix"), each checked in headless
 * Chromium against a real server on 127.0.0.1 serving a client built for this file: a late
 * joiner's camera frames the other players' cursors and what they hold, not only the bodies; the
 * replay page keeps its HUD and the ground clear of its control bar and never opens the spawn
 * sliders.
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
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

/** Boxes (CSS px) of page elements by id; null for one not shown. */
function boxes(page: Page, ids: string[]) {
  return page.evaluate((list) => {
    const out: Record<string, { left: number; top: number; right: number; bottom: number } | null> = {}
    for (const id of list) {
      const e = document.getElementById(id)
      const r = e?.getBoundingClientRect()
      out[id] =
        e && r && r.width > 0 && r.height > 0
          ? { left: r.left, top: r.top, right: r.right, bottom: r.bottom }
          : null
    }
    return out
  }, ids)
}

describe('the replay page', () => {
  it('keeps the HUD and the ground above the control bar and opens no spawn sliders', async () => {
    const replayDir = await mkdtemp(join(tmpdir(), 'concord-newcomer-'))
    const recording = await serveClient(DIST, { record: true, replayDir })
    const bot = await BotClient.connect({ url: recording.url, room: 'hud-replay', name: 'b' })
    await bot.waitFor(() => bot.mirror.tick > 120, 'two seconds recorded')
    await bot.close()
    await recording.close()
    const replays = await serveClient(DIST, { replayDir })
    try {
      for (const [width, height] of [
        [1280, 800],
        [1920, 1080],
      ]) {
        const context = await browser.newContext({ viewport: { width, height } })
        const page = await context.newPage()
        await page.goto(`${replays.url}/?replay`)
        await page.click('#replay-list button:has-text("hud-replay")')
        await page.waitForSelector('#replay-play')
        await page.waitForFunction(() =>
          /replay of hud-replay/.test(document.getElementById('hud')?.textContent ?? ''),
        )
        const b = await boxes(page, ['hud', 'replay-panel'])
        expect(b.hud && b['replay-panel']).toBeTruthy()
        // The HUD ends above the bar (they overlapped: the bar covered the HUD's last lines).
        expect(b.hud!.bottom).toBeLessThanOrEqual(b['replay-panel']!.top)
        const ground = await onScreen(page, 0, 0)
        expect(ground.y).toBeLessThan(b['replay-panel']!.top)
        // A spawn tool's key opens no sliders in a replay (nothing can be spawned there).
        for (const key of ['c', 'b', 'p']) {
          await page.keyboard.press(key)
          expect(await page.locator('#spawn-panel').isVisible()).toBe(false)
        }
        await page.screenshot({ path: `${ARTIFACTS}/replay-hud-${width}.png` })
        await context.close()
      }
    } finally {
      await replays.close()
    }
  })
})
