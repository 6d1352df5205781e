/*
 * A game room's page offers only the tools and controls its game lists (rules.builtins and
 * rules.commands; PROTOCOL.md RoomRules), so it sends no command the game lacks. A real server on
 * 127.0.0.1 serving the built client, headless Chromium, and the page's own WebSocket frames read
 * through Playwright (decoded as MessagePack). In a goal room (the goal game lists no built-in
 * command) the toolbar shows the Lab alone of the tools and none of the room controls, the HUD
 * names the game instead of a scene it never loaded, the pointer moving over the canvas sends no
 * `move` and the page shows no refusal; a tool key (C) is answered on the page and sends nothing. The
 * same pointer moves in a sandbox room do send `move` (the control: the frame reading works).
 */
import { Unpackr } from 'msgpackr'
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { startClientServer } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

const unpackr = new Unpackr({ useRecords: false, mapsAsObjects: true, int64AsType: 'number' })
let server: RunningServer
let browser: Browser
const contexts: BrowserContext[] = []

beforeAll(async () => {
  server = await startClientServer()
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  for (const c of contexts) await c.close()
  await browser?.close()
  await server?.close()
})

/** Open a page and record the kinds of the messages it sends (`input` as `input:KIND`). */
async function openRecording(url: string): Promise<{ page: Page; sent: string[]; errors: string[] }> {
  const sent: string[] = []
  const context = await browser.newContext({ viewport: { width: 1000, height: 700 } })
  context.setDefaultTimeout(90_000)
  contexts.push(context)
  const page = await context.newPage()
  page.on('websocket', (ws) =>
    ws.on('framesent', ({ payload }) => {
      if (typeof payload === 'string') return
      try {
        const m = unpackr.unpack(payload) as { t?: string; cmd?: { k?: string } }
        sent.push(m.t === 'input' ? `input:${m.cmd?.k}` : String(m.t))
      } catch {
        sent.push('undecodable')
      }
    }),
  )
  const errors: string[] = []
  page.on('pageerror', (e) => errors.push(e.message))
  await page.goto(url)
  await page.waitForFunction(() => {
    const c = window.concord
    return c && c.sandbox.status().state === 'connected' && c.sandbox.rules() !== null && c.fps.value > 0
  })
  return { page, sent, errors }
}

/** Move the pointer back and forth over the canvas until `done` holds. */
async function hoverUntil(page: Page, done: () => boolean, what: string): Promise<void> {
  let i = 0
  await until(async () => {
    i++
    await page.mouse.move(300 + (i % 20) * 15, 300 + (i % 7) * 10)
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(r)))
    return done()
  }, what)
}

/** The tool buttons the page shows (not hidden), by data-tool. */
function shownTools(page: Page): Promise<string[]> {
  return page.evaluate(() =>
    [...document.querySelectorAll<HTMLButtonElement>('#toolbar [data-tool]')]
      .filter((b) => !b.hidden)
      .map((b) => b.dataset.tool ?? ''),
  )
}

describe('tools a game lists', { timeout: 180_000 }, () => {
  it('a goal room offers the Lab alone and sends no command the goal game lacks', async () => {
    const { page, sent, errors } = await openRecording(`${server.url}/?room=tools-goal&game=goal`)
    const rules = await page.evaluate(() => window.concord.sandbox.rules())
    expect(rules).toMatchObject({
      game: 'goal',
      builtins: [],
      scenes: [],
      commands: ['kick', 'rematch', 'run'],
    })
    await page.waitForFunction(() => document.querySelector<HTMLButtonElement>('[data-tool="grab"]')?.hidden)
    expect(await shownTools(page)).toEqual(['inspect'])
    const controls = await page.evaluate(() =>
      ['scene', 'pause', 'step', 'reset', 'gravity', 'slow', 'lock', 'joints', 'static', 'open-scene'].filter(
        (id) => !document.getElementById(id)?.hidden,
      ),
    )
    expect(controls).toEqual([])
    expect(await page.evaluate(() => document.getElementById('hud')?.textContent)).toContain('game goal')

    // Until the page has acknowledged five more snapshots (time passing, measured by the room).
    const acks = () => sent.filter((k) => k === 'ack').length
    const before = acks()
    await hoverUntil(page, () => acks() >= before + 5, 'five snapshots acknowledged while hovering')
    await page.keyboard.press('c')
    await page.waitForFunction(() =>
      /has no circle tool/.test(document.getElementById('toast')?.textContent ?? ''),
    )
    expect(sent.filter((k) => k.startsWith('input:'))).toEqual([])
    const notices = await page.evaluate(() => window.concord.sandbox.notices())
    expect(notices.latest ?? '').not.toMatch(/has no \w+ command/)
    expect(errors).toEqual([])
  })

  it('the same pointer moves in a sandbox room send move (the control)', async () => {
    const { page, sent } = await openRecording(`${server.url}/?room=tools-sandbox`)
    expect((await page.evaluate(() => window.concord.sandbox.rules()))?.builtins).toContain('move')
    expect(await shownTools(page)).toContain('grab')
    await hoverUntil(page, () => sent.includes('input:move'), 'a move sent while hovering')
  })
})
