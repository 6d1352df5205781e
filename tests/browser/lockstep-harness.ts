/*
 * The lockstep browser tests' shared harness, for any browser driver: the page bundle
 * (lockstep-page.ts, optionally with the engine's sin swapped for the host's Math.sin), starting it
 * in a page served by the test server, reading its report, and the long run both browsers must
 * pass: snapshot-mode bots acting in one room (spawns, grabs, drags, pins, ropes, unjoints,
 * deletes, a scene load halfway), a Node LockstepBot and the page stepping the same room, until
 * both are `ticks` past where they started; every hash checkpoint must match, with no desync.
 * Then the perturbed page: the same bundle with the engine's own sin replaced by the browser's
 * Math.sin; a bot spawns bodies at angles where the two differ (found in an unperturbed page of the
 * same browser), and the page must report the desync within one hash interval, be repaired by a
 * sync and be counted in the server's /metrics.
 * Chromium drives both through playwright-core (lockstep.test.ts), Firefox ESR through
 * puppeteer-core over WebDriver BiDi (lockstep-firefox.test.ts).
 */
import { readFile } from 'node:fs/promises'
import { build, type Plugin } from 'esbuild'
import { expect } from 'vitest'
import { BotClient } from '../../bots/bot-client.ts'
import { LockstepBot } from '../../bots/lockstep-bot.ts'
import type { RunningServer } from '../../server/server.ts'
import { ActiveBots } from '../support/lockstep-bots.ts'
import { until as waitUntil } from '../support/wait.ts'
import type { PageReport } from './lockstep-page.ts'

/** What the harness needs of a browser page: playwright-core's and puppeteer-core's both fit. */
export interface ScriptPage {
  goto(url: string): Promise<unknown>
  evaluate(expression: string): Promise<unknown>
}

/** Replaces the engine's own sin with the host's Math.sin. */
const mathSin: Plugin = {
  name: 'math-sin',
  setup(b) {
    b.onLoad({ filter: /engine[\\/]math\.ts$/ }, async (args) => {
      const source = await readFile(args.path, 'utf8')
      const patched = source.replace(
        'export function sin(x: number): number {',
        'export function sin(x: number): number {\n  return Math.sin(x)\n}\nexport function ownSin(x: number): number {',
      )
      if (patched === source) throw new Error('engine/math.ts no longer declares sin as expected')
      return { contents: patched, loader: 'ts' }
    })
  },
}

/** lockstep-page.ts bundled for a browser; `perturbed` swaps the engine's sin for Math.sin. */
export async function bundleLockstepPage(perturbed: boolean): Promise<string> {
  const result = await build({
    entryPoints: [new URL('./lockstep-page.ts', import.meta.url).pathname],
    bundle: true,
    platform: 'browser',
    format: 'iife',
    target: 'es2022',
    write: false,
    plugins: perturbed ? [mathSin] : [],
  })
  return result.outputFiles[0].text
}

/** Load the server's page, inject `code` and join `room` in lockstep mode as `name`. */
export async function startLockstepPage(
  page: ScriptPage,
  serverUrl: string,
  code: string,
  room: string,
  name: string,
): Promise<void> {
  await page.goto(`${serverUrl}/`)
  // Evaluated by the test driver, not added as an inline <script>: the server's page policy
  // forbids inline scripts (server/http/http-headers.ts), and the driver's evaluation is not a page script.
  await page.evaluate(code)
  await page.evaluate(`globalThis.concordLockstep.start(${JSON.stringify(room)}, ${JSON.stringify(name)})`)
}

/** The page runner's figures (lockstep-page.ts report()). */
export async function readReport(page: ScriptPage): Promise<PageReport> {
  return (await page.evaluate('globalThis.concordLockstep.report()')) as PageReport
}

/** Waits up to 10 minutes (the long runs), polling every 250 ms. */
export function until(what: string, condition: () => Promise<boolean>, timeoutMs = 600_000): Promise<void> {
  return waitUntil(condition, what, timeoutMs, 250)
}

/**
 * The long run: three acting bots, a Node lockstep client and `page` (already started in `room`
 * with startLockstepPage) until both have stepped `ticks` past their start, a scene load halfway.
 * Asserts every checkpoint matched in both with no desync, resync or refusal. `label` names the
 * browser in the printed line.
 */
