/*
 * The browser replay player against a real recorded session: two bots play in a room of a real
 * server that records (spawns, a grab dragged around, a pin, a rope, a delete, gravity, a scene
 * load); the server shuts down cleanly, a second server on the same replay directory, with a join
 * token, serves the page and the log (to a page opened with the key; one without it is told the
 * logs need a key). In Chromium the player opens the log from the server's list, plays it, seeks
 * back and forward through the seek bar, and the hash indicator stays green. At every sought tick
 * the page's world hash equals the replay CLI's (server/replay/replay-tool.ts, `--to TICK`) in Node, and
 * the page's engine reaches the same final hash as Node's.
 */
import { mkdir, mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import { replayLog } from '../../server/replay/replay-tool.ts'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { collectErrors, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-replay/dist'
const ROOM = 'replayed'
const TICKS = 900

/** The serving server's join token: its replays need it, as its rooms do. */
const KEY = 'replay-key-5d1e'

let browser: Browser
let server: RunningServer
let logName = ''
let logBytes: Uint8Array

async function recordSession(replayDir: string): Promise<void> {
  const recording = await serveClient(DIST, { record: true, replayDir, keyframeTicks: 120 })
  try {
    const a = await BotClient.connect({ url: recording.url, room: ROOM, name: 'ada' })
    const b = await BotClient.connect({ url: recording.url, room: ROOM, name: 'bob' })
    const dynamic = (): number[] => [...a.mirror.bodies.values()].filter((x) => x.kind === 2).map((x) => x.id)
    a.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 12, vx: 2, vy: 0 })
    await a.waitFor(() => dynamic().length > 0, 'a dynamic body')
    const ids = dynamic()
    a.command({ k: 'grab', body: ids[0], lx: 0, ly: 0 })
    if (ids.length > 3) b.command({ k: 'rope', a: ids[1], b: ids[2], ax: 0, ay: 0, bx: 0, by: 0 })
    // The room's tick as ada sees it (the rooms run on worker threads, out of this thread's reach).
    const tick = (): number => a.mirror.tick
    let i = 0
    while (tick() < TICKS) {
      i++
      a.command({ k: 'move', x: Math.sin(i / 5) * 3, y: 5 + Math.cos(i / 7) })
      if (i === 20)
        b.command({ k: 'spawn', shape: { type: 'box', hw: 0.3, hh: 0.3 }, x: -2, y: 9, vx: 0, vy: 0 })
      if (i === 30) b.command({ k: 'gravity', x: 1, y: -9 })
      if (i === 60) b.command({ k: 'scene', name: 'joints' })
      await a.waitFor(() => tick() >= Math.min(TICKS, i * 3), 'room ticks')
    }
    await a.close()
    await b.close()
  } finally {
    await recording.close()
  }
}

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  const replayDir = await mkdtemp(join(tmpdir(), 'concord-replays-'))
  await recordSession(replayDir)
  server = await serveClient(DIST, { replayDir, joinToken: KEY })
  const listed = (await (await fetch(`${httpBase()}/replays?key=${KEY}`)).json()) as Array<{
    name: string
    room: string
    status: string
  }>
  const entry = listed.find((l) => l.room === ROOM)
  if (!entry) throw new Error(`no log of room ${ROOM} in ${JSON.stringify(listed)}`)
  expect(entry.status).toBe('clean')
  logName = entry.name
  logBytes = new Uint8Array(await readFile(join(replayDir, logName)))
  browser = await launchBrowser()
}, 240_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

const httpBase = (): string => `http://127.0.0.1:${server.port}`

const pageHash = (page: Page): Promise<number> =>
  page.evaluate(() => window.concordReplay!.sandbox!.player.sim.hash())
const pageTick = (page: Page): Promise<number> =>
  page.evaluate(() => window.concordReplay!.sandbox!.player.tick)

/** Move the seek bar as a person would: set its value and fire its input event. */
async function seekBar(page: Page, tick: number): Promise<void> {
  await page.evaluate((t) => {
    const seek = document.getElementById('replay-seek') as HTMLInputElement
    seek.value = String(t)
    seek.dispatchEvent(new Event('input'))
  }, tick)
  await page.waitForFunction((t) => window.concordReplay?.sandbox?.player.tick === t, tick)
}

