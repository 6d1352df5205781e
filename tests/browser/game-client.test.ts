/*
 * The goal game's client module in real pages (headless Chromium; docs/games.md, "Client
 * modules"): a real server on 127.0.0.1 serving the client, rooms on the main thread so the test
 * reads the room's own simulation. A lockstep page (red, first to join) and a snapshot page (blue)
 * join one goal room. Both game panels show "0 - 0" and a clock that counts down from 2:00. Keys
 * pressed in each page reach the server's game state: D (lockstep page) sets red's target
 * velocity to (+MAX_SPEED, 0) and its disc moves right; released, the target is 0; ArrowUp (snapshot
 * page) moves blue's disc up and out of the way. Space far from the ball is refused by the room
 * (red's last kick stays -1); red then runs into the ball holding D and kicks it with Space when
 * touching it, until the ball is in blue's goal: the server's score is red 1, and both panels
 * follow it to "1 - 0".
 */
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type GoalState, MAX_SPEED } from '../../games/index.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox, serveClient } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'

const DIST = 'test-results/browser-game-client/dist'
const ROOM = 'goal-keys'
let server: RunningServer
let browser: Browser
const contexts: BrowserContext[] = []

beforeAll(async () => {
  await buildClient(DIST)
  // Kicks out of reach are refused by the game, each a strike: allow plenty.
  server = await serveClient(DIST, { workers: 0, maxRejects: 10_000 })
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  for (const c of contexts) await c.close()
  await browser?.close()
  await server?.close()
})

async function join(mode: string): Promise<{ page: Page; errors: string[]; id: number }> {
  const { page, errors, context } = await openSandbox(
    browser,
    `${server.url}/?room=${ROOM}&game=goal${mode ? `&mode=${mode}` : ''}`,
  )
  contexts.push(context)
  const id = await page.evaluate(() => window.concord.sandbox.playerId())
  return { page, errors, id }
}

/** The game panel's items, label to value. */
function panel(page: Page): Promise<Record<string, string>> {
  return page.evaluate(() => {
    const out: Record<string, string> = {}
    const el = document.getElementById('game-panel')
    if (!el || el.hidden) return out
    for (const item of el.querySelectorAll<HTMLElement>('.item'))
      out[item.dataset.label ?? ''] = item.querySelector('b')?.textContent ?? ''
    return out
  })
}

/** Wait until the page's game panel shows `label` as `value`. */
async function shows(page: Page, label: string, value: string): Promise<void> {
  await page.waitForFunction(
    ([label, value]) => {
      const item = document.querySelector<HTMLElement>(
        `#game-panel:not([hidden]) .item[data-label="${label}"] b`,
      )
      return item?.textContent === value
    },
    [label, value],
  )
}

const seconds = (clock: string): number => {
  const m = /^(\d+):(\d\d)$/.exec(clock)
  if (!m) throw new Error(`clock "${clock}" is not m:ss`)
  return Number(m[1]) * 60 + Number(m[2])
}

describe('the goal game client module in a lockstep page and a snapshot page', () => {
  it('both show 0 - 0 and a running clock; keys steer and kick; the panels follow the server to 1 - 0', async () => {
    const red = await join('lockstep')
    const room = server.rooms.get(ROOM)
    if (!room) throw new Error(`no room ${ROOM}`)
    const blue = await join('')
    const state = (): GoalState => room.sim.gameState as GoalState
    const disc = (id: number) => room.sim.world.getPosition(state().players[id].disc)
    expect(state().players[red.id].team).toBe('red')
    expect(state().players[blue.id].team).toBe('blue')
    await until(() => state().phase === 'playing', 'the match to start')

    // Score and clock in both panels; the clock counts down from 2:00.
    for (const p of [red.page, blue.page]) {
      await shows(p, 'score', '0 - 0')
      await shows(p, 'match', 'playing')
      const first = seconds((await panel(p)).clock)
      expect(first).toBeLessThanOrEqual(120)
      await p.waitForFunction((first) => {
        const b = document.querySelector('#game-panel .item[data-label="clock"] b')?.textContent ?? ''
        const m = /^(\d+):(\d\d)$/.exec(b)
        return m !== null && Number(m[1]) * 60 + Number(m[2]) < first
      }, first)
    }
    expect((await panel(red.page)).team).toBe('red')
    expect((await panel(blue.page)).team).toBe('blue')

    // Space far from the ball: the room refuses the kick (red is 4 m away).
    await red.page.keyboard.press(' ')
    await red.page.waitForFunction(
      () => window.concord.sandbox.notices().latest === 'the ball is out of reach',
    )
    expect(state().players[red.id].lastKick).toBe(-1)

    // The snapshot page: ArrowUp runs blue up (out of red's way), release stops it.
    const blueStart = disc(blue.id).y
    await blue.page.keyboard.down('ArrowUp')
    await until(() => state().players[blue.id].vy === MAX_SPEED, "blue's run up on the server")
    await until(() => disc(blue.id).y > blueStart + 3, "blue's disc 3 m up")
    await blue.page.keyboard.up('ArrowUp')
    await until(() => state().players[blue.id].vy === 0, "blue's stop on the server")

    // The lockstep page: D runs red right (the key the sandbox uses for body ids).
    const redStart = disc(red.id).x
    await red.page.keyboard.down('d')
    await until(
      () => state().players[red.id].vx === MAX_SPEED && state().players[red.id].vy === 0,
      "red's run",
    )
    await until(() => disc(red.id).x > redStart + 1, "red's disc 1 m right")
    // Into the ball and through to blue's goal, kicking whenever touching it.
    await until(
      async () => {
        if (state().score.red > 0) return true
        const ball = room.sim.world.getPosition(state().ball)
        const d = disc(red.id)
        if (Math.hypot(ball.x - d.x, ball.y - d.y) < 0.85) await red.page.keyboard.press(' ')
        return false
      },
      'a red goal',
      60_000,
    )
    await red.page.keyboard.up('d')
    expect(state().players[red.id].lastKick).toBeGreaterThan(0)
    expect(state().score).toEqual({ red: 1, blue: 0 })
    await until(() => state().players[red.id].vx === 0, "red's stop on the server")
    await shows(blue.page, 'score', '1 - 0')
    await shows(red.page, 'score', '1 - 0')
    expect(red.errors).toEqual([])
    expect(blue.errors).toEqual([])
  }, 240_000)
})
