/*
 * Client benchmark (numbers, not a test): the gzipped size of the browser bundle (engine, protocol
 * and client together), and frame times with 1,000 bodies in headless Chromium. The page runs in
 * offline mode (no server, so the numbers are the page's own), with the 300-body pile scene plus
 * 700 spawned shapes. Two runs of 10 s each, timed by requestAnimationFrame deltas and by the
 * renderer's draw call alone:
 *   render:  the world paused, so a frame is interpolation-free drawing of 1,000 bodies
 *   running: the engine stepping 1,000 bodies in the page as well (offline mode's real load)
 * A baseline run of the empty scene first shows what the machine gives any page at that moment.
 * Then motion smoothness (client-motion.ts): the pile scene with shapes raining on it, offline
 * (the engine in the page) and online (a real server on 127.0.0.1 with its default per-client
 * bandwidth budget, so bodies are left out of snapshots and the page must fill the gaps).
 * Run: npx tsx bench/client-bench.ts [--seconds 10] [--motion-only]; saves bench/results/client.json.
 */
import { readFile } from 'node:fs/promises'
import { createServer } from 'node:http'
import type { AddressInfo } from 'node:net'
import type { Page } from 'playwright-core'
import { buildClient } from '../scripts/build-client.mjs'
import { loadConfig, startServer } from '../server/index.ts'
import { launchBrowser } from '../tests/support/chromium.ts'
import { measureMotion } from './client-motion.ts'
import { machineInfo, saveResults, summarize } from './stats.ts'

const OUT = 'test-results/client-bench-dist'
const argSeconds = process.argv.indexOf('--seconds')
const SECONDS = argSeconds > 0 ? Number(process.argv[argSeconds + 1]) : 10
if (!(SECONDS > 0) || !Number.isFinite(SECONDS)) {
  throw new Error(
    `--seconds takes a number of seconds above 0, got ${JSON.stringify(process.argv[argSeconds + 1])}`,
  )
}
const MOTION_ONLY = process.argv.includes('--motion-only')

/*
 * The in-page measurement, as source text: functions passed to page.evaluate from a tsx-compiled
 * file would carry esbuild's __name helper, which the page does not have.
 */
const MEASURE = `async (ms) => {
  const app = window.concord
  const draws = []
  const original = app.renderer.draw.bind(app.renderer)
  app.renderer.draw = (frame) => {
    const t = performance.now()
    original(frame)
    draws.push(performance.now() - t)
  }
  const frames = []
  await new Promise((resolve) => {
    let last = -1
    const start = performance.now()
    const tick = (now) => {
      if (last >= 0) frames.push(now - last)
      last = now
      if (now - start < ms) requestAnimationFrame(tick)
      else resolve()
    }
    requestAnimationFrame(tick)
  })
  app.renderer.draw = original
  return { frames, draws, bodies: app.sandbox.bodies().length, awake: app.sandbox.stats().awake }
}`

/** Measure rAF frame deltas and draw() times for `seconds` on the page. */
async function measure(page: Page, seconds: number) {
  const result = (await page.evaluate(`(${MEASURE})(${seconds * 1000})`)) as {
    frames: number[]
    draws: number[]
    bodies: number
    awake: number
  }
  const round = (v: number): number => Math.round(v * 1000) / 1000
  const brief = (samples: number[]) => {
    const s = summarize(samples)
    return { n: s.n, p50: round(s.median), p95: round(s.p95), max: round(s.max), mean: round(s.mean) }
  }
  return {
    bodies: result.bodies,
    awakeAtEnd: result.awake,
    fps: Math.round((result.frames.length / seconds) * 10) / 10,
    frameMs: brief(result.frames),
    drawMs: brief(result.draws),
  }
}