export async function expectLongSync(
  server: RunningServer,
  page: ScriptPage,
  room: string,
  ticks: number,
  label: string,
): Promise<PageReport> {
  const bots = await ActiveBots.start(server.url, room, 3, 20, 7)
  const node = await LockstepBot.connect({ url: server.url, room, name: 'node' })
  await until(`the ${label} page to sync`, async () => (await readReport(page)).hashesChecked > 0)
  const start = Math.max(node.runner.sim?.tick ?? 0, (await readReport(page)).tick)
  let loaded = false
  await until(
    `${ticks} ticks in ${label} and Node`,
    async () => {
      const r = await readReport(page)
      const nodeTick = node.runner.sim?.tick ?? 0
      if (!loaded && nodeTick > start + ticks / 2) {
        bots.command(0, { k: 'scene', name: 'wrecking-ball' })
        loaded = true
      }
      if (r.desyncs > 0 || node.runner.stats.desyncs > 0 || r.closed) return true
      return r.tick > start + ticks && nodeTick > start + ticks
    },
    900_000,
  )
  const r = await readReport(page)
  console.log(
    `lockstep ${ticks} ticks: ${label} ${r.hashesChecked} checkpoints, node ${node.runner.stats.hashesChecked}; ` +
      `room at tick ${server.host.summaries().find((x) => x.name === room)?.tick}, scene ${node.runner.sim?.scene}`,
  )
  expect(r.closed).toBe('')
  expect(r.desyncs, r.problem).toBe(0)
  expect(node.runner.stats.desyncs, node.runner.lastProblem).toBe(0)
  expect(r.resyncs + node.runner.stats.resyncs).toBe(0)
  expect(r.refused + node.runner.stats.refused).toBe(0)
  expect(r.hashesChecked).toBeGreaterThanOrEqual(Math.floor(ticks / 60) - 2)
  expect(node.runner.stats.hashesChecked).toBeGreaterThanOrEqual(Math.floor(ticks / 60) - 2)
  expect(r.verifiedTick).toBeGreaterThan(start + ticks - 60)
  expect(node.runner.sim?.scene).toBe('wrecking-ball')
  expect(await desyncsCounted(server)).toBe(0)
  await Promise.all([node.close(), bots.stop()])
  return r
}

/** A page the harness may open and close: `open` starts lockstep-page code in `room`. */
export type OpenPage = (code: string, room: string) => Promise<ScriptPage & { close(): Promise<void> }>

/**
 * The perturbed run: a page whose engine uses the browser's Math.sin joins `room`, bodies are
 * spawned at angles where that sin differs from the engine's; asserts the desync is reported within
 * one hash interval (60 ticks, plus 30 for the spawns to land in the stream), repaired by a sync,
 * followed by a verified checkpoint, and counted in /metrics. Returns the angles used.
 */
export async function expectSinPerturbationCaught(
  server: RunningServer,
  open: OpenPage,
  room: string,
): Promise<number[]> {
  const plain = await open(await bundleLockstepPage(false), `${room}-probe`)
  const angles = (await plain.evaluate('globalThis.concordLockstep.anglesWhereSinDiffers()')) as number[]
  await plain.close()
  expect(angles.length, 'angles where Math.sin differs from the engine sin').toBeGreaterThan(0)
  const page = await open(await bundleLockstepPage(true), room)
  await until(
    'the perturbed page to verify a checkpoint',
    async () => (await readReport(page)).hashesChecked >= 1,
  )
  const before = await desyncsCounted(server)
  const spawner = await BotClient.connect({ url: server.url, room, name: 'spawner' })
  // The room's tick when the spawner joined (its welcome): the spawns land at or after it.
  const spawnTick = spawner.mirror.tick
  for (const angle of angles.slice(0, 5)) {
    spawner.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.2 }, x: angle * 3, y: 5, angle })
  }
  await until('the desync and the repair', async () => {
    const r = await readReport(page)
    return r.desyncs >= 1 && r.resyncs >= 1 && r.state === 'running'
  })
  const r = await readReport(page)
  const detectedAt = Number(r.problem.match(/tick (\d+)/)?.[1])
  expect(detectedAt - spawnTick).toBeLessThanOrEqual(60 + 30)
  await until(
    'a verified checkpoint after the repair',
    async () => (await readReport(page)).verifiedTick > detectedAt,
  )
  // Rooms on workers report their metrics once a second: wait for the count to arrive.
  await until('the desync counted in /metrics', async () => (await desyncsCounted(server)) > before)
  await page.close()
  await spawner.close()
  return angles
}

/** concord_desyncs_total from /metrics, summed over every series (the main thread's and each worker's). */
export async function desyncsCounted(server: RunningServer): Promise<number> {
  const text = await fetch(`${server.url}/metrics`).then((res) => res.text())
  let total = 0
  for (const line of text.split('\n')) {
    if (/^concord_desyncs_total(\{[^}]*\})? /.test(line)) total += Number(line.split(' ').pop())
  }
  return total
}
