/*
 * Debian's Chromium for the browser tests: no browser download works on these machines, so every
 * test launches /usr/bin/chromium with the flags this network needs (no sandbox as root, no GPU,
 * no QUIC or background traffic to hosts that cannot be reached).
 */
import { type Browser, chromium } from 'playwright-core'

/** Chromium flags for this machine. */
export const CHROMIUM_ARGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-quic',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
]

/** Launches Debian's Chromium, headless, with a fresh temporary profile. */
export function launchBrowser(): Promise<Browser> {
  return chromium.launch({ executablePath: '/usr/bin/chromium', args: CHROMIUM_ARGS })
}
