/*
 * The screenshots of docs/client.md and the README (docs/images/*.png), taken from the real page:
 * the client built as the browser tests build it, a real server on 127.0.0.1, Debian's Chromium
 * (tests/support/chromium.ts), and each tool driven with real mouse and keyboard input as the
 * browser tests drive it. One function per picture, named in SHOTS; a new tool adds one function
 * and one entry.
 *
 *   npx tsx scripts/screenshots.ts            every picture
 *   npx tsx scripts/screenshots.ts pin rope   only these
 *
 * Each picture is a crop of a 1280 x 800 page, at most 800 x 500 CSS px at a device pixel ratio
 * of 1, so a PNG stays well under 80 KB. The rooms run on the server's clock, so two runs do not
 * give identical pixels; what each picture shows is fixed by the input.
 */
import { mkdir, mkdtemp } from 'node:fs/promises'
import { join } from 'node:path'
import type { Browser, Page } from 'playwright-core'
import type { RunningServer } from '../server/server.ts'
import { launchBrowser } from '../tests/support/chromium.ts'
import {
  bodies,
  loadScene,
  openSandbox,
  pickTool,
  pressUntilGrabbed,
  screenOf,
  serveClient,
} from '../tests/support/client-harness.ts'
import { buildClient } from './build-client.mjs'

/** Where the pictures go. */
const OUT = 'docs/images'
const DIST = 'test-results/screenshots/dist'
const VIEW = { width: 1280, height: 800 }
/** A crop in CSS px of the 1280 x 800 page. */
type Clip = { x: number; y: number; width: number; height: number }
/** The usual crop: the top left of the page, with the toolbar's tools and the panels under it. */
const TOP_LEFT: Clip = { x: 0, y: 0, width: 760, height: 460 }
/** The crop with the lab panel (bottom left). */
const BOTTOM_LEFT: Clip = { x: 0, y: 300, width: 760, height: 500 }

type Pt = { x: number; y: number }

/** What every shot gets: the browser and the server's base URL. */
interface Stage {
  browser: Browser
  base: string
  /** A server that records rooms into `replayDir` (the replay picture). */
  recording: RunningServer
  replayDir: string
}

/** Open a page in room `room` (a fresh one per shot) on `scene`, paused or running. */
async function room(stage: Stage, name: string, scene: string, joints = 0, paused = false): Promise<Page> {
  const { page } = await openSandbox(stage.browser, `${stage.base}/?room=${name}&name=ada`, { size: VIEW })
  await showScene(page, scene, joints)
  await setPaused(page, paused)
  return page
}

/**
 * Load a scene in the page's room once and wait for it with its joints (loadScene of the tests
 * asks again every 500 ms, and the room's notice about its rate limit would be in the picture).
 */
async function showScene(page: Page, scene: string, joints: number): Promise<void> {
  const shown = (): Promise<unknown> =>
    page.waitForFunction(
      ([name, count]) =>
        window.concord.sandbox.scene() === name && window.concord.sandbox.joints().length === count,
      [scene, joints] as const,
      { timeout: 20_000 },
    )
  await page.evaluate((name) => window.concord.sandbox.send({ k: 'scene', name }), scene)
  await shown().catch(() => loadScene(page, scene, joints))
}

async function setPaused(page: Page, paused: boolean): Promise<void> {
  await page.evaluate((p) => window.concord.sandbox.send({ k: 'pause', paused: p }), paused)
  await page.waitForFunction((p) => window.concord.sandbox.paused() === p, paused)
}

/** Point the camera so world point `at` is drawn at `screen` (CSS px), `scale` px per metre. */
async function look(page: Page, at: Pt, scale: number, screen: Pt = { x: 380, y: 270 }): Promise<void> {
  await page.evaluate(
    ([a, s, k, view]) => {
      const c = window.concord.camera
      c.scale = k
      c.x = a.x + (view.width / 2 - s.x) / k
      c.y = a.y - (view.height / 2 - s.y) / k
    },
    [at, screen, scale, VIEW] as const,
  )
}

