/*
 * The joint tools in real Chromium against a real server: a car built in three clicks (a box and
 * two clicks of the wheel tool, with the room paused so the clicks land where aimed) drives right
 * at its wheels' motor speed times their radius while the right arrow key is held, and stops when
 * it is released; weld, hinge, spring and slider come from their shortcut keys, show a preview of
 * the joint before the click, and make the joint they show (the spring by touch).
 */
import type { Browser } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import { DRIVE_SPEED } from '../../client/input/index.ts'
import type { RunningServer } from '../../server/server.ts'
import {
  clickWorld,
  Finger,
  loadScene,
  openSandbox,
  pageJoints,
  pickTool,
  screenOf,
  setPaused,
  snapshotAfter,
  snapshotOf,
  useClientPages,
} from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

describe('joint tools', { timeout: 300_000 }, () => {
  it('builds a car in three clicks (a box, two wheels) and drives it with the arrow key at motor speed x radius', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=car`)
    await loadScene(page, 'empty', 0)
    await setPaused(page, true)
    const me = await page.evaluate(() => window.concord.sandbox.playerId())
    // Click 1: a 1 m box, 3 m up.
    await pickTool(page, 'box')
    await clickWorld(page, 0, 3)
    await page.waitForFunction(() =>
      window.concord.sandbox.bodies().some((b: { kind: number }) => b.kind === 2),
    )
    const chassis = await page.evaluate(
      () => window.concord.sandbox.bodies().find((b: { kind: number }) => b.kind === 2)!.id as number,
    )
    // Clicks 2 and 3: the wheel tool on the box's lower corners makes a wheel at each.
    await page.keyboard.press(',')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('wheel')
    // The preview: the wheel a click would make, under the pointer.
    const corner = await screenOf(page, -0.4, 2.6)
    await page.mouse.move(corner.x, corner.y)
    await page.waitForFunction(() => {
      const o = window.concord.tools.overlay('#fff')
      const g = o.ghost
      return (
        o.joint?.kind === 'wheel' &&
        g !== null &&
        g.shapes[0].type === 'circle' &&
        g.shapes[0].radius === 0.25
      )
    })
    await clickWorld(page, -0.4, 2.6)
    await clickWorld(page, 0.4, 2.6)
    await page.waitForFunction(() => window.concord.sandbox.joints().length === 2)
    const wheels = await pageJoints(page)
    expect(wheels.map((j) => [j.kind, j.a, j.owner, j.motor])).toEqual([
      ['wheel', chassis, me, true],
      ['wheel', chassis, me, true],
    ])
    await setPaused(page, false)
    // The car lands on its wheels and settles: chassis level, on the suspension.
    await until(async () => {
      const b = await snapshotOf(page, chassis)
      return Math.abs(b.angle) < 0.05 && b.y < 1.2
    }, 'the car on its wheels')
    const rest = await snapshotOf(page, chassis)
    // Hold the right arrow: both wheels turn clockwise at DRIVE_SPEED.turn; rolling, the car moves
    // at that times the wheel radius (10 rad/s x 0.25 m = 2.5 m/s). Measured over the second after
    // the first second of driving, from the snapshots' server ticks.
    await page.keyboard.down('ArrowRight')
    const pressed = await snapshotOf(page, chassis)
    const t1 = await snapshotAfter(page, chassis, pressed.tick + 60)
    const t2 = await snapshotAfter(page, chassis, t1.tick + 60)
    await page.keyboard.up('ArrowRight')
    const speed = (t2.x - t1.x) / ((t2.tick - t1.tick) / 60)
    const expected = DRIVE_SPEED.turn * 0.25
    expect(speed).toBeGreaterThan(expected * 0.97)
    expect(speed).toBeLessThan(expected * 1.01)
    expect(Math.abs(t2.angle)).toBeLessThan(0.5)
    // Released: the motors hold the wheels (speed 0, a brake); the car pitches forward on its
    // suspension, rocks for about three seconds and comes to rest: it falls asleep (the server
    // then stops sending it), well to the right of where it started.
    await until(async () => (await snapshotOf(page, chassis)).awake === false, 'the car at rest')
    const s2 = await snapshotOf(page, chassis)
    expect(s2.tick - t2.tick).toBeGreaterThan(60)
    expect(s2.x).toBeGreaterThan(rest.x + 2)
    expect(errors).toEqual([])
    await context.close()
  })

  it('weld, hinge, slider and spring from their keys, each previewed, then made as shown (the spring by touch)', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?room=jtools`)
    await loadScene(page, 'empty', 0)
    await setPaused(page, true)
    const spawn = (x: number, y: number) =>
      page.evaluate(
        ([sx, sy]) =>
          window.concord.sandbox.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: sx, y: sy }),
        [x, y] as const,
      )
    for (const x of [-4, -2, 0, 2, 4]) await spawn(x, 3)
    await page.waitForFunction(
      () => window.concord.sandbox.bodies().filter((b: { kind: number }) => b.kind === 2).length === 5,
    )
    // The toolbar's Joints button opens the joint panel with the five tools and picks one.
    expect(await page.isHidden('#joint-panel')).toBe(true)
    await page.click('#joints')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('weld')
    expect(await page.isVisible('#joint-panel [data-tool="wheel"]')).toBe(true)
    await page.click('#joint-panel [data-tool="slider"]')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('slider')
    const made: string[] = []
    for (const [key, tool, kind, x] of [
      ['y', 'weld', 'weld', -4],
      ['e', 'hinge', 'pin', -2],
    ] as const) {
      await page.keyboard.press(key)
      expect(await page.evaluate(() => window.concord.tools.tool)).toBe(tool)
      const at = await screenOf(page, x + 0.2, 3)
      await page.mouse.move(at.x, at.y)
      await page.waitForFunction((k) => window.concord.tools.overlay('#fff').joint?.kind === k, kind)
      await page.mouse.click(at.x, at.y)
      made.push(kind)
      await page.waitForFunction((n) => window.concord.sandbox.joints().length === n, made.length)
    }
    // Slider: drag from the box at x = 0 to the right; the preview is a slider along the drag.
    await page.keyboard.press('z')
    const from = await screenOf(page, 0, 3)
    const to = await screenOf(page, 1.5, 3)
    await page.mouse.move(from.x, from.y)
    await page.mouse.down()
    await page.mouse.move(to.x, to.y, { steps: 8 })
    await page.waitForFunction(() => window.concord.tools.overlay('#fff').joint?.kind === 'slider')
    await page.mouse.up()
    made.push('slider')
    await page.waitForFunction((n) => window.concord.sandbox.joints().length === n, made.length)
    // Spring by touch: a finger from the box at x = 2 to the box at x = 4.
    await page.keyboard.press('q')
    expect(await page.evaluate(() => window.concord.tools.tool)).toBe('spring')
    const finger = await Finger.down(page, await screenOf(page, 2, 3.2))
    await finger.moveTo(await screenOf(page, 4, 3.2))
    await page.waitForFunction(() => window.concord.tools.overlay('#fff').joint?.kind === 'spring')
    await finger.up()
    made.push('spring')
    await page.waitForFunction((n) => window.concord.sandbox.joints().length === n, made.length)
    const all = await pageJoints(page)
    expect(all.map((j) => j.kind)).toEqual(made)
    const me = await page.evaluate(() => window.concord.sandbox.playerId())
    for (const j of all) expect(j.owner).toBe(me)
    // The weld and hinge joined their box to the background (nothing under it), the spring two boxes.
    expect(all[0].a).toBe(0)
    expect(all[3].a).not.toBe(0)
    expect(errors).toEqual([])
    await context.close()
  })
})
