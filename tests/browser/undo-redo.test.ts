/*
 * Undo and redo in real Chromium against a real server (issue 31): a page spawns a box with the
 * Box tool and deletes it with the Delete tool; Ctrl+Z brings it back and a second page in the
 * room sees it where it was (the room is paused, so the pose is the one it was deleted with, to
 * the wire's 1 mm); the Redo button, Ctrl+Shift+Z and Ctrl+Y each delete it again and Ctrl+Z or
 * the Undo button bring it back; the second page's own undo is refused with a notice ("nothing to
 * undo": the actions were the first page's); Ctrl+Z is not the Slider tool's Z; Help lists the keys.
 */
import type { Browser, Page } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import {
  bodies,
  loadScene,
  openSandbox,
  type PageBody,
  pickTool,
  screenOf,
  useClientPages,
} from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

/** The page's dynamic bodies. */
const boxes = async (page: Page): Promise<PageBody[]> => (await bodies(page)).filter((b) => b.kind === 2)

/** Wait until the page shows exactly `n` dynamic bodies. */
const waitForBoxes = (page: Page, n: number) =>
  page.waitForFunction(
    (n) => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length === n,
    n,
  )

describe('undo and redo in the page', { timeout: 300_000 }, () => {
  it('spawn, delete, Ctrl+Z: the body is back on a second page; Redo and Ctrl+Shift+Z redo; the other page has nothing to undo', async () => {
    const a = await openSandbox(browser, `${base}/?room=undo-page`)
    const b = await openSandbox(browser, `${base}/?room=undo-page`)
    await loadScene(a.page, 'empty', 0)
    await b.page.waitForFunction(() => window.concord.sandbox.scene() === 'empty')
    await a.page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await b.page.waitForFunction(() => window.concord.sandbox.paused())
    // The buttons are there (the room runs the sandbox).
    await a.page.waitForFunction(() => !(document.getElementById('undo') as HTMLButtonElement).hidden)

    // Spawn a box with the Box tool at (1, 3), then delete it with the Delete tool.
    await pickTool(a.page, 'box')
    const at = await screenOf(a.page, 1, 3)
    await a.page.mouse.click(at.x, at.y)
    await waitForBoxes(b.page, 1)
    const [spawned] = await boxes(b.page)
    await pickTool(a.page, 'delete')
    const on = await screenOf(a.page, spawned.x, spawned.y)
    await a.page.mouse.click(on.x, on.y)
    await waitForBoxes(b.page, 0)

    // Ctrl+Z brings it back: a new id, the same place, shape and colour, on the other page.
    await a.page.keyboard.press('Control+z')
    await waitForBoxes(b.page, 1)
    const [back] = await boxes(b.page)
    expect(back.id).toBeGreaterThan(spawned.id)
    expect(Math.abs(back.x - spawned.x)).toBeLessThanOrEqual(0.001)
    expect(Math.abs(back.y - spawned.y)).toBeLessThanOrEqual(0.001)
    expect(back.shapes).toEqual(spawned.shapes)
    expect(back.color).toBe(spawned.color)
    // Ctrl+Z did not pick the Slider tool (Z).
    expect(await a.page.evaluate(() => window.concord.tools.tool)).toBe('delete')

    // The Redo button deletes it again; Ctrl+Z brings it back; Ctrl+Shift+Z deletes it; Ctrl+Y after
    // another Ctrl+Z too.
    await a.page.click('#redo')
    await waitForBoxes(b.page, 0)
    await a.page.keyboard.press('Control+z')
    await waitForBoxes(b.page, 1)
    await a.page.keyboard.press('Control+Shift+Z')
    await waitForBoxes(b.page, 0)
    await a.page.keyboard.press('Control+z')
    await waitForBoxes(b.page, 1)
    await a.page.keyboard.press('Control+y')
    await waitForBoxes(b.page, 0)
    await a.page.click('#undo')
    await waitForBoxes(b.page, 1)

    // The second page has done nothing: its undo is refused with a notice, the box stays.
    await b.page.keyboard.press('Control+z')
    await b.page.waitForFunction(() => document.getElementById('toast')?.textContent === 'nothing to undo')
    expect(await boxes(a.page)).toHaveLength(1)
    // The first page undoes its spawn: nothing left.
    await a.page.keyboard.press('Control+z')
    await waitForBoxes(b.page, 0)

    // Help lists the keys.
    const help = await a.page.evaluate(() => document.getElementById('help-rows')?.textContent ?? '')
    expect(help).toContain('Ctrl/⌘+Z')
    expect(help).toContain('Ctrl/⌘+Shift+Z')
    expect(help).toContain('Ctrl/⌘+Y')
    expect(a.errors).toEqual([])
    expect(b.errors).toEqual([])
    await Promise.all([a.context.close(), b.context.close()])
  })

  for (const mode of ['lockstep', 'predict'] as const) {
    it(`in a ${mode} page: an undo whose body another player deleted is refused naming them, and pressing again skips it`, async () => {
      const a = await openSandbox(browser, `${base}/?room=undo-${mode}&mode=${mode}`)
      const b = await openSandbox(browser, `${base}/?room=undo-${mode}`)
      await loadScene(b.page, 'empty', 0)
      await a.page.waitForFunction(() => window.concord.sandbox.scene() === 'empty')
      await b.page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
      await a.page.waitForFunction(() => window.concord.sandbox.paused())
      await a.page.waitForFunction(() => !(document.getElementById('undo') as HTMLButtonElement).hidden)
      for (const x of [-2, 2]) {
        await a.page.evaluate(
          (x) =>
            window.concord.sandbox.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x, y: 2 }),
          x,
        )
        await waitForBoxes(b.page, x < 0 ? 1 : 2)
      }
      const [first, second] = (await boxes(b.page)).sort((p, q) => p.id - q.id)
      await b.page.evaluate((id) => window.concord.sandbox.send({ k: 'delete', body: id }), second.id)
      await waitForBoxes(a.page, 1)
      const bob = await b.page.evaluate(() => window.concord.sandbox.playerId())
      await a.page.keyboard.press('Control+z')
      await a.page.waitForFunction(
        (text) => document.getElementById('toast')?.textContent === text,
        `cannot undo spawn: body ${second.id} was deleted by player ${bob} (press Undo again to skip it)`,
      )
      expect((await boxes(b.page)).map((p) => p.id)).toEqual([first.id])
      // Again: the gone spawn is skipped and the first spawn undone.
      await a.page.keyboard.press('Control+z')
      await waitForBoxes(b.page, 0)
      await waitForBoxes(a.page, 0)
      expect(a.errors).toEqual([])
      expect(b.errors).toEqual([])
      await Promise.all([a.context.close(), b.context.close()])
    })
  }
})
