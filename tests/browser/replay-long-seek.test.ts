/*
 * Long seeks in the browser player: a 120,000-tick log with no keyframes (keyframe-free-log.ts:
 * the server's recorder, a hash record every 60 ticks) opened in Chromium through the file picker.
 * A seek to its end replays every tick (about a second of work here, far more on a slower machine
 * or a longer log); the page must answer script calls, paint frames and show the seek's progress
 * meanwhile, and no single task may take a large part of the seek. A drag of the seek bar (many
 * input events, each a seek) must land on the last value, and Step and Play pressed during a seek
 * act from where it lands. Every landing is compared with the live hash Node recorded the log
 * from.
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { type KeyframeFreeLog, recordKeyframeFreeLog } from '../client/replay/keyframe-free-log.ts'
import { launchBrowser } from '../support/chromium.ts'
import { collectErrors, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-replay-long/dist'
const TICKS = 120_000

let browser: Browser
let server: RunningServer
let long: KeyframeFreeLog

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  long = await recordKeyframeFreeLog(TICKS)
  server = await serveClient(DIST, { replayDir: await mkdtemp(join(tmpdir(), 'concord-long-seek-')) })
  browser = await launchBrowser()
}, 240_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** Open the log through the file picker; returns the page once the player is ready. */
async function openLog(): Promise<{ page: Page; errors: string[]; close: () => Promise<void> }> {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } })
  const page = await context.newPage()
  const errors = collectErrors(page)
  await page.goto(`http://127.0.0.1:${server.port}/?replay`)
  await page.setInputFiles('#replay-file', {
    name: 'no-keyframes.cclog',
    mimeType: 'application/octet-stream',
    buffer: Buffer.from(long.bytes),
  })
  await page.waitForSelector('#replay-play')
  return { page, errors, close: () => context.close() }
}

/** Move the seek bar as a person would: set its value and fire its input event. */
const moveSeekBar = (tick: number): string =>
  `(() => {
    const seek = document.getElementById('replay-seek')
    seek.value = String(${tick})
    seek.dispatchEvent(new Event('input'))
  })()`

/** The player's tick and world hash, and whether a move is under way. */
const playerState = (page: Page): Promise<{ tick: number; hash: number; busy: boolean }> =>
  page.evaluate(() => {
    const player = window.concordReplay!.sandbox!.player
    return { tick: player.tick, hash: player.sim.world.hash(), busy: player.busy }
  })

/** Wait until no move is under way and the player is at `tick`. */
const landedAt = (page: Page, tick: number): Promise<unknown> =>
  page.waitForFunction(
    (t) => {
      const player = window.concordReplay?.sandbox?.player
      return player !== undefined && !player.busy && player.tick === t
    },
    tick,
    { timeout: 120_000 },
  )

describe('browser replay player, long seeks', () => {
  it('seeks to the end of a 120,000-tick log with no keyframes while the page answers, paints and shows progress', async () => {
    const { page, errors, close } = await openLog()
    // Frames painted and tasks over 50 ms (the Long Tasks API), counted by the page itself.
    await page.evaluate(`(() => {
      const probe = { frames: 0, longest: 0, start: 0 }
      window.probe = probe
      new PerformanceObserver((list) => {
        for (const e of list.getEntries()) if (e.startTime >= probe.start) probe.longest = Math.max(probe.longest, e.duration)
      }).observe({ type: 'longtask' })
      const frame = () => {
        probe.frames++
        requestAnimationFrame(frame)
      }
      requestAnimationFrame(frame)
    })()`)
    const started = Date.now()
    await page.evaluate('window.probe.start = performance.now()')
    await page.evaluate(moveSeekBar(TICKS))
    // Each call below answers only between two slices of the seek: with the seek in one task, the
    // first answer would come after it ended.
    const samples: Array<{ tick: number; frames: number; text: string }> = []
    for (;;) {
      const s = await page.evaluate(() => ({
        busy: window.concordReplay!.sandbox!.player.busy,
        tick: window.concordReplay!.sandbox!.player.tick,
        frames: (window as unknown as { probe: { frames: number } }).probe.frames,
        text: document.getElementById('replay-tick')!.textContent ?? '',
      }))
      if (!s.busy) break
      samples.push(s)
    }
    const seekMs = Date.now() - started
    // Long-task entries reach the observer in a later task: wait for two more painted frames.
    await page.evaluate(`new Promise((resolve) => {
      const after = window.probe.frames + 2
      const check = () => (window.probe.frames >= after ? resolve() : requestAnimationFrame(check))
      check()
    })`)
    const longest = await page.evaluate(
      () => (window as unknown as { probe: { longest: number } }).probe.longest,
    )
    const summary = `seek ${seekMs} ms, ${samples.length} answers during it, longest task ${longest} ms`
    expect(samples.length, summary).toBeGreaterThanOrEqual(3)
    const [first, last] = [samples[0], samples[samples.length - 1]]
    expect(last.tick, summary).toBeGreaterThan(first.tick)
    expect(last.frames, summary).toBeGreaterThan(first.frames)
    expect(
      samples.some((s) => s.text.includes(`seeking to ${TICKS}: `)),
      samples.map((s) => s.text).join('\n'),
    ).toBe(true)
    expect(longest, summary).toBeLessThan(seekMs / 4)

    const end = await playerState(page)
    expect(end.tick).toBe(TICKS)
    expect(end.hash).toBe(long.live[TICKS])
    await page.waitForFunction(() => document.getElementById('replay-tick')?.dataset.seeking === 'false')
    expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')
    const checked = await page.evaluate(() => window.concordReplay!.sandbox!.player.checked)
    expect(checked).toBe(Math.floor(TICKS / 60))
    expect(errors).toEqual([])
    await close()
  })

  it('lands a drag of the seek bar on its last value, and steps from there when Step is pressed during the seek', async () => {
    const { page, errors, close } = await openLog()
    // Each input event a seek, sent while the one before runs (back, forward, back, forward).
    for (const t of [TICKS, 90_000, 30_000, 60_000]) await page.evaluate(moveSeekBar(t))
    const busy = await page.evaluate(`(() => {
      ${moveSeekBar(100_000)}
      const busy = window.concordReplay.sandbox.player.busy
      document.getElementById('replay-step').click()
      return busy
    })()`)
    expect(busy).toBe(true)
    await landedAt(page, 100_001)
    const stepped = await playerState(page)
    expect(stepped.hash).toBe(long.live[100_001])
    expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')
    expect(errors).toEqual([])
    await close()
  })

  it('plays from where a seek lands when Play is pressed during it', async () => {
    const { page, errors, close } = await openLog()
    const busy = await page.evaluate(`(() => {
      ${moveSeekBar(110_000)}
      const busy = window.concordReplay.sandbox.player.busy
      document.getElementById('replay-play').click()
      return busy
    })()`)
    expect(busy).toBe(true)
    await page.waitForFunction(() => (window.concordReplay?.sandbox?.player.tick ?? 0) > 110_030, undefined, {
      timeout: 120_000,
    })
    await page.click('#replay-play')
    await page.waitForFunction(() => !window.concordReplay!.sandbox!.player.busy)
    const paused = await playerState(page)
    expect(paused.tick).toBeGreaterThan(110_030)
    expect(paused.hash).toBe(long.live[paused.tick])
    expect(await page.getAttribute('#replay-hash', 'data-ok')).toBe('true')
    expect(errors).toEqual([])
    await close()
  })
})
