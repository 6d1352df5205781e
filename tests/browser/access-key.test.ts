/*
 * The page's access key: on a server with a join token, `?room=NAME&key=KEY` joins (the key goes
 * on to the WebSocket URL), and the same page without the key is refused at the upgrade and says so
 * instead of showing a joined room.
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
})