describe('browser replay player', () => {
  it('opens a log from the server list, plays, seeks both ways with the hashes green, matching the CLI in Node', async () => {
    const context = await browser.newContext({ viewport: { width: 1280, height: 800 } })
    const page = await context.newPage()
    const errors = collectErrors(page)
    await page.goto(`${httpBase()}/?replay&key=${KEY}`)
    await page.click(`#replay-list button[data-log="${logName}"]`)
    await page.waitForSelector('#replay-play')
    await page.waitForFunction(() => (window.concord?.sandbox.bodies().length ?? 0) > 0)

    const full = await replayLog(logBytes)
    expect(full.divergence).toBeNull()

    await page.click('#replay-speed')
    await page.selectOption('#replay-speed', '8')
    await page.click('#replay-play')
    await page.waitForFunction(() => window.concordReplay!.sandbox!.player.tick > 300, undefined, {
      timeout: 60_000,
    })
    expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')

    for (const t of [700, 150, 899, 61, 480]) {
      const target = Math.min(t, full.lastTick)
      await seekBar(page, target)
      const cli = await replayLog(logBytes, { to: target })
      expect(await pageHash(page), `hash at tick ${target}`).toBe(cli.finalHash)
      expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')
    }

    await seekBar(page, full.firstTick)
    await page.click('#replay-play')
    await page.waitForFunction(() => window.concordReplay!.sandbox!.player.atEnd, undefined, {
      timeout: 120_000,
    })
    expect(await pageTick(page)).toBe(full.lastTick)
    expect(await pageHash(page)).toBe(full.finalHash)
    const checked = await page.evaluate(() => window.concordReplay!.sandbox!.player.checked)
    expect(checked).toBeGreaterThanOrEqual(full.hashesChecked - 1)
    expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')
    expect(errors).toEqual([])
    await context.close()
  })

  it('without the key, says the logs need it; says in one line what is wrong with a file that is not a log', async () => {
    const context = await browser.newContext()
    const page = await context.newPage()
    await page.goto(`${httpBase()}/?replay`)
    await page.waitForFunction(() =>
      /need its key \(HTTP 401\)/.test(document.getElementById('replay-list')?.textContent ?? ''),
    )
    await page.setInputFiles('#replay-file', {
      name: 'notes.txt',
      mimeType: 'text/plain',
      buffer: Buffer.from('these are not the bytes of a replay log'),
    })
    await page.waitForFunction(() =>
      /not a replay log/.test(document.getElementById('replay-message')?.textContent ?? ''),
    )
    await context.close()
  })

  it('?replay=NAME for a missing log, a room name or a path shows why, above the picker', async () => {
    const context = await browser.newContext({ viewport: { width: 1000, height: 700 } })
    const page = await context.newPage()
    const cases = [
      [
        'gone-20260101T000000000Z.cclog',
        /Cannot open the replay "gone-20260101T000000000Z\.cclog": no such replay \(HTTP 404\)\.$/,
      ],
      [
        ROOM,
        /Cannot open the replay "replayed": no such replay \(HTTP 404\)\. A replay is named by its log file/,
      ],
      [
        '../../etc/passwd',
        /Cannot open the replay "\.\.\/\.\.\/etc\/passwd": bad replay name \(HTTP 400\)\. A replay is named/,
      ],
    ] as const
    for (const [name, expected] of cases) {
      await page.goto(`${httpBase()}/?replay=${encodeURIComponent(name)}&key=${KEY}`)
      await page.waitForSelector(`#replay-list button[data-log="${logName}"]`)
      const message = page.locator('#replay-message')
      expect(await message.isVisible()).toBe(true)
      expect(await message.textContent()).toMatch(expected)
      // The picker is there to go on from: the file input takes the server's own log files.
      expect(await page.locator('#replay-file').isVisible()).toBe(true)
      const accept = (await page.getAttribute('#replay-file', 'accept')) ?? ''
      expect(accept.split(',')).toContain(logName.slice(logName.lastIndexOf('.')))
    }
    await context.close()
  })
})
