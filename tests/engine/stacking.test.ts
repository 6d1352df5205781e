/*
 * The stacking targets of issue 2 at the default settings (DEFAULT_WORLD_DEF: 4 sub-steps, contact
 * hertz 45, damping ratio 10, push speed 3 m/s, slop 0.005 m, sleep after 0.5 s below 0.05 m/s), in
 * simulated time.
 *
 * Definitions used below, so a pass means something precise:
 * - "stands": every box is within 0.05 m (5 % of its width) of its starting x, tilted less than
 *   0.02 rad, and at most 2 slops (0.01 m) per supporting contact below its starting height;
 *   a toppled or crushed stack moves boxes by tenths of a metre.
 * - "sleeps within T": every body is asleep at some step <= T / (1/60 s).
 * - "still" / "settles" (sleeping off): every body moves slower than the sleep threshold,
 *   0.05 m/s, i.e. it would be allowed to fall asleep.
 * Each test logs its measured numbers (sleep time, compression, drift, ...).
 *
 * Runtime: the 50-row pyramid (600 steps of 1,275 boxes) and the 1,000-body pile take the most,
 * measured 20 s and 9 s on the shared 2-core machine; everything else takes a few seconds together.
 */
import { describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  createWorld,
  DEFAULT_WORLD_DEF,
  groundDef,
  heavyOnLightScene,
  LINEAR_SLOP,
  pileScene,
  pyramidScene,
  type SceneBlueprint,
  STEP_SECONDS,
  towerScene,
  type World,
} from '../../engine/index.ts'
import { driftOver } from '../support/motion-measures.ts'

const SLEEP_SPEED = DEFAULT_WORLD_DEF.sleepThreshold

interface Built {
  world: World
  ids: number[]
  scene: SceneBlueprint
}

function build(scene: SceneBlueprint, enableSleep = true): Built {
  const world = createWorld({ enableSleep })
  return { world, ids: buildScene(world, scene), scene }
}

/** Steps until every body sleeps; returns the step count, or -1 after maxSteps. */
function stepsUntilAsleep({ world }: Built, maxSteps: number): number {
  for (let i = 1; i <= maxSteps; i++) {
    world.step()
    if (world.awakeBodyCount() === 0) return i
  }
  return -1
}

/** The worst violation of "stands" (see the header), or null; `row` gives a box's supporting contacts. */
function standViolation({ world, ids, scene }: Built, row: (index: number) => number): string | null {
  for (let i = 0; i < ids.length; i++) {
    const def = scene.bodies[i]
    if (def.type === 'static') continue
    const start = def.position ?? { x: 0, y: 0 }
    const p = world.getPosition(ids[i])
    const angle = world.getAngle(ids[i])
    const sink = start.y - p.y
    if (Math.abs(p.x - start.x) > 0.05) return `box ${i} moved ${p.x - start.x} m sideways`
    if (Math.abs(angle) > 0.02) return `box ${i} tilted ${angle} rad`
    if (sink > 2 * LINEAR_SLOP * (row(i) + 1) || sink < -0.01) return `box ${i} sank ${sink} m`
  }
  return null
}

/** Largest starting-height minus current height over the bodies (m). */
function maxSink({ world, ids, scene }: Built): number {
  let worst = 0
  for (let i = 0; i < ids.length; i++) {
    const def = scene.bodies[i]
    if (def.type === 'static') continue
    worst = Math.max(worst, (def.position?.y ?? 0) - world.getPosition(ids[i]).y)
  }
  return worst
}

