/*
 * Sensor shapes are drawn translucent with a dashed outline, solid shapes opaque with a solid one
 * (client/draw/renderer.ts), read from the canvas's pixels in Chromium. The page (offline, paused)
 * holds two static 2 m boxes side by side: a solid one (coloured 0x40a060) and one whose only shape is a sensor (the
 * wire's `sensor: true`). The oracles are the canvas compositing rule (source-over: alpha * colour
 * + (1 - alpha) * what was under it) with the renderer's published colours, and the dash pattern:
 * along the sensor's top edge some pixels are the outline colour and others are not (the gaps),
 * while the solid box's top edge is outline colour end to end. A second page holds a gate (a
 * static box whose filter [1, 2, 0] collides only with category 2) and a static box with a category
 * alone ([4, 0xffffffff, 0], excluding nothing): the gate is its own colour (0xc03030) at
 * GATE_FILL_ALPHA with a dashed GATE_COLOR outline, the other its own colour's solid fill.
 */
import type { Browser, Page } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import { GATE_COLOR, GATE_FILL_ALPHA, SENSOR_COLOR, SENSOR_FILL_ALPHA } from '../../client/draw/renderer.ts'
import type { RunningServer } from '../../server/server.ts'
import { openSandbox, pixelAt, screenOf, useClientPages } from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

type Rgb = [number, number, number]
const rgb = (hex: string): Rgb => [1, 3, 5].map((i) => Number.parseInt(hex.slice(i, i + 2), 16)) as Rgb
const near = (a: Rgb, b: Rgb, tolerance: number): boolean =>
  a.every((v, i) => Math.abs(v - b[i]) <= tolerance)
/** Source-over compositing of `colour` at `alpha` over `under`. */
const over = (colour: Rgb, alpha: number, under: Rgb): Rgb =>
  colour.map((c, i) => alpha * c + (1 - alpha) * under[i]) as Rgb

// The renderer's background and grid (client/draw/renderer.ts STYLE); a spawned body is filled in
// its colour (here 0x40a060) and outlined in #e8edf5.
const BACKGROUND = rgb('#161a22')
const GRID = rgb('#1f2530')
const SOLID_FILL = rgb('#40a060')
const SOLID_LINE = rgb('#e8edf5')
const SENSOR = rgb(SENSOR_COLOR)
const GATE = rgb(GATE_COLOR)

/**
 * Along a horizontal world edge from x0 to x1 at height y: per canvas column, whether some pixel
 * within 2 px of the edge's row is within `tolerance` of `colour`.
 */
async function edgeColumns(page: Page, x0: number, x1: number, y: number, colour: Rgb, tolerance: number) {
  const a = await screenOf(page, x0, y)
  const b = await screenOf(page, x1, y)
  return page.evaluate(
    ([ax, bx, sy, c, tol]) => {
      const canvas = window.concord.renderer.canvas as HTMLCanvasElement
      const r = canvas.getBoundingClientRect()
      const k = canvas.width / r.width
      const left = Math.round((ax - r.left) * k)
      const width = Math.round((bx - ax) * k)
      const top = Math.round((sy - r.top) * k) - 2
      const d = canvas.getContext('2d')!.getImageData(left, top, width, 5).data
      const out: boolean[] = []
      for (let x = 0; x < width; x++) {
        let hit = false
        for (let row = 0; row < 5; row++) {
          const i = (row * width + x) * 4
          if (
            Math.abs(d[i] - c[0]) <= tol &&
            Math.abs(d[i + 1] - c[1]) <= tol &&
            Math.abs(d[i + 2] - c[2]) <= tol
          )
            hit = true
        }
        out.push(hit)
      }
      return out
    },
    [a.x, b.x, a.y, colour, tolerance] as [number, number, number, Rgb, number],
  )
}

