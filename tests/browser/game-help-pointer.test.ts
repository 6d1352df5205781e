/*
 * A game's client module in the page's Help (docs/games.md, "Client modules"), in headless
 * Chromium against a real server on 127.0.0.1 serving the client (rooms on the main thread so the
 * test reads the room's own simulation). In a goal room, Help lists the goal keys first, each row
 * with what the goal client's keysHelp says (written out here by hand), and the page's shortcuts
 * lose the keys the game takes (Space, R, A, D, W, S: still listed for their other keys, or not
 * at all); in a sandbox room, Help has no game rows and lists those shortcuts.
 */
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox, serveClient } from '../support/client-harness.ts'

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
})