async function clickAt(page: Page, p: Pt): Promise<void> {
  const s = await screenOf(page, p.x, p.y)
  await page.mouse.click(s.x, s.y)
}

async function hover(page: Page, p: Pt): Promise<void> {
  const s = await screenOf(page, p.x, p.y)
  await page.mouse.move(s.x, s.y, { steps: 4 })
}

/** Press at the first point and move through the rest (world m), leaving the button down. */
async function press(page: Page, points: Pt[], steps = 4): Promise<void> {
  const screen = await Promise.all(points.map((p) => screenOf(page, p.x, p.y)))
  await page.mouse.move(screen[0].x, screen[0].y)
  await page.mouse.down()
  for (const p of screen.slice(1)) await page.mouse.move(p.x, p.y, { steps })
}

/** Press, move through `points` and release. */
async function drag(page: Page, points: Pt[], steps = 4): Promise<void> {
  await press(page, points, steps)
  await page.mouse.up()
}

/** Pick the Draw tool in one of its forms (W cycles outline, rect, circle, capsule). */
async function pickDrawForm(page: Page, form: string): Promise<void> {
  if ((await page.evaluate(() => window.concord.tools.tool)) !== 'draw') await pickTool(page, 'draw')
  for (let i = 0; i < 4 && (await page.evaluate(() => window.concord.tools.drawForm)) !== form; i++)
    await page.keyboard.press('w')
  if ((await page.evaluate(() => window.concord.tools.drawForm)) !== form)
    throw new Error(`no Draw form ${form}`)
}

/** Wait until the page shows more than `n` bodies. */
async function bodiesAbove(page: Page, n: number): Promise<void> {
  await page.waitForFunction((count) => window.concord.sandbox.bodies().length > count, n)
}

/** Wait until the page shows `n` joints; says which notice the page shows if it does not. */
async function joined(page: Page, n: number): Promise<void> {
  const ok = await page
    .waitForFunction((count) => window.concord.sandbox.joints().length === count, n, { timeout: 15_000 })
    .then(() => true)
    .catch(() => false)
  if (!ok) {
    const seen = await page.evaluate(() => [
      window.concord.sandbox.joints().length,
      window.concord.sandbox.notices(),
    ])
    throw new Error(`waited for ${n} joints; the page shows ${JSON.stringify(seen)}`)
  }
}

const bodyCount = (page: Page): Promise<number> => page.evaluate(() => window.concord.sandbox.bodies().length)
const jointCount = (page: Page): Promise<number> =>
  page.evaluate(() => window.concord.sandbox.joints().length)

/** Wait `ticks` room ticks (the server's clock, seen in the page). */
async function ticks(page: Page, n: number): Promise<void> {
  const now = await page.evaluate(() => window.concord.sandbox.stats().tick)
  await page.waitForFunction((t) => window.concord.sandbox.stats().tick >= t, now + n, { timeout: 90_000 })
}

/** The dynamic body nearest a world point. */
async function nearest(page: Page, p: Pt): Promise<number> {
  const all = (await bodies(page)).filter((b) => b.kind === 2)
  all.sort((a, b) => Math.hypot(a.x - p.x, a.y - p.y) - Math.hypot(b.x - p.x, b.y - p.y))
  if (all.length === 0) throw new Error('no dynamic body on the page')
  return all[0].id
}

/** Save the crop after two drawn frames, and close the page's context. */
async function shoot(page: Page, name: string, clip: Clip = TOP_LEFT, close = true): Promise<void> {
  // The Draw form's short notice ("Draw: rectangle (drag)") would be in the picture: let it go.
  await page.waitForFunction(() => document.getElementById('toast')?.hidden !== false, undefined, {
    timeout: 15_000,
  })
  await page.evaluate(
    () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(() => r(null)))),
  )
  await page.screenshot({ path: `${OUT}/${name}.png`, clip })
  if (close) await page.context().close()
}