describe('sensors on the canvas', { timeout: 300_000 }, () => {
  it('a sensor is filled translucent with a dashed outline; a solid shape opaque with a solid outline', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?offline&scene=empty`)
    await page.evaluate(() => {
      const s = window.concord.sandbox
      s.send({ k: 'pause', paused: true })
      s.send({
        k: 'spawn',
        shape: { type: 'box', hw: 1, hh: 1 },
        x: -2.5,
        y: 3,
        static: true,
        color: 0x40a060,
      })
      s.send({
        k: 'spawn',
        shapes: [{ type: 'box', hw: 1, hh: 1, sensor: true }],
        x: 2.5,
        y: 3,
        static: true,
      })
    })
    await page.waitForFunction(
      () =>
        window.concord.sandbox.bodies().filter((b: { x: number }) => Math.abs(Math.abs(b.x) - 2.5) < 1e-6)
          .length === 2,
    )
    await page.evaluate(() => window.concord.act('fit'))
    // Inside each box, off the 1 m grid lines: the solid box's fill, and the sensor's colour at
    // SENSOR_FILL_ALPHA over the background or a grid line.
    const solidAt = await screenOf(page, -2.5 + 0.37, 3 + 0.41)
    const sensorAt = await screenOf(page, 2.5 + 0.37, 3 + 0.41)
    await page.waitForFunction(
      ([x, y, c]) => {
        const canvas = window.concord.renderer.canvas as HTMLCanvasElement
        const r = canvas.getBoundingClientRect()
        const d = canvas.getContext('2d')!.getImageData(x - r.left, y - r.top, 1, 1).data
        return Math.abs(d[0] - c[0]) <= 2 && Math.abs(d[1] - c[1]) <= 2 && Math.abs(d[2] - c[2]) <= 2
      },
      [solidAt.x, solidAt.y, SOLID_FILL] as [number, number, Rgb],
    )
    const sensorPixel = await pixelAt(page, sensorAt.x, sensorAt.y)
    const expected = [over(SENSOR, SENSOR_FILL_ALPHA, BACKGROUND), over(SENSOR, SENSOR_FILL_ALPHA, GRID)]
    expect(
      expected.some((e) => near(sensorPixel, e, 3)),
      `sensor fill ${sensorPixel}, expected ${expected.map((e) => e.map(Math.round)).join(' or ')}`,
    ).toBe(true)

    // The top edges, between the corners (0.2 m in from each): dashes and gaps on the sensor's,
    // unbroken on the solid box's.
    const sensorEdge = await edgeColumns(page, 1.7, 3.3, 4, SENSOR, 40)
    const onDash = sensorEdge.filter(Boolean).length
    expect(onDash, `sensor edge ${sensorEdge.map((h) => (h ? '-' : ' ')).join('')}`).toBeGreaterThan(
      sensorEdge.length / 4,
    )
    expect(sensorEdge.length - onDash, 'gaps in the dashed outline').toBeGreaterThan(sensorEdge.length / 8)
    const solidEdge = await edgeColumns(page, -3.3, -1.7, 4, SOLID_LINE, 40)
    expect(solidEdge.every(Boolean), `solid edge ${solidEdge.map((h) => (h ? '-' : ' ')).join('')}`).toBe(
      true,
    )
    expect(errors).toEqual([])
    await context.close()
  })

  it('a gate (a static shape that lets some bodies through) is faint with a dashed outline; a category alone is solid', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?offline&scene=empty`)
    await page.evaluate(() => {
      const s = window.concord.sandbox
      s.send({ k: 'pause', paused: true })
      s.send({
        k: 'spawn',
        shapes: [{ type: 'box', hw: 1, hh: 1, filter: [4, 0xffffffff, 0] }],
        x: -2.5,
        y: 3,
        static: true,
        color: 0x40a060,
      })
      s.send({
        k: 'spawn',
        shapes: [{ type: 'box', hw: 1, hh: 1, filter: [1, 2, 0] }],
        x: 2.5,
        y: 3,
        static: true,
        color: 0xc03030,
      })
    })
    await page.waitForFunction(
      () =>
        window.concord.sandbox.bodies().filter((b: { x: number }) => Math.abs(Math.abs(b.x) - 2.5) < 1e-6)
          .length === 2,
    )
    await page.evaluate(() => window.concord.act('fit'))
    const solidAt = await screenOf(page, -2.5 + 0.37, 3 + 0.41)
    const gateAt = await screenOf(page, 2.5 + 0.37, 3 + 0.41)
    await page.waitForFunction(
      ([x, y, c]) => {
        const canvas = window.concord.renderer.canvas as HTMLCanvasElement
        const r = canvas.getBoundingClientRect()
        const d = canvas.getContext('2d')!.getImageData(x - r.left, y - r.top, 1, 1).data
        return Math.abs(d[0] - c[0]) <= 2 && Math.abs(d[1] - c[1]) <= 2 && Math.abs(d[2] - c[2]) <= 2
      },
      [solidAt.x, solidAt.y, SOLID_FILL] as [number, number, Rgb],
    )
    const gatePixel = await pixelAt(page, gateAt.x, gateAt.y)
    // A gate keeps its body's colour, faint (a player's static body on a layer is still its colour).
    const own: Rgb = [0xc0, 0x30, 0x30]
    const expected = [over(own, GATE_FILL_ALPHA, BACKGROUND), over(own, GATE_FILL_ALPHA, GRID)]
    expect(
      expected.some((e) => near(gatePixel, e, 3)),
      `gate fill ${gatePixel}, expected ${expected.map((e) => e.map(Math.round)).join(' or ')}`,
    ).toBe(true)
    const gateEdge = await edgeColumns(page, 1.7, 3.3, 4, GATE, 40)
    const onDash = gateEdge.filter(Boolean).length
    expect(onDash, `gate edge ${gateEdge.map((h) => (h ? '-' : ' ')).join('')}`).toBeGreaterThan(
      gateEdge.length / 4,
    )
    expect(gateEdge.length - onDash, 'gaps in the dashed outline').toBeGreaterThan(gateEdge.length / 8)
    expect(errors).toEqual([])
    await context.close()
  })
})
