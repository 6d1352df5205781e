/*
 * The Draw and Ground tools in real Chromium against a real server (issue 31, Build: Draw, Ground
 * and tracks): a freehand concave outline becomes one body of convex pieces covering what was
 * drawn, in the player's colour on the canvas; a self-intersecting one is refused with a notice
 * and makes nothing; corners clicked one by one close into a body; W cycles to rectangle, circle
 * and capsule, each dragged out to the size of the drag; Ground draws static segment lines; the
 * Static toggle makes a drawn body static; a finger draws too; a preview follows the pointer. The
 * room is paused so drawn bodies stay where they were drawn. Oracles: the drawn world points
 * (areas by the shoelace formula, sizes from the drag), the roster's colour, pixel reads.
 */
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import {
  bodies,
  Finger,
  loadScene,
  openSandbox,
  type PageBody,
  pickTool,
  pixelAt,
  screenOf,
  startClientServer,
} from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser

beforeAll(async () => {
  ;[server, browser] = await Promise.all([startClientServer(), launchBrowser()])
})
afterAll(async () => {
  await browser?.close()
  await server?.close()
})

type Pt = { x: number; y: number }

/** An empty, paused room with the camera showing x in [-10, 10], y in [-1, 12] or so. */
async function emptyRoom(
  room: string,
  touch = false,
): Promise<{ page: Page; close: () => Promise<void>; errors: string[] }> {
  const { page, context, errors } = await openSandbox(
    browser,
    `http://127.0.0.1:${server.port}/?room=${room}`,
    { touch },
  )
  await loadScene(page, 'empty', 0)
  await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
  await page.waitForFunction(() => window.concord.sandbox.paused())
  await page.evaluate(() => {
    const c = window.concord.camera
    c.x = 0
    c.y = 5
    c.scale = 40
  })
  return { page, errors, close: () => context.close() }
}

/** Press, move through `points` (world m, a few steps between each) and release, with the mouse. */
async function drag(page: Page, points: Pt[], steps = 4): Promise<void> {
  const screen = await Promise.all(points.map((p) => screenOf(page, p.x, p.y)))
  await page.mouse.move(screen[0].x, screen[0].y)
  await page.mouse.down()
  for (const p of screen.slice(1)) await page.mouse.move(p.x, p.y, { steps })
  await page.mouse.up()
}

async function click(page: Page, p: Pt): Promise<void> {
  const s = await screenOf(page, p.x, p.y)
  await page.mouse.click(s.x, s.y)
}

/** The bodies that appear after `before` (the count of bodies then; ids only grow), newest last. */
const made = async (page: Page, before: number): Promise<PageBody[]> => {
  await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, before)
  const all = (await bodies(page)).sort((a, b) => a.id - b.id)
  return all.slice(before)
}

/** Shoelace area of a flat polygon (m^2). */
function area(v: readonly number[]): number {
  let twice = 0
  for (let i = 0; i < v.length; i += 2) {
    const j = (i + 2) % v.length
    twice += v[i] * v[j + 1] - v[j] * v[i + 1]
  }
  return Math.abs(twice) / 2
}

/** The page's own player colour (its roster colour, as the page reports it). */
const myColor = (page: Page): Promise<string> => page.evaluate(() => window.concord.sandbox.color())

