/*
 * The marble-run scene (engine/scenes/scenes.ts): marbles arrive in the bin, and the bin sensor's
 * begin and end events agree, step by step, with a brute-force overlap test of every marble's shape
 * against the sensor box (circle: distance from the centre to the box; capsule: distance from its
 * core segment to the box, zero if they cross). And a save in the middle of the run continues
 * bit-identically, events included.
 */
import { describe, expect, it } from 'vitest'
import {
  buildScene,
  type CapsuleShape,
  createWorld,
  loadWorld,
  MARBLE_RUN_BALLS,
  MARBLE_RUN_CAPSULES,
  MARBLE_RUN_LAYOUT,
  marbleRunScene,
  SCENES,
  type Vec2,
  type World,
} from '../../engine/index.ts'

const L = MARBLE_RUN_LAYOUT

/** Distance from p to the sensor box (0 inside). */
function boxDistance(p: Vec2): number {
  const dx = Math.max(L.binLeft - p.x, 0, p.x - L.binRight)
  const dy = Math.max(0 - p.y, 0, p.y - L.sensorTop)
  return Math.hypot(dx, dy)
}

/** Distance from segment a-b to the sensor box: 0 if it enters it, else the least over ends and corners. */
function segmentBoxDistance(a: Vec2, b: Vec2): number {
  // Sampling is not exact; instead clip the segment to the box (Liang-Barsky) to see if it enters.
  let t0 = 0
  let t1 = 1
  const dx = b.x - a.x
  const dy = b.y - a.y
  const clip = (p: number, q: number): boolean => {
    if (p === 0) return q >= 0
    const r = q / p
    if (p < 0) t0 = Math.max(t0, r)
    else t1 = Math.min(t1, r)
    return t0 <= t1
  }
  if (
    clip(-dx, a.x - L.binLeft) &&
    clip(dx, L.binRight - a.x) &&
    clip(-dy, a.y - 0) &&
    clip(dy, L.sensorTop - a.y)
  )
    return 0
  const corners = [
    { x: L.binLeft, y: 0 },
    { x: L.binRight, y: 0 },
    { x: L.binRight, y: L.sensorTop },
    { x: L.binLeft, y: L.sensorTop },
  ]
  let best = Math.min(boxDistance(a), boxDistance(b))
  for (const c of corners) {
    const t = Math.max(0, Math.min(1, ((c.x - a.x) * dx + (c.y - a.y) * dy) / (dx * dx + dy * dy)))
    best = Math.min(best, Math.hypot(a.x + t * dx - c.x, a.y + t * dy - c.y))
  }
  return best
}

interface Run {
  world: World
  marbles: number[]
  sensor: number
  /** Shape id -> body id of the marbles. */
  bodyOf: Map<number, number>
}

function start(): Run {
  const world = createWorld()
  const scene = marbleRunScene()
  const ids = buildScene(world, scene)
  const marbles = ids.slice(1, scene.bodies.length)
  // The bin is the last body: two walls, then the sensor.
  const sensor = world.bodyShapes(ids[ids.length - 1])[2]
  const bodyOf = new Map(marbles.map((m) => [world.bodyShapes(m)[0], m]))
  return { world, marbles, sensor, bodyOf }
}

/** The marbles that overlap the sensor box now, by brute force. */
function overlapping(run: Run): Set<number> {
  const inside = new Set<number>()
  for (const m of run.marbles) {
    const shape = run.world.getShapeGeometry(run.world.bodyShapes(m)[0])
    const p = run.world.getPosition(m)
    const angle = run.world.getAngle(m)
    let gap: number
    if (shape.type === 'circle') gap = boxDistance(p) - shape.radius
    else {
      const v = (shape as CapsuleShape).vertices
      const world = v.map((q) => ({
        x: p.x + Math.cos(angle) * q.x - Math.sin(angle) * q.y,
        y: p.y + Math.sin(angle) * q.x + Math.cos(angle) * q.y,
      }))
      gap = segmentBoxDistance(world[0], world[1]) - shape.radius
    }
    if (gap < -1e-6) inside.add(m)
    else if (gap < 1e-6) return new Set([-1]) // too close to call: the caller skips this step
  }
  return inside
}

describe('marble run', () => {
  it('is listed in SCENES and builds 18 marbles, four chain tracks and the bin', () => {
    expect(SCENES['marble-run'].make().name).toBe('marble-run')
    const run = start()
    expect(run.marbles.length).toBe(MARBLE_RUN_BALLS + MARBLE_RUN_CAPSULES)
    expect(run.world.getShapeGeometry(run.sensor).type).toBe('polygon')
    // Four tracks of chain segments.
    const chainSegments = run.world
      .bodyIds()
      .flatMap((b) => run.world.bodyShapes(b))
      .filter((s) => run.world.getShapeGeometry(s).type === 'chainSegment')
    expect(chainSegments.length).toBeGreaterThan(4 * 40)
  })

  it('every marble arrives within 40 s; the sensor events track a brute-force overlap test at every step', () => {
    const run = start()
    const visitors = new Set<number>()
    const arrived = new Set<number>()
    let begins = 0
    let checked = 0
    for (let step = 1; step <= 40 * 60; step++) {
      run.world.step()
      const events = run.world.sensorEvents()
      for (const e of events.begin) {
        expect(e.sensor).toBe(run.sensor)
        const body = run.bodyOf.get(e.visitor)
        expect(body, `visitor ${e.visitor} is a marble`).toBeDefined()
        visitors.add(body as number)
        arrived.add(body as number)
        begins++
      }
      for (const e of events.end) visitors.delete(run.bodyOf.get(e.visitor) as number)
      const truth = overlapping(run)
      if (truth.has(-1)) continue
      checked++
      expect(
        [...visitors].sort((a, b) => a - b),
        `step ${step}`,
      ).toEqual([...truth].sort((a, b) => a - b))
    }
    expect(checked).toBeGreaterThan(2300)
    expect(arrived.size).toBe(MARBLE_RUN_BALLS + MARBLE_RUN_CAPSULES)
    expect(begins).toBeGreaterThanOrEqual(arrived.size)
  })

  it('a save at 12 s continues bit-identically for 10 s, sensor events included', () => {
    const a = start().world
    for (let i = 0; i < 12 * 60; i++) a.step()
    const b = loadWorld(a.save())
    expect(b.hash()).toBe(a.hash())
    for (let i = 0; i < 10 * 60; i++) {
      a.step()
      b.step()
      expect(b.hash(), `step ${i}`).toBe(a.hash())
      expect(b.sensorEvents()).toEqual(a.sensorEvents())
      expect(b.contactEvents()).toEqual(a.contactEvents())
    }
  })
})
