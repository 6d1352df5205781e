/*
 * A game's client module in the page's Help (docs/games.md, "Client modules"), in headless
 * Chromium against a real server on 127.0.0.1 serving the client (rooms on the main thread so the
 * test reads the room's own simulation). In a goal room, Help lists the goal keys first, each row
 * with what the goal client's keysHelp says (written out here by hand), and the page's shortcuts
 * lose the keys the game takes (Space, R, A, D, W, S: still listed for their other keys, or not
 * at all), then the pointer gesture; in a sandbox room, Help has no game rows and lists those
 * shortcuts. The goal client's pointer binding: a mouse press 3 m right of the page's own disc
 * sets the server's target velocity to (MAX_SPEED, 0) and the disc runs right; dragged to 3 m left
 * of the disc, the run turns to (-MAX_SPEED, 0); released, (0, 0); at rest again, a press 3 m
 * right and 4 m up runs at MAX_SPEED * (3, 4) / 5 = (3.6, 4.8) (hand computed). The presses never
 * reach the page's grab tool (no grab on the server). A finger (real touch events through the
 * DevTools protocol) goes the same way: held 3 m below the disc it runs it down at full speed,
 * lifted it stops it. On a phone (a mobile touch context), a goal room's Help has no key rows
 * (no kbd at all) and lists the gesture as "Tap" under a "goal" heading, before the buttons.
 */
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type GoalState, MAX_SPEED } from '../../games/index.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import type { SimulationObserver } from '../../shared/index.ts'
import { launchBrowser } from '../support/chromium.ts'
import { Finger, openSandbox, screenOf, serveClient } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

const DIST = 'test-results/browser-game-help-pointer/dist'
let server: RunningServer
let browser: Browser
const contexts: BrowserContext[] = []

beforeAll(async () => {
  await buildClient(DIST)
  server = await serveClient(DIST, { workers: 0 })
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  for (const c of contexts) await c.close()
  await browser?.close()
  await server?.close()
})

async function open(query: string): Promise<{ page: Page; errors: string[] }> {
  const { page, errors, context } = await openSandbox(browser, `${server.url}/?${query}`)
  contexts.push(context)
  return { page, errors }
}

/** Record every `run` game command player `id` sends, as the room applies it (a simulation observer). */
function recordRuns(room: RoomLike, id: number): { runs: Array<{ x: number; y: number }>; stop: () => void } {
  const runs: Array<{ x: number; y: number }> = []
  const observer: SimulationObserver = {
    command: (_tick, player, cmd) => {
      if (player === id && cmd.k === 'cmd' && cmd.kind === 'run') runs.push(cmd.a as { x: number; y: number })
    },
    join: () => {},
    leave: () => {},
    worldLoaded: () => {},
  }
  room.sim.observers.push(observer)
  return { runs, stop: () => void room.sim.observers.splice(room.sim.observers.indexOf(observer), 1) }
}

type RoomLike = { sim: { observers: SimulationObserver[] } }

/** Open Help with its button and read its rows: the keys (kbd texts) and the text of each. */
async function helpRows(page: Page): Promise<Array<{ keys: string[]; text: string; game: boolean }>> {
  await page.click('#help-button')
  await page.waitForSelector('#help:not([hidden])')
  const rows = await page.evaluate(() =>
    [...document.querySelectorAll('#help-rows tr')].map((tr) => ({
      keys: [...tr.querySelectorAll('kbd')].map((k) => k.textContent ?? ''),
      text: tr.querySelectorAll('td')[1]?.textContent ?? tr.textContent ?? '',
      game: tr.classList.contains('game-key') || tr.classList.contains('game-keys'),
    })),
  )
  await page.click('#help-close')
  return rows
}