/** Frame and draw times: the empty scene, then 1,000 bodies running and paused (offline). */
async function measureFrames(page: Page, port: number) {
  // Baseline: the same page with only the ground, i.e. what this machine's headless Chromium gives
  // any page (the machine is shared; compare the 1,000-body numbers with this, not with 60).
  await page.goto(`http://127.0.0.1:${port}/?offline&scene=empty`)
  await page.waitForFunction('window.concord?.sandbox.bodies().length > 0')
  const baseline = await measure(page, SECONDS / 2)
  await page.goto(`http://127.0.0.1:${port}/?offline&scene=pile`)
  await page.waitForFunction('window.concord?.sandbox.bodies().length > 300')
  await page.evaluate(`(() => {
    const s = window.concord.sandbox
    for (let i = 0; i < 700; i++) {
      const x = -24 + (i % 35) * 1.4
      const y = 30 + Math.floor(i / 35) * 1.4
      const shape = i % 2 ? { type: 'circle', radius: 0.4 } : { type: 'box', hw: 0.4, hh: 0.4 }
      s.send({ k: 'spawn', shape, x, y })
    }
  })()`)
  await page.waitForFunction('window.concord.sandbox.bodies().length >= 1000')
  // Let the shapes land, then frame them all.
  await page.waitForTimeout(6000)
  await page.evaluate(`window.concord.act('fit')`)
  const running = await measure(page, SECONDS)
  await page.evaluate(`window.concord.sandbox.send({ k: 'pause', paused: true })`)
  const render = await measure(page, SECONDS)
  await page.screenshot({ path: 'test-results/client-bench-1000.png' })
  return { baselineEmptyScene: baseline, render1000: render, running1000: running }
}

async function main(): Promise<void> {
  const size = await buildClient(OUT)
  console.log(
    `bundle: app.js ${size.bytes} B, ${size.gzipBytes} B gzipped; index.html ${size.htmlGzipBytes} B gzipped`,
  )
  // A static file server for the built page (offline mode needs no game server).
  const http = createServer(async (req, res) => {
    const path = new URL(req.url ?? '/', 'http://x').pathname
    const file = path === '/' ? 'index.html' : path.slice(1)
    try {
      const body = await readFile(`${OUT}/${file}`)
      res.writeHead(200, { 'content-type': file.endsWith('.js') ? 'text/javascript' : 'text/html' })
      res.end(body)
    } catch {
      res.writeHead(404).end()
    }
  })
  await new Promise<void>((r) => http.listen(0, '127.0.0.1', r))
  const port = (http.address() as AddressInfo).port
  const browser = await launchBrowser()
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1 })
  const frames = MOTION_ONLY ? null : await measureFrames(page, port)

  // Motion: offline first, then online through a real server serving the same build.
  await page.goto(`http://127.0.0.1:${port}/?offline&scene=pile`)
  await page.waitForFunction('window.concord?.sandbox.bodies().length > 300')
  const motionOffline = await measureMotion(page, SECONDS)
  const game = await startServer(loadConfig([], {}, { port: 0, staticDir: OUT, logLevel: 'silent' }), {
    processMetrics: false,
  })
  await page.goto(`http://127.0.0.1:${game.port}/?room=bench-motion`)
  await page.waitForFunction('window.concord?.sandbox.status().state === "connected"')
  await page.evaluate(`window.concord.sandbox.send({ k: 'scene', name: 'pile' })`)
  await page.waitForFunction(
    `window.concord.sandbox.scene() === 'pile' && window.concord.sandbox.bodies().length > 300`,
  )
  const motionOnline = await measureMotion(page, SECONDS)
  await page.screenshot({ path: 'test-results/client-bench-motion-online.png' })
  await browser.close()
  http.close()
  await game.close()

  const result = {
    machine: machineInfo(),
    browser: 'Debian chromium, headless, --disable-gpu (software canvas), 1280x800 at 1x',
    bundle: {
      appJsBytes: size.bytes,
      appJsGzipBytes: size.gzipBytes,
      indexHtmlGzipBytes: size.htmlGzipBytes,
    },
    ...frames,
    motion: {
      scene: 'pile (300) with 30 shapes a second raining from 12-20 m',
      offline: motionOffline,
      online: motionOnline,
    },
  }
  console.log(JSON.stringify(result, null, 2))
  saveResults('bench/results/client.json', result)
}

await main()
