/*
 * The Content-Security-Policy (server/http/http-headers.ts) against the built client in Debian's
 * Chromium (issue 30, point 11): the sandbox joins a room and draws it, the lobby lists the rooms
 * (with the page's key, on a server with a join token), the replay page lists the logs, and the
 * benchmark page compiles its WebAssembly peers and runs one, each with the policy the server
 * sends and without a single CSP violation (the `securitypolicyviolation` events of every page,
 * and the console's errors, which is where Chromium reports a blocked script, style or socket).
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { PEER_ENGINES } from '../../bench/peers/peer-registry.ts'
import { buildBenchPage } from '../../scripts/build-bench-page.mjs'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { collectErrors, serveClient } from '../support/client-harness.ts'

const DIST = 'test-results/browser-csp/dist'
const KEY = 'csp-join-key-41'
let browser: Browser
let server: RunningServer

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  await buildBenchPage(DIST)
  const replayDir = await mkdtemp(join(tmpdir(), 'concord-csp-'))
  server = await serveClient(DIST, { joinToken: KEY, record: true, replayDir })
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** A page that records every CSP violation (before any of its scripts run) and console error. */
async function watchedPage(): Promise<{ page: Page; errors: string[]; violations: () => Promise<string[]> }> {
  const page = await browser.newPage()
  await page.addInitScript(() => {
    const seen: string[] = []
    ;(window as unknown as { cspViolations: string[] }).cspViolations = seen
    document.addEventListener('securitypolicyviolation', (e) => {
      seen.push(`${e.violatedDirective} ${e.blockedURI}`)
    })
  })
  const errors = collectErrors(page)
  const violations = (): Promise<string[]> =>
    page.evaluate(() => (window as unknown as { cspViolations: string[] }).cspViolations)
  return { page, errors, violations }
}

describe('the client under the Content-Security-Policy', { timeout: 120_000 }, () => {
  it('sends the policy with the page, and the sandbox and its lobby work with no violation', async () => {
    const { page, errors, violations } = await watchedPage()
    const answer = await page.goto(`http://127.0.0.1:${server.port}/?room=csp&key=${KEY}&name=ada`)
    expect(answer?.headers()['content-security-policy']).toContain("script-src 'self'")
    await page.waitForFunction(() => window.concord?.sandbox.status().state === 'connected')
    await page.waitForFunction(() => (window.concord?.sandbox.bodies().length ?? 0) > 0)
    // A spawn: a room where nothing was done leaves no log, and the replay page below lists this one.
    const before = await page.evaluate(() => window.concord.sandbox.bodies().length)
    await page.evaluate(() =>
      window.concord.sandbox.send({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 4 }),
    )
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, before)
    await page.click('#rooms')
    await page.waitForSelector('#lobby-list a')
    expect(await page.textContent('#lobby-list')).toContain('csp')
    expect(await violations()).toEqual([])
    expect(errors).toEqual([])
    await page.close()
  })

  it('runs the replay page and the benchmark page (WebAssembly peers included) with no violation', async () => {
    const replay = await watchedPage()
    await replay.page.goto(`http://127.0.0.1:${server.port}/?replay&key=${KEY}`)
    await replay.page.waitForFunction(() => window.concordReplay !== undefined)
    await replay.page.waitForFunction(() => document.body.textContent?.includes('csp'), undefined, {
      timeout: 30_000,
    })
    expect(await replay.violations()).toEqual([])
    expect(replay.errors).toEqual([])
    await replay.page.close()

    const bench = await watchedPage()
    await bench.page.goto(`http://127.0.0.1:${server.port}/bench.html`)
    await bench.page.waitForFunction(() => window.concordBench?.state.status === 'idle')
    const engines = [...PEER_ENGINES]
    await bench.page.evaluate((e) => {
      void window.concordBench.run({ scene: 'pile-1000', count: 20, steps: 3, sleep: false, engines: e })
    }, engines)
    await bench.page.waitForFunction(
      () => ['done', 'error'].includes(window.concordBench.state.status),
      undefined,
      { timeout: 90_000 },
    )
    const state = await bench.page.evaluate(() => window.concordBench.state)
    expect(state.error).toBeNull()
    for (const r of state.results) expect(r.error, r.engine).toBeNull()
    expect(await bench.violations()).toEqual([])
    expect(bench.errors).toEqual([])
    await bench.page.close()
  })
})
