/*
 * Editing a joint from the Edit panel, in real Chromium against a real server, read back by a raw
 * WebSocket client in the same room (bots/bot-client.ts: the server's own events, not the page's
 * drawing). A 2 m arm (0.4 kg, centre 1.5 m from the pin: its gravity torque m g r is 6 N m) hangs
 * on a hinge to the world with a motor at +1 rad/s and 1 N m, too weak to lift it. With the room
 * paused, `;` picks the Edit tool, a click beside the arm selects the hinge, and the panel's
 * fields set its upper and lower limits (0.4 and -0.3 rad), turn the limit on and raise the torque
 * to 20 N m (above m g r). Unpaused, the arm rises and the server's poses keep it within the new
 * limit; the raw client sees the joint's new settings under its id. Ctrl+Z undoes the torque: the
 * raw client sees the rebuilt joint with 1 N m again, and the arm sinks back to the lower limit.
 * A lockstep page in the room, which applies every command itself, verifies the room's hashes past
 * the end without a desync and draws the same rebuilt joint.
 */
import type { Browser, Page } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import type { RunningServer } from '../../server/server.ts'
import type { WireJoint } from '../../shared/index.ts'
import { bodies, loadScene, openSandbox, screenOf, useClientPages } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

/** Set one of the panel's joint fields and commit it (as Enter or leaving the field does). */
async function setJointField(page: Page, key: string, value: string | boolean): Promise<void> {
  await page.evaluate(
    ([k, v]) => {
      const input = document.querySelector<HTMLInputElement>(`#edit-panel [data-joint-edit="${k}"]`)!
      if (typeof v === 'boolean') input.checked = v
      else input.value = v
      input.dispatchEvent(new Event('change'))
    },
    [key, value] as const,
  )
}

/** How long a wait on the raw client may take on a loaded machine (the pages' waits allow as long). */
const WAIT = 90_000

/** The bot's joints of kind pin. */
const pins = (bot: BotClient): WireJoint[] => [...bot.mirror.joints.values()].filter((j) => j.kind === 'pin')

