/*
 * Lockstep in Firefox ESR (Debian's firefox-esr, SpiderMonkey) driven by puppeteer-core over
 * WebDriver BiDi: the same page bundle and the same long run as the Chromium test
 * (lockstep-harness.ts expectLongSync): one room on a real server on 127.0.0.1, three snapshot-mode
 * bots acting, a scene load halfway, a Node LockstepBot and the Firefox page stepping the room for
 * at least 10,000 ticks; every hash checkpoint must match in both, with no desync. The server's
 * clock is driven at 240 Hz by the test (lockstep-bots.ts). Without firefox-esr installed the test
 * is skipped and the reason printed.
 */
import type { Browser, Page } from 'puppeteer-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import { driveClock } from '../server/lockstep-bots.ts'
import { startTestServer } from '../server/test-server.ts'
import { firefoxMissing, launchFirefox } from './firefox.ts'
import { bundleLockstepPage, expectLongSync, startLockstepPage } from './lockstep-harness.ts'

const TICKS = 10_000
const missing = firefoxMissing()
if (missing) console.warn(`lockstep-firefox.test.ts skipped: ${missing}`)

let server: RunningServer
let stopClock: () => void
let browser: Browser

describe.skipIf(missing !== '')('lockstep in Firefox ESR and Node', () => {
  beforeAll(async () => {
    server = await startTestServer({ roomControls: true, heartbeatMs: 5000 })
    stopClock = driveClock(server, 240)
    browser = await launchFirefox()
  }, 120_000)

  afterAll(async () => {
    stopClock?.()
    await browser?.close()
    await server?.close()
  })

  it(`both stay in sync for ${TICKS.toLocaleString('en')} ticks of bot activity with a scene load`, async () => {
    const page: Page = await browser.newPage()
    const errors: string[] = []
    page.on('pageerror', (e) => errors.push(e instanceof Error ? e.message : String(e)))
    await startLockstepPage(page, server.url, await bundleLockstepPage(false), 'ls-firefox', 'firefox')
    const engine = (await page.evaluate('navigator.userAgent')) as string
    expect(engine).toMatch(/Firefox\//)
    await expectLongSync(server, page, 'ls-firefox', TICKS, engine.match(/Firefox\/[\d.]+/)?.[0] ?? 'firefox')
    expect(errors).toEqual([])
    await page.close()
  }, 960_000)
})
