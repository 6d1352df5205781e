/*
 * The page's layout and notices in real Chromium against a real server: the toolbar fits on one
 * row and keeps its width whatever tool is active, and the HUD is never clipped, at 1280x800 and
 * 1920x1080; on a 390x844 touch phone the toolbar and the lab panel leave the selected body in
 * sight; 40 spawns clicked at once all arrive (none dropped by the per-tick input budget) and the
 * player is told they are queued; inputs the server does drop (sent past the page's pacing) are
 * reported and dropped spawns sent again, each arriving once; a room name the server cannot accept says what is wrong.
 */
import type { Browser, Page } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import {
  ARTIFACTS,
  collectErrors,
  pickTool,
  screenOfBody,
  useClientPages,
} from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

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

/** Whether two boxes overlap (CSS px). */
const overlaps = (a: Box, b: Box): boolean =>
  a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom
type Box = { left: number; right: number; top: number; bottom: number }

describe('layout', { timeout: 300_000 }, () => {
  for (const [width, height, phone] of [
    [1280, 800, false],
    [1920, 1080, false],
    [390, 844, true],
  ] as const) {
    it(`fits the toolbar (${phone ? 'wrapped, every button in reach' : 'one row'}, constant size) and never clips or covers with the HUD at ${width}x${height}`, async () => {
      const { context, page, errors } = await open(
        `${base}/?room=layout-${width}&name=a-rather-long-player-name`,
        width,
        height,
        phone,
      )
      await joined(page)
      const sizes = new Set<string>()
      for (const tool of ['grab', 'circle', 'box', 'polygon', 'delete', 'pin', 'rope', 'cut', 'inspect']) {
        await pickTool(page, tool)
        const bar = await layout(page, 'toolbar')
        expect(bar.overflowX, `toolbar overflows with ${tool}`).toBe(false)
        if (!phone) expect(bar.height, 'one row').toBeLessThan(50)
        sizes.add(`${Math.round(bar.width)}x${Math.round(bar.height)}`)
      }
      expect([...sizes]).toHaveLength(1)
      // Every control lies wholly inside the toolbar and the screen: nothing scrolled out of reach.
      const bar = await layout(page, 'toolbar')
      const controls = await page.evaluate(() =>
        [...document.querySelectorAll('#toolbar > button, #toolbar > select')].map((e) => {
          const r = e.getBoundingClientRect()
          return { id: e.textContent, left: r.left, right: r.right, top: r.top, bottom: r.bottom }
        }),
      )
      expect(controls.length).toBeGreaterThanOrEqual(19)
      for (const c of controls) {
        expect(c.left, `${c.id} left`).toBeGreaterThanOrEqual(Math.max(0, bar.left))
        expect(c.right, `${c.id} right`).toBeLessThanOrEqual(Math.min(width, bar.right))
        expect(c.bottom, `${c.id} bottom`).toBeLessThanOrEqual(bar.bottom)
      }
      const hud = await layout(page, 'hud')
      expect(hud.overflowX || hud.overflowY).toBe(false)
      expect(hud.left).toBeGreaterThanOrEqual(0)
      expect(hud.right).toBeLessThanOrEqual(width)
      expect(hud.bottom).toBeLessThanOrEqual(height)
      expect(overlaps(hud, bar), 'HUD over the toolbar').toBe(false)
      // The Debug layer row is hidden until Debug is pressed, then covers neither bar nor HUD.
      expect(await page.isHidden('#layers-panel')).toBe(true)
      await page.click('#layers')
      await page.waitForFunction(() => !document.getElementById('layers-panel')!.hidden)
      await page.waitForFunction(() => {
        const r = (id: string) => document.getElementById(id)!.getBoundingClientRect()
        const [a, b, c] = [r('layers-panel'), r('toolbar'), r('hud')]
        const apart = (x: DOMRect, y: DOMRect) =>
          x.right <= y.left || y.right <= x.left || x.bottom <= y.top || y.bottom <= x.top
        return a.height > 0 && apart(a, b) && apart(a, c)
      })
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
      { timeout: 90_000 },
    )
    await page.screenshot({ path: `${ARTIFACTS}/phone-lab.png` })
    expect(errors).toEqual([])
    await context.close()
  })
})

describe('notices', { timeout: 300_000 }, () => {
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
      /^Sending your next \d+ actions a few at a time, so the room keeps up\.$/.test(
        document.getElementById('toast')!.textContent!,
      ),
    )
    await page.waitForFunction(
      () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length === 40,
      undefined,
      { timeout: 90_000 },
    )
    // None doubled either (a spawn the server dropped under load is sent again, once).
    const tick = await page.evaluate(() => window.concord.sandbox.stats().tick)
    await page.waitForFunction((t) => window.concord.sandbox.stats().tick > t + 60, tick)
    expect(
      await page.evaluate(
        () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length,
      ),
    ).toBe(40)
    expect(errors).toEqual([])
    await context.close()
  })

  it('tells the player when the server drops inputs over the budget, and sends the dropped spawns again', async () => {
    const { context, page, errors } = await open(`${base}/?room=dropped`, 1280, 800)
    await joined(page)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'scene', name: 'empty' }))
    await page.waitForFunction(() => window.concord.sandbox.scene() === 'empty')
    const perTick = await page.evaluate(() => window.concord.sandbox.rules()!.inputsPerTick)
    // Bypass the page's pacing (as a script or a long stall would): 12 ticks' worth in one go.
    // The server applies a tick's worth, keeps 4 ticks' worth waiting and must refuse the rest.
    const sent = 12 * perTick
    // Every notice shown, in order (a later one replaces an earlier one on screen).
    await page.evaluate(() => {
      const shown: string[] = []
      ;(window as unknown as { shown: string[] }).shown = shown
      const toast = document.getElementById('toast')!
      new MutationObserver(() => shown.push(toast.textContent!)).observe(toast, { childList: true })
    })
    const shown = (pattern: string) =>
      page
        .waitForFunction(
          (p) => (window as unknown as { shown: string[] }).shown.some((t) => new RegExp(p).test(t)),
          pattern,
        )
        .catch(async (e) => {
          console.log(
            'notices shown:',
            await page.evaluate(() => (window as unknown as { shown: string[] }).shown),
          )
          throw e
        })
    await page.evaluate((n) => {
      const raw = window.concord.sandbox as unknown as { transmit(cmd: unknown, now: number): void }
      for (let i = 0; i < n; i++)
        raw.transmit(
          {
            k: 'spawn',
            shape: { type: 'circle', radius: 0.3 },
            x: -20 + (i % 40),
            y: 3 + Math.floor(i / 40),
          },
          0,
        )
    }, sent)
    await shown(
      '^The room was too busy for \\d+ of your actions at once; the \\d+ new shapes among them are sent again\\.$',
    )
    // Every spawn arrives once: none lost, none doubled (still so a second of server ticks later).
    const count = () =>
      page.evaluate(
        () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length,
      )
    await page.waitForFunction(
      (n) => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length >= n,
      sent,
      { timeout: 90_000 },
    )
    const tick = await page.evaluate(() => window.concord.sandbox.stats().tick)
    await page.waitForFunction((t) => window.concord.sandbox.stats().tick > t + 60, tick)
    expect(await count()).toBe(sent)
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