describe('Draw and Ground tools', { timeout: 300_000 }, () => {
  it('a freehand concave outline becomes one body of convex pieces in the player colour; a crossing one is refused with a notice', async () => {
    const { page, close, errors } = await emptyRoom('draw-outline')
    await page.keyboard.press('w')
    expect(await page.getAttribute('[data-tool="draw"]', 'class')).toContain('active')
    // A U: 4 m wide, 3 m tall, the notch 2 m wide and 2 m deep (area 12 - 4 = 8 m^2).
    const u: Pt[] = [
      { x: -2, y: 2 },
      { x: 2, y: 2 },
      { x: 2, y: 5 },
      { x: 1, y: 5 },
      { x: 1, y: 3 },
      { x: -1, y: 3 },
      { x: -1, y: 5 },
      { x: -2, y: 5 },
      { x: -2, y: 2 },
    ]
    const before = (await bodies(page)).length
    await drag(page, u)
    const [body] = await made(page, before)
    expect(body.kind).toBe(2)
    expect(body.shapes.length).toBeGreaterThanOrEqual(3)
    const total = body.shapes.reduce((sum, s) => sum + area(s.v ?? []), 0)
    expect(total).toBeGreaterThan(8 * 0.97)
    expect(total).toBeLessThan(8 * 1.03)
    expect(body.color).toBe(await myColor(page))
    // On the canvas: inside a leg of the U, the player's colour; inside the notch, the background.
    const leg = await screenOf(page, -1.5, 4)
    const notch = await screenOf(page, 0, 4.5)
    const want = (await myColor(page))
      .slice(1)
      .match(/../g)!
      .map((h) => Number.parseInt(h, 16))
    await page.waitForFunction(() => new Promise((r) => requestAnimationFrame(() => r(true))))
    const [r, g, b] = await pixelAt(page, leg.x, leg.y)
    expect(Math.abs(r - want[0]) + Math.abs(g - want[1]) + Math.abs(b - want[2])).toBeLessThan(30)
    const bg = await pixelAt(page, notch.x, notch.y)
    expect(bg[0] + bg[1] + bg[2]).toBeLessThan(150)
    // A figure eight crosses itself: a notice says so, and nothing is made.
    const count = (await bodies(page)).length
    await drag(page, [
      { x: 4, y: 2 },
      { x: 7, y: 5 },
      { x: 7, y: 2 },
      { x: 4, y: 5 },
      { x: 4, y: 2 },
    ])
    await page.waitForFunction(() => !document.getElementById('toast')!.hidden)
    expect(await page.textContent('#toast')).toMatch(/cannot be a body: .*(cross|touch)/)
    await page.waitForTimeout(300)
    expect((await bodies(page)).length).toBe(count)
    expect(errors).toEqual([])
    await close()
  })

  it('clicked corners close into a body; W cycles to rectangle, circle and capsule, each the size of the drag; Static makes them static', async () => {
    const { page, close } = await emptyRoom('draw-forms')
    await pickTool(page, 'draw')
    let before = (await bodies(page)).length
    for (const p of [
      { x: -6, y: 2 },
      { x: -4, y: 2 },
      { x: -4, y: 4 },
      { x: -6, y: 4 },
      { x: -6, y: 2 },
    ])
      await click(page, p)
    const [square] = await made(page, before)
    expect(square.shapes.reduce((sum, s) => sum + area(s.v ?? []), 0)).toBeCloseTo(4, 1)
    // Rectangle: dragged from (-2, 2) to (1, 4): half extents 1.5 and 1.
    await page.keyboard.press('w')
    before = (await bodies(page)).length
    // While dragging, the preview is the body the drag will make.
    const a = await screenOf(page, -2, 2)
    const b = await screenOf(page, 1, 4)
    await page.mouse.move(a.x, a.y)
    await page.mouse.down()
    await page.mouse.move(b.x, b.y, { steps: 5 })
    const ghost = await page.evaluate(() => window.concord.tools.overlay('#fff').ghost?.shapes[0])
    expect(ghost).toMatchObject({ type: 'box' })
    await page.mouse.up()
    const [rect] = await made(page, before)
    expect(rect.shapes[0].type).toBe('box')
    expect(rect.shapes[0].hw).toBeCloseTo(1.5, 1)
    expect((rect.shapes[0] as { hh?: number }).hh).toBeCloseTo(1, 1)
    expect(rect.x).toBeCloseTo(-0.5, 1)
    expect(rect.y).toBeCloseTo(3, 1)
    // Circle: centre (3, 3), dragged 1.2 m.
    await page.keyboard.press('w')
    before = (await bodies(page)).length
    await drag(page, [
      { x: 3, y: 3 },
      { x: 3, y: 4.2 },
    ])
    const [disc] = await made(page, before)
    expect(disc.shapes[0]).toMatchObject({ type: 'circle' })
    expect(disc.shapes[0].radius).toBeCloseTo(1.2, 1)
    // Capsule, with Static on: from (5, 2) to (8, 3), static.
    await page.keyboard.press('w')
    await page.keyboard.press('m')
    expect(await page.getAttribute('#static', 'aria-pressed')).toBe('true')
    before = (await bodies(page)).length
    await drag(page, [
      { x: 5, y: 2 },
      { x: 8, y: 3 },
    ])
    const [pill] = await made(page, before)
    expect(pill.kind).toBe(0)
    expect(pill.shapes[0].type).toBe('capsule')
    const [x1, y1, x2, y2] = pill.shapes[0].v!
    expect(Math.hypot(x2 - x1, y2 - y1)).toBeCloseTo(Math.hypot(3, 1), 1)
    await close()
  })

  it('Ground draws static segment lines, drawn on the canvas; a finger draws an outline too', async () => {
    const { page, close } = await emptyRoom('ground', true)
    await page.keyboard.press('t')
    const before = (await bodies(page)).length
    const line: Pt[] = [
      { x: -8, y: 6 },
      { x: -4, y: 4 },
      { x: 0, y: 4.5 },
      { x: 4, y: 3 },
    ]
    await drag(page, line, 6)
    const [ground] = await made(page, before)
    expect(ground.kind).toBe(0)
    expect(ground.shapes.length).toBeGreaterThanOrEqual(3)
    expect(ground.shapes.every((s) => s.type === 'segment')).toBe(true)
    await page.waitForFunction(() => new Promise((r) => requestAnimationFrame(() => r(true))))
    const on = await screenOf(page, -6, 5)
    const [r, g, b] = await pixelAt(page, on.x, on.y)
    expect(r + g + b).toBeGreaterThan(250) // the line is painted (#8a94a8 or lighter)
    // A finger draws a triangle with the Draw tool.
    await page.tap('[data-tool="draw"]')
    const count = (await bodies(page)).length
    const pts = await Promise.all(
      [
        { x: 2, y: 6 },
        { x: 6, y: 6 },
        { x: 4, y: 9 },
        { x: 2, y: 6 },
      ].map((p) => screenOf(page, p.x, p.y)),
    )
    const finger = await Finger.down(page, pts[0])
    for (const p of pts.slice(1)) await finger.moveTo(p, 8)
    await finger.up()
    const [tri] = await made(page, count)
    expect(tri.kind).toBe(2)
    expect(tri.shapes.reduce((sum, s) => sum + area(s.v ?? []), 0)).toBeCloseTo(6, 0)
    await close()
  })

  it('lockstep and predict pages draw the same compound, capsule and outline bodies, in the same colours', async () => {
    const { page, close } = await emptyRoom('draw-modes')
    const before = (await bodies(page)).length
    await page.evaluate(() => {
      const s = window.concord.sandbox
      s.send({
        k: 'spawn',
        shapes: [
          { type: 'box', hw: 1, hh: 0.25 },
          { type: 'circle', radius: 0.4, x: -1, y: -0.5 },
          { type: 'capsule', v: [0.5, 0.5, 1.5, 0.5], radius: 0.2 },
        ],
        x: -4,
        y: 4,
        color: 0x33cc66,
      })
      s.send({ k: 'spawn', outline: [0, 0, 3, 0, 3, 3, 2, 3, 2, 1, 1, 1, 1, 3, 0, 3], x: 2, y: 3 })
    })
    await made(page, before)
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length >= n + 2, before)
    const shown = (await bodies(page))
      .sort((a, b) => a.id - b.id)
      .map((b) => [b.id, b.kind, b.shapes, b.color])
    for (const mode of ['lockstep', 'predict']) {
      const other = await openSandbox(
        browser,
        `http://127.0.0.1:${server.port}/?room=draw-modes&mode=${mode}`,
      )
      await other.page.waitForFunction((n) => window.concord.sandbox.bodies().length >= n, shown.length)
      const there = (await bodies(other.page))
        .sort((a, b) => a.id - b.id)
        .map((b) => [b.id, b.kind, b.shapes, b.color])
      expect(there, mode).toEqual(shown)
      // The compound's box, on the canvas, in its colour.
      await other.page.evaluate(() => {
        const c = window.concord.camera
        c.x = 0
        c.y = 5
        c.scale = 40
      })
      await other.page.waitForFunction(() => new Promise((r) => requestAnimationFrame(() => r(true))))
      const at = await screenOf(other.page, -3.5, 4)
      const [r, g, b] = await pixelAt(other.page, at.x, at.y)
      expect(Math.abs(r - 0x33) + Math.abs(g - 0xcc) + Math.abs(b - 0x66), mode).toBeLessThan(30)
      expect(other.errors, mode).toEqual([])
      await other.context.close()
    }
    await close()
  })
})
