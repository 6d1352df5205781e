/*
 * The page's access key: on a server with a join token, `?room=NAME&key=KEY` joins (the key goes
 * on to the WebSocket URL), and the same page without the key is refused at the upgrade and says so
 * instead of showing a joined room: "Access key missing" or "Access key wrong", with no retrying
 * (a browser cannot read a refused upgrade's status; the page asks with a plain GET of the URL).
 */
import { mkdir } from 'node:fs/promises'
import type { Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-access/dist'
let browser: Browser
let server: RunningServer

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  server = await serveClient(DIST, { joinToken: 'open-sesame' })
  browser = await launchBrowser()
}, 120_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

describe('access key in the page URL', () => {
  it('joins a token-only room with ?key= and is refused without it', async () => {
    const context = await browser.newContext()
    const page = await context.newPage()
    await page.goto(`http://127.0.0.1:${server.port}/?room=club&key=open-sesame&name=ada`)
    await page.waitForFunction(() => window.concord?.sandbox.status().state === 'connected')
    await page.waitForFunction(() => (window.concord?.sandbox.bodies().length ?? 0) > 0)
    expect(server.host.summaries().find((r) => r.name === 'club')?.players).toBe(1)

    const stranger = await context.newPage()
    await stranger.goto(`http://127.0.0.1:${server.port}/?room=club&name=eve`)
    await stranger.waitForFunction(() => window.concord?.sandbox.status().state === 'error')
    expect(server.host.summaries().find((r) => r.name === 'club')?.players).toBe(1)
    await context.close()
  })

  it('a missing or wrong key is named on the banner and the page stops retrying', async () => {
    const context = await browser.newContext()
    const refused = async (): Promise<number> => {
      const text = await server.metrics.registry.getSingleMetricAsString('concord_connections_refused_total')
      return [...text.matchAll(/^concord_connections_refused_total\{[^}]*\} (\d+)$/gm)].reduce(
        (sum, m) => sum + Number(m[1]),
        0,
      )
    }
    for (const [query, expected] of [
      ['', 'Access key missing: room "club" is open only with'],
      ['&key=guess', 'Access key wrong: the key matches neither the join token nor the admin token'],
    ] as const) {
      const page = await context.newPage()
      await page.goto(`http://127.0.0.1:${server.port}/?room=club&name=eve${query}`)
      await page.waitForFunction(() => {
        const status = window.concord?.sandbox.status()
        return status?.state === 'error' && !status.retrying
      })
      const status = await page.evaluate(() => window.concord?.sandbox.status())
      expect(status).toMatchObject({ state: 'error', retrying: false })
      expect(status && 'message' in status ? status.message : '').toContain(expected)
      // The banner is refreshed a few times a second: wait for it to show the status.
      await page.waitForFunction(
        (text) => (document.getElementById('banner-text')?.textContent ?? '').includes(text),
        expected,
      )
      expect(await page.locator('#retry').isHidden()).toBe(true)
      // No more upgrades: the page's first retry would come 0.5 s after the refusal; wait 3 s of
      // the page's own clock and count the server's refusals again.
      const before = await refused()
      const start = await page.evaluate(() => performance.now())
      await page.waitForFunction((t) => performance.now() > t + 3000, start)
      expect(await refused()).toBe(before)
      await page.close()
    }
    await context.close()
  })
})
