/*
 * The page follows `moved` (PROTOCOL.md: "the client reconnects there"; README, Several servers):
 * two servers sharing a room directory in a real redis-server, each serving the built client.
 * Server A holds room `hall` (a player joined it there); a Chromium page opened at server B's
 * address for `hall` is answered with `moved` and close 4006, joins at A, and plays there: A's
 * room has both players, B opened no copy, and the page sees a box spawned in A's room.
 */
import { mkdir } from 'node:fs/promises'
import type { Browser } from 'playwright-core'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { buildClient } from '../../scripts/build-client.mjs'
import { connect } from '../../sdk/index.ts'
import type { RunningServer } from '../../server/server.ts'
import { launchBrowser } from '../support/chromium.ts'
import { serveClient } from '../support/client-harness.ts'
import { startRedis, type TestRedis } from '../support/redis-server.ts'
import { until } from '../support/wait.ts'

const DIST = 'test-results/browser-moved/dist'
let browser: Browser
let redis: TestRedis
let a: RunningServer
let b: RunningServer

beforeAll(async () => {
  await mkdir(DIST, { recursive: true })
  await buildClient(DIST)
  redis = await startRedis()
  a = await serveClient(DIST, { redisUrl: redis.url })
  b = await serveClient(DIST, { redisUrl: redis.url })
  browser = await launchBrowser()
}, 120_000)

afterAll(async () => {
  await browser?.close()
  await a?.close()
  await b?.close()
  await redis?.stop()
})

const playersIn = (s: RunningServer, room: string): number | undefined =>
  s.host.summaries().find((r) => r.name === room)?.players

describe('a page asking the wrong server for a room', () => {
  it('follows moved to the server holding it and plays there', async () => {
    const holder = await connect({
      url: `http://127.0.0.1:${a.port}`,
      room: 'hall',
      name: 'holder',
      WebSocket: WebSocket as never,
    })
    expect(playersIn(a, 'hall')).toBe(1)

    const page = await browser.newPage()
    const problems: string[] = []
    page.on('pageerror', (e) => problems.push(e.message))
    await page.goto(`http://127.0.0.1:${b.port}/?room=hall&name=guest`)
    await page.waitForFunction(() => window.concord?.sandbox.status().state === 'connected')
    await until(() => playersIn(a, 'hall') === 2, "the page in A's room")
    expect(playersIn(b, 'hall')).toBeUndefined()

    // The page is in A's room: a box the holder spawns there shows in the page.
    const before = await page.evaluate(() => window.concord?.sandbox.bodies().length ?? 0)
    holder.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 8 })
    await page.waitForFunction((n) => (window.concord?.sandbox.bodies().length ?? 0) > n, before)
    expect(problems).toEqual([])
    await page.close()
    await holder.close()
  })
})