// The shots, in toolbar order.

async function grab(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-grab', 'playground', 6)
  await look(page, { x: -4, y: 2 }, 55)
  await ticks(page, 60)
  await pickTool(page, 'grab')
  const box = await nearest(page, { x: -1.5, y: 1.5 })
  const at = await pressUntilGrabbed(page, box)
  await page.mouse.move(at.x + 60, at.y - 140, { steps: 12 })
  await ticks(page, 20)
  await shoot(page, 'grab')
}

/** Drop shapes with a spawn tool at `drops`, then press at `aim` and pull back to `pull` (the throw). */
async function spawnShot(stage: Stage, tool: string, drops: Pt[], hoverAt: Pt): Promise<void> {
  const page = await room(stage, `shot-${tool}`, 'empty')
  await look(page, { x: 0, y: 3 }, 50)
  await pickTool(page, tool)
  for (const p of drops) {
    const n = await bodyCount(page)
    await clickAt(page, p)
    await bodiesAbove(page, n)
  }
  await ticks(page, 90)
  await hover(page, hoverAt)
  await shoot(page, tool)
}

async function circle(stage: Stage): Promise<void> {
  await spawnShot(
    stage,
    'circle',
    [
      { x: -3, y: 2 },
      { x: -1, y: 4 },
      { x: -0.6, y: 6 },
      { x: 2, y: 3 },
    ],
    { x: 3, y: 4 },
  )
}

async function box(stage: Stage): Promise<void> {
  await spawnShot(
    stage,
    'box',
    [0.6, 1.8, 3, 4.2, 5.4].map((y, i) => ({ x: -2 + 0.15 * i, y })).concat([{ x: 1.5, y: 1 }]),
    { x: 3, y: 4 },
  )
}

async function polygon(stage: Stage): Promise<void> {
  await spawnShot(
    stage,
    'polygon',
    [
      { x: -4, y: 1 },
      { x: -2, y: 1 },
      { x: 0, y: 1 },
      { x: 2, y: 1 },
      { x: -1, y: 4 },
    ],
    { x: 3, y: 4.5 },
  )
}

async function remove(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-delete', 'pyramid', 0, true)
  await look(page, { x: 0, y: 6 }, 24)
  await pickTool(page, 'delete')
  for (const p of [
    { x: 0, y: 2.5 },
    { x: -1, y: 2.5 },
    { x: 1, y: 2.5 },
    { x: -0.5, y: 3.5 },
    { x: 0.5, y: 3.5 },
  ]) {
    const n = await bodyCount(page)
    const id = await nearest(page, p)
    await clickAt(page, (await bodies(page)).find((b) => b.id === id)!)
    await page.waitForFunction((count) => window.concord.sandbox.bodies().length < count, n)
  }
  await setPaused(page, false)
  await ticks(page, 25)
  await shoot(page, 'delete')
}

async function pin(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-pin', 'empty', 0, true)
  await look(page, { x: 0, y: 3.5 }, 60)
  await pickTool(page, 'box')
  await clickAt(page, { x: 0, y: 5 })
  await bodiesAbove(page, 1)
  await clickAt(page, { x: 0.85, y: 4.15 })
  await bodiesAbove(page, 2)
  await pickTool(page, 'pin')
  // The lower box to the upper one where they overlap, then the upper one to the world.
  await clickAt(page, { x: 0.45, y: 4.55 })
  await joined(page, 1)
  await clickAt(page, { x: -0.4, y: 5.4 })
  await joined(page, 2)
  await setPaused(page, false)
  await ticks(page, 50)
  await shoot(page, 'pin')
}

