/*
 * Shared setup for the client's browser tests: the client bundle built into a scratch folder, a
 * real server on 127.0.0.1 (port 0) serving it, one headless Debian Chromium, and page helpers
 * that read the page's state through the `window.concord` handle (main.ts) and act through real
 * mouse and touch input.
 */
import { readdirSync, rmSync } from 'node:fs'
import { mkdir } from 'node:fs/promises'
import type { Browser, BrowserContext, CDPSession, Page } from 'playwright-core'
import { afterAll, beforeAll } from 'vitest'
import { buildClient } from '../../scripts/build-client.mjs'
import { loadConfig, type ServerConfig } from '../../server/config/config.ts'
import { type RunningServer, startServer } from '../../server/server.ts'
import { launchBrowser } from './chromium.ts'

/** Where screenshots go (git-ignored). */
export const ARTIFACTS = 'test-results/browser-client'
/**
 * Where startClientServer builds the client: one folder per test process, since test files run
 * in parallel (two at once on two cores) and must not rebuild each other's served files.
 */
export const CLIENT_DIST = `${ARTIFACTS}/dist-${process.pid}`

/** Build the client and start a server that serves it (on `port`, or any free port). */
export async function startClientServer(port = 0): Promise<RunningServer> {
  await mkdir(ARTIFACTS, { recursive: true })
  if (port === 0) {
    removeStaleBuilds()
    await buildClient(CLIENT_DIST)
  }
  return serveClient(CLIENT_DIST, { port })
}

/** What useClientPages hands a test file: the server serving the client, Chromium, the page address. */
export interface ClientPages {
  server: RunningServer
  browser: Browser
  base: string
}

/**
 * A test file's server and browser: before its tests, build and serve the client
 * (startClientServer) and launch Chromium, and hand both to `use`; after its tests, close them.
 */
export function useClientPages(use: (pages: ClientPages) => void): void {
  let pages: ClientPages | undefined
  beforeAll(async () => {
    const [server, browser] = await Promise.all([startClientServer(), launchBrowser()])
    pages = { server, browser, base: `http://127.0.0.1:${server.port}` }
    use(pages)
  })
  afterAll(async () => {
    await pages?.browser.close()
    await pages?.server.close()
  })
}

/** Remove the client builds of test processes that have ended (test workers are killed, not exited). */
function removeStaleBuilds(): void {
  for (const name of readdirSync(ARTIFACTS)) {
    const pid = /^dist-(\d+)$/.exec(name)?.[1]
    if (pid === undefined || Number(pid) === process.pid) continue
    try {
      process.kill(Number(pid), 0)
    } catch {
      rmSync(`${ARTIFACTS}/${name}`, { recursive: true, force: true })
    }
  }
}

/**
 * A server on 127.0.0.1 (any free port) serving the client already built in `dist`, with
 * `settings` over these. No recording unless asked: a test must not leave files in ./replays.
 * Test files that build the client in parallel each use a `dist` of their own. New rooms open on
 * the pyramid, named here rather than left to the server's default (the playground since issue
 * 31), because the browser tests click its boxes; tests/browser/default-scene.test.ts checks the
 * default itself.
 */
export function serveClient(dist: string, settings: Partial<ServerConfig> = {}): Promise<RunningServer> {
  const config = loadConfig(
    [],
    {},
    {
      port: 0,
      host: '127.0.0.1',
      staticDir: dist,
      logLevel: 'silent',
      heartbeatMs: 60_000,
      record: false,
      // A closed server closes its rooms' logs (as tests/support/test-server.ts): a test that
      // wants a planned restart's open logs asks for keepRooms.
      keepRooms: false,
      defaultScene: 'pyramid',
      ...settings,
    },
  )
  return startServer(config, { processMetrics: false })
}

/** A body's snapshot pose in an online page's mirror, with the server tick it is from. */
export type SnapshotPose = { x: number; y: number; angle: number; tick: number; awake: boolean }
/** The online sandbox's mirror of the room (snapshot mode), which the Sandbox interface does not list. */
type Mirrored = { mirror: { bodies: Map<number, SnapshotPose> } }

