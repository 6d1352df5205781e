/*
 * The Edit tool in real Chromium against a real server, with two pages in one room (the room
 * paused, so bodies stay where they are put): on the first page the `;` key picks the tool, a click
 * selects a box, the panel changes its friction, colour and static state, a mouse drag moves
 * another box (a faint copy follows the pointer first), the panel turns it 15 degrees and its
 * Duplicate copies it (turned alike); on the
 * second page (a touch screen) a finger drags a rectangle around three bodies and the Delete key
 * removes them. After each step both pages show the same bodies, poses equal to the millimetre.
 */
import type { Browser, Page } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import type { RunningServer } from '../../server/server.ts'
import {
  bodies,
  Finger,
  loadScene,
  openSandbox,
  type PageBody,
  screenOf,
  setEditControl,
  useClientPages,
} from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

/** Spawn a box (half width `hw`) at a point and return its id once the page has it. */
async function spawnBox(page: Page, x: number, y: number, hw: number): Promise<number> {
  const before = new Set((await bodies(page)).map((b) => b.id))
  await page.evaluate(
    ([bx, by, h]) =>
      window.concord.sandbox.send({ k: 'spawn', shape: { type: 'box', hw: h, hh: h }, x: bx, y: by }),
    [x, y, hw] as const,
  )
  await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, before.size)
  return (await bodies(page)).find((b) => !before.has(b.id))!.id
}

/** The online sandbox's copy of the room's bodies as the server sent them (snapshot poses, not interpolated). */
type Mirrored = { mirror: { bodies: Map<number, Omit<PageBody, 'color'> & { color?: number }> } }
const mirrored = (page: Page): Promise<PageBody[]> =>
  page.evaluate(() =>
    [...(window.concord.sandbox as unknown as Mirrored).mirror.bodies.values()].map((b) => ({
      id: b.id,
      kind: b.kind,
      shapes: b.shapes,
      color: b.color === undefined ? null : `#${b.color.toString(16).padStart(6, '0')}`,
      x: b.x,
      y: b.y,
      angle: b.angle,
    })),
  )

/**
 * Wait until the page draws body `id` where its copy of the room (the server's pose) has it, and
 * keeps drawing it there for half a second (longer than the 18-tick extrapolation a wrong track
 * would draw): a paused room sends no later snapshot to correct a wrong drawing.
 */
async function drawnAtServerPose(page: Page, id: number): Promise<void> {
  await page.waitForFunction((bodyId) => {
    const w = window as unknown as { concord: typeof window.concord; since?: number }
    const drawn = w.concord.sandbox.bodies().find((v: { id: number }) => v.id === bodyId)
    const m = (w.concord.sandbox as unknown as Mirrored).mirror.bodies.get(bodyId)
    const at =
      drawn !== undefined &&
      m !== undefined &&
      Math.abs(drawn.x - m.x) < 1e-4 &&
      Math.abs(drawn.y - m.y) < 1e-4 &&
      Math.abs(drawn.angle - m.angle) < 1e-4
    if (!at) w.since = undefined
    else w.since ??= performance.now()
    return w.since !== undefined && performance.now() - w.since > 500
  }, id)
}

/** Both pages' copies of the room, once they list the same bodies with poses equal to the millimetre. */
async function agreed(a: Page, b: Page): Promise<PageBody[]> {
  const mm = (v: number) => Math.round(v * 1000)
  const key = (list: PageBody[]) =>
    JSON.stringify(
      list
        .map((x) => [x.id, x.kind, x.color, mm(x.x), mm(x.y), mm(x.angle * 100), x.shapes])
        .sort((p, q) => (p[0] as number) - (q[0] as number)),
    )
  for (let i = 0; ; i++) {
    const [pa, pb] = await Promise.all([mirrored(a), mirrored(b)])
    if (key(pa) === key(pb)) return pa
    if (i > 300) expect(key(pb)).toBe(key(pa))
    await a.evaluate(() => new Promise((r) => requestAnimationFrame(() => r(null))))
  }
}

