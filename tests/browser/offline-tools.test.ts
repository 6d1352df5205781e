/*
 * The offline page (`?offline`, and the static build opened from disk) in real Chromium: the room
 * runs in the page (the sandbox game's RoomSimulation with one local player), so the game's tools
 * work without a server. With the world paused (so clicks land where aimed): the Box tool drops a
 * box in the player's colour, the hinge tool (E) joins two overlapping boxes, Ctrl+Z takes the
 * hinge away and Ctrl+Shift+Z brings it back between the same bodies, and the Edit tool (;) gives
 * a box a new colour and density: its mass is then density x area (a closed form, from the lab's
 * numbers); slow motion (-) is the game's too. Opened from disk (file:), the static build drops a
 * box, undoes it, saves the world as a scene file (a download: a valid scene with the page's
 * bodies) and opens that file again.
 */
import { readFile } from 'node:fs/promises'
import { join, resolve } from 'node:path'
import { pathToFileURL } from 'node:url'
import type { Browser, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { parseScene } from '../../games/index.ts'
import { buildStatic } from '../../scripts/build-static.mjs'
import type { RunningServer } from '../../server/server.ts'
import { PLAYER_PALETTE } from '../../shared/index.ts'
import { launchBrowser } from '../support/chromium.ts'
import {
  bodies,
  clickWorld,
  collectErrors,
  openSandbox,
  pageJoints,
  pickTool,
  screenOf,
  setEditControl,
  setPaused,
  startClientServer,
} from '../support/client-harness.ts'

const STATIC_DIR = 'test-results/offline-tools/static'

let server: RunningServer
let browser: Browser
let base: string

beforeAll(async () => {
  ;[server, browser] = await Promise.all([startClientServer(), launchBrowser(), buildStatic(STATIC_DIR)])
  base = `http://127.0.0.1:${server.port}`
})

afterAll(async () => {
  await browser?.close()
  await server?.close()
})

/** Ids of the page's dynamic bodies. */
const dynamicIds = async (page: Page): Promise<number[]> =>
  (await bodies(page)).filter((b) => b.kind === 2).map((b) => b.id)

describe('the offline page runs the sandbox game', { timeout: 300_000 }, () => {
  it('drops a box, hinges two boxes, undoes and redoes the hinge, and edits colour and density', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?offline&scene=empty`)
    expect(await page.evaluate(() => window.concord.sandbox.mode)).toBe('offline')
    await setPaused(page, true)
    // The Box tool: a 1 m box at (0, 3), in the colour of the room's first player.
    await pickTool(page, 'box')
    await clickWorld(page, 0, 3)
    await page.waitForFunction(() =>
      window.concord.sandbox.bodies().some((b: { kind: number }) => b.kind === 2),
    )
    const [first] = await dynamicIds(page)
    const dropped = (await bodies(page)).find((b) => b.id === first)!
    expect(dropped.color).toBe(PLAYER_PALETTE[0])
    expect(Math.abs(dropped.x) < 0.05 && Math.abs(dropped.y - 3) < 0.05).toBe(true)
    // A second box overlapping its right half.
    await page.evaluate(() =>
      window.concord.sandbox.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0.6, y: 3 }),
    )
    await page.waitForFunction(
      () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length === 2,
    )
    const second = (await dynamicIds(page)).find((id) => id !== first)!

    // The hinge tool (E) on the overlap joins the box under the pointer to the one below it.
    expect(await page.isVisible('#undo')).toBe(true)
    await page.keyboard.press('e')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('hinge')
    const overlap = await screenOf(page, 0.3, 3)
    await page.mouse.move(overlap.x, overlap.y)
    await page.waitForFunction(() => window.concord.tools.overlay('#fff').joint?.kind === 'pin')
    await page.mouse.click(overlap.x, overlap.y)
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 1)
    const [hinge] = await pageJoints(page)
    const me = await page.evaluate(() => window.concord.sandbox.playerId())
    expect(me).toBeGreaterThan(0)
    expect(hinge.kind).toBe('pin')
    expect([hinge.a, hinge.b].sort()).toEqual([first, second].sort())
    expect(hinge.owner).toBe(me)

    // Undo takes the hinge away (the boxes stay); redo brings it back between the same boxes.
    await page.keyboard.press('Control+z')
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 0)
    expect((await dynamicIds(page)).sort()).toEqual([first, second].sort())
    await page.keyboard.press('Control+Shift+z')
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 1)
    const [again] = await pageJoints(page)
    expect([again.kind, again.a, again.b, again.owner]).toEqual([hinge.kind, hinge.a, hinge.b, me])

    // The Edit tool (;): select the first box by its free left half, then colour and density.
    await page.keyboard.press(';')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('edit')
    await clickWorld(page, -0.35, 3)
    await page.waitForFunction(
      (id) => document.querySelector('#edit-panel [data-edit="title"]')?.textContent === `body ${id}`,
      first,
    )
    await setEditControl(page, 'color', '#ff3366')
    await setEditControl(page, 'density', '2.5')
    // An edit rebuilds the body in place: same id, new colour and density; mass = 2.5 kg/m^2 x 1 m^2.
    await page.waitForFunction((id) => {
      const b = window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)
      return b?.color === '#ff3366' && b.shapes[0].density === 2.5
    }, first)
    const mass = await page.evaluate((id) => window.concord.sandbox.lab(id)?.mass, first)
    expect(mass).toBeCloseTo(2.5, 9)
    // Slow motion (-) is the game's: the room steps every second tick and the view says so; the
    // lock is hidden (the page's player is alone in its room).
    await page.keyboard.press('Escape')
    await page.keyboard.press('-')
    await page.waitForFunction(() => window.concord.sandbox.roomControl?.().slow === 2)
    await page.waitForFunction(() => /Slow motion 1\/2/.test(document.getElementById('paused')!.textContent!))
    expect(await page.isHidden('#lock')).toBe(true)
    // Nothing was refused on the way (no "needs a room").
    expect(await page.evaluate(() => window.concord.sandbox.notices().count)).toBe(0)
    expect(errors).toEqual([])
    await context.close()
  })

  it('opened from disk (file:): drops and undoes a box, saves the world as a file and opens it again', async () => {
    const context = await browser.newContext({
      viewport: { width: 1000, height: 700 },
      acceptDownloads: true,
    })
    context.setDefaultTimeout(90_000)
    const page = await context.newPage()
    const errors = collectErrors(page)
    await page.goto(pathToFileURL(join(resolve(STATIC_DIR), 'index.html')).href)
    await page.waitForFunction(() => {
      const c = window.concord
      return c && c.sandbox.mode === 'offline' && c.sandbox.bodies().length > 0 && c.fps.value > 0
    })
    await setPaused(page, true)
    const before = await page.evaluate(() => window.concord.sandbox.bodies().length)
    await pickTool(page, 'box')
    await clickWorld(page, 0, 6)
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length === n + 1, before)
    await page.keyboard.press('Control+z')
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length === n, before)

    // Save: the page makes the file itself; it names what only a server gives (share links).
    expect(await page.isVisible('#save-scene')).toBe(true)
    expect(await page.getAttribute('#save-scene', 'title')).toContain('share links need the sandbox online')
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-scene')])
    const text = await readFile((await download.path())!, 'utf8')
    const parsed = parseScene(text)
    if (!parsed.ok) throw new Error(parsed.error)
    expect(parsed.scene.bodies.length).toBe(before)
    await page.waitForFunction(() =>
      /Share links need the sandbox online/.test(document.getElementById('toast')!.textContent!),
    )

    // Open: the same file, checked in the page, replaces the world with its bodies.
    await page.setInputFiles('#scene-file', {
      name: 'saved.json',
      mimeType: 'application/json',
      buffer: Buffer.from(text),
    })
    await page.waitForFunction(() => window.concord.sandbox.scene() === 'file:saved.json')
    expect(await page.evaluate(() => window.concord.sandbox.bodies().length)).toBe(before)
    // A file that is not a scene is refused with the field named, and the world stays.
    await page.setInputFiles('#scene-file', {
      name: 'bad.json',
      mimeType: 'application/json',
      buffer: Buffer.from('{"format":"concord-scene","version":1,"bodies":[{"type":"dynamic"}]}'),
    })
    await page.waitForFunction(() =>
      /bad\.json is not a scene file/.test(document.getElementById('toast')!.textContent!),
    )
    expect(await page.evaluate(() => window.concord.sandbox.scene())).toBe('file:saved.json')
    expect(errors).toEqual([])
    await context.close()
  })
})
