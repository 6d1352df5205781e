/*
 * The hill game's client module in the Concord page (docs/games.md, "Client modules"; docs/client.md,
 * "Game rooms"): a server started with --games on this folder serves the built page; a Chromium
 * page that opens `?room=X&game=hill` shows the module's HUD items in its game panel, and the
 * module's arrow keys send `push`. The oracle for where two full pushes leave the page's puck is
 * the closed form of linear damping (hill-server.test.ts): each moves it J / (m c) = 3 / (pi / 4)
 * = 3.82 m, so from its spot (-6, 0) it rests 2.18 m left of the hill's centre after one push
 * (off the hill: 2.18 > 2) and 1.64 m right of it after two (on it), where it is king.
 */
import { mkdirSync, rmSync } from 'node:fs'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import { launchBrowser } from '../support/chromium.ts'
import { type ServerProcess, startServerProcess } from '../support/server-process.ts'
import { until } from '../support/wait.ts'
import { HillPlayer } from './hill-player.ts'

const DIST = `test-results/games-from-docs/dist-${process.pid}`
let server: ServerProcess
let browser: Browser

beforeAll(async () => {
  mkdirSync(DIST, { recursive: true })
  await buildClient(DIST)
  server = await startServerProcess([
    '--games',
    'tests/games-from-docs/games',
    '--static-dir',
    DIST,
    '--workers',
    '1',
    '--record',
    'false',
  ])
  browser = await launchBrowser()
}, 120_000)
afterAll(async () => {
  await browser?.close()
  if (server && server.process.exitCode === null) {
    server.process.kill('SIGTERM')
    await server.exited
  }
  rmSync(DIST, { recursive: true, force: true })
})

/** The page's text, for finding the HUD items without knowing the panel's markup. */
const text = (page: Page): Promise<string> => page.evaluate(() => document.body.innerText)

describe('the hill client module in a Chromium page', { timeout: 120_000 }, () => {
  it('shows the HUD in a ?room=X&game=hill page, and its arrow keys push the puck onto the hill', async () => {
    const page = await browser.newPage()
    const problems: string[] = []
    page.on('pageerror', (e) => problems.push(e.message))
    await page.goto(`${server.url}/?room=hill-page&game=hill&name=ada`)
    await until(
      async () => (await text(page)).includes('hold 3.0 s alone'),
      'the HUD item "hold 3.0 s alone"',
    )
    await until(async () => (await text(page)).includes('waiting for a second player'), 'the waiting status')
    expect(await text(page)).toMatch(/you \(\d+\)\s*0\.0 s/)
    expect(await text(page)).toContain('6.0 m')

    const bob = await HillPlayer.join(server.url, 'hill-page', 'bob')
    await until(async () => (await text(page)).includes('nobody is king'), 'the round to start in the HUD')
    expect(await text(page)).toMatch(new RegExp(`player ${bob.id}\\s*0\\.0 s`))

    await page.keyboard.press('ArrowRight')
    await until(async () => (await text(page)).includes('2.2 m'), 'one push: 2.18 m from the hill')
    // The room's clock (bob's snapshots) past the page's cooldown before the second push.
    const t = bob.tick
    await until(() => bob.tick >= t + 12, 'the push cooldown to pass')
    await page.keyboard.press('ArrowRight')
    await until(async () => (await text(page)).includes('king: you'), 'the page to be king')
    // Alone on the hill for 3 s she wins. Her puck still glides (damping 1/s: 3 s after entering,
    // 3.82 e^-3 = 0.19 m of its run is left) and comes to rest 1.64 m right of the centre; it
    // passed 1.6 m on its way in, so the distance is read after the win, when it only grows.
    await until(async () => (await text(page)).includes('you win'), 'the page to win')
    await until(
      async () => /to the hill\s*1\.6 m/.test(await text(page)),
      'the puck at rest 1.64 m from the centre',
    )
    expect(bob.view?.king).not.toBe(0)
    expect(bob.view?.king).not.toBe(bob.id)
    await page.screenshot({ path: `test-results/games-from-docs/hill-page.png` })
    expect(problems).toEqual([])
    await bob.close()
    await page.close()
  })

  it('plays a round to its end in a lockstep page and a predicting page, which load the game from the server and never desync', async () => {
    const ada = await browser.newPage()
    const bob = await browser.newPage()
    const problems: string[] = []
    for (const page of [ada, bob]) page.on('pageerror', (e) => problems.push(e.message))
    await ada.goto(`${server.url}/?room=hill-lockstep&game=hill&mode=lockstep&name=ada`)
    await bob.goto(`${server.url}/?room=hill-lockstep&game=hill&mode=predict&name=bob`)
    for (const page of [ada, bob])
      await until(async () => (await text(page)).includes('nobody is king'), 'the round to start')
    // Bob's puck (spot (6, 0)) goes 3.82 m left per push: 2.18 m from the hill, then 1.64 m past it.
    await bob.keyboard.press('ArrowLeft')
    await until(
      async () => (await text(bob)).includes('2.2 m'),
      "bob's first push to end 2.18 m from the hill",
    )
    await bob.keyboard.press('ArrowLeft')
    await until(async () => (await text(bob)).includes('king: you'), 'bob to be king in his page')
    await until(async () => /king: player \d+/.test(await text(ada)), "bob to be king in ada's page")
    await until(async () => (await text(bob)).includes('you win'), 'bob to win in his page', 60_000)
    await until(async () => /player \d+ wins/.test(await text(ada)), "bob's win in ada's page", 60_000)
    expect(await text(bob)).toMatch(/you \(\d+\)\s*3\.0 s/)
    // Both pages checked the server's hashes after the end, and none differed.
    for (const [page, mode] of [
      [ada, 'lockstep'],
      [bob, 'predict'],
    ] as const) {
      const verified = async () => Number(/verified\s+tick\s+(\d+)/.exec(await text(page))?.[1] ?? 0)
      const first = await verified()
      await until(async () => (await verified()) > first, `${mode}: a later hash verified`)
      expect(await text(page)).toMatch(new RegExp(`${mode}\\s+running`))
      expect(await text(page)).toMatch(/desyncs\s+0\s+resyncs\s+0/)
    }
    expect(problems).toEqual([])
    await ada.close()
    await bob.close()
  })

  // Found by writing this game from the docs: the page offered every sandbox tool in a hill room
  // and sent `move` as the pointer moved (each refused: "game hill has no move command"). Fixed
  // with rules.builtins (PROTOCOL.md RoomRules); tests/browser/game-tools.test.ts has the details.
  it('sends no command the game lacks when the pointer moves over the canvas', async () => {
    const page = await browser.newPage()
    await page.goto(`${server.url}/?room=hill-pointer&game=hill`)
    await until(async () => (await text(page)).includes('hold 3.0 s alone'), 'the HUD')
    const box = await page.locator('canvas').first().boundingBox()
    if (!box) throw new Error('no canvas')
    for (let i = 0; i < 10; i++) await page.mouse.move(box.x + box.width / 2 + i * 5, box.y + box.height / 2)
    await page.mouse.click(box.x + box.width / 2, box.y + box.height / 3)
    // Give the room a second of its own clock to answer (a refusal comes back within a tick).
    const watcher = await HillPlayer.join(server.url, 'hill-pointer', 'watcher')
    const t = watcher.tick
    await until(() => watcher.tick >= t + 60, 'a second of room time')
    expect(await text(page)).not.toMatch(/has no \w+ command/)
    await watcher.close()
    await page.close()
  })
})