/** A body's snapshot pose and the server tick it is from (the page's mirror of the room). */
export function snapshotOf(page: Page, id: number): Promise<SnapshotPose> {
  return page.evaluate((bodyId) => {
    const b = (window.concord.sandbox as unknown as Mirrored).mirror.bodies.get(bodyId)!
    return { x: b.x, y: b.y, angle: b.angle, tick: b.tick, awake: b.awake }
  }, id)
}

/** Wait until the page has a snapshot of body `id` newer than server tick `tick`, and return it. */
export async function snapshotAfter(page: Page, id: number, tick: number): Promise<SnapshotPose> {
  await page.waitForFunction(
    ([bodyId, t]) => (window.concord.sandbox as unknown as Mirrored).mirror.bodies.get(bodyId)!.tick > t,
    [id, tick] as const,
  )
  return snapshotOf(page, id)
}

/** Pause or resume the room from the page, and wait until the page shows it. */
export async function setPaused(page: Page, paused: boolean): Promise<void> {
  await page.evaluate((p) => window.concord.sandbox.send({ k: 'pause', paused: p }), paused)
  await page.waitForFunction((p) => window.concord.sandbox.paused() === p, paused)
}

/** Click at a world point with the mouse. */
export async function clickWorld(page: Page, x: number, y: number): Promise<void> {
  const at = await screenOf(page, x, y)
  await page.mouse.click(at.x, at.y)
}

/** Console errors and page errors seen by a page. */
export function collectErrors(page: Page): string[] {
  const errors: string[] = []
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text())
  })
  page.on('pageerror', (e) => errors.push(e.message))
  return errors
}

/** Open a page in a new context and wait until it has joined (or, offline, drawn) the world. */
export async function openSandbox(
  browser: Browser,
  url: string,
  options: { touch?: boolean; pixelRatio?: number; size?: { width: number; height: number } } = {},
): Promise<{ context: BrowserContext; page: Page; errors: string[] }> {
  const context = await browser.newContext({
    viewport: options.size ?? { width: 1000, height: 700 },
    deviceScaleFactor: options.pixelRatio ?? 1,
    hasTouch: options.touch ?? false,
    isMobile: false,
  })
  // Waits are for conditions; on a machine at load 20 a page can take well over Playwright's
  // default 30 s to reach one, so every wait on these pages may take 90 s before it fails.
  context.setDefaultTimeout(90_000)
  const page = await context.newPage()
  const errors = collectErrors(page)
  await page.goto(url)
  await page.waitForFunction(() => {
    const c = window.concord
    return c && c.sandbox.bodies().length > 0 && c.fps.value > 0
  })
  return { context, page, errors }
}

/** Load a scene in the page's room and wait until the page shows it with its joints. */
export async function loadScene(page: Page, scene: string, joints: number): Promise<void> {
  await page.waitForFunction(
    ([name, count]) => {
      const s = window.concord.sandbox
      if (s.scene() === name && s.joints().length === count) return true
      // Scene loads are rate limited per room: ask again until the room takes it.
      if (s.scene() !== name) s.send({ k: 'scene', name })
      return false
    },
    [scene, joints] as const,
    { polling: 500, timeout: 90_000 },
  )
}

/** A body as the page draws it (pose in metres). */
export interface PageBody {
  id: number
  kind: number
  /** Its shapes (the first is the only one for the toolbar's spawns). */
  shapes: Array<{ type: string; hw?: number; radius?: number; v?: number[] }>
  /** CSS colour, or null. */
  color: string | null
  x: number
  y: number
  angle: number
}

/** The page's bodies this frame. */
export function bodies(page: Page): Promise<PageBody[]> {
  return page.evaluate(() =>
    window.concord.sandbox.bodies().map((b: PageBody) => ({
      id: b.id,
      kind: b.kind,
      shapes: b.shapes,
      color: b.color,
      x: b.x,
      y: b.y,
      angle: b.angle,
    })),
  )
}

/** A joint as the page draws it: id, kind, its bodies (a 0: the world), maker and whether it has a motor. */
export interface PageJoint {
  id: number
  kind: string
  a: number
  b: number
  owner: number
  motor: boolean
}

