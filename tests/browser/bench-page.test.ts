/*
 * The benchmark page in real headless Chromium. Served by the real server (/bench.html), it runs a
 * short comparison of every engine on a small pile: each engine must report finite, positive step
 * times and an end state, and Concord's broadphase check (its tree's pairs against a brute-force
 * loop over the same boxes) must have run and passed. The static build (npm run build:static) is
 * then served from a sub-path by a tiny static file server that answers nothing outside that
 * path, so any absolute URL would fail: the benchmark page must load its bundle and the wasm
 * binaries from there and run, and the sandbox's index.html must run offline with no game server.
 */
import { createReadStream } from 'node:fs'
import { stat } from 'node:fs/promises'
import { createServer, type Server } from 'node:http'
import type { AddressInfo } from 'node:net'
import { extname, join, normalize, resolve } from 'node:path'
import { pathToFileURL } from 'node:url'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { BenchOptions, BenchState } from '../../bench/page/bench-page.ts'
import { PEER_ENGINES } from '../../bench/peers/peer-registry.ts'
import { buildBenchPage } from '../../scripts/build-bench-page.mjs'
import { buildStatic } from '../../scripts/build-static.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { CLIENT_DIST, collectErrors, startClientServer } from '../support/client-harness.ts'

const STATIC_DIR = 'test-results/bench-page/static'
const SUB_PATH = '/some/sub/path/'
const TYPES: Record<string, string> = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.wasm': 'application/wasm',
  '.map': 'application/json',
}

let server: RunningServer
let staticServer: Server
let browser: Browser

/** Serves `root` under `prefix` only (404 elsewhere, and for paths that leave the root). */
function serveStatic(root: string, prefix: string): Promise<Server> {
  const http = createServer((req, res) => {
    const path = decodeURIComponent(new URL(req.url ?? '/', 'http://x').pathname)
    const relative = path.startsWith(prefix) ? normalize(path.slice(prefix.length) || 'index.html') : null
    if (relative === null || relative.startsWith('..')) {
      res.writeHead(404).end(`not under ${prefix}: ${path}`)
      return
    }
    const file = join(root, relative)
    stat(file).then(
      (s) => {
        if (!s.isFile()) throw new Error('not a file')
        res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' })
        createReadStream(file).pipe(res)
      },
      () => res.writeHead(404).end(`no file ${relative}`),
    )
  })
  return new Promise((resolve) => http.listen(0, '127.0.0.1', () => resolve(http)))
}

/** Runs the page's comparison and waits for it to finish. */
async function runComparison(page: Page, options: BenchOptions): Promise<BenchState> {
  await page.waitForFunction(() => window.concordBench?.state.status === 'idle')
  await page.evaluate((o) => {
    void window.concordBench.run(o)
  }, options)
  await page.waitForFunction(() => ['done', 'error'].includes(window.concordBench.state.status), undefined, {
    timeout: 90_000,
  })
  return page.evaluate(() => window.concordBench.state)
}

/**
 * Every engine ran, with finite step times and an end state; the broadphase check passed. A step
 * time may be 0: the page's timer is coarsened (0.1 ms in Chromium here), and a fast engine's
 * sleeping steps took less than that on a fast machine (Nov 24: box2d3-wasm-compat, median 0).
 */
function expectSoundRun(state: BenchState, engines: readonly string[]): void {
  expect(state.error).toBeNull()
  expect(state.status).toBe('done')
  expect(state.timerResolutionMs).toBeGreaterThan(0)
  expect(state.timerResolutionMs).toBeLessThanOrEqual(1)
  expect(state.results.map((r) => r.engine)).toEqual(engines)
  for (const r of state.results) {
    expect(r.error, `${r.engine} failed`).toBeNull()
    for (const value of [r.steps?.mean, r.steps?.median, r.steps?.p95]) {
      expect(Number.isFinite(value) && (value as number) >= 0, `${r.engine} step time ${value}`).toBe(true)
    }
    const ratio = r.concordOverThis
    expect(ratio === null || (Number.isFinite(ratio) && ratio > 0), `${r.engine} ratio ${ratio}`).toBe(true)
    // The ratio the table shows (median over rounds) and its spread over the run's quarters.
    for (const value of [r.roundRatio, r.ratioRange?.low, r.ratioRange?.high])
      expect(value === null || value === undefined || (Number.isFinite(value) && value > 0)).toBe(true)
    if (r.ratioRange) expect(r.ratioRange.low).toBeLessThanOrEqual(r.ratioRange.high)
    expect(r.steps?.n, `${r.engine} timed steps`).toBeGreaterThan(0)
    expect(r.quality?.verdict, `${r.engine} end state`).toBe('contained')
  }
  expect(state.broadPhase.length).toBeGreaterThan(0)
  for (const check of state.broadPhase) {
    expect(check.firstDifference).toBeNull()
    expect(check.treePairs).toBe(check.bruteForcePairs)
    expect(check.match).toBe(true)
  }
  // A pile in a container touches: an empty pair list would make the comparison vacuous.
  expect(state.broadPhase[state.broadPhase.length - 1].treePairs).toBeGreaterThan(10)
}