describe('editing a joint in the Edit panel', { timeout: 300_000 }, () => {
  it("a hinge's torque and limit changed in the panel reach the server; the arm stays in the new limit; undo restores the torque", async () => {
    const room = 'edit-joint'
    const { page, errors } = await openSandbox(browser, `${base}/?room=${room}`)
    await loadScene(page, 'empty', 0)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: true }))
    await page.waitForFunction(() => window.concord.sandbox.paused())
    const before = new Set((await bodies(page)).map((b) => b.id))
    await page.evaluate(() =>
      window.concord.sandbox.send({ k: 'spawn', shape: { type: 'box', hw: 1, hh: 0.1 }, x: 1.5, y: 3 }),
    )
    await page.waitForFunction((n) => window.concord.sandbox.bodies().length > n, before.size)
    const arm = (await bodies(page)).find((b) => !before.has(b.id))!.id
    await page.evaluate(
      (b) => window.concord.sandbox.sendGame('hinge', { a: 0, b, x: 0, y: 3, speed: 1, torque: 1 }),
      arm,
    )
    const bot = await BotClient.connect({ url: server.url, room, name: 'reader' })
    await until(() => pins(bot).length === 1, 'the hinge at the raw client', WAIT)
    const hinge = pins(bot)[0]
    expect(hinge).toMatchObject({ b: arm, motor: true, speed: 1, torque: 1, limit: false })
    // A lockstep page runs the room itself: it must apply every editJoint (and the undo) as the server does.
    const lockstep = await openSandbox(browser, `${base}/?room=${room}&mode=lockstep`)

    // Select the hinge: the Edit tool, a click on empty space next to the pin (the arm starts 0.5 m away).
    await page.keyboard.press(';')
    await page.waitForFunction(
      (id) => window.concord.sandbox.joints().some((j: { id: number }) => j.id === id),
      hinge.id,
    )
    const pin = await screenOf(page, -0.05, 3)
    await page.mouse.click(pin.x, pin.y)
    await page.waitForFunction(
      (id) =>
        document
          .querySelector('#edit-panel [data-edit="title"]')
          ?.textContent?.startsWith(`joint ${id}: pin`),
      hinge.id,
    )
    // Only a pin's settings: no force, no length.
    const fields = await page.$$eval('#edit-panel [data-joint-edit]', (list) =>
      list.map((e) => (e as HTMLElement).dataset.jointEdit),
    )
    expect(fields).toEqual([
      'limit',
      'lower',
      'upper',
      'motor',
      'speed',
      'torque',
      'spring',
      'hz',
      'damping',
      'target',
      'breakForce',
      'breakTorque',
    ])
    expect(await page.inputValue('#edit-panel [data-joint-edit="torque"]')).toBe('1')

    // Each field is one editJoint; wait for the server's answer before the next (the panel is rewritten).
    const steps: Array<[string, string | boolean, (j: WireJoint) => boolean]> = [
      ['upper', '0.4', (j) => j.upper === 0.4],
      ['lower', '-0.3', (j) => j.lower === -0.3],
      ['limit', true, (j) => j.limit],
      ['torque', '20', (j) => j.torque === 20],
    ]
    for (const [key, value, done] of steps) {
      await setJointField(page, key, value)
      await until(() => done(bot.mirror.joints.get(hinge.id)!), `${key} at the raw client`, WAIT)
      await page.waitForFunction(
        ([k, v]) => {
          const input = document.querySelector<HTMLInputElement>(`#edit-panel [data-joint-edit="${k}"]`)
          return input !== null && (typeof v === 'boolean' ? input.checked === v : input.value === v)
        },
        [key, value] as const,
      )
    }
    expect(bot.mirror.joints.get(hinge.id)).toEqual({
      ...hinge,
      torque: 20,
      limit: true,
      lower: -0.3,
      upper: 0.4,
    })

    // Unpaused: 20 N m > m g r = 6 N m lifts the arm at 1 rad/s to the upper limit, and no further.
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: false }))
    const start = bot.mirror.tick
    let top = Number.NEGATIVE_INFINITY
    await bot.waitFor(() => {
      top = Math.max(top, bot.mirror.bodies.get(arm)!.angle)
      return bot.mirror.tick > start + 180
    }, '3 s of the lifted arm')
    const lifted = bot.mirror.bodies.get(arm)!.angle
    console.log(
      `edit-joint: arm at ${lifted.toFixed(4)} rad after 3 s, highest ${top.toFixed(4)} rad (limit 0.4)`,
    )
    expect(lifted).toBeGreaterThan(0.38)
    expect(top).toBeLessThan(0.42)

    // Undo (Ctrl+Z) the torque: the joint is rebuilt (new id) with 1 N m, keeping the limit; the arm sinks to -0.3.
    await page.keyboard.press('Control+z')
    await until(() => pins(bot).some((j) => j.id !== hinge.id), 'the rebuilt hinge', WAIT)
    expect(bot.mirror.joints.has(hinge.id)).toBe(false)
    const undone = pins(bot)[0]
    expect(undone).toMatchObject({
      b: arm,
      torque: 1,
      limit: true,
      lower: -0.3,
      upper: 0.4,
      motor: true,
      speed: 1,
    })
    const from = bot.mirror.tick
    let low = Number.POSITIVE_INFINITY
    await bot.waitFor(() => {
      low = Math.min(low, bot.mirror.bodies.get(arm)!.angle)
      return bot.mirror.tick > from + 180
    }, '3 s of the sinking arm')
    const sunk = bot.mirror.bodies.get(arm)!.angle
    console.log(
      `edit-joint: after undo the arm is at ${sunk.toFixed(4)} rad, lowest ${low.toFixed(4)} rad (limit -0.3)`,
    )
    expect(sunk).toBeLessThan(-0.28)
    expect(low).toBeGreaterThan(-0.32)
    // The lockstep page verified the room's hashes past this point without a desync, and draws the rebuilt hinge.
    const end = bot.mirror.tick
    await lockstep.page.waitForFunction((t) => {
      const l = window.concord.sandbox.stats().lockstep
      return l !== null && l !== undefined && l.verifiedTick > t
    }, end)
    const l = await lockstep.page.evaluate(() => window.concord.sandbox.stats().lockstep!)
    expect([l.desyncs, l.resyncs]).toEqual([0, 0])
    const drawn = await lockstep.page.evaluate(
      (id) => window.concord.sandbox.joints().find((j: { id: number }) => j.id === id)?.spec,
      undone.id,
    )
    expect(drawn).toEqual(undone)
    expect(errors).toEqual([])
    expect(lockstep.errors).toEqual([])
    await lockstep.context.close()
    await bot.close()
  })
})
