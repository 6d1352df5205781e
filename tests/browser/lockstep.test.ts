/*
 * Lockstep in headless Chromium (Debian's, via playwright-core) and Node side by side: one room on
 * a real server on 127.0.0.1, snapshot-mode bots acting (spawns, grabs, drags, pins, ropes,
 * unjoints, deletes, a scene load), a Node LockstepBot and a page running the same LockstepClient
 * (lockstep-page.ts). Over at least 10,000 ticks every hash checkpoint must match in both, with no
 * desync (lockstep-harness.ts expectLongSync, shared with the Firefox test). The server's clock is
 * driven at 240 Hz by the test (lockstep-bots.ts), so 10,000 ticks take about 45 s instead of 170 s
 * when the machine keeps up.
 *
 * Then a perturbed page: the same bundle with the engine's own sin replaced by Chromium's
 * Math.sin (lockstep-harness.ts expectSinPerturbationCaught). A bot spawns bodies at angles where
 * the two differ (found in the unperturbed page); the perturbed client must report the desync
 * within one hash interval, be repaired by a sync and be counted in the server's /metrics.
 */
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { driveClock } from '../support/lockstep-bots.ts'
import { inProcessRooms, startTestServer } from '../support/test-server.ts'
import {
  bundleLockstepPage,
  expectLongSync,
  expectSinPerturbationCaught,
  startLockstepPage,
} from './lockstep-harness.ts'

const TICKS = 10_000

let server: RunningServer
let stopClock: () => void
let browser: Browser

beforeAll(async () => {
  // Rooms on the main thread: driveClock runs them faster than real time from the main tick clock.
  server = await startTestServer({ ...inProcessRooms, roomControls: true, heartbeatMs: 5000 })
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
  await startLockstepPage(page, server.url, code, room, 'chromium')
  expect(errors).toEqual([])
  return page
}

describe('lockstep in Chromium and Node', () => {
  it(`both stay in sync for ${TICKS.toLocaleString('en')} ticks of bot activity with a scene load`, async () => {
    const page = await openPage(await bundleLockstepPage(false), 'ls-long')
    await expectLongSync(server, page, 'ls-long', TICKS, 'chromium')
    await page.close()
  }, 960_000)

  it('a page whose engine uses Math.sin is caught within one hash interval, repaired and counted', async () => {
    await expectSinPerturbationCaught(server, openPage, 'ls-sin')
  }, 300_000)
})
