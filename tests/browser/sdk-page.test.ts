/*
 * examples/sdk-page in Chromium: the page uses only the built SDK (`npm run build:sdk`'s output,
 * served beside it as /sdk/ by a real server's static directory). It joins, lists its players and
 * the body count, and its Spawn button sends a built-in command whose box a second client (a bot
 * on the same room) sees, drawn by the SDK's renderer in the box's colour; in a goal-game room its
 * Kick button sends the custom command, refused by the game in words the page shows.
 */
import { cp, mkdir, rm } from 'node:fs/promises'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/index.ts'
import { buildSdk } from '../../scripts/build-sdk.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { startTestServer } from '../support/test-server.ts'

const STATIC = 'test-results/sdk-page/static'
const BOX_COLOR = 0xf0a030
let browser: Browser
let server: RunningServer
const bots: BotClient[] = []

beforeAll(async () => {
  await rm(STATIC, { recursive: true, force: true })
  await mkdir(STATIC, { recursive: true })
  await cp('examples/sdk-page', STATIC, { recursive: true })
  await buildSdk(`${STATIC}/sdk`)
  server = await startTestServer({ staticDir: STATIC })
  browser = await launchBrowser()
}, 120_000)

afterAll(async () => {
  await Promise.all(bots.map((b) => b.close()))
  await browser?.close()
  await server?.close()
})

async function openPage(query: string): Promise<{ page: Page; problems: string[] }> {
  const page = await browser.newPage()
  const problems: string[] = []
  page.on('pageerror', (e) => problems.push(e.message))
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(m.text())
  })
  await page.goto(`${server.url}/?${query}`)
  await page.waitForFunction(() => document.getElementById('status')?.textContent?.startsWith('joined'))
  return { page, problems }
}

/** Canvas pixels within 12 of the colour in every channel. */
const pixelsOf = (page: Page, rgb: number) =>
  page.evaluate((color) => {
    const canvas = document.getElementById('world') as HTMLCanvasElement
    const data = canvas.getContext('2d')!.getImageData(0, 0, canvas.width, canvas.height).data
    const [r, g, b] = [(color >> 16) & 255, (color >> 8) & 255, color & 255]
    let n = 0
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - r) < 12 && Math.abs(data[i + 1] - g) < 12 && Math.abs(data[i + 2] - b) < 12) n++
    return n
  }, rgb)

describe('the SDK example page', () => {
  it('joins, shows players and bodies, and spawns a box that another client sees', async () => {
    const { page, problems } = await openPage('room=sdk-page&name=ada')
    const bot = await BotClient.connect({ url: server.url, room: 'sdk-page', name: 'bot' })
    bots.push(bot)
    await page.waitForFunction(() => document.getElementById('players')?.textContent === 'ada, bot')
    const before = bot.mirror.bodies.size
    expect(await page.textContent('#bodies')).toBe(String(before))
    expect(await pixelsOf(page, BOX_COLOR)).toBe(0)
    await page.click('#spawn')
    await bot.waitFor(
      () => [...bot.mirror.bodies.values()].some((b) => b.color === BOX_COLOR && b.kind === 2),
      'the page’s box',
    )
    const box = [...bot.mirror.bodies.values()].find((b) => b.color === BOX_COLOR)!
    const pageId = await page.evaluate(
      () => (window as unknown as { sdkSession: { id: number } }).sdkSession.id,
    )
    expect(box.player).toBe(pageId)
    await page.waitForFunction(
      (n) => document.getElementById('bodies')?.textContent === String(n),
      before + 1,
    )
    // The renderer draws it: pixels of the box's colour appear on the canvas.
    await page.waitForFunction((color) => {
      const canvas = document.getElementById('world') as HTMLCanvasElement
      const data = canvas.getContext('2d')!.getImageData(0, 0, canvas.width, canvas.height).data
      const [r, g, b] = [(color >> 16) & 255, (color >> 8) & 255, color & 255]
      let n = 0
      for (let i = 0; i < data.length; i += 4)
        if (Math.abs(data[i] - r) < 12 && Math.abs(data[i + 1] - g) < 12 && Math.abs(data[i + 2] - b) < 12)
          n++
      return n > 50
    }, BOX_COLOR)
    expect(problems).toEqual([])
    await page.close()
  })

  it('sends the goal game’s custom command in a goal room', async () => {
    const { page, problems } = await openPage('room=sdk-goal-page&game=goal&name=ada')
    expect(await page.isHidden('#kick')).toBe(false)
    await page.click('#kick')
    // One player: the ball sits at the centre, out of the disc's reach, and the game says so.
    await page.waitForFunction(() =>
      document.getElementById('last')?.textContent?.includes('the ball is out of reach'),
    )
    expect(problems).toEqual([])
    await page.close()
  })
})
