/*
 * The lab's plot of speed and kinetic energy, in Chromium with the engine stepping in the page: a
 * circle dropped from rest is selected with the lab tool and plotted, sample by room tick. While it
 * falls the speed rises at g (a least-squares slope over the samples against the ticks), the peak
 * speed is sqrt(2 g h) and the peak energy m g h for the height h it fell (read from its rest
 * pose), energy is 1/2 m v^2 at every sample, and both curves are painted on the plot's canvas.
 */
import type { Browser } from 'playwright-core'
import { describe, expect, it } from 'vitest'
import { PLOT_COLORS, type PlotSample } from '../../client/draw/lab-plot.ts'
import type { RunningServer } from '../../server/server.ts'
import {
  ARTIFACTS,
  openSandbox,
  pickTool,
  screenOfBody,
  useClientPages,
  waitForBody,
} from '../support/client-harness.ts'

let server: RunningServer
let browser: Browser
let base: string
useClientPages((pages) => ({ server, browser, base } = pages))

const Y0 = 8

describe('lab plot', { timeout: 300_000 }, () => {
  it('plots a dropped circle: speed rising at g, peaks at sqrt(2 g h) and m g h, energy 1/2 m v^2', async () => {
    const { context, page, errors } = await openSandbox(browser, `${base}/?offline&scene=empty`)
    await page.evaluate((y) => {
      const s = window.concord.sandbox
      s.send({ k: 'pause', paused: true })
      s.send({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y })
    }, Y0)
    await page.waitForFunction(() =>
      window.concord.sandbox.bodies().some((b: { kind: number }) => b.kind === 2),
    )
    const id = await page.evaluate(
      () => window.concord.sandbox.bodies().find((b: { kind: number }) => b.kind === 2)!.id,
    )
    await page.evaluate(() => window.concord.act('fit'))
    await pickTool(page, 'inspect')
    const at = await screenOfBody(page, id)
    await page.mouse.click(at.x, at.y)
    await page.waitForFunction(() => window.concord.labPlot.samples.length > 0)
    await page.evaluate(() => window.concord.sandbox.send({ k: 'pause', paused: false }))
    await waitForBody(page, id, '!b.awake', 30_000)
    const rest = await page.evaluate(
      (bodyId) => window.concord.sandbox.bodies().find((b: { id: number }) => b.id === bodyId)!.y,
      id,
    )
    const samples: PlotSample[] = await page.evaluate(() => window.concord.labPlot.samples.slice())
    const { mass, g } = await page.evaluate(() => {
      const fb = window.concord.freeBody!
      return { mass: fb.mass, g: Math.hypot(fb.gravity.x, fb.gravity.y) / fb.mass }
    })
    const h = Y0 - rest
    const peak = samples.reduce((a, b) => (b.speed > a.speed ? b : a))
    // Free fall: the samples from the first motion to just before the peak lie on v = g t.
    const fall = samples.filter((p) => p.speed > 0.3 && p.tick < peak.tick - 1)
    expect(fall.length).toBeGreaterThan(10)
    const slope = leastSquaresSlope(fall.map((p) => [p.tick / 60, p.speed]))
    expect(Math.abs(slope / g - 1)).toBeLessThan(0.02)
    // The last sample before the ground: within one step (g / 60 m/s) and the fixed step's
    // discretization (2 %) of sqrt(2 g h).
    const expected = Math.sqrt(2 * g * h)
    expect(Math.abs(peak.speed - expected)).toBeLessThan(g / 60 + 0.02 * expected)
    expect(Math.abs(peak.kinetic / (mass * g * h) - 1)).toBeLessThan(0.05)
    for (const p of samples) expect(p.kinetic).toBeCloseTo(0.5 * mass * p.speed * p.speed, 1)
    expect(samples[samples.length - 1].speed).toBeLessThan(0.1)
    // Both curves are on the plot's canvas.
    const painted = await page.evaluate((colors) => {
      const canvas = document.getElementById('lab-plot') as HTMLCanvasElement
      const d = canvas.getContext('2d')!.getImageData(0, 0, canvas.width, canvas.height).data
      return Object.values(colors).map((hex) => {
        const n = Number.parseInt(hex.slice(1), 16)
        const rgb = [n >> 16, (n >> 8) & 255, n & 255]
        let count = 0
        for (let i = 0; i < d.length; i += 4)
          if (Math.abs(d[i] - rgb[0]) + Math.abs(d[i + 1] - rgb[1]) + Math.abs(d[i + 2] - rgb[2]) < 40)
            count++
        return count
      })
    }, PLOT_COLORS)
    expect(painted[0]).toBeGreaterThan(30)
    expect(painted[1]).toBeGreaterThan(30)
    await page.screenshot({ path: `${ARTIFACTS}/lab-plot.png` })
    expect(errors).toEqual([])
    await context.close()
  })
})

/** Slope of the least-squares line through points (x, y). */
function leastSquaresSlope(points: Array<[number, number]>): number {
  const n = points.length
  const mx = points.reduce((s, [x]) => s + x, 0) / n
  const my = points.reduce((s, [, y]) => s + y, 0) / n
  let sxy = 0
  let sxx = 0
  for (const [x, y] of points) {
    sxy += (x - mx) * (y - my)
    sxx += (x - mx) * (x - mx)
  }
  return sxy / sxx
}