async function rope(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-rope', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 55)
  await pickTool(page, 'box')
  await clickAt(page, { x: -1, y: 3 })
  await bodiesAbove(page, 1)
  await pickTool(page, 'circle')
  await clickAt(page, { x: 2.5, y: 2 })
  await bodiesAbove(page, 2)
  await pickTool(page, 'rope')
  // From the world above to the box, then a slack rope from the box to the ball.
  await drag(page, [
    { x: -3, y: 6 },
    { x: -1, y: 3 },
  ])
  await joined(page, 1)
  await drag(page, [
    { x: -1, y: 3 },
    { x: 1, y: 1 },
    { x: 2.5, y: 2 },
  ])
  await joined(page, 2)
  await setPaused(page, false)
  await ticks(page, 45)
  await shoot(page, 'rope')
}

async function cut(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-cut', 'chain-bridge', 21)
  await ticks(page, 120)
  const mid = await page.evaluate(() => {
    const js = window.concord.sandbox.joints()
    const j = js[Math.floor(js.length / 2)]
    return { x: j.bx, y: j.by }
  })
  await look(page, mid, 40)
  await pickTool(page, 'cut')
  await hover(page, mid)
  await page.waitForFunction(() => window.concord.tools.overlay('#fff').cutJoint !== null)
  await shoot(page, 'cut')
}

async function lab(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-lab', 'ramp')
  await pickTool(page, 'inspect')
  const id = await nearest(page, { x: 0, y: 3 })
  const b = (await bodies(page)).find((v) => v.id === id)!
  // The box right of and above the lab panel (bottom left), its arrows in view.
  await look(page, b, 50, { x: 560, y: 430 })
  await clickAt(page, b)
  await page.waitForFunction(() => /normal/.test(document.getElementById('lab-text')?.textContent ?? ''))
  await ticks(page, 60)
  await shoot(page, 'lab', BOTTOM_LEFT)
}

async function drawOutline(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-draw', 'empty')
  await look(page, { x: 0, y: 3 }, 45)
  await pickTool(page, 'draw')
  // A U, freehand: one concave body of convex pieces.
  const n = await bodyCount(page)
  await drag(
    page,
    [
      { x: -6, y: 1 },
      { x: -2, y: 1 },
      { x: -2, y: 4 },
      { x: -3, y: 4 },
      { x: -3, y: 2 },
      { x: -5, y: 2 },
      { x: -5, y: 4 },
      { x: -6, y: 4 },
      { x: -6, y: 1 },
    ],
    5,
  )
  await bodiesAbove(page, n)
  // The next outline, half drawn: the stroke so far follows the pointer.
  await press(
    page,
    [
      { x: 0, y: 1 },
      { x: 3, y: 1.5 },
      { x: 4, y: 4 },
      { x: 2, y: 5 },
      { x: 1.5, y: 3 },
    ],
    6,
  )
  await shoot(page, 'draw-outline', TOP_LEFT, false)
  await page.mouse.up()
  await page.context().close()
}

async function drawForms(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-draw-forms', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 45)
  await pickDrawForm(page, 'rect')
  let n = await bodyCount(page)
  await drag(page, [
    { x: -6, y: 1 },
    { x: -3, y: 3 },
  ])
  await bodiesAbove(page, n)
  await page.keyboard.press('w') // circle
  n = await bodyCount(page)
  await drag(page, [
    { x: -0.5, y: 2.5 },
    { x: -0.5, y: 3.7 },
  ])
  await bodiesAbove(page, n)
  await page.keyboard.press('w') // capsule, being dragged
  await press(page, [
    { x: 2, y: 2 },
    { x: 5, y: 4 },
  ])
  await shoot(page, 'draw-forms', TOP_LEFT, false)
  await page.mouse.up()
  await page.context().close()
}

/** Terrain drawn with the Ground tool (world m), used by the ground, wheel and README pictures. */
const TERRAIN: Pt[] = [
  { x: -9, y: 3.2 },
  { x: -6.5, y: 1.6 },
  { x: -4, y: 0.9 },
  { x: -1, y: 1 },
  { x: 2, y: 1.9 },
  { x: 4.5, y: 1.5 },
  { x: 7, y: 0.6 },
]