beforeAll(async () => {
  ;[server, browser] = await Promise.all([startClientServer(), launchBrowser()])
  await buildBenchPage(CLIENT_DIST)
  await buildStatic(STATIC_DIR)
  staticServer = await serveStatic(STATIC_DIR, SUB_PATH)
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
  await new Promise((resolve) => staticServer?.close(resolve))
})

describe('benchmark page', () => {
  it('served by the server, runs every engine on a small pile with finite numbers and a passing broadphase check', async () => {
    const page = await browser.newPage()
    const errors = collectErrors(page)
    await page.goto(`http://127.0.0.1:${server.port}/bench.html`)
    const engines = [...PEER_ENGINES]
    const state = await runComparison(page, {
      scene: 'pile-1000',
      count: 60,
      steps: 20, // four rounds of 5 steps: the least that has a spread over quarters
      sleep: false,
      engines,
    })
    expectSoundRun(state, engines)
    expect(await page.textContent('#broadphase')).toContain('PASSED')
    expect(await page.locator('#results tbody tr').count()).toBe(engines.length)
    // The table shows each ratio with its range; a visitor's default run is 1,000 timed steps.
    expect(await page.textContent('#results thead')).toContain('concord / this (quarters)')
    expect(await page.textContent('#results tbody tr:first-child')).toMatch(/\d\.\d\d \(\d\.\d\d-\d\.\d\d\)/)
    await page.goto(`http://127.0.0.1:${server.port}/bench.html`)
    expect(await page.inputValue('#steps')).toBe('1000')
    expect(errors).toEqual([])
    await page.close()
  })

  it('works as static files from a sub-path: the benchmark with its wasm peers, and the sandbox offline', async () => {
    const base = `http://127.0.0.1:${(staticServer.address() as AddressInfo).port}${SUB_PATH}`
    const page = await browser.newPage()
    const errors = collectErrors(page)
    await page.goto(`${base}bench.html`)
    const engines = ['concord', 'box2d-wasm', 'box2d3-wasm', 'box2d3-wasm-compat', 'rapier'] as const
    const state = await runComparison(page, {
      scene: 'pile-1000',
      count: 40,
      steps: 10,
      sleep: true,
      engines: [...engines],
    })
    expectSoundRun(state, engines)
    expect(errors).toEqual([])

    const sandbox = await browser.newPage()
    const sandboxErrors = collectErrors(sandbox)
    await sandbox.goto(base)
    await sandbox.waitForFunction(() => {
      const c = window.concord
      return c && c.sandbox.mode === 'offline' && c.sandbox.bodies().length > 0 && c.fps.value > 0
    })
    expect(sandboxErrors).toEqual([])
    await Promise.all([page.close(), sandbox.close()])
  })

  it('opened from disk (file:): the sandbox runs with Online and Rooms hidden; the benchmark says why it cannot', async () => {
    const folder = resolve(STATIC_DIR)
    const sandbox = await browser.newPage()
    const errors = collectErrors(sandbox)
    await sandbox.goto(pathToFileURL(join(folder, 'index.html')).href)
    await sandbox.waitForFunction(() => {
      const c = window.concord
      return c && c.sandbox.mode === 'offline' && c.sandbox.bodies().length > 0 && c.fps.value > 0
    })
    expect(await sandbox.locator('#mode').isVisible()).toBe(false)
    expect(await sandbox.locator('#rooms').isVisible()).toBe(false)
    // The tools act: a box dropped with the Box tool joins the world.
    const before = await sandbox.evaluate(() => window.concord.sandbox.bodies().length)
    await sandbox.click('[data-tool="box"]')
    await sandbox.mouse.click(200, 200)
    await sandbox.waitForFunction((n) => window.concord.sandbox.bodies().length === n + 1, before)
    await sandbox.keyboard.press('o')
    expect(await sandbox.locator('#lobby').isVisible()).toBe(false)
    expect(errors).toEqual([])

    const bench = await browser.newPage()
    await bench.goto(pathToFileURL(join(folder, 'bench.html')).href)
    await bench.waitForFunction(() =>
      /Opened from disk/.test(document.getElementById('status')!.textContent!),
    )
    expect(await bench.textContent('#status')).toContain('Serve this folder over http')
    expect(await bench.locator('#run').isDisabled()).toBe(true)
    await Promise.all([sandbox.close(), bench.close()])
  })
})