/** The page's joints this frame. */
export function pageJoints(page: Page): Promise<PageJoint[]> {
  return page.evaluate(() =>
    window.concord.sandbox.joints().map((j: { id: number; kind: string; spec: PageJoint }) => ({
      id: j.id,
      kind: j.kind,
      a: j.spec.a,
      b: j.spec.b,
      owner: j.spec.owner,
      motor: j.spec.motor,
    })),
  )
}

/** Set an Edit panel control's value and fire its change, as a person letting go of it does. */
export async function setEditControl(page: Page, key: string, value: string): Promise<void> {
  await page.evaluate(
    ([k, v]) => {
      const input = document.querySelector<HTMLInputElement>(`#edit-panel [data-edit="${k}"]`)!
      input.value = v
      input.dispatchEvent(new Event('input'))
      input.dispatchEvent(new Event('change'))
    },
    [key, value] as const,
  )
}

/** Viewport coordinates (CSS px) of a world point. */
export function screenOf(page: Page, x: number, y: number): Promise<{ x: number; y: number }> {
  return page.evaluate(
    ([wx, wy]) => {
      const app = window.concord
      const r = app.renderer.canvas.getBoundingClientRect()
      const p = app.camera.toScreen(wx, wy)
      return { x: p.x + r.left, y: p.y + r.top }
    },
    [x, y],
  )
}

/** Viewport coordinates of a body's centre. */
export async function screenOfBody(page: Page, id: number): Promise<{ x: number; y: number }> {
  const b = (await bodies(page)).find((v) => v.id === id)
  if (!b) throw new Error(`body ${id} is not on the page`)
  return screenOf(page, b.x, b.y)
}

/**
 * With the grab tool picked, press on body `id` until the page shows it grabbed, and leave the
 * button down: on a loaded machine the page can lag behind the position read here, and a press
 * that misses grabs nothing, so nothing would move. Throws after `attempts` presses.
 */
export async function pressUntilGrabbed(
  page: Page,
  id: number,
  attempts = 5,
): Promise<{ x: number; y: number }> {
  for (let attempt = 1; ; attempt++) {
    const at = await screenOfBody(page, id)
    await page.mouse.move(at.x, at.y)
    await page.mouse.down()
    const grabbed = await page
      .waitForFunction(
        (bodyId) =>
          window.concord.sandbox
            .bodies()
            .some((v: { id: number; grabColor: string | null }) => v.id === bodyId && v.grabColor !== null),
        id,
        { timeout: 15_000 },
      )
      .then(() => true)
      .catch(() => false)
    if (grabbed) return at
    await page.mouse.up()
    if (attempt === attempts)
      throw new Error(`${attempts} presses on body ${id} at ${at.x}, ${at.y} did not grab it`)
  }
}

/**
 * Open the Debug layer row: click Debug until the row shows. In a fresh-clone .ci/run (Nov 24,
 * 10:00) one click on a loaded machine left the row hidden for 90 s; a click the page missed is
 * clicked again, a click it took is never repeated (Debug toggles the row). Throws after `attempts`.
 */
export async function openLayerRow(page: Page, attempts = 5): Promise<void> {
  for (let attempt = 1; attempt <= attempts; attempt++) {
    await page.click('#layers')
    const open = await page
      .waitForFunction(() => document.getElementById('layers-panel')?.hidden === false, undefined, {
        timeout: 15_000,
      })
      .then(() => true)
      .catch(() => false)
    if (open) return
  }
  throw new Error(`${attempts} clicks on Debug did not open the layer row`)
}

/**
 * Wait until a body satisfies a predicate (an expression of `b`), read once per animation frame.
 * The predicate runs here in Node, not in the page: the server's Content-Security-Policy
 * (server/http/http-headers.ts) forbids the page to compile strings.
 */
export async function waitForBody(
  page: Page,
  id: number,
  predicate: string,
  timeout = 15_000,
): Promise<void> {
  const test = new Function('b', `return ${predicate}`) as (b: unknown) => boolean
  const deadline = Date.now() + timeout
  for (;;) {
    const body = await page.evaluate(
      (bodyId) =>
        new Promise((resolve) =>
          requestAnimationFrame(() =>
            resolve(window.concord.sandbox.bodies().find((v: { id: number }) => v.id === bodyId) ?? null),
          ),
        ),
      id,
    )
    if (body !== null && test(body)) return
    if (Date.now() > deadline) throw new Error(`body ${id} did not satisfy ${predicate} within ${timeout} ms`)
  }
}

