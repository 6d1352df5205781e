/*
 * Shared parts of the game match tests (game-match.test.ts for goal, tower-match.test.ts for
 * tower): a real server on 127.0.0.1 serving the client bundle (built into a folder of the test's
 * own), rooms on the main thread so the test can watch the room's own simulation, recording on;
 * pages joined with `?room=&game=&mode=` and driven by game-match-page.ts; the comparison of each
 * page's game summary at every tick it was seen at against the server room's at that tick; and
 * the recorded log checked with `npm run replay -- FILE --verify`.
 */
import { spawnSync } from 'node:child_process'
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { build } from 'esbuild'
import type { Browser, BrowserContext, Page } from 'playwright-core'
import { expect } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import type { Room } from '../../server/rooms/room.ts'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { openSandbox, serveClient } from '../support/client-harness.ts'
import { until } from '../support/wait.ts'
import { type MatchReport, type MatchRole, matchSummary } from './game-match-page.ts'

/** A started match setup: the server, the browser, the page script and the replay folder. */
export interface MatchSetup {
  server: RunningServer
  browser: Browser
  code: string
  replayDir: string
  contexts: BrowserContext[]
}

/** Build the client into `dist`, start the server and the browser, bundle the page script. */
export async function startMatchSetup(dist: string): Promise<MatchSetup> {
  await buildClient(dist)
  const replayDir = await mkdtemp(join(tmpdir(), 'concord-game-match-'))
  // A script that misjudges (a kick out of reach) has commands refused by the game, each a strike.
  const server = await serveClient(dist, { workers: 0, record: true, replayDir, maxRejects: 10_000 })
  const bundle = await build({
    entryPoints: [new URL('./game-match-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
  })
  return { server, browser: await launchBrowser(), code: bundle.outputFiles[0].text, replayDir, contexts: [] }
}

/** Close the pages, the browser and the server. */
export async function closeMatchSetup(setup: MatchSetup | undefined): Promise<void> {
  for (const c of setup?.contexts ?? []) await c.close()
  await setup?.browser.close()
  await setup?.server.close()
}

/** A page's report (game-match-page.ts). */
export function report(page: Page): Promise<MatchReport> {
  return page.evaluate(() =>
    (window as unknown as { concordGameMatch: { report(): MatchReport } }).concordGameMatch.report(),
  )
}

/** A page that joined `room` running `game` in `mode`, with the match script loaded (not started). */
export async function joinMatch(
  setup: MatchSetup,
  room: string,
  game: string,
  mode: 'lockstep' | 'predict',
): Promise<{ page: Page; errors: string[] }> {
  const url = `${setup.server.url}/?room=${room}&game=${game}&mode=${mode}`
  const { page, errors, context } = await openSandbox(setup.browser, url)
  setup.contexts.push(context)
  // Evaluated by the driver: the page's policy forbids inline scripts, not the driver's evaluation.
  await page.evaluate(setup.code)
  await page.waitForFunction(() => {
    const r = (window as unknown as { concordGameMatch: { report(): MatchReport } }).concordGameMatch.report()
    return r.player !== 0 && r.joined
  })
  return { page, errors }
}

/** Start a page's script in `role`. */
export function startScript(page: Page, role: MatchRole): Promise<void> {
  return page.evaluate(
    (r) => (window as unknown as { concordGameMatch: { start(r: string): void } }).concordGameMatch.start(r),
    role,
  )
}

/** The server room's game summary at every tick from now on. */
export function watchRoom(room: Room): Map<number, string> {
  const summaries = new Map<number, string>()
  const record = (tick: number) => summaries.set(tick, matchSummary(room.sim))
  record(room.sim.tick)
  room.sim.observers.push({
    command: () => {},
    join: () => {},
    leave: () => {},
    worldLoaded: () => {},
    ticked: record,
  })
  return summaries
}

/**
 * Wait until the page's confirmed simulation reaches `serverTick` with two checkpoints checked,
 * then compare its summary at every tick it was seen at with the server's; returns the summaries
 * seen and the page's last report. No desync or resync is allowed.
 */
export async function expectPageFollowed(
  label: string,
  page: Page,
  summaries: Map<number, string>,
  serverTick: number,
): Promise<{ seen: Set<string>; last: MatchReport }> {
  await until(async () => {
    const r = await report(page)
    return r.tick >= serverTick && r.hashesChecked >= 2
  }, `the ${label} page at tick ${serverTick}`)
  const last = await report(page)
  const history = (await page.evaluate(() =>
    (
      window as unknown as { concordGameMatch: { history(): Array<[number, string]> } }
    ).concordGameMatch.history(),
  )) as Array<[number, string]>
  const compared = history.filter(([tick]) => summaries.has(tick))
  expect(compared, `${label} page summaries by tick`).toEqual(
    compared.map(([tick]) => [tick, summaries.get(tick)]),
  )
  const seen = new Set(compared.map(([, s]) => s))
  console.log(
    `${label} page: tick ${last.tick}, ${last.hashesChecked} checkpoints, ${last.sent} commands sent; ` +
      `${compared.length} ticks compared, ${seen.size} distinct summaries`,
  )
  expect([last.desyncs, last.resyncs]).toEqual([0, 0])
  expect(last.sent).toBeGreaterThan(0)
  return { seen, last }
}

/** No desync counted by the server, and the room's log so far verifies to at least `serverTick`. */
export async function expectServerClean(setup: MatchSetup, room: string, serverTick: number): Promise<void> {
  const metrics = await (await fetch(`${setup.server.url}/metrics`)).text()
  expect(metrics).toMatch(/^concord_desyncs_total 0$/m)
  const recorder = setup.server.recordings.recorders.get(room)
  if (!recorder) throw new Error(`room ${room} is not recorded`)
  await recorder.flush()
  const run = spawnSync(
    'npx',
    ['tsx', 'server/replay/replay-cli.ts', join(setup.replayDir, recorder.name), '--verify', '--json'],
    { encoding: 'utf8', timeout: 180_000 },
  )
  expect(run.status, run.stderr).toBe(0)
  const replay = JSON.parse(run.stdout) as { hashesChecked: number; divergence: unknown; lastTick: number }
  console.log(`replay of ${room}: ${replay.hashesChecked} hashes checked to tick ${replay.lastTick}`)
  expect(replay.divergence).toBeNull()
  // After the round the room is idle: its log gets a record at each once-a-second hash checkpoint
  // (60 ticks), so the last record may be up to a second before the tick the test read.
  expect(replay.lastTick).toBeGreaterThanOrEqual(serverTick - 60)
  expect(replay.hashesChecked).toBeGreaterThan(10)
}
