/*
 * A long recorded session replayed in a fresh process and in Chromium. A real server on 127.0.0.1
 * records a room where three bots play for more than 5,000 ticks (spawns, grabs and drags, pins,
 * ropes, unjoints, deletes, and pins at bodies' positions) with a scene load and a reset in the middle; the room's clock is driven
 * faster than real time by the test (lockstep-bots.ts driveClock). Then:
 * - `npm run replay -- FILE --verify` (the replay CLI in its own Node process) exits 0: every
 *   recorded hash and keyframe matched;
 * - the same log replayed in Chromium by the page's bundle of the same headless replay
 *   (replay-check-page.ts) checks the same number of hashes without a divergence and gives the
 *   CLI's world hash at every 60th tick and at the end.
 */
import { spawnSync } from 'node:child_process'
import { mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { build } from 'esbuild'
import type { Browser } from 'playwright-core'
import { afterAll, describe, expect, it } from 'vitest'
import { listLogNames } from '../../server/replay/replay-files.ts'
import type { RunningServer } from '../../server/server.ts'
import type { ReplayReport } from '../../shared/replay/replay-headless.ts'
import { ReplayLogReader } from '../../shared/replay/replay-log-reader.ts'
import { launchBrowser } from '../support/chromium.ts'
import { ActiveBots, driveClock } from '../support/lockstep-bots.ts'
import { inProcessRooms, startTestServer } from '../support/test-server.ts'
import type { ReplayCheck } from './replay-check-page.ts'

const ROOM = 'long'
const TICKS = 5_100

let browser: Browser | undefined
let server: RunningServer | undefined
let stopClock: (() => void) | undefined
afterAll(async () => {
  stopClock?.()
  await browser?.close()
  await server?.close()
})

/** Record the session; returns the log's bytes. */
async function record(dir: string): Promise<Uint8Array> {
  // Rooms on the main thread: this file drives the main tick clock by hand and reads the room's tick.
  server = await startTestServer({
    ...inProcessRooms,
    record: true,
    replayDir: dir,
    defaultScene: 'tower',
    heartbeatMs: 60_000,
  })
  stopClock = driveClock(server, 300)
  const bots = await ActiveBots.start(server.url, ROOM, 3, 20, 7)
  const room = server.rooms.get(ROOM)!
  const until = (tick: number): Promise<void> =>
    bots.bots[0].bot.waitFor(() => room.tick >= tick, `room tick ${tick}`)
  // Pins and ropes anchored at bodies' own positions (the bots' script anchors them at random
  // points, so most of its joints are refused).
  const joiner = bots.bots[0].bot
  const pinEvery = async (from: number, to: number): Promise<void> => {
    for (let t = from; t < to; t += 200) {
      await until(t)
      const [a, b] = [...joiner.mirror.bodies.values()].filter((x) => x.kind === 2).slice(-2)
      if (a && b && (t / 200) % 2 === 0) bots.command(0, { k: 'pin', a: 0, b: b.id, x: b.x, y: b.y })
      else if (a && b) bots.command(0, { k: 'rope', a: a.id, b: b.id, ax: a.x, ay: a.y, bx: b.x, by: b.y })
    }
  }
  await pinEvery(200, 1_700)
  bots.command(1, { k: 'scene', name: 'joints' })
  await pinEvery(1_800, 3_400)
  bots.command(2, { k: 'reset' })
  await pinEvery(3_500, TICKS)
  await until(TICKS)
  await bots.stop()
  stopClock()
  stopClock = undefined
  await server.close()
  server = undefined
  const name = (await listLogNames(dir)).find((n) => n.startsWith(`${ROOM}-`))!
  return new Uint8Array(await readFile(join(dir, name)))
}

describe('a 5,000-tick recorded session', () => {
  it('replays in a fresh process with every hash matching, and in Chromium with the same hashes as Node', {
    timeout: 300_000,
  }, async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-long-'))
    const bytes = await record(dir)

    // What the log holds (read with the reader, not the replay).
    const reader = new ReplayLogReader()
    const records = reader.push(bytes)
    expect(reader.finish()).toMatchObject({ state: 'end', closed: true })
    const kinds = new Set(records.flatMap((r) => (r.type === 'command' ? [r.cmd.k] : [])))
    for (const k of ['spawn', 'grab', 'move', 'release', 'pin', 'rope', 'delete', 'scene', 'reset'])
      expect(kinds, `a ${k} command`).toContain(k)
    // The scene load started a new world: later keyframes hold the joints scene.
    expect(records.some((r) => r.type === 'keyframe' && r.state.scene === 'joints')).toBe(true)
    const recordedHashes = records.filter((r) => r.type === 'hash')
    expect(records.at(-1)!.tick).toBeGreaterThanOrEqual(TICKS)

    // The replay CLI in its own process.
    const file = join(dir, 'session.cclog')
    await writeFile(file, bytes)
    const cli = spawnSync(
      process.execPath,
      ['--import', 'tsx', 'server/replay/replay-cli.ts', file, '--verify', '--json', '--hash-every', '60'],
      { encoding: 'utf8', maxBuffer: 64 * 1024 * 1024 },
    )
    expect(cli.stderr).toBe('')
    expect(cli.status).toBe(0)
    const node = JSON.parse(cli.stdout) as ReplayReport
    expect(node.divergence).toBeNull()
    expect(node.hashesChecked).toBe(recordedHashes.length)
    expect(node.hashesChecked).toBeGreaterThanOrEqual(Math.floor(TICKS / 60))
    expect(node.keyframesChecked).toBeGreaterThanOrEqual(Math.floor(TICKS / 600) - 1)
    // The room opened at a tick below 60 (room-manager.ts spreads rooms' checkpoints) and ran to TICKS.
    expect(node.firstTick).toBeLessThan(60)
    expect(node.ticks).toBeGreaterThanOrEqual(TICKS - node.firstTick)
    // The CLI's hash at each 60th tick is the recorded one (the recorder writes one every 60 ticks).
    const byTick = new Map(node.hashes.map((h) => [h.tick, h.hash]))
    let compared = 0
    for (const h of recordedHashes)
      if (
        h.tick % 60 === 0 &&
        byTick.has(h.tick) &&
        !records.some((r) => r.tick === h.tick && r.type === 'world')
      ) {
        expect(byTick.get(h.tick), `tick ${h.tick}`).toBe(h.hash)
        compared++
      }
    expect(compared).toBeGreaterThan(TICKS / 60 - 10)

    // The same log in Chromium.
    const bundle = await build({
      entryPoints: [new URL('./replay-check-page.ts', import.meta.url).pathname],
      bundle: true,
      platform: 'browser',
      format: 'iife',
      target: 'es2022',
      write: false,
    })
    browser = await launchBrowser()
    const page = await browser.newPage()
    const errors: string[] = []
    page.on('pageerror', (e) => errors.push(e.message))
    await page.setContent('<!doctype html><html><head><title>replay check</title></head><body></body></html>')
    await page.addScriptTag({ content: bundle.outputFiles[0].text })
    const inPage = await page.evaluate(
      (base64) =>
        (globalThis as unknown as { concordReplayCheck: ReplayCheck }).concordReplayCheck.replayBase64(
          base64,
          60,
        ),
      Buffer.from(bytes).toString('base64'),
    )
    expect(errors).toEqual([])
    expect(inPage.divergence).toBeNull()
    expect(inPage.hashesChecked).toBe(node.hashesChecked)
    expect(inPage.keyframesChecked).toBe(node.keyframesChecked)
    expect(inPage.commands).toBe(node.commands)
    expect(inPage.lastTick).toBe(node.lastTick)
    expect(inPage.hashes.length).toBe(node.hashes.length)
    expect(inPage.hashes).toEqual(node.hashes)
    expect(inPage.finalHash).toBe(node.finalHash)
    console.log(
      `${node.ticks} ticks, ${node.commands} commands, ${node.hashesChecked} hashes and ${node.keyframesChecked} keyframes checked, ${bytes.length} bytes; Chromium equal at ${inPage.hashes.length} ticks`,
    )
  })
})