/** Select a tool by its toolbar button. */
export async function pickTool(page: Page, tool: string): Promise<void> {
  await page.click(`[data-tool="${tool}"]`)
}

/** Count canvas pixels (device px) that differ from the background colour. */
export function paintedPixels(page: Page): Promise<{ painted: number; total: number }> {
  return page.evaluate(() => {
    const canvas = window.concord.renderer.canvas as HTMLCanvasElement
    const ctx = canvas.getContext('2d')!
    const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data
    let painted = 0
    // Background #161a22 and grid #1f2530 are both dark blue-greys; bodies are brighter.
    for (let i = 0; i < data.length; i += 16) if (data[i] + data[i + 1] + data[i + 2] > 150) painted++
    return { painted, total: data.length / 16 }
  })
}

/** The colour (r, g, b) of one canvas pixel at a viewport point. */
export function pixelAt(page: Page, x: number, y: number): Promise<[number, number, number]> {
  return page.evaluate(
    ([sx, sy]) => {
      const canvas = window.concord.renderer.canvas as HTMLCanvasElement
      const r = canvas.getBoundingClientRect()
      const k = canvas.width / r.width
      const d = canvas.getContext('2d')!.getImageData((sx - r.left) * k, (sy - r.top) * k, 1, 1).data
      return [d[0], d[1], d[2]] as [number, number, number]
    },
    [x, y],
  )
}

/** One finger driven through the DevTools protocol (real touch events, as a touchscreen sends). */
export class Finger {
  private constructor(
    private readonly page: Page,
    private readonly cdp: CDPSession,
    private at: { x: number; y: number },
  ) {}

  /** Put a finger down at a viewport point. */
  static async down(page: Page, at: { x: number; y: number }): Promise<Finger> {
    const cdp = await page.context().newCDPSession(page)
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ ...at, id: 1 }] })
    return new Finger(page, cdp, at)
  }

  /** Slide to a point in `steps` moves, one per animation frame. */
  async moveTo(to: { x: number; y: number }, steps = 12): Promise<void> {
    const from = this.at
    for (let i = 1; i <= steps; i++) {
      const p = {
        x: from.x + ((to.x - from.x) * i) / steps,
        y: from.y + ((to.y - from.y) * i) / steps,
        id: 1,
      }
      await this.cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [p] })
      await this.page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r(null))))
    }
    this.at = to
  }

  /** Lift the finger. */
  async up(): Promise<void> {
    await this.cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] })
    await this.cdp.detach()
  }
}

/** Two fingers placed `from` px apart horizontally about `center`, spread to `to` px apart. */
export async function pinch(
  page: Page,
  center: { x: number; y: number },
  from: number,
  to: number,
): Promise<void> {
  const cdp = await page.context().newCDPSession(page)
  const points = (d: number) => [
    { x: center.x - d / 2, y: center.y, id: 1 },
    { x: center.x + d / 2, y: center.y, id: 2 },
  ]
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: points(from) })
  for (let i = 1; i <= 10; i++) {
    await cdp.send('Input.dispatchTouchEvent', {
      type: 'touchMove',
      touchPoints: points(from + ((to - from) * i) / 10),
    })
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r(null))))
  }
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] })
  await cdp.detach()
}

/** The lab panel's numbers: normal and friction of the first contact, and the net force (N). */
export async function labNumbers(
  page: Page,
): Promise<{ normal: number; friction: number; net: number; text: string }> {
  const text = (await page.textContent('#lab-text')) ?? ''
  const contact = /normal ([\d.]+) N\s+friction ([\d.]+) N/.exec(text)
  const net = /net force ([\d.]+) N/.exec(text)
  return {
    normal: contact ? Number(contact[1]) : Number.NaN,
    friction: contact ? Number(contact[2]) : Number.NaN,
    net: net ? Number(net[1]) : Number.NaN,
    text,
  }
}
