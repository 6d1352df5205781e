/*
 * Issue 31's whole path in real Chromium against a real server, with the page's own tools and
 * real mouse and key input: draw terrain with the Ground tool, build a car (a box and two clicks of
 * the Wheel tool), drive it over the terrain with the arrow key, save the room as a scene file,
 * open its share link in a second page, and find the same bodies and joints there.
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import {
  bodies,
  clickWorld,
  loadScene,
  openSandbox,
  pickTool,
  screenOf,
  serveClient,
  setPaused,
  snapshotAfter,
  snapshotOf,
} from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

const DIST = 'test-results/browser-build-share/dist'
let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  const sceneDir = await mkdtemp(join(tmpdir(), 'concord-build-share-'))
  ;[server, browser] = await Promise.all([serveClient(DIST, { sceneDir }), launchBrowser()])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

const bodyCount = (page: Page): Promise<number> => page.evaluate(() => window.concord.sandbox.bodies().length)
const jointCount = (page: Page): Promise<number> =>
  page.evaluate(() => window.concord.sandbox.joints().length)

/** Bodies by kind and position (m), sorted by kind then x: the same world whatever the ids. */
async function layout(page: Page): Promise<Array<[number, number, number]>> {
  return (await bodies(page))
    .map((b): [number, number, number] => [b.kind, b.x, b.y])
    .sort((p, q) => p[0] - q[0] || p[1] - q[1] || p[2] - q[2])
}

describe('build, drive, save and share', { timeout: 300_000 }, () => {
  it('draws terrain, builds a car from the tools, drives it over the terrain, and its share link opens the same world', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=build`)
    await loadScene(page, 'empty', 0)
    await setPaused(page, true)

    // Terrain: one drag of the Ground tool over bumps above the empty scene's ground.
    await pickTool(page, 'ground')
    const before = await bodyCount(page)
    const line = [
      { x: -9, y: 0.6 },
      { x: -6, y: 0.3 },
      { x: -3, y: 0.9 },
      { x: 0, y: 0.4 },
      { x: 3, y: 1.1 },
      { x: 6, y: 0.5 },
      { x: 9, y: 0.8 },
    ]
    const first = await screenOf(page, line[0].x, line[0].y)
    await page.mouse.move(first.x, first.y)
    await page.mouse.down()
    for (const p of line.slice(1)) {
      const at = await screenOf(page, p.x, p.y)
      await page.mouse.move(at.x, at.y, { steps: 6 })
    }
    await page.mouse.up()
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, before)
    const terrain = (await bodies(page)).length - before

    // The car: a box, then two clicks of the Wheel tool on its lower corners.
    await pickTool(page, 'box')
    const boxes = await bodyCount(page)
    await clickWorld(page, -6, 2.5)
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, boxes)
    const chassis = (await bodies(page)).filter((b) => b.kind === 2)[0].id
    await page.keyboard.press(',')
    await clickWorld(page, -6.4, 2.1)
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 1)
    await clickWorld(page, -5.6, 2.1)
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 2)
    await setPaused(page, false)

    // Drive right over the bumps with the arrow key for four seconds of room time.
    await until(async () => {
      const b = await snapshotOf(page, chassis)
      return Math.abs(b.angle) < 0.2 && b.y < 2
    }, 'the car on its wheels')
    const start = await snapshotOf(page, chassis)
    await page.keyboard.down('ArrowRight')
    await snapshotAfter(page, chassis, start.tick + 240)
    await page.keyboard.up('ArrowRight')
    const driven = await snapshotOf(page, chassis)
    // It drove over the terrain (rightwards by metres, above the drawn line's lowest point: it
    // neither fell through the chains nor flipped over).
    expect(driven.x).toBeGreaterThan(start.x + 3)
    expect(driven.y).toBeGreaterThan(0.3)
    expect(Math.abs(driven.angle)).toBeLessThan(1.2)

    // Let it come to rest, pause, and save: the share link opens the world in a new room.
    await until(async () => (await snapshotOf(page, chassis)).awake === false, 'the car at rest')
    await setPaused(page, true)
    const saved = await layout(page)
    const savedJoints = await jointCount(page)
    expect(savedJoints).toBe(2)
    await page.click('#save-scene')
    await page.waitForFunction(() => window.concord.sceneFiles.lastShareLink !== '')
    const link = await page.evaluate(() => window.concord.sceneFiles.lastShareLink)
    const id = link.slice(-16)

    const shared = await openSandbox(browser, link)
    await shared.page.waitForFunction((want) => window.concord.sandbox.scene() === want, `file:${id}`)
    await setPaused(shared.page, true)
    await shared.page.waitForFunction((n) => window.concord.sandbox.joints().length === n, savedJoints)
    // The same bodies: the scene's ground, the drawn terrain, the chassis and its two wheels, each
    // where it was saved (within 2 cm: the opened room may step a tick or two before pausing).
    const opened = await layout(shared.page)
    expect(opened.map(([kind]) => kind)).toEqual(saved.map(([kind]) => kind))
    opened.forEach(([, x, y], i) => {
      expect(Math.abs(x - saved[i][1]), `body ${i} x`).toBeLessThan(0.02)
      expect(Math.abs(y - saved[i][2]), `body ${i} y`).toBeLessThan(0.02)
    })
    expect(opened.filter(([kind]) => kind === 2)).toHaveLength(3)
    expect(opened.filter(([kind]) => kind === 0).length).toBe(1 + terrain)

    for (const e of [errors, shared.errors]) expect(e).toEqual([])
    await Promise.all([context.close(), shared.context.close()])
  })
})
