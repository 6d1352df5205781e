/*
 * Lockstep in Firefox ESR (Debian's firefox-esr, SpiderMonkey) driven by puppeteer-core over
 * WebDriver BiDi: the same page bundle and the same long run as the Chromium test
 * (lockstep-harness.ts expectLongSync): one room on a real server on 127.0.0.1, three snapshot-mode
 * bots acting, a scene load halfway, a Node LockstepBot and the Firefox page stepping the room for
 * at least 10,000 ticks; every hash checkpoint must match in both, with no desync. The server's
 * clock is driven at 240 Hz by the test (lockstep-bots.ts). Then the perturbed page with Firefox's
 * own Math.sin in the engine (SpiderMonkey's sin, like V8's, starts from fdlibm, so the two differ
 * on few inputs: 6 of the 2,900 angles the page searches in [0.1, 3)): caught within one hash interval,
 * repaired and counted. Without firefox-esr installed the tests are skipped and the reason printed.
 */
import type { Browser, Page } from 'puppeteer-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { firefoxMissing, launchFirefox } from '../support/firefox.ts'
import { driveClock } from '../support/lockstep-bots.ts'
import { inProcessRooms, startTestServer } from '../support/test-server.ts'
import {
  bundleLockstepPage,
  expectLongSync,
  expectSinPerturbationCaught,
  startLockstepPage,
} from './lockstep-harness.ts'

const TICKS = 10_000
const missing = firefoxMissing()
if (missing) console.warn(`lockstep-firefox.test.ts skipped: ${missing}`)

let server: RunningServer
let stopClock: () => void
let browser: Browser
const errors: string[] = []

describe.skipIf(missing !== '')('lockstep in Firefox ESR and Node', () => {
  beforeAll(async () => {
    // Rooms on the main thread: driveClock runs them faster than real time from the main tick clock.
    server = await startTestServer({ ...inProcessRooms, roomControls: true, heartbeatMs: 5000 })
    stopClock = driveClock(server, 240)
    browser = await launchFirefox()
  }, 120_000)

  afterAll(async () => {
    stopClock?.()
    await browser?.close()
    await server?.close()
  })

  async function openPage(code: string, room: string): Promise<Page> {
    const page = await browser.newPage()
    page.on('pageerror', (e) => errors.push(e instanceof Error ? e.message : String(e)))
    await startLockstepPage(page, server.url, code, room, 'firefox')
    return page
  }

  it(`both stay in sync for ${TICKS.toLocaleString('en')} ticks of bot activity with a scene load`, async () => {
    const page = await openPage(await bundleLockstepPage(false), 'ls-firefox')
    const engine = (await page.evaluate('navigator.userAgent')) as string
    expect(engine).toMatch(/Firefox\//)
    await expectLongSync(server, page, 'ls-firefox', TICKS, engine.match(/Firefox\/[\d.]+/)?.[0] ?? 'firefox')
    expect(errors).toEqual([])
    await page.close()
  }, 960_000)

  it("a page whose engine uses Firefox's Math.sin is caught within one hash interval, repaired and counted", async () => {
    const angles = await expectSinPerturbationCaught(server, openPage, 'ls-firefox-sin')
    console.log(
      `Firefox Math.sin differs from the engine's sin at ${angles.length} of the angles searched, e.g. ${angles[0]}`,
    )
    expect(errors).toEqual([])
  }, 300_000)
})