/** Fastest linear speed (m/s) and angular speed (rad/s) of the dynamic bodies, and the kinetic energy (J). */
function motion(world: World, ids: number[]) {
  let maxSpeed = 0
  let maxSpin = 0
  let energy = 0
  let finite = true
  for (const id of ids) {
    if (world.getBodyType(id) !== 'dynamic') continue
    const v = world.getLinearVelocity(id)
    const w = world.getAngularVelocity(id)
    const p = world.getPosition(id)
    if (!Number.isFinite(p.x + p.y + v.x + v.y + w + world.getAngle(id))) finite = false
    maxSpeed = Math.max(maxSpeed, Math.hypot(v.x, v.y))
    maxSpin = Math.max(maxSpin, Math.abs(w))
    energy += 0.5 * world.getMass(id) * (v.x * v.x + v.y * v.y) + 0.5 * world.getInertia(id) * w * w
  }
  return { maxSpeed, maxSpin, energy, finite }
}

const towerRow = (i: number) => i - 1 // body 0 is the ground; box i rests on i - 1 contacts below it

describe('stacking with sleeping on (default settings)', () => {
  it('a 10-box aligned tower stands and falls asleep within 1.5 s', () => {
    const built = build(towerScene(10, false))
    const n = stepsUntilAsleep(built, 90)
    console.log(`10-box tower: asleep at ${(n * STEP_SECONDS).toFixed(3)} s, top sank ${maxSink(built)} m`)
    expect(n).toBeGreaterThan(0)
    expect(standViolation(built, towerRow)).toBeNull()
  })

  it('a 20-box staggered tower stands and falls asleep within 4 s', () => {
    const built = build(towerScene(20, true))
    const n = stepsUntilAsleep(built, 240)
    console.log(
      `20-box staggered tower: asleep at ${(n * STEP_SECONDS).toFixed(3)} s, sank ${maxSink(built)} m`,
    )
    expect(n).toBeGreaterThan(0)
    expect(standViolation(built, towerRow)).toBeNull()
  })

  it('a 20-row pyramid (210 boxes) stands and falls asleep (within 10 s)', () => {
    const built = build(pyramidScene(20))
    const n = stepsUntilAsleep(built, 600)
    console.log(`20-row pyramid: asleep at ${(n * STEP_SECONDS).toFixed(3)} s, sank ${maxSink(built)} m`)
    expect(n).toBeGreaterThan(0)
    // Box i of the pyramid sits in row floor-ish: rows hold 20, 19, ... boxes.
    const rowOf = (i: number) => {
      let k = i - 1
      let row = 0
      while (k >= 20 - row) k -= 20 - row++
      return row
    }
    expect(standViolation(built, rowOf)).toBeNull()
  })

  for (const drop of [0, 1]) {
    it(`a single box resting on the ground (dropped from ${drop} m) penetrates less than the slop`, () => {
      const world = createWorld()
      world.createBody(groundDef())
      const id = world.createBody({
        shape: box(0.5, 0.5),
        position: { x: 0, y: 0.5 + drop },
        angle: 0.01 * drop,
      })
      for (let i = 0; i < 180; i++) world.step()
      expect(world.isAwake(id)).toBe(false)
      // Lowest corner of the box from its pose (independent of the contact's reported separation).
      const p = world.getPosition(id)
      const q = world.getRotation(id)
      const lowest = p.y - 0.5 * Math.abs(q.c) - 0.5 * Math.abs(q.s)
      console.log(`single box (drop ${drop} m): penetration ${-lowest} m, slop ${LINEAR_SLOP} m`)
      expect(-lowest).toBeLessThan(LINEAR_SLOP)
      expect(-lowest).toBeGreaterThan(-LINEAR_SLOP) // resting, not hovering
    })
  }
})

