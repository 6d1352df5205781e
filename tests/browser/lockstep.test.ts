/*
 * Lockstep in headless Chromium (Debian's, via playwright-core) and Node side by side: one room on
 * a real server on 127.0.0.1, snapshot-mode bots acting (spawns, grabs, drags, pins, ropes,
 * unjoints, deletes, a scene load), a Node LockstepBot and a page running the same LockstepClient
 * (lockstep-page.ts). Over at least 10,000 ticks every hash checkpoint must match in both, with no
 * desync. The server's clock is driven at 240 Hz by the test (lockstep-bots.ts), so 10,000 ticks
 * take about 45 s instead of 170 s when the machine keeps up.
 *
 * Then a perturbed page: the same bundle with the engine's own sin replaced by Chromium's
 * Math.sin. A bot spawns bodies at angles where the two differ (found in the unperturbed page);
 * the perturbed client must report the desync within one hash interval, be repaired by a sync and
 * be counted in the server's /metrics.
 */
import { build, type Plugin } from 'esbuild'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../server/bot-client.ts'
import { LockstepBot } from '../../server/lockstep-bot.ts'
import type { RunningServer } from '../../server/server.ts'
import { ActiveBots, driveClock } from '../server/lockstep-bots.ts'
import { startTestServer } from '../server/test-server.ts'
import { launchBrowser } from './chromium.ts'
import type { PageReport } from './lockstep-page.ts'

const TICKS = 10_000

/** Replaces the engine's own sin with the host's Math.sin. */
const mathSin: Plugin = {
  name: 'math-sin',
  setup(b) {
    b.onLoad({ filter: /engine[\\/]math\.ts$/ }, async (args) => {
      const { readFile } = await import('node:fs/promises')
      const source = await readFile(args.path, 'utf8')
      const patched = source.replace(
        'export function sin(x: number): number {',
        'export function sin(x: number): number {\n  return Math.sin(x)\n}\nexport function ownSin(x: number): number {',
      )
      if (patched === source) throw new Error('engine/math.ts no longer declares sin as expected')
      return { contents: patched, loader: 'ts' }
    })
  },
}

