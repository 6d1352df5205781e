/*
 * A goal match between two client pages in headless Chromium: the client bundle served by a real
 * server on 127.0.0.1 (rooms on the main thread, so the test can watch the room's own
 * simulation), one page joined with `?game=goal&mode=lockstep` (red, the first to join) and one
 * with `&mode=predict` (blue). Each page plays its player with a script (game-match-page.ts: the
 * red page a striker, the blue page keeps out of the way) computed from its own simulation and
 * sent over its own connection as `cmd` messages, until the match ends (red wins 5-0). Then: at
 * every tick a page was seen at (every 5 ms through the match), its score and phase equal what
 * the server's room held at that tick (recorded by an observer on the room); no page reported a
 * desync (the server's concord_desyncs_total is 0 and each page's own count is 0 after at least
 * two checkpoints each); and the room's recorded log verifies with `npm run replay -- --verify`.
 */
import { spawnSync } from 'node:child_process'
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join as joinPath } from 'node:path'
import { build } from 'esbuild'
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { type GoalState, WIN_SCORE } from '../../games/index.ts'
import { buildClient } from '../../scripts/build-client.mjs'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox, serveClient } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'
import type { MatchReport } from './game-match-page.ts'

const DIST = 'test-results/browser-game-match/dist'
const ROOM = 'goal-match'

let server: RunningServer
let browser: Browser
let code = ''
let replayDir = ''
const contexts: BrowserContext[] = []

beforeAll(async () => {
  await buildClient(DIST)
  replayDir = await mkdtemp(joinPath(tmpdir(), 'concord-game-match-'))
  server = await serveClient(DIST, { workers: 0, record: true, replayDir })
  const bundle = await build({
    entryPoints: [new URL('./game-match-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  code = bundle.outputFiles[0].text
  browser = await launchBrowser()
}, 180_000)

afterAll(async () => {
  for (const c of contexts) await c.close()
  await browser?.close()
  await server?.close()
})

const report = (page: Page): Promise<MatchReport> =>
  page.evaluate(() =>
    (window as unknown as { concordGameMatch: { report(): MatchReport } }).concordGameMatch.report(),
  )

async function join(mode: 'lockstep' | 'predict'): Promise<{ page: Page; errors: string[] }> {
  const { page, errors, context } = await openSandbox(
    browser,
    `${server.url}/?room=${ROOM}&game=goal&mode=${mode}`,
  )
  contexts.push(context)
  // Evaluated by the driver: the page's policy forbids inline scripts, not the driver's evaluation.
  await page.evaluate(code)
  await page.waitForFunction(() => {
    const r = (window as unknown as { concordGameMatch: { report(): MatchReport } }).concordGameMatch.report()
    return r.player !== 0 && r.team !== null
  })
  return { page, errors }
}

describe('a goal match between a lockstep page and a predicting page', () => {
  it(`red wins ${WIN_SCORE}-0; both pages see the server's score at every tick they simulate, with no desync; the log replays`, async () => {
    const lockstep = await join('lockstep')
    const room = server.rooms.get(ROOM)
    if (!room) throw new Error(`no room ${ROOM} on the server`)
    // The server room's score at every tick from now on.
    const scores = new Map<number, string>()
    const state = () => room.sim.gameState as GoalState
    const record = (tick: number) => scores.set(tick, JSON.stringify([state().score, state().phase]))
    record(room.sim.tick)
    room.sim.observers.push({
      command: () => {},
      join: () => {},
      leave: () => {},
      worldLoaded: () => {},
      ticked: record,
    })
    const predict = await join('predict')
    expect((await report(lockstep.page)).team).toBe('red')
    expect((await report(predict.page)).team).toBe('blue')
    expect(room.game.name).toBe('goal')

    await lockstep.page.evaluate(() =>
      (window as unknown as { concordGameMatch: { start(r: string): void } }).concordGameMatch.start(
        'striker',
      ),
    )
    await predict.page.evaluate(() =>
      (window as unknown as { concordGameMatch: { start(r: string): void } }).concordGameMatch.start('bench'),
    )
    await until(() => state().phase === 'over', 'the end of the match on the server', 240_000)
    expect(state()).toMatchObject({ winner: 'red', score: { red: WIN_SCORE, blue: 0 } })
    const serverTick = room.sim.tick
    console.log(`server: ${JSON.stringify(state().score)} at tick ${serverTick}`)

    for (const [label, { page }] of [
      ['lockstep', lockstep],
      ['predict', predict],
    ] as const) {
      await until(async () => {
        const r = await report(page)
        return r.tick >= serverTick && r.hashesChecked >= 2
      }, `the ${label} page at tick ${serverTick}`)
      const r = await report(page)
      // The page's score at every tick it was seen at, against the server room's at that tick.
      const history = (await page.evaluate(() =>
        (
          window as unknown as { concordGameMatch: { history(): Array<[number, string]> } }
        ).concordGameMatch.history(),
      )) as Array<[number, string]>
      const compared = history.filter(([tick]) => scores.has(tick))
      expect(
        compared.map(([tick, score]) => [tick, score]),
        `${label} page scores by tick`,
      ).toEqual(compared.map(([tick]) => [tick, scores.get(tick)]))
      const seen = new Set(compared.map(([, score]) => score))
      console.log(
        `${label} page: ${JSON.stringify(r)}; scores compared at ${compared.length} ticks: ${[...seen].join(' ')}`,
      )
      // The page saw the match go 0-0, 1-0, ... 5-0 and end.
      expect(seen.size).toBeGreaterThanOrEqual(WIN_SCORE + 1)
      expect(seen).toContain(JSON.stringify([{ red: WIN_SCORE, blue: 0 }, 'over']))
      expect([r.score, r.phase]).toEqual([{ red: WIN_SCORE, blue: 0 }, 'over'])
      expect([r.desyncs, r.resyncs]).toEqual([0, 0])
    }
    expect((await report(lockstep.page)).sent).toBeGreaterThan(0)
    expect((await report(predict.page)).sent).toBeGreaterThan(0)
    const metrics = await (await fetch(`${server.url}/metrics`)).text()
    expect(metrics).toMatch(/^concord_desyncs_total 0$/m)
    expect(lockstep.errors).toEqual([])
    expect(predict.errors).toEqual([])

    // The match's log, as recorded so far (flushed, not closed), replays with every hash matching.
    const recorder = server.recordings.recorders.get(ROOM)
    if (!recorder) throw new Error('the room is not recorded')
    await recorder.flush()
    const run = spawnSync(
      'npx',
      ['tsx', 'server/replay/replay-cli.ts', joinPath(replayDir, recorder.name), '--verify', '--json'],
      {
        encoding: 'utf8',
        timeout: 180_000,
      },
    )
    expect(run.status, run.stderr).toBe(0)
    const replay = JSON.parse(run.stdout) as { hashesChecked: number; divergence: unknown; lastTick: number }
    console.log(`replay: ${replay.hashesChecked} hashes checked to tick ${replay.lastTick}`)
    expect(replay.divergence).toBeNull()
    expect(replay.lastTick).toBeGreaterThanOrEqual(serverTick)
    expect(replay.hashesChecked).toBeGreaterThan(10)
  }, 400_000)
})
