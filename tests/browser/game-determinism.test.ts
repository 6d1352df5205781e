/*
 * The shipped games are deterministic across JavaScript engines: a 10,000-tick scripted run of
 * each (goal, tower, ball-drop; tests/games/game-runs.ts: four scripted players, one leaving and
 * one joining midway, finished matches and rounds started again) gives the same simulation hash
 * (world, PRNG position and game state) every 500 ticks in Node (V8), in Debian's Chromium (V8
 * again, but a browser build) and in Firefox ESR (SpiderMonkey). The runs are bundled with
 * esbuild and evaluated in blank pages: no server is involved, so a difference can only come from
 * the engines' arithmetic or from an order the games' rules do not fix. Without firefox-esr the
 * Firefox case is skipped with the reason printed.
 */
import { build } from 'esbuild'
import type { Browser } from 'playwright-core'
import type { Browser as PuppeteerBrowser } from 'puppeteer-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type GameRun, RUN_GAMES, runGame } from '../games/game-runs.ts'
import { launchBrowser } from '../support/chromium.ts'
import { firefoxMissing, launchFirefox } from '../support/firefox.ts'

const TICKS = 10_000
const EVERY = 500
const missing = firefoxMissing()
if (missing) console.warn(`game-determinism.test.ts: Firefox skipped: ${missing}`)

let code = ''
let chromium: Browser
let firefox: PuppeteerBrowser | undefined
const node = new Map<string, GameRun>()

/** Run every game in a page that evaluates the bundle; `evaluate` is the driver's. */
async function runInPage(evaluate: (source: string) => Promise<unknown>): Promise<Map<string, GameRun>> {
  await evaluate(code)
  const out = new Map<string, GameRun>()
  for (const game of RUN_GAMES) {
    out.set(
      game,
      (await evaluate(
        `globalThis.concordGameRuns.run(${JSON.stringify(game)}, ${TICKS}, ${EVERY})`,
      )) as GameRun,
    )
  }
  return out
}

const hex = (h: number): string => h.toString(16).padStart(8, '0')

function expectSame(label: string, runs: Map<string, GameRun>): void {
  for (const game of RUN_GAMES) {
    const mine = runs.get(game) as GameRun
    const reference = node.get(game) as GameRun
    console.log(
      `${label} ${game}: final ${hex(mine.finalHash)} (node ${hex(reference.finalHash)}), ${mine.events} events`,
    )
    expect(mine.hashes.map(hex), `${label} ${game}`).toEqual(reference.hashes.map(hex))
    expect(mine.state).toEqual(reference.state)
    expect(mine.events).toBe(reference.events)
  }
}

beforeAll(async () => {
  const bundle = await build({
    entryPoints: [new URL('./game-runs-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  code = bundle.outputFiles[0].text
  ;[chromium, firefox] = await Promise.all([launchBrowser(), missing ? undefined : launchFirefox()])
  for (const game of RUN_GAMES) node.set(game, runGame(game, TICKS, EVERY))
}, 120_000)

afterAll(async () => {
  await chromium?.close()
  await firefox?.close()
})

describe(`the games over ${TICKS.toLocaleString('en')} scripted ticks`, () => {
  it('do something in Node: goals, blocks and drops happen, players come and go', () => {
    const goal = node.get('goal') as GameRun
    const tower = node.get('tower') as GameRun
    const drop = node.get('ball-drop') as GameRun
    expect(goal.hashes.length).toBe(TICKS / EVERY)
    // Goals and whole matches (each goal, kickoff and end is an event), blocks falling, balls scoring.
    expect(goal.events).toBeGreaterThan(20)
    expect(tower.events).toBeGreaterThan(20)
    expect(drop.events).toBeGreaterThan(20)
    expect(Object.keys((goal.state as { players: object }).players)).toEqual(['1', '2', '3', '5'])
    // Not a run that stopped changing: the last hashes differ.
    for (const run of [goal, tower, drop]) expect(new Set(run.hashes.slice(-4)).size).toBe(4)
  })

  it('give the same hashes in Chromium as in Node', async () => {
    const page = await chromium.newPage()
    const errors: string[] = []
    page.on('pageerror', (e) => errors.push(e.message))
    const runs = await runInPage((source) => page.evaluate(source))
    expect(await page.evaluate(() => navigator.userAgent)).toMatch(/Chrom/)
    expectSame(`Chromium ${chromium.version()}`, runs)
    expect(errors).toEqual([])
  }, 180_000)

  it.skipIf(missing !== '')(
    'give the same hashes in Firefox as in Node',
    async () => {
      const page = await (firefox as PuppeteerBrowser).newPage()
      const errors: string[] = []
      page.on('pageerror', (e) => errors.push(e instanceof Error ? e.message : String(e)))
      await page.goto('about:blank')
      const runs = await runInPage((source) => page.evaluate(source))
      const agent = (await page.evaluate('navigator.userAgent')) as string
      expect(agent).toMatch(/Firefox\//)
      expectSame(agent.match(/Firefox\/[\d.]+/)?.[0] ?? 'Firefox', runs)
      expect(errors).toEqual([])
    },
    180_000,
  )
})