describe('a game client module in the page', () => {
  it("a goal room's Help lists the goal keys first, and the shortcuts lose the keys goal takes", async () => {
    const { page, errors } = await open('room=help-goal&game=goal')
    const rows = await helpRows(page)
    const game = rows.filter((r) => r.game)
    expect(game[0].text).toBe('goal keys')
    expect(game.slice(1)).toEqual([
      { keys: ['↑', '←', '↓', '→'], text: 'run your disc (held: keep running)', game: true },
      { keys: ['W', 'A', 'S', 'D'], text: 'run your disc, as the arrows do', game: true },
      { keys: ['Space'], text: 'kick the ball away from your disc, when it is within reach', game: true },
      { keys: ['R'], text: 'rematch, once the match is over', game: true },
      {
        keys: [],
        text: 'press and hold on the field: your disc runs toward the pointer; let go: it stops',
        game: true,
      },
    ])
    // The game rows come first; no shortcut row names a key the game takes.
    expect(rows.slice(0, game.length).every((r) => r.game)).toBe(true)
    const shortcutKeys = rows.filter((r) => !r.game).flatMap((r) => r.keys)
    for (const k of ['Space', 'R', 'A', 'D', 'W', 'S']) expect(shortcutKeys).not.toContain(k)
    // What the page keeps: Step on '.', the other Wireframe key '0', Help itself.
    expect(rows.find((r) => r.text.startsWith('Single step'))?.keys).toEqual(['.'])
    expect(rows.find((r) => r.text === 'This help')?.keys).toEqual(['H', '?'])
    expect(rows.some((r) => r.text === 'Pause / resume')).toBe(false)
    expect(errors).toEqual([])
  }, 120_000)

  it("a sandbox room's Help has no game rows and lists the page's own Space and R", async () => {
    const { page, errors } = await open('room=help-sandbox')
    const rows = await helpRows(page)
    expect(rows.some((r) => r.game)).toBe(false)
    expect(rows.find((r) => r.text === 'Pause / resume')?.keys).toEqual(['Space'])
    expect(rows.find((r) => r.text === 'Reset the scene')?.keys).toEqual(['R'])
    expect(errors).toEqual([])
  }, 120_000)

  it("a press on a goal room's field runs the page's disc toward the pointer; a drag re-aims it; letting go stops it", async () => {
    const { page, errors } = await open('room=pointer-goal&game=goal')
    const room = server.rooms.get('pointer-goal')
    if (!room) throw new Error('no room pointer-goal')
    const id = await page.evaluate(() => window.concord.sandbox.playerId())
    const state = (): GoalState => room.sim.gameState as GoalState
    const disc = state().players[id].disc
    const serverDisc = () => room.sim.world.getPosition(disc)
    // The page's view names its disc, and draws it where the server has it (at rest).
    await until(
      async () =>
        (await page.evaluate(() => (window.concord.sandbox.gameState?.() as { disc?: number })?.disc)) ===
        disc,
      'the disc in the view',
    )
    const drawn = () =>
      page.evaluate((disc) => {
        const b = window.concord.sandbox.bodies().find((body) => body.id === disc)
        return b ? { x: b.x, y: b.y } : null
      }, disc)
    await until(async () => {
      const d = await drawn()
      return d !== null && Math.abs(d.x - serverDisc().x) < 1e-3 && Math.abs(d.y - serverDisc().y) < 1e-3
    }, 'the disc drawn where the server has it')
    const start = serverDisc()
    // Pointer events land on whole CSS pixels here, so the pressed point is within 1/scale m of the
    // one aimed at; at d m from the disc the run's direction, times MAX_SPEED, is within
    // MAX_SPEED / (scale * d) m/s of the exact one (plus the 1 mm the drawn disc may be off).
    const scale = await page.evaluate(() => window.concord.camera.scale)
    const within = (d: number) => (MAX_SPEED * (1 / scale + 1e-3)) / d + 1e-9
    const player = () => state().players[id]
    // Every `run` this player's page sent, as the room applied it: each gesture's first command is
    // checked, not whatever a later 50 ms re-aim sent.
    const { runs, stop } = recordRuns(room, id)

    // Press 3 m to the right: run right at full speed.
    const right = await screenOf(page, start.x + 3, start.y)
    await page.mouse.move(right.x, right.y)
    let from = runs.length
    await page.mouse.down()
    await until(() => runs.length > from, 'the run on the server')
    expect(Math.abs(runs[from].x - MAX_SPEED)).toBeLessThanOrEqual(within(3))
    expect(Math.abs(runs[from].y)).toBeLessThanOrEqual(within(3))
    await until(() => serverDisc().x > start.x + 0.5, 'the disc half a metre right')
    expect(room.sim.players.get(id)?.grab ?? null).toBeNull()

    // Drag to 3 m left of where the page draws the disc now: the run turns left.
    const now = await drawn()
    if (!now) throw new Error('the disc is not drawn')
    const left = await screenOf(page, now.x - 3, now.y)
    from = runs.length
    await page.mouse.move(left.x, left.y, { steps: 4 })
    await until(() => runs.slice(from).some((r) => r.x < 0), 'the run re-aimed left')
    const turned = runs.slice(from).find((r) => r.x < 0) ?? { x: 0, y: 0 }
    expect(turned.x).toBeCloseTo(-MAX_SPEED, 0)
    expect(Math.abs(turned.y)).toBeLessThan(0.5)

    // Let go: stop.
    await page.mouse.up()
    await until(() => player().vx === 0 && player().vy === 0, 'the stop on the server')
    expect(runs.at(-1)).toEqual({ x: 0, y: 0 })
    expect(room.sim.players.get(id)?.grab ?? null).toBeNull()

    // At rest again, a press 3 m right and 4 m up: MAX_SPEED * (3, 4) / 5 = (3.6, 4.8).
    await until(async () => {
      const v = room.sim.world.getLinearVelocity(disc)
      const d = await drawn()
      const at = serverDisc()
      return Math.hypot(v.x, v.y) < 1e-4 && d !== null && Math.hypot(d.x - at.x, d.y - at.y) < 1e-3
    }, 'the disc at rest, drawn where the server has it')
    const rest = serverDisc()
    const diagonal = await screenOf(page, rest.x + 3, rest.y + 4)
    await page.mouse.move(diagonal.x, diagonal.y)
    from = runs.length
    await page.mouse.down()
    await until(() => runs.length > from, 'the diagonal run')
    expect(Math.abs(runs[from].x - 3.6)).toBeLessThanOrEqual(within(5))
    expect(Math.abs(runs[from].y - 4.8)).toBeLessThanOrEqual(within(5))
    expect(Math.hypot(runs[from].x, runs[from].y)).toBeCloseTo(MAX_SPEED, 9)
    await page.mouse.up()
    await until(() => player().vx === 0 && player().vy === 0, 'the second stop')
    stop()
    expect(errors).toEqual([])
  }, 120_000)

  it("a finger on a goal room's field runs the disc the same way; lifting it stops it", async () => {
    const { page, errors, context } = await openSandbox(browser, `${server.url}/?room=touch-goal&game=goal`, {
      touch: true,
    })
    contexts.push(context)
    const room = server.rooms.get('touch-goal')
    if (!room) throw new Error('no room touch-goal')
    const id = await page.evaluate(() => window.concord.sandbox.playerId())
    const state = (): GoalState => room.sim.gameState as GoalState
    const disc = state().players[id].disc
    await until(
      async () =>
        (await page.evaluate(() => (window.concord.sandbox.gameState?.() as { disc?: number })?.disc)) ===
        disc,
      'the disc in the view',
    )
    await until(async () => {
      const d = await page.evaluate((disc) => {
        const b = window.concord.sandbox.bodies().find((body) => body.id === disc)
        return b ? { x: b.x, y: b.y } : null
      }, disc)
      const at = room.sim.world.getPosition(disc)
      return d !== null && Math.hypot(d.x - at.x, d.y - at.y) < 1e-3
    }, 'the disc drawn where the server has it')
    const at = room.sim.world.getPosition(disc)
    // Touch points land on whole CSS pixels: within MAX_SPEED / (scale * 3) m/s of (0, -MAX_SPEED).
    const scale = await page.evaluate(() => window.concord.camera.scale)
    const within = (MAX_SPEED * (1 / scale + 1e-3)) / 3 + 1e-9
    const { runs, stop } = recordRuns(room, id)
    const finger = await Finger.down(page, await screenOf(page, at.x, at.y - 3))
    await until(() => runs.length > 0, 'the run on the server')
    expect(Math.abs(runs[0].x)).toBeLessThanOrEqual(within)
    expect(Math.abs(runs[0].y + MAX_SPEED)).toBeLessThanOrEqual(within)
    await finger.up()
    await until(() => state().players[id].vx === 0 && state().players[id].vy === 0, 'the stop')
    expect(runs.at(-1)).toEqual({ x: 0, y: 0 })
    stop()
    expect(room.sim.players.get(id)?.grab ?? null).toBeNull()
    expect(errors).toEqual([])
  }, 120_000)

  it("a phone's Help in a goal room lists the tap gesture and no keys", async () => {
    const context = await browser.newContext({
      viewport: { width: 390, height: 844 },
      deviceScaleFactor: 2,
      hasTouch: true,
      isMobile: true,
    })
    contexts.push(context)
    const page = await context.newPage()
    await page.goto(`${server.url}/?room=phone-goal&game=goal`)
    await page.waitForFunction(
      () =>
        window.concord?.sandbox.status().state === 'connected' &&
        (window.concord.sandbox.gameState?.() as { disc?: number } | null)?.disc !== undefined,
    )
    await page.tap('#help-button')
    await page.waitForSelector('#help', { state: 'visible' })
    const rows = await page.evaluate(() =>
      [...document.querySelectorAll('#help-rows tr')].map((tr) => ({
        first: tr.querySelector('td')?.textContent ?? '',
        text: tr.querySelectorAll('td')[1]?.textContent ?? '',
        kbd: tr.querySelectorAll('kbd').length,
      })),
    )
    expect(rows.slice(0, 2)).toEqual([
      { first: 'goal', text: '', kbd: 0 },
      {
        first: 'Tap',
        text: 'press and hold on the field: your disc runs toward the pointer; let go: it stops',
        kbd: 0,
      },
    ])
    expect(rows[2].first).toBe('Grab')
    expect(rows.every((r) => r.kbd === 0)).toBe(true)
  }, 120_000)
})
