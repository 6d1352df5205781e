/*
 * How smoothly the page moves bodies (numbers for bench:client, not a test). While the page runs,
 * shapes keep raining onto the scene (SPAWNS_PER_SECOND, from 12-20 m up across the pile), so many
 * bodies are awake and falling at once; on every animation frame each awake dynamic body's drawn
 * displacement since the previous frame is recorded:
 *   movedShare  of the frames on which a body is in motion (it moved more than 5 cm over the last
 *               10 frames: falling, sliding, tumbling), the share on which it moved at all: a body
 *               held still between snapshots (left out by the bandwidth budget) shows up here.
 *               Awake bodies resting in the pile are left out: online their quantized (1 mm)
 *               pose does not change, and drawing them still is right
 *   awakeMovedShare  the same share over every awake body, resting ones included
 *   jumpPx      the displacement on frames where it moved, in CSS px at the default zoom (30 px/m,
 *               the camera's scale before any fit), scaled to a 1/60 s frame so a slow frame of a
 *               loaded machine does not count as a jump: p50 and p99
 *   kinkPx      the change of that displacement from one frame to the next (px per 1/60 s frame):
 *               near zero for smooth motion, large where a pose pops
 */
import type { Page } from 'playwright-core'
import { summarize } from './stats.ts'

/** Shapes spawned per second during the measurement. */
export const SPAWNS_PER_SECOND = 30

const MEASURE_MOTION = `async ([ms, perSecond]) => {
  const app = window.concord
  const SCALE = 30
  const last = new Map()
  const lastStep = new Map()
  const history = new Map()
  let awake = 0
  let moved = 0
  let moving = 0
  let movingMoved = 0
  const jumps = []
  const kinks = []
  let spawned = 0
  const start = performance.now()
  await new Promise((resolve) => {
    let prev = -1
    const tick = (now) => {
      const due = Math.floor(((now - start) / 1000) * perSecond)
      for (; spawned < due; spawned++) {
        const x = -12 + ((spawned * 7.3) % 24)
        const y = 12 + (spawned % 5) * 2
        const shape = spawned % 2 ? { type: 'circle', radius: 0.35 } : { type: 'box', hw: 0.35, hh: 0.35 }
        app.sandbox.send({ k: 'spawn', shape, x, y })
      }
      const frameMs = prev < 0 ? 1000 / 60 : now - prev
      prev = now
      const norm = (1000 / 60) / Math.max(1000 / 60, frameMs)
      for (const b of app.sandbox.bodies()) {
        if (b.kind !== 2) continue
        const p = last.get(b.id)
        last.set(b.id, [b.x, b.y])
        if (!p || !b.awake) { lastStep.delete(b.id); continue }
        awake++
        const d = Math.hypot(b.x - p[0], b.y - p[1]) * SCALE * norm
        if (d > 0) { moved++; jumps.push(d) }
        let h = history.get(b.id)
        if (!h) { h = []; history.set(b.id, h) }
        h.push([b.x, b.y])
        if (h.length > 11) h.shift()
        if (h.length === 11 && Math.hypot(b.x - h[0][0], b.y - h[0][1]) > 0.05) {
          moving++
          if (d > 0) movingMoved++
        }
        const s = lastStep.get(b.id)
        if (s !== undefined) kinks.push(Math.abs(d - s))
        lastStep.set(b.id, d)
      }
      if (now - start < ms) requestAnimationFrame(tick)
      else resolve()
    }
    requestAnimationFrame(tick)
  })
  return { awake, moved, moving, movingMoved, jumps, kinks, spawned, bodies: app.sandbox.bodies().length }
}`

/** Motion numbers of one run (see the file comment). */
export interface MotionResult {
  awakeBodyFrames: number
  movingBodyFrames: number
  movedShare: number
  awakeMovedShare: number
  jumpPx: { p50: number; p99: number; max: number }
  kinkPx: { p50: number; p99: number }
  spawned: number
  bodiesAtEnd: number
}

/** Rain shapes on the page's scene for `seconds` and measure how its awake bodies move. */
export async function measureMotion(page: Page, seconds: number): Promise<MotionResult> {
  const r = (await page.evaluate(`(${MEASURE_MOTION})([${seconds * 1000}, ${SPAWNS_PER_SECOND}])`)) as {
    awake: number
    moved: number
    moving: number
    movingMoved: number
    jumps: number[]
    kinks: number[]
    spawned: number
    bodies: number
  }
  const round = (v: number): number => Math.round(v * 100) / 100
  const q = (values: number[], p: number): number => {
    if (values.length === 0) return Number.NaN
    const sorted = [...values].sort((a, b) => a - b)
    return sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))]
  }
  const jumps = summarize(r.jumps.length ? r.jumps : [0])
  return {
    awakeBodyFrames: r.awake,
    movingBodyFrames: r.moving,
    movedShare: round(r.movingMoved / Math.max(1, r.moving)),
    awakeMovedShare: round(r.moved / Math.max(1, r.awake)),
    jumpPx: { p50: round(jumps.median), p99: round(q(r.jumps, 0.99)), max: round(jumps.max) },
    kinkPx: { p50: round(q(r.kinks, 0.5)), p99: round(q(r.kinks, 0.99)) },
    spawned: r.spawned,
    bodiesAtEnd: r.bodies,
  }
}