async function bundle(perturbed: boolean): Promise<string> {
  const result = await build({
    entryPoints: [new URL('./lockstep-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
    plugins: perturbed ? [mathSin] : [],
  })
  return result.outputFiles[0].text
}

let server: RunningServer
let stopClock: () => void
let browser: Browser

beforeAll(async () => {
  server = await startTestServer({ roomControls: true, heartbeatMs: 5000 })
  stopClock = driveClock(server, 240)
  browser = await launchBrowser()
}, 120_000)

afterAll(async () => {
  stopClock?.()
  await browser?.close()
  await server?.close()
})

async function openPage(code: string, room: string): Promise<Page> {
  const page = await browser.newPage()
  const errors: string[] = []
  page.on('pageerror', (e) => errors.push(e.message))
  await page.goto(`${server.url}/`)
  await page.addScriptTag({ content: code })
  await page.evaluate(
    (r) => (globalThis as never as { concordLockstep: { start(r: string): void } }).concordLockstep.start(r),
    room,
  )
  expect(errors).toEqual([])
  return page
}

const report = (page: Page): Promise<PageReport> =>
  page.evaluate(() =>
    (globalThis as never as { concordLockstep: { report(): PageReport } }).concordLockstep.report(),
  )

/** Poll until `condition` holds (generous timeout; no fixed sleeps in the assertions). */
async function until(what: string, condition: () => Promise<boolean>, timeoutMs = 600_000): Promise<void> {
  const start = Date.now()
  while (!(await condition())) {
    if (Date.now() - start > timeoutMs) throw new Error(`timed out waiting for ${what}`)
    await new Promise((resolve) => setTimeout(resolve, 250))
  }
}

describe('lockstep in Chromium and Node', () => {
  it(`both stay in sync for ${TICKS.toLocaleString('en')} ticks of bot activity with a scene load`, async () => {
    const bots = await ActiveBots.start(server.url, 'ls-long', 3, 20, 7)
    const node = await LockstepBot.connect({ url: server.url, room: 'ls-long', name: 'node' })
    const page = await openPage(await bundle(false), 'ls-long')
    await until('the page to sync', async () => (await report(page)).hashesChecked > 0)
    const start = Math.max(node.runner.sim?.tick ?? 0, (await report(page)).tick)
    let loaded = false
    await until(
      `${TICKS} ticks in both`,
      async () => {
        const r = await report(page)
        const nodeTick = node.runner.sim?.tick ?? 0
        if (!loaded && nodeTick > start + TICKS / 2) {
          bots.command(0, { k: 'scene', name: 'wrecking-ball' })
          loaded = true
        }
        if (r.desyncs > 0 || node.runner.stats.desyncs > 0 || r.closed) return true
        return r.tick > start + TICKS && nodeTick > start + TICKS
      },
      900_000,
    )
    const r = await report(page)
    console.log(
      `lockstep ${TICKS} ticks: page ${r.hashesChecked} checkpoints, node ${node.runner.stats.hashesChecked}; ` +
        `room at tick ${server.rooms.get('ls-long')?.tick}, scene ${node.runner.sim?.scene}`,
    )
    expect(r.closed).toBe('')
    expect(r.desyncs, r.problem).toBe(0)
    expect(node.runner.stats.desyncs, node.runner.lastProblem).toBe(0)
    expect(r.resyncs + node.runner.stats.resyncs).toBe(0)
    expect(r.refused + node.runner.stats.refused).toBe(0)
    expect(r.hashesChecked).toBeGreaterThanOrEqual(Math.floor(TICKS / 60) - 2)
    expect(node.runner.stats.hashesChecked).toBeGreaterThanOrEqual(Math.floor(TICKS / 60) - 2)
    expect(node.runner.sim?.scene).toBe('wrecking-ball')
    expect((await server.metrics.desyncs.get()).values[0]?.value ?? 0).toBe(0)
    await page.close()
    await Promise.all([node.close(), bots.stop()])
  }, 960_000)

  it('a page whose engine uses Math.sin is caught within one hash interval, repaired and counted', async () => {
    const plain = await openPage(await bundle(false), 'ls-sin-probe')
    const angles = await plain.evaluate(() =>
      (
        globalThis as never as { concordLockstep: { anglesWhereSinDiffers(): number[] } }
      ).concordLockstep.anglesWhereSinDiffers(),
    )
    await plain.close()
    expect(angles.length).toBeGreaterThan(0)
    const page = await openPage(await bundle(true), 'ls-sin')
    await until(
      'the perturbed page to verify a checkpoint',
      async () => (await report(page)).hashesChecked >= 1,
    )
    const before = (await server.metrics.desyncs.get()).values[0]?.value ?? 0
    const spawner = await BotClient.connect({ url: server.url, room: 'ls-sin', name: 'spawner' })
    const spawnTick = server.rooms.get('ls-sin')?.tick ?? 0
    for (const angle of angles.slice(0, 5)) {
      spawner.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.2 }, x: angle * 3, y: 5, angle })
    }
    await until('the desync and the repair', async () => {
      const r = await report(page)
      return r.desyncs >= 1 && r.resyncs >= 1 && r.state === 'running'
    })
    const r = await report(page)
    const detectedAt = Number(r.problem.match(/tick (\d+)/)?.[1])
    expect(detectedAt - spawnTick).toBeLessThanOrEqual(60 + 30)
    await until(
      'a verified checkpoint after the repair',
      async () => (await report(page)).verifiedTick > detectedAt,
    )
    expect((await server.metrics.desyncs.get()).values[0]?.value ?? 0).toBeGreaterThan(before)
    const metrics = await fetch(`${server.url}/metrics`).then((res) => res.text())
    expect(metrics).toMatch(/concord_desyncs_total [1-9]/)
    await page.close()
    await spawner.close()
  }, 300_000)
})
