/*
 * Debian's Firefox ESR for the browser tests that need a second JavaScript engine (SpiderMonkey
 * beside Chromium's V8): puppeteer-core launches /usr/bin/firefox-esr headless over WebDriver BiDi
 * (puppeteer 24 speaks BiDi to Firefox by default) with a fresh temporary profile. No browser is
 * downloaded. A test that needs Firefox calls firefoxMissing() first and skips with that reason
 * printed when the package is not installed (.ci/run installs it).
 */
import { accessSync, constants } from 'node:fs'
import puppeteer, { type Browser } from 'puppeteer-core'

/** Where Debian's firefox-esr package puts the browser. */
export const FIREFOX_PATH = '/usr/bin/firefox-esr'

/** Why Firefox cannot be launched here, or '' when the executable is present. */
export function firefoxMissing(): string {
  try {
    accessSync(FIREFOX_PATH, constants.X_OK)
    return ''
  } catch (e) {
    return `${FIREFOX_PATH} is not an executable here (${(e as Error).message}); install Debian's firefox-esr`
  }
}

/** Launches Debian's Firefox ESR headless through puppeteer-core (WebDriver BiDi). */
export function launchFirefox(): Promise<Browser> {
  return puppeteer.launch({
    browser: 'firefox',
    executablePath: FIREFOX_PATH,
    headless: true,
    protocolTimeout: 120_000,
    extraPrefsFirefox: {
      // No traffic to hosts this network cannot reach.
      'network.captive-portal-service.enabled': false,
      'network.connectivity-service.enabled': false,
      'browser.safebrowsing.update.enabled': false,
    },
  })
}
