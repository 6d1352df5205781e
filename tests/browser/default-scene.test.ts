/*
 * The starting scene (issue 31: "a 'playground' starting scene with ground and a few ready-made
 * machines"): a server left at its defaults opens its default room and every new room on the
 * playground, and the page run offline (no server, no `&scene=`) starts on it too. The playground's
 * machines, counted by hand from its description: a car on two wheel joints, a seesaw on a pin, a
 * lift on a slider, a windmill of two blades welded together and pinned to the background: 6 joints.
 * PROTOCOL.md and the README say the same.
 */
import { readFileSync } from 'node:fs'
import type { Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import { loadConfig } from '../../server/config/config.ts'
import { type RunningServer, startServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox } from '../support/client-harness.ts'

const DIST = 'test-results/default-scene/dist'
const PLAYGROUND_JOINTS = 6

let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  await buildClient(DIST)
  // The server's own defaults: no defaultScene here (serveClient names the pyramid).
  const config = loadConfig(
    [],
    {},
    { port: 0, host: '127.0.0.1', staticDir: DIST, logLevel: 'silent', record: false, heartbeatMs: 60_000 },
  )
  ;[server, browser] = await Promise.all([startServer(config, { processMetrics: false }), launchBrowser()])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** The scene a page shows once its joints have arrived: name and joint count. */
async function sceneOf(url: string): Promise<{ scene: string; joints: number; errors: string[] }> {
  const { context, page, errors } = await openSandbox(browser, url)
  // Another scene fails at once on its name; the playground's joints come with its state.
  await page.waitForFunction((n) => {
    const s = window.concord.sandbox
    return s.scene() !== '' && (s.scene() !== 'playground' || s.joints().length >= n)
  }, PLAYGROUND_JOINTS)
  const shown = await page.evaluate(() => ({
    scene: window.concord.sandbox.scene(),
    joints: window.concord.sandbox.joints().length,
  }))
  await context.close()
  return { ...shown, errors }
}

describe('the default scene', { timeout: 300_000 }, () => {
  it('is the playground in the default room, in a new room, and offline', async () => {
    for (const url of [`${base}/`, `${base}/?room=fresh-room`, `${base}/?offline`]) {
      const shown = await sceneOf(url)
      expect(shown, url).toEqual({ scene: 'playground', joints: PLAYGROUND_JOINTS, errors: [] })
    }
    // The documents promise the same default.
    const protocol = readFileSync('shared/protocol/PROTOCOL.md', 'utf8')
    expect(/`--default-scene`, `([a-z-]+)` unless set/.exec(protocol)?.[1]).toBe('playground')
    expect(readFileSync('README.md', 'utf8')).toContain('every room opens on the playground scene')
    // A room created with a scene named in the address still gets that one.
    const named = await openSandbox(browser, `${base}/?offline&scene=tower`)
    expect(await named.page.evaluate(() => window.concord.sandbox.scene())).toBe('tower')
    await named.context.close()
  })
})