async function drawTerrain(page: Page, line: Pt[] = TERRAIN): Promise<void> {
  await pickTool(page, 'ground')
  const n = await bodyCount(page)
  await drag(page, line, 6)
  await bodiesAbove(page, n)
}

async function ground(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-ground', 'empty')
  await look(page, { x: -1, y: 2.5 }, 42)
  await drawTerrain(page)
  await pickTool(page, 'circle')
  for (const x of [-8.5, -7.5]) {
    const n = await bodyCount(page)
    await clickAt(page, { x, y: 5.5 })
    await bodiesAbove(page, n)
  }
  await ticks(page, 70)
  await shoot(page, 'ground')
}

async function staticToggle(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-static', 'empty')
  await look(page, { x: 0, y: 3 }, 50)
  await page.keyboard.press('m')
  await pickDrawForm(page, 'rect')
  let n = await bodyCount(page)
  await drag(page, [
    { x: -4, y: 3 },
    { x: 0, y: 3.3 },
  ])
  await bodiesAbove(page, n)
  await page.keyboard.press('m') // off again: the boxes fall onto the shelf
  await pickTool(page, 'box')
  for (const x of [-3.2, -1.8, -2.5]) {
    n = await bodyCount(page)
    await clickAt(page, { x, y: x === -2.5 ? 6 : 5 })
    await bodiesAbove(page, n)
  }
  await page.keyboard.press('m') // on: the next box stays in the air where it is dropped
  n = await bodyCount(page)
  await clickAt(page, { x: 3, y: 4 })
  await bodiesAbove(page, n)
  await ticks(page, 90)
  await hover(page, { x: 3, y: 5.6 })
  await shoot(page, 'static')
}

/** Where the joint shots put their subject: lower, clear of the joint panel under the toolbar. */
const JOINT_FOCUS: Pt = { x: 380, y: 320 }

/** Open the joint panel and pick a joint tool by its key. */
async function jointTool(page: Page, key: string): Promise<void> {
  await page.keyboard.press(key)
  await page.waitForFunction(() => document.getElementById('joint-panel')?.hidden === false)
}

async function setSlider(page: Page, key: string, value: number): Promise<void> {
  await page.evaluate(
    ([k, v]) => {
      const input = document.querySelector(`[data-joint="${k}"]`) as HTMLInputElement
      input.value = String(v)
      input.dispatchEvent(new Event('input'))
    },
    [key, value] as const,
  )
}

async function weld(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-weld', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 55)
  await pickTool(page, 'box')
  for (const [i, p] of [
    { x: -1.5, y: 4 },
    { x: -0.6, y: 4.9 },
    { x: 2, y: 3 },
  ].entries()) {
    await clickAt(page, p)
    await bodiesAbove(page, i + 1)
  }
  await jointTool(page, 'y')
  // The two overlapping boxes glued into one piece, and the third to the background.
  await clickAt(page, { x: -1.05, y: 4.45 })
  await joined(page, 1)
  await clickAt(page, { x: 2, y: 3 })
  await joined(page, 2)
  await setPaused(page, false)
  await ticks(page, 100)
  await hover(page, { x: 4, y: 5 })
  await shoot(page, 'weld')
}

async function hinge(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-hinge', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 55, JOINT_FOCUS)
  await pickDrawForm(page, 'rect') // a 4 m bar
  const n = await bodyCount(page)
  await drag(page, [
    { x: -2, y: 3.8 },
    { x: 2, y: 4.2 },
  ])
  await bodiesAbove(page, n)
  await jointTool(page, 'e')
  await setSlider(page, 'torque', 200)
  await setSlider(page, 'limit', 60)
  await clickAt(page, { x: -1.6, y: 4 })
  await joined(page, 1)
  await setPaused(page, false)
  // Drive it with the arrow key: it turns until the limit stops it.
  await page.keyboard.down('ArrowLeft')
  await ticks(page, 60)
  await page.keyboard.up('ArrowLeft')
  await hover(page, { x: 3, y: 1.5 })
  await shoot(page, 'hinge')
}