describe('the Edit tool', { timeout: 300_000 }, () => {
  it('selects, changes material, colour and static, moves, duplicates, box-selects by touch and deletes; another page sees it all', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=edit-tool`)
    await loadScene(page, 'empty', 0)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await page.waitForFunction(() => window.concord.sandbox.paused())
    const ids = [
      await spawnBox(page, -3, 0.5, 0.5),
      await spawnBox(page, -1, 0.5, 0.5),
      await spawnBox(page, 2, 0.5, 0.4),
      await spawnBox(page, 3.5, 0.5, 0.4),
    ]
    const other = await openSandbox(browser, `${base}/?room=edit-tool`, { touch: true })
    // A third page runs the room's simulation itself (lockstep): it applies every edit command.
    const lockstep = await openSandbox(browser, `${base}/?room=edit-tool&mode=lockstep`)
    await agreed(page, other.page)

    // Select the first box: `;` picks the tool, a click selects; the panel names it.
    await page.keyboard.press(';')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('edit')
    expect(await page.isVisible('#edit-panel')).toBe(true)
    const first = await screenOf(page, -3, 0.5)
    await page.mouse.click(first.x, first.y)
    await page.waitForFunction(
      (id) => document.querySelector('#edit-panel [data-edit="title"]')?.textContent === `body ${id}`,
      ids[0],
    )
    expect(await page.inputValue('#edit-panel [data-edit="friction"]')).toBe('0.6')
    // Friction, colour and static from the panel.
    await setEditControl(page, 'friction', '0.25')
    await setEditControl(page, 'color', '#ff3366')
    await page.check('#edit-panel [data-edit="static"]')
    await other.page.waitForFunction((id) => {
      const b = window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)
      return b?.kind === 0 && b.color === '#ff3366' && b.shapes[0].friction === 0.25
    }, ids[0])
    expect(await page.isChecked('#edit-panel [data-edit="static"]')).toBe(true)

    // Move the second box 2 m right with the mouse: a faint copy follows the pointer first.
    const from = await screenOf(page, -1, 0.5)
    const to = await screenOf(page, 1, 1.5)
    await page.mouse.move(from.x, from.y)
    await page.mouse.down()
    await page.mouse.move(to.x, to.y, { steps: 10 })
    const ghost = await page.evaluate(() => window.concord.tools.overlay('#fff').ghost)
    expect(ghost?.id).toBe(ids[1])
    expect(ghost!.x).toBeCloseTo(1, 1)
    await page.mouse.up()
    await other.page.waitForFunction((id) => {
      const b = window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)
      return b !== undefined && Math.abs(b.x - 1) < 0.05 && Math.abs(b.y - 1.5) < 0.05
    }, ids[1])
    // ... and keeps drawing it where the server has it (a teleport is not a velocity to carry on).
    await drawnAtServerPose(other.page, ids[1])
    // Turn it twice 15 degrees from the panel (touch has no Shift), quickly: the other page draws
    // the new angle and stays there (two close jumps are no velocity to carry the body on with).
    await page.click('#edit-panel [data-edit-action="turn-left"]')
    // (A turn is from the drawn angle: the second waits until this page draws the first.)
    await page.waitForFunction((id) => {
      const b = window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)
      return b !== undefined && Math.abs(b.angle - Math.PI / 12) < 0.002
    }, ids[1])
    await page.click('#edit-panel [data-edit-action="turn-left"]')
    await other.page.waitForFunction((id) => {
      const b = window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)
      return b !== undefined && Math.abs(b.angle - Math.PI / 6) < 0.002
    }, ids[1])
    await drawnAtServerPose(other.page, ids[1])
    // Scale it up from the panel: 1.25 x the 0.5 m half extents.
    await page.click('#edit-panel [data-edit-action="bigger"]')
    await other.page.waitForFunction(
      (id) =>
        (
          window.concord.sandbox.bodies().find((v: { id: number }) => v.id === id)?.shapes[0] as {
            hw?: number
          }
        )?.hw === 0.625,
      ids[1],
    )
    // Duplicate it from the panel: a box of the same shapes beside it.
    await page.click('#edit-panel [data-edit-action="duplicate"]')
    await other.page.waitForFunction(() => window.concord.sandbox.bodies().length === 6)
    let seen = await agreed(page, other.page)
    const moved = seen.find((b) => b.id === ids[1])!
    expect(moved.x).toBeCloseTo(1, 1)
    expect(moved.y).toBeCloseTo(1.5, 1)
    const copy = seen.find((b) => !ids.includes(b.id) && b.kind === 2)!
    expect(copy.shapes).toEqual(moved.shapes)
    expect(moved.angle).toBeCloseTo(Math.PI / 6, 3)
    expect(copy.angle).toBe(moved.angle)
    // The copy is 2 x 0.8839 m (the scaled box's reach, 0.625 sqrt 2) + 0.1 m to the right, to the mm: 1.868 m.
    expect(copy.x - moved.x).toBeCloseTo(1.868, 6)
    expect(copy.y).toBeCloseTo(moved.y, 3)

    // On the touch page: the Edit button, a finger drags a rectangle around the two small boxes
    // and the copy (not the static box, not the ground), and the Delete key removes them.
    await other.page.click('#toolbar [data-tool="edit"]')
    const corner = await screenOf(other.page, 1.6, -0.3)
    const far = await screenOf(other.page, Math.max(4, copy.x + 0.5), 2.5)
    const finger = await Finger.down(other.page, corner)
    await finger.moveTo(far)
    const rectangle = await other.page.evaluate(() => window.concord.tools.overlay('#fff').stroke)
    expect(rectangle).toHaveLength(4)
    await finger.up()
    await other.page.waitForFunction(() => window.concord.tools.edit.selection.length === 3)
    expect(await other.page.evaluate(() => window.concord.tools.edit.selection)).toEqual(
      [ids[2], ids[3], copy.id].sort((a, b) => a - b),
    )
    await other.page.waitForFunction(
      () => document.querySelector('#edit-panel [data-edit="title"]')?.textContent === '3 bodies',
    )
    await other.page.keyboard.press('Delete')
    await page.waitForFunction(() => window.concord.sandbox.bodies().length === 3)
    seen = await agreed(page, other.page)
    expect(seen.map((b) => b.id).sort((a, b) => a - b)).toEqual([1, ids[0], ids[1]])
    expect(errors).toEqual([])
    expect(other.errors).toEqual([])
    // The lockstep page, which simulated every command itself, has the same bodies: shapes (the
    // scaled box redrawn), colours, kinds and poses (within the snapshots' 1 mm and 1/65536 turn).
    await lockstep.page.waitForFunction(() => window.concord.sandbox.bodies().length === 3)
    const own = await bodies(lockstep.page)
    expect(own.map((b) => b.id).sort((a, b) => a - b)).toEqual([1, ids[0], ids[1]])
    for (const b of seen) {
      const mine = own.find((o) => o.id === b.id)!
      expect([mine.kind, mine.color, mine.shapes]).toEqual([b.kind, b.color, b.shapes])
      expect(Math.abs(mine.x - b.x)).toBeLessThanOrEqual(0.0005)
      expect(Math.abs(mine.y - b.y)).toBeLessThanOrEqual(0.0005)
      expect(Math.abs(mine.angle - b.angle)).toBeLessThanOrEqual(1e-4)
    }
    expect(lockstep.errors).toEqual([])
    await Promise.all([context.close(), other.context.close(), lockstep.context.close()])
  })
})
