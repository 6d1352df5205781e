/*
 * The five-storey card house of issue 27 and the slender-shape rule that makes it stand
 * (constants.ts SLENDER_RATIO, collision/shapes.ts isSlender, dynamics/contact-solver.ts).
 *
 * Oracles: Box2D v3.1 (box2d3-wasm 5.2.0) keeps this house standing as built, its worst card
 * 3.5 cm from where it was made after 10 s; a fallen card moves by about its own height, 0.4 m
 * (this engine's house used to fall, its cards moving 1.8 m). Slenderness is checked against widths
 * and lengths computed by hand.
 */
import { execFile } from 'node:child_process'
import { mkdtempSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { promisify } from 'node:util'
import { build } from 'esbuild'
import { describe, expect, it } from 'vitest'
import { isSlender } from '../../engine/collision/shapes.ts'
import { SLENDER_RATIO } from '../../engine/constants.ts'
import { box, capsule, circle, createWorld, polygon, segment } from '../../engine/index.ts'
import { buildHouse, type runBattery, STANDING, STEPS, worstDrift } from './card-house-scene.ts'

/** runBattery() in a plain node process (the engine bundled with esbuild), for full speed. */
async function runBatteryInNode(): Promise<ReturnType<typeof runBattery>> {
  const dir = mkdtempSync(join(tmpdir(), 'concord-card-house-'))
  try {
    const file = join(dir, 'battery.mjs')
    await build({
      stdin: {
        contents:
          "import { runBattery } from './card-house-scene.ts'\nconsole.log(JSON.stringify(runBattery()))",
        resolveDir: fileURLToPath(new URL('.', import.meta.url)),
        loader: 'ts',
      },
      bundle: true,
      platform: 'node',
      format: 'esm',
      target: 'node20',
      outfile: file,
    })
    const { stdout } = await promisify(execFile)(process.execPath, [file], { maxBuffer: 1 << 20 })
    return JSON.parse(stdout)
  } finally {
    rmSync(dir, { recursive: true, force: true })
  }
}

describe('the five-storey card house (issue 27)', () => {
  it('stands 10 s as built with sleeping off (Box2D v3: 3.5 cm; before the slender rule: 1.8 m)', () => {
    const world = createWorld({ enableSleep: false })
    const { ids, defs } = buildHouse(world, { order: 0, mirrored: false, jitter: 0 })
    for (let i = 0; i < STEPS; i++) world.step()
    const drift = worstDrift(world, ids, defs)
    console.log(`5-storey card house as built: worst card ${drift.toFixed(4)} m after 10 s`)
    expect(drift).toBeLessThan(STANDING)
  })

  it('stands and falls asleep at the default settings', () => {
    const world = createWorld()
    const { ids, defs } = buildHouse(world, { order: 0, mirrored: false, jitter: 0 })
    let asleepAt = -1
    for (let i = 1; i <= STEPS && asleepAt < 0; i++) {
      world.step()
      if (world.awakeBodyCount() === 0) asleepAt = i
    }
    console.log(
      `5-storey card house, sleeping on: asleep at step ${asleepAt}, worst card ${worstDrift(world, ids, defs).toFixed(4)} m`,
    )
    expect(asleepAt).toBeGreaterThan(0)
    expect(worstDrift(world, ids, defs)).toBeLessThan(STANDING)
  })

  it('stands in 66 of 66 perturbed builds: 22 creation orders x as built, mirrored, jittered 0.3 mm', async () => {
    // Box2D v3.1 falls in 5 of the same 66 (creation order 12 as built and mirrored, orders 8, 11
    // and 18 jittered; issue 27 notes); this engine without the slender rule fell in 18.
    const runs = await runBatteryInNode()
    expect(runs.length).toBe(66)
    const fallen = runs
      .filter((r) => !(r.drift < STANDING))
      .map(
        (r) =>
          `order ${r.order}${r.mirrored ? ' mirrored' : ''}${r.jitter ? ' jittered' : ''}: ${r.drift.toFixed(3)} m`,
      )
    const worst = Math.max(...runs.map((r) => r.drift))
    console.log(`5-storey card house, 66 builds: ${fallen.length} fell; worst card ${worst.toFixed(4)} m`)
    expect(fallen).toEqual([])
  })
})

describe('slender shapes (isSlender: thickness < SLENDER_RATIO x length)', () => {
  it('is 1/20', () => {
    expect(SLENDER_RATIO).toBe(0.05)
  })

  it('boxes: thickness is the short side, length the diagonal', () => {
    // card: 0.002 / (2 sqrt(0.001^2 + 0.2^2)) = 0.005
    expect(isSlender(box(0.001, 0.2))).toBe(true)
    // 1 x 0.1 m plank: 0.1 / 2.0025 = 0.0499 (slender); 0.102 / 2.0026 = 0.0509 (not)
    expect(isSlender(box(1, 0.05))).toBe(true)
    expect(isSlender(box(1, 0.051))).toBe(false)
    expect(isSlender(box(0.5, 0.05))).toBe(false) // the bridge plank: 0.1 / 1.005 = 0.0995
    expect(isSlender(box(0.5, 0.5))).toBe(false)
    // turned and moved: the same answer
    expect(isSlender(box(1, 0.05, { x: 3, y: -2 }, 0.7))).toBe(true)
    expect(isSlender(box(1, 0.051, { x: 3, y: -2 }, 0.7))).toBe(false)
  })

  it('polygons: the least width over the edge normals, plus twice the rounding radius', () => {
    /** The triangle (0, 0), (1, 0), (x, y), rounded by `radius`. */
    const triangle = (x: number, y: number, radius = 0) =>
      polygon(
        [
          { x: 0, y: 0 },
          { x: 1, y: 0 },
          { x, y },
        ],
        radius,
      )
    // A sliver 1 m long and 1 cm high: least width 0.01 (across its base), length 1.
    expect(isSlender(triangle(0.5, 0.01))).toBe(true)
    // Rounded by 0.03 m: thickness 0.07, length 1.06: 0.066 (not slender).
    expect(isSlender(triangle(0.5, 0.01, 0.03))).toBe(false)
    // A right triangle with legs 1 and 0.06: least width is its height over the hypotenuse,
    // 0.06 / sqrt(1.0036) = 0.0599; length sqrt(1.0036) = 1.0018: 0.0598 (not slender).
    expect(isSlender(triangle(0, 0.06))).toBe(false)
    // Legs 1 and 0.045: 0.04495 / 1.001 = 0.0449 (slender).
    expect(isSlender(triangle(0, 0.045))).toBe(true)
  })

  it('capsules: the diameter against the length end to end; segments always; circles never', () => {
    // 2 r < 0.05 (2 + 2 r) <=> r < 0.0526
    expect(isSlender(capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.05))).toBe(true)
    expect(isSlender(capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.055))).toBe(false)
    expect(isSlender(segment({ x: 0, y: 0 }, { x: 0.01, y: 0 }))).toBe(true)
    expect(isSlender(circle(0.001))).toBe(false)
  })
})