async function spring(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-spring', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 55, JOINT_FOCUS)
  await pickTool(page, 'box')
  await clickAt(page, { x: -1, y: 3 })
  await bodiesAbove(page, 1)
  await pickTool(page, 'circle')
  await clickAt(page, { x: 2, y: 2.5 })
  await bodiesAbove(page, 2)
  await jointTool(page, 'q')
  await setSlider(page, 'hz', 2)
  await drag(page, [
    { x: -1, y: 5.5 },
    { x: -1, y: 3 },
  ])
  await joined(page, 1)
  await drag(page, [
    { x: 2, y: 5.5 },
    { x: 2, y: 2.5 },
  ])
  await joined(page, 2)
  await setPaused(page, false)
  await ticks(page, 40)
  await hover(page, { x: 4, y: 1 })
  await shoot(page, 'spring')
}

async function slider(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-slider', 'empty', 0, true)
  await look(page, { x: 0, y: 3 }, 55, JOINT_FOCUS)
  await pickTool(page, 'box')
  await clickAt(page, { x: -1, y: 3 })
  await bodiesAbove(page, 1)
  await jointTool(page, 'z')
  // From the box, up and to the right: it slides along that line, the drag's length each way.
  await drag(page, [
    { x: -1, y: 3 },
    { x: 1, y: 4.5 },
  ])
  await joined(page, 1)
  await setPaused(page, false)
  await page.keyboard.down('ArrowUp')
  await ticks(page, 40)
  await page.keyboard.up('ArrowUp')
  await hover(page, { x: 4, y: 1 })
  await shoot(page, 'slider')
}

/** A car from the tools: a drawn 2.4 m chassis and two clicks of the wheel tool. Returns the chassis. */
async function buildCar(page: Page, at: Pt): Promise<number> {
  await pickDrawForm(page, 'rect')
  const n = await bodyCount(page)
  await drag(page, [
    { x: at.x - 1.2, y: at.y - 0.3 },
    { x: at.x + 1.2, y: at.y + 0.3 },
  ])
  await bodiesAbove(page, n)
  const chassis = await nearest(page, at)
  const joints = await jointCount(page)
  // Wheels of 0.45 m: the wheel radius is a quarter of the spawn size slider's box side.
  await page.evaluate(() => {
    const input = document.querySelector('[data-spawn="size"]') as HTMLInputElement
    input.value = '1.8'
    input.dispatchEvent(new Event('input'))
  })
  await jointTool(page, ',')
  await setSlider(page, 'torque', 100)
  await clickAt(page, { x: at.x - 0.9, y: at.y - 0.25 })
  await page.waitForFunction((j) => window.concord.sandbox.joints().length === j + 1, joints)
  await clickAt(page, { x: at.x + 0.9, y: at.y - 0.25 })
  await page.waitForFunction((j) => window.concord.sandbox.joints().length === j + 2, joints)
  return chassis
}

async function wheel(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-wheel', 'empty', 0, true)
  await look(page, { x: -1, y: 3 }, 45)
  await drawTerrain(page)
  await buildCar(page, { x: -6.5, y: 3.4 })
  await setPaused(page, false)
  await ticks(page, 60)
  await page.keyboard.down('ArrowRight')
  await ticks(page, 75)
  await page.keyboard.up('ArrowRight')
  await hover(page, { x: 5, y: 5 })
  await shoot(page, 'wheel')
}

async function explode(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-explode', 'tower')
  await look(page, { x: 0, y: 5 }, 30)
  await ticks(page, 30)
  await page.keyboard.press('/')
  await press(page, [
    { x: -2, y: 1 },
    { x: -1.2, y: 1.5 },
  ])
  await shoot(page, 'explode', TOP_LEFT, false)
  await page.mouse.up()
  await page.context().close()
}

