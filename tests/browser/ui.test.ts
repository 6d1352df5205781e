/*
 * The page's layout and notices in real Chromium against a real server: the toolbar fits on one
 * row and keeps its width whatever tool is active, and the HUD is never clipped, at 1280x800 and
 * 1920x1080; on a 390x844 touch phone the toolbar and the lab panel leave the selected body in
 * sight; 40 spawns clicked at once all arrive (none dropped by the per-tick input budget) and the
 * player is told they are queued; a room name the server cannot accept says what is wrong.
 */
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from './chromium.ts'
import { ARTIFACTS, collectErrors, pickTool, screenOfBody, startClientServer } from './client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  ;[server, browser] = await Promise.all([startClientServer(), launchBrowser()])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

async function open(url: string, width: number, height: number, touch = false) {
  const context = await browser.newContext({
    viewport: { width, height },
    deviceScaleFactor: 1,
    hasTouch: touch,
    isMobile: touch,
  })
  const page = await context.newPage()
  const errors = collectErrors(page)
  await page.goto(url)
  return { context, page, errors }
}

async function joined(page: Page): Promise<void> {
  await page.waitForFunction(
    () =>
      window.concord?.sandbox.status().state === 'connected' && window.concord.sandbox.bodies().length > 0,
  )
  // The panels refresh four times a second: wait for the HUD's first refresh.
  await page.waitForFunction(() => /room /.test(document.getElementById('hud')!.textContent!))
}

/** Box of an element (CSS px) and whether its content overflows it. */
function layout(page: Page, id: string) {
  return page.evaluate((elementId) => {
    const e = document.getElementById(elementId)!
    const r = e.getBoundingClientRect()
    return {
      left: r.left,
      right: r.right,
      top: r.top,
      bottom: r.bottom,
      width: r.width,
      height: r.height,
      overflowX: e.scrollWidth > e.clientWidth + 1,
      overflowY: e.scrollHeight > e.clientHeight + 1,
    }
  }, id)
}

describe('layout', { timeout: 60_000 }, () => {
  for (const [width, height] of [
    [1280, 800],
    [1920, 1080],
  ]) {
    it(`fits the toolbar on one row of constant width and never clips the HUD at ${width}x${height}`, async () => {
      const { context, page, errors } = await open(
        `${base}/?room=layout-${width}&name=a-rather-long-player-name`,
        width,
        height,
      )
      await joined(page)
      const widths = new Set<number>()
      for (const tool of ['grab', 'circle', 'box', 'polygon', 'delete', 'pin', 'rope', 'inspect']) {
        await pickTool(page, tool)
        const bar = await layout(page, 'toolbar')
        expect(bar.overflowX, `toolbar overflows with ${tool}`).toBe(false)
        expect(bar.height, 'one row').toBeLessThan(50)
        widths.add(Math.round(bar.width))
      }
      expect(widths.size).toBe(1)
      const hud = await layout(page, 'hud')
      expect(hud.overflowX || hud.overflowY).toBe(false)
      expect(hud.left).toBeGreaterThanOrEqual(0)
      expect(hud.right).toBeLessThanOrEqual(width)
      expect(hud.bottom).toBeLessThanOrEqual(height)
      const bar = await layout(page, 'toolbar')
      expect(hud.top >= bar.bottom || hud.bottom <= bar.top).toBe(true)
      await page.screenshot({ path: `${ARTIFACTS}/layout-${width}.png` })
      expect(errors).toEqual([])
      await context.close()
    })
  }

  it('keeps the selected body clear of the toolbar and the lab panel on a 390x844 phone', async () => {
    const { context, page, errors } = await open(`${base}/?room=phone`, 390, 844, true)
    await joined(page)
    await pickTool(page, 'inspect')
    // The pyramid's top box: select it by tapping it.
    const top = await page.evaluate(
      () =>
        window.concord.sandbox
          .bodies()
          .filter((b: { kind: number }) => b.kind === 2)
          .sort((a: { y: number }, b: { y: number }) => b.y - a.y)[0].id,
    )
    const at = await screenOfBody(page, top)
    await page.touchscreen.tap(at.x, at.y)
    await page.waitForFunction(() => !document.getElementById('lab')!.hidden)
    await page.waitForFunction(
      (id) => {
        const app = window.concord
        const b = app.sandbox.bodies().find((v: { id: number }) => v.id === id)
        if (!b) return false
        const p = app.camera.toScreen(b.x, b.y)
        const bar = document.getElementById('toolbar')!.getBoundingClientRect()
        const lab = document.getElementById('lab')!.getBoundingClientRect()
        return p.y > bar.bottom && p.y < lab.top && p.x > 0 && p.x < app.camera.width
      },
      top,
      { timeout: 15_000 },
    )
    await page.screenshot({ path: `${ARTIFACTS}/phone-lab.png` })
    expect(errors).toEqual([])
    await context.close()
  })
})

describe('notices', { timeout: 60_000 }, () => {
  it('delivers 40 spawns clicked at once, none dropped by the input budget, and says they are queued', async () => {
    const { context, page, errors } = await open(`${base}/?room=burst`, 1280, 800)
    await joined(page)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'scene', name: 'empty' }))
    await page.waitForFunction(() => window.concord.sandbox.scene() === 'empty')
    await page.evaluate(() => {
      for (let i = 0; i < 40; i++) {
        window.concord.sandbox.send({
          k: 'spawn',
          shape: { type: 'circle', radius: 0.3 },
          x: -12 + i * 0.6,
          y: 3,
        })
      }
    })
    await page.waitForFunction(() =>
      /Sending \d+ more inputs/.test(document.getElementById('toast')!.textContent!),
    )
    await page.waitForFunction(
      () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length === 40,
      undefined,
      { timeout: 20_000 },
    )
    expect(await page.evaluate(() => window.concord.sandbox.notices().latest)).not.toMatch(/budget exceeded/)
    expect(errors).toEqual([])
    await context.close()
  })

  it('says what is wrong with an invalid room name instead of retrying', async () => {
    const { context, page } = await open(`${base}/?room=bad%20name!!`, 1280, 800)
    await page.waitForFunction(() => /not valid/.test(document.getElementById('banner-text')!.textContent!))
    const text = (await page.textContent('#banner-text'))!
    expect(text).toContain('bad name!!')
    expect(text).toMatch(/1-32 letters, digits, - or _/)
    expect(text).not.toMatch(/Cannot reach/)
    expect(await page.isHidden('#retry')).toBe(true)
    await context.close()
  })
})
