/*
 * The rough edges a newcomer hit in the sandbox page (issue 31, "Fix"), each checked in headless
 * Chromium against a real server on 127.0.0.1 serving a client built for this file: a late
 * joiner's camera frames the other players' cursors and what they hold, not only the bodies; the
 * replay page keeps its HUD and the ground clear of its control bar and never opens the spawn
 * sliders; a paused room says so on the view; room controls are disabled for a player whose key
 * does not open them; Help names the tools as the toolbar does, in its order, with the digit keys
 * along it; a 200-character room name does not fill the HUD; on a phone the empty scene is zoomed
 * so a dropped 1 m shape is at least 40 px wide, and Help (tools by button, no keys) fits unscrolled.
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

describe('the room and its controls', () => {
  it('shows "Paused" on the view, and disables the room controls for a player without the admin key', async () => {
    const guarded = await serveClient(DIST, { adminToken: 'boss-key' })
    try {
      const room = 'paused-room'
      const admin = await openSandbox(browser, `${guarded.url}/?room=${room}&name=admin&key=boss-key`)
      const guest = await openSandbox(browser, `${guarded.url}/?room=${room}&name=guest`)
      const controls = ['scene', 'pause', 'step', 'reset', 'gravity']
      const disabled = (page: Page) =>
        page.evaluate(
          (ids) => ids.map((id) => (document.getElementById(id) as HTMLButtonElement).disabled),
          controls,
        )
      await guest.page.waitForFunction(() => (document.getElementById('pause') as HTMLButtonElement).disabled)
      expect(await disabled(guest.page)).toEqual([true, true, true, true, true])
      expect(await guest.page.getAttribute('#pause', 'title')).toContain('not open to you in this room')
      // The admin key opens them (the page asked the server, as the guest's did).
      await admin.page.waitForFunction(() => window.concord.sandbox.rules() !== null)
      await admin.page.waitForFunction(() => {
        const c = (
          window as unknown as { concord: { sandbox: { connection: { controlsAllowed: boolean | null } } } }
        ).concord.sandbox.connection
        return c.controlsAllowed === true
      })
      // The panels refresh a few times a second: wait for the buttons to show it.
      await admin.page.waitForFunction(
        () => !(document.getElementById('pause') as HTMLButtonElement).disabled,
      )
      expect(await disabled(admin.page)).toEqual([false, false, false, false, false])
      expect(await admin.page.locator('#paused').isVisible()).toBe(false)

      await admin.page.click('#pause')
      for (const [page, text] of [
        [admin.page, '❚❚ Paused: Space or Play resumes'],
        [guest.page, '❚❚ Paused by the room'],
      ] as const) {
        await page.waitForFunction(() => !document.getElementById('paused')!.hidden)
        expect(await page.locator('#paused').textContent()).toBe(text)
        // Drawn over the view, below the toolbar, clear of the HUD.
        const b = await boxes(page, ['paused', 'toolbar', 'hud'])
        expect(b.paused!.top).toBeGreaterThanOrEqual(b.toolbar!.bottom)
        expect(b.paused!.right < b.hud!.left || b.paused!.bottom < b.hud!.top).toBe(true)
      }
      await guest.page.screenshot({ path: `${ARTIFACTS}/paused-guest.png` })
      await admin.page.keyboard.press(' ')
      await admin.page.waitForFunction(() => document.getElementById('paused')!.hidden)
      await guest.page.waitForFunction(() => document.getElementById('paused')!.hidden)
      expect(admin.errors).toEqual([])
      await admin.context.close()
      await guest.context.close()
    } finally {
      await guarded.close()
    }
  })

  it('Help calls the tools what the toolbar does, in toolbar order, and the digit keys follow it', async () => {
    const { page, context } = await openSandbox(browser, `${server.url}/?room=help-order`)
    const toolbar = await page.evaluate(() =>
      [...document.querySelectorAll<HTMLButtonElement>('#toolbar [data-tool]')].map((b) => ({
        tool: b.dataset.tool!,
        // The button's name: its text, or its aria-label when it shows an icon (Explode).
        label: (b.getAttribute('aria-label') ?? b.textContent!).trim(),
      })),
    )
    expect(toolbar.map((t) => t.label)).toEqual([
      'Grab',
      'Circle',
      'Box',
      'Polygon',
      'Delete',
      'Pin',
      'Rope',
      'Cut',
      'Lab',
      'Draw',
      'Ground',
      'Explode',
      'Edit',
    ])
    const rows = await page.evaluate(() =>
      [...document.querySelectorAll('#help-rows tr')].map((r) => ({
        keys: [...r.querySelectorAll('kbd')].map((k) => k.textContent),
        text: r.querySelectorAll('td')[1].textContent!,
      })),
    )
    for (const [i, t] of toolbar.entries()) {
      expect(rows[i].text.startsWith(`${t.label}:`), `help row ${i}: ${rows[i].text}`).toBe(true)
      // The digits 1-9 follow the toolbar; a tenth tool has its letter only.
      const key = i < 9 ? String(i + 1) : (rows[i].keys[0] ?? '').toLowerCase()
      if (i < 9) expect(rows[i].keys).toContain(key)
      // The key picks that button's tool.
      await page.keyboard.press(key)
      expect(await page.getAttribute(`#toolbar [data-tool="${t.tool}"]`, 'class')).toContain('active')
    }
    expect(rows.map((r) => r.text).join('\n')).not.toMatch(/Inspect/)
    expect(await page.getAttribute('#toolbar [data-tool="inspect"]', 'title')).toMatch(/^Lab/)
    await context.close()
  })

  it('a 200-character room name is cut short in the HUD', async () => {
    const name = 'a'.repeat(200)
    const context = await browser.newContext({ viewport: { width: 1280, height: 800 } })
    const page = await context.newPage()
    await page.goto(`${server.url}/?room=${name}`)
    await page.waitForFunction(() => window.concord?.sandbox.status().state === 'error')
    await page.waitForFunction(() => /^room /.test(document.getElementById('hud')?.textContent ?? ''))
    const first = (await page.locator('#hud').textContent())!.split('\n')[0]
    expect(first).toMatch(/^room a{31}… /)
    const b = await boxes(page, ['hud'])
    expect(b.hud!.right - b.hud!.left).toBeLessThan(400)
    await page.screenshot({ path: `${ARTIFACTS}/long-room-name.png` })
    await context.close()
  })
})

describe('on a phone', () => {
  it('zooms the empty scene so a dropped 1 m box is at least 40 px, and Help fits without scrolling', async () => {
    const phone = await serveClient(DIST, { defaultScene: 'empty' })
    const context = await browser.newContext({
      viewport: { width: 390, height: 844 },
      deviceScaleFactor: 2,
      hasTouch: true,
      isMobile: true,
    })
    try {
      const page = await context.newPage()
      await page.goto(`${phone.url}/?room=phone&name=thumb`)
      await page.waitForFunction(
        () =>
          window.concord?.sandbox.status().state === 'connected' &&
          window.concord.sandbox.scene() === 'empty',
      )
      await page.waitForFunction(() => window.concord.sandbox.bodies().length > 0)
      // Drop a box with the Box tool by a tap in the middle of the view.
      await page.tap('[data-tool="box"]')
      await page.touchscreen.tap(195, 500)
      await page.waitForFunction(() => window.concord.sandbox.bodies().some((b) => b.kind === 2))
      const width = await page.evaluate(() => {
        const box = window.concord.sandbox.bodies().find((b) => b.kind === 2)!
        const shape = box.shapes[0]
        if (shape.type !== 'box') throw new Error(`dropped a ${shape.type}`)
        return 2 * shape.hw * window.concord.camera.scale
      })
      expect(width).toBeGreaterThanOrEqual(40)
      // The ground line stays in view.
      const ground = await onScreen(page, 0, 0)
      expect(ground.y).toBeGreaterThan(ground.top)
      expect(ground.y).toBeLessThan(ground.height)
      await page.screenshot({ path: `${ARTIFACTS}/phone-empty.png` })

      await page.tap('#help-button')
      await page.waitForSelector('#help', { state: 'visible' })
      const help = await page.evaluate(() => {
        const h = document.getElementById('help')!
        const close = document.getElementById('help-close')!.getBoundingClientRect()
        return {
          fits: h.scrollHeight <= h.clientHeight && h.scrollWidth <= h.clientWidth,
          closeVisible: close.bottom <= window.innerHeight && close.top >= 0,
          keys: h.querySelectorAll('kbd').length,
          names: [...h.querySelectorAll('#help-rows tr td:first-child')].map((td) => td.textContent),
        }
      })
      expect(help).toEqual({
        fits: true,
        closeVisible: true,
        keys: 0,
        names: [
          'Grab',
          'Circle, Box, Polygon',
          'Delete',
          'Pin',
          'Rope',
          'Cut',
          'Lab',
          'Draw',
          'Ground',
          'Explode',
          'Edit',
          'Joints',
          'Undo, Redo',
          'Pause, Step',
          'Reset',
          'Gravity',
          'Fit',
        ],
      })
      await page.screenshot({ path: `${ARTIFACTS}/phone-help.png` })
      await page.tap('#help-close')
      await page.waitForSelector('#help', { state: 'hidden' })
    } finally {
      await context.close()
      await phone.close()
    }
  })
})