async function slow(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-slow', 'wrecking-ball', 1)
  await look(page, { x: 0, y: 5 }, 28)
  await page.keyboard.press('-')
  await page.waitForFunction(() => /Slow motion/.test(document.getElementById('paused')?.textContent ?? ''))
  await ticks(page, 60)
  await shoot(page, 'slow')
}

async function lock(stage: Stage): Promise<void> {
  const creator = await room(stage, 'shot-lock', 'playground', 6)
  await creator.waitForFunction(() => !(document.getElementById('lock') as HTMLButtonElement).hidden)
  const { page } = await openSandbox(stage.browser, `${stage.base}/?room=shot-lock&name=bob`, { size: VIEW })
  await creator.keyboard.press('=')
  await page.waitForFunction(() =>
    /Controls locked/.test(document.getElementById('paused')?.textContent ?? ''),
  )
  await look(page, { x: -4, y: 1 }, 40)
  // The other player's page: the room controls greyed out, the lock said on the view.
  await shoot(page, 'lock', { x: 0, y: 0, width: 800, height: 300 })
  await creator.context().close()
}

async function edit(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-edit', 'empty')
  await look(page, { x: 0, y: 3 }, 50)
  await pickTool(page, 'box')
  for (const p of [
    { x: -2.5, y: 0.6 },
    { x: 0, y: 0.6 },
    { x: 2.5, y: 0.6 },
  ]) {
    const n = await bodyCount(page)
    await clickAt(page, p)
    await bodiesAbove(page, n)
  }
  await ticks(page, 60)
  await pickTool(page, 'edit')
  const id = await nearest(page, { x: 0, y: 0.5 })
  await clickAt(page, (await bodies(page)).find((b) => b.id === id)!)
  await page.waitForFunction(() => document.getElementById('edit-panel')?.hidden === false)
  await hover(page, { x: 3.5, y: 3 })
  await shoot(page, 'edit')
}

async function pause(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-pause', 'playground', 6)
  await look(page, { x: -4, y: 2 }, 45)
  await page.keyboard.press(' ')
  await page.waitForFunction(() => window.concord.sandbox.paused())
  await page.keyboard.press('s')
  await shoot(page, 'pause', { x: 0, y: 0, width: 800, height: 400 })
}

async function replay(stage: Stage): Promise<void> {
  // A short session in a room of the recording server: the playground, a few boxes and a throw.
  const { page } = await openSandbox(stage.browser, `${stage.recording.url}/?room=replayed&name=ada`, {
    size: VIEW,
  })
  await showScene(page, 'playground', 6)
  await pickTool(page, 'box')
  for (const p of [
    { x: 14, y: 4 },
    { x: 15, y: 6 },
    { x: 13, y: 8 },
  ]) {
    const n = await bodyCount(page)
    await clickAt(page, p)
    await bodiesAbove(page, n)
  }
  await ticks(page, 180)
  await page.context().close()
  const listed = (await (await fetch(`${stage.recording.url}/replays`)).json()) as Array<{
    name: string
    room: string
  }>
  const logs = listed.filter((l) => l.room === 'replayed').map((l) => l.name)
  if (logs.length === 0) throw new Error(`no log of room "replayed" in ${JSON.stringify(listed)}`)
  // A page the picture's size: the control bar spans it.
  const context = await stage.browser.newContext({ viewport: { width: 800, height: 500 } })
  const player = await context.newPage()
  await player.goto(`${stage.recording.url}/?replay=${encodeURIComponent(logs[0])}`)
  await player.waitForSelector('#replay-play')
  const first = await player.evaluate(() => window.concordReplay!.sandbox!.player.tick)
  await player.click('#replay-play')
  await player.waitForFunction((t) => window.concordReplay!.sandbox!.player.tick >= t + 150, first, {
    timeout: 90_000,
  })
  await player.click('#replay-play') // pause there
  await shoot(player, 'replay', { x: 0, y: 0, width: 800, height: 500 })
}