describe('stacking with sleeping off for 10 s (default settings)', () => {
  // At Box2D's 30 Hz contact stiffness this tower leaned 0.40 m by 10 s and toppled at about 17 s;
  // at the 45 Hz default its top was 0.016 m off and the fastest body 0.006 m/s at 10 s; solved as a
  // column (contact-columns.ts, Nov 24) 0.011 m and 0.005 m/s.
  it('a 15-box stack dropped with 10 cm gaps ends standing and still', () => {
    const built = build(towerScene(15, false, 0.1), false)
    for (let i = 0; i < 600; i++) built.world.step()
    const { maxSpeed } = motion(built.world, built.ids)
    const top = built.world.getPosition(built.ids[15])
    console.log(`dropped 15-box stack at 10 s: top x ${top.x} m, fastest body ${maxSpeed} m/s`)
    // Dropped boxes start 0.1 m apart: allow their gaps on top of "stands" (0.1 m per box below).
    for (let i = 1; i < built.ids.length; i++) {
      const p = built.world.getPosition(built.ids[i])
      expect(Math.abs(p.x), `box ${i} x`).toBeLessThan(0.05)
      expect(Math.abs(built.world.getAngle(built.ids[i])), `box ${i} angle`).toBeLessThan(0.02)
      const expectedY = 0.5 + (i - 1) // resting on each other
      expect(Math.abs(p.y - expectedY), `box ${i} y`).toBeLessThan(2 * LINEAR_SLOP * i)
    }
    expect(maxSpeed).toBeLessThan(SLEEP_SPEED)
  })

  it('a 50-row pyramid (1,275 boxes) drifts less than 0.1 m between 5 s and 10 s', () => {
    const { world, ids } = build(pyramidScene(50), false)
    const drift = driftOver(world, ids, 300, 300)
    console.log(`50-row pyramid: largest drift between 5 s and 10 s ${drift} m`)
    expect(drift).toBeLessThan(0.1)
  })

  it('a 20 x 20 m box on two 1 m boxes (400:1) is held up: its centre stays above 10.7 m', () => {
    const { world, ids } = build(heavyOnLightScene(), false)
    const heavy = ids[3]
    expect(world.getMass(heavy) / world.getMass(ids[1])).toBe(400)
    let lowest = Number.POSITIVE_INFINITY
    for (let i = 0; i < 600; i++) {
      world.step()
      lowest = Math.min(lowest, world.getPosition(heavy).y)
    }
    console.log(`heavy on light: lowest centre ${lowest} m (rest height 11 m)`)
    expect(lowest).toBeGreaterThan(10.7)
  })

  describe('a pile of 1,000 mixed bodies', () => {
    let result: {
      finiteEverywhere: boolean
      last: ReturnType<typeof motion>
      worst: ReturnType<typeof motion>
    }
    const run = () => {
      if (result) return result
      const { world, ids } = build(pileScene(1000), false)
      let finiteEverywhere = true
      const worst = { maxSpeed: 0, maxSpin: 0, energy: 0, finite: true }
      let last = motion(world, ids)
      for (let i = 1; i <= 600; i++) {
        world.step()
        if (i % 60 === 0 || i > 570) {
          last = motion(world, ids)
          finiteEverywhere &&= last.finite
          if (i > 570) {
            worst.maxSpeed = Math.max(worst.maxSpeed, last.maxSpeed)
            worst.maxSpin = Math.max(worst.maxSpin, last.maxSpin)
            worst.energy = Math.max(worst.energy, last.energy)
          }
        }
      }
      result = { finiteEverywhere, last, worst }
      console.log(`pile 1000, last 0.5 s of 10 s: ${JSON.stringify(worst)}`)
      return result
    }

    it('stays finite for 10 s', () => {
      expect(run().finiteEverywhere).toBe(true)
    })

    // At 30 Hz one small square under the pile rocked on a corner forever (0.5-0.8 m/s); at the
    // 45 Hz default the fastest body moves 0.0002 m/s in the last 0.5 s, energy 7e-9 J.
    it('settles: in the last 0.5 s every body is slower than 0.05 m/s and 0.2 rad/s, energy < 0.01 J', () => {
      const { worst } = run()
      expect(worst.maxSpeed).toBeLessThan(SLEEP_SPEED)
      expect(worst.maxSpin).toBeLessThan(0.2)
      expect(worst.energy).toBeLessThan(0.01)
    })
  })
})