async function lobby(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-lobby', 'playground', 6)
  await page.keyboard.press('o')
  await page.waitForFunction(() => {
    const list = document.getElementById('lobby-list')
    return document.getElementById('lobby')?.hidden === false && (list?.children.length ?? 0) > 0
  })
  const box = (await page.locator('#lobby').boundingBox())!
  const clip = {
    x: Math.max(0, box.x - 20),
    y: Math.max(0, box.y - 20),
    width: Math.min(800, box.width + 40),
    height: Math.min(500, box.height + 40),
  }
  await shoot(page, 'lobby', clip)
}

/** The README's first picture: a car built from the tools, driving over drawn ground. */
async function readme(stage: Stage): Promise<void> {
  const page = await room(stage, 'shot-readme', 'empty', 0, true)
  await look(page, { x: -1, y: 2.2 }, 44, { x: 400, y: 300 })
  await drawTerrain(page)
  // Two boxes on the hill (dropped before the car: its wheels set the size slider).
  await pickTool(page, 'box')
  for (const p of [
    { x: 2, y: 2.5 },
    { x: 2.1, y: 3.6 },
  ]) {
    const count = await bodyCount(page)
    await clickAt(page, p)
    await bodiesAbove(page, count)
  }
  await buildCar(page, { x: -6.5, y: 3.4 })
  // A drawn outline and a few dropped boxes on the far slope.
  await pickDrawForm(page, 'outline')
  const n = await bodyCount(page)
  await drag(
    page,
    [
      { x: 4, y: 2.6 },
      { x: 5.6, y: 2.2 },
      { x: 5.8, y: 3.6 },
      { x: 4.9, y: 3 },
      { x: 4.1, y: 3.8 },
      { x: 4, y: 2.6 },
    ],
    5,
  )
  await bodiesAbove(page, n)
  await setPaused(page, false)
  await ticks(page, 60)
  await page.keyboard.down('ArrowRight')
  await ticks(page, 70)
  await page.keyboard.up('ArrowRight')
  await pickTool(page, 'grab')
  await page.mouse.move(790, 470)
  await shoot(page, 'sandbox-built', { x: 0, y: 70, width: 800, height: 420 })
}

/** Every picture, by name: docs/images/NAME.png (drawOutline and drawForms make draw-*.png). */
const SHOTS: Record<string, (stage: Stage) => Promise<void>> = {
  grab,
  circle,
  box,
  polygon,
  delete: remove,
  pin,
  rope,
  cut,
  lab,
  'draw-outline': drawOutline,
  'draw-forms': drawForms,
  ground,
  static: staticToggle,
  weld,
  hinge,
  spring,
  slider,
  wheel,
  explode,
  slow,
  lock,
  edit,
  pause,
  replay,
  lobby,
  readme,
}

async function main(): Promise<void> {
  const wanted = process.argv.slice(2)
  const unknown = wanted.filter((w) => !Object.hasOwn(SHOTS, w))
  if (unknown.length > 0)
    throw new Error(`unknown picture ${unknown.join(', ')}; pictures: ${Object.keys(SHOTS).join(', ')}`)
  await mkdir(OUT, { recursive: true })
  await buildClient(DIST)
  const replayDir = await mkdtemp(join('test-results', 'screenshots-replays-'))
  const [server, recording, browser] = await Promise.all([
    serveClient(DIST, { defaultScene: 'playground' }),
    serveClient(DIST, { defaultScene: 'playground', record: true, replayDir }),
    launchBrowser(),
  ])
  const stage: Stage = { browser, base: `http://127.0.0.1:${server.port}`, recording, replayDir }
  try {
    for (const name of wanted.length > 0 ? wanted : Object.keys(SHOTS)) {
      const started = Date.now()
      await SHOTS[name](stage)
      console.log(`${name}: ${((Date.now() - started) / 1000).toFixed(1)} s`)
    }
  } finally {
    await browser.close()
    await Promise.all([server.close(), recording.close()])
  }
}

await main()
