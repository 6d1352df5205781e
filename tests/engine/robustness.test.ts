/*
 * Robustness under the abuse a sandbox invites (issue 13), at the default settings with sleeping off
 * unless a test says otherwise. Every expectation comes from geometry or mechanics, not from a past
 * run: a stack's true rest height is the sum of its boxes' heights, a push-out speed is the world's
 * maxContactPushSpeed, a rolling disc accelerates at (2/3) g sin(theta).
 * Each test logs what it measured.
 */
import { describe, expect, it } from 'vitest'
import { decomposeOutline as decompose } from '../../engine/collision/decompose.ts'
import {
  box,
  buildScene,
  capsule,
  cardHouseScene,
  circle,
  cos,
  createWorld,
  DEFAULT_WORLD_DEF,
  groundDef,
  MAX_LINEAR_SPEED,
  PI,
  Prng,
  pileScene,
  polygon,
  STEP_SECONDS,
  segment,
  sin,
  type Vec2,
  type World,
} from '../../engine/index.ts'

const PUSH_SPEED = DEFAULT_WORLD_DEF.maxContactPushSpeed
const SLEEP_SPEED = DEFAULT_WORLD_DEF.sleepThreshold

function speed(world: World, id: number): number {
  const v = world.getLinearVelocity(id)
  return Math.hypot(v.x, v.y)
}

/** Steps `steps` times; returns the largest linear speed any of `ids` reached at the end of a step. */
function runTracking(world: World, ids: number[], steps: number): number {
  let fastest = 0
  for (let i = 0; i < steps; i++) {
    world.step()
    for (const id of ids) fastest = Math.max(fastest, speed(world, id))
  }
  return fastest
}

/** The largest distance of any body from where it was created. */
function worstDrift(world: World, ids: number[], starts: Vec2[]): number {
  let worst = 0
  ids.forEach((id, k) => {
    const p = world.getPosition(id)
    worst = Math.max(worst, Math.hypot(p.x - starts[k].x, p.y - starts[k].y))
  })
  return worst
}

describe('heavy on light', () => {
  for (const density of [100, 300]) {
    it(`a 10-row pyramid whose top box is ${density} times denser keeps its shape and flings nothing`, () => {
      const world = createWorld({ enableSleep: false })
      world.createBody(groundDef())
      const ids: number[] = []
      const starts: Vec2[] = []
      const rows = 10
      for (let r = 0; r < rows; r++) {
        for (let i = 0; i < rows - r; i++) {
          const p = { x: i - (rows - r - 1) / 2, y: 0.5 + r }
          ids.push(
            world.createBody({ position: p, shape: box(0.5, 0.5), density: r === rows - 1 ? density : 1 }),
          )
          starts.push(p)
        }
      }
      const fastest = runTracking(world, ids, 600)
      const drift = worstDrift(world, ids, starts)
      console.log(
        `heavy-topped pyramid x${density}: worst drift ${drift.toFixed(4)} m, fastest ${fastest.toFixed(3)} m/s`,
      )
      // Kept shape: no box moved by a tenth of its width (a crushed row drops by 1 m).
      expect(drift).toBeLessThan(0.1)
      // Nothing flung: slower than the push-out speed at all times.
      expect(fastest).toBeLessThan(PUSH_SPEED)
    })
  }
})

describe('a 400:1 box dropped onto two 1 m boxes', () => {
  // Ground top at y = 0; two 1 kg boxes (1 m) at x = -9 and 9; a 20 x 20 m box (400 kg) dropped with
  // its bottom 15 m up, so it lands at sqrt(2 g 14) = 16.7 m/s. True rest height of its centre:
  // 1 m box + 10 m half height = 11 m. Soft contacts sag by F K / omega^2 at rest (the solve's
  // steady state: massScale * biasRate * s = -impulseScale * K * lambda, with lambda = F h, gives
  // s = -F K / (h omega a1 * omega / a1) = -F K / omega^2), per point, with K the point's inverse
  // effective mass: a small box's ground points carry (4000 + 2 * 10) / 4 = 1005 N at 90 Hz (static
  // contacts are twice the 45 Hz contact stiffness) with K = 1/m + 0.5^2 / (m/6) = 2.5 per kg^-1, its
  // points under the heavy box 1000 N at 45 Hz with K = 2.5 + 1/400 + 9^2 / (400 * 800 / 12) = 2.5055.
  // Box2D v3 (box2d3-wasm 5.2.0, the same scene at its defaults) ends with the heavy box at 10.953 m
  // and still, after bouncing back up at 4.6 m/s, with the small boxes shoved 1.0 and 1.1 m outward
  // and one left tilted; this engine at 45 Hz before the extra sweeps over pinched contacts bounced
  // at 9 m/s, flung a small box out and ended at 10.56 m.
  const sag = (force: number, k: number, hertz: number) => (force * k) / (2 * PI * hertz) ** 2
  const hertz = Math.min(DEFAULT_WORLD_DEF.contactHertz, 0.25 * 4 * 60)
  const restHeight =
    11 - sag(1005, 2.5, 2 * hertz) - sag(1000, 2.5 + 1 / 400 + 81 / ((400 * 800) / 12), hertz)
  for (const [name, halfThickness] of [
    ['thin (1 cm)', 0.005],
    ['thick (2 m)', 1],
  ] as const) {
    it(`on ${name} ground it ends resting at its true height, still, the small boxes in place`, () => {
      const world = createWorld({ enableSleep: false })
      world.createBody({
        type: 'static',
        position: { x: 0, y: -halfThickness },
        shape: box(100, halfThickness),
      })
      const small = [-9, 9].map((x) => world.createBody({ position: { x, y: 0.5 }, shape: box(0.5, 0.5) }))
      const heavy = world.createBody({ position: { x: 0, y: 25 }, shape: box(10, 10) })
      expect(world.getMass(heavy) / world.getMass(small[0])).toBe(400)
      const ids = [...small, heavy]
      runTracking(world, ids, 480)
      const lateFastest = runTracking(world, ids, 120)
      const y = world.getPosition(heavy).y
      const offsets = small.map((id, k) => Math.abs(world.getPosition(id).x - [-9, 9][k]))
      const tilts = small.map((id) => Math.abs(world.getAngle(id)))
      console.log(
        `400:1 drop on ${name} ground: heavy centre ${y.toFixed(4)} m (hand rest height ${restHeight.toFixed(4)},` +
          ` true 11), fastest body over the last 2 s ${lateFastest.toFixed(4)} m/s, small boxes moved` +
          ` ${offsets.map((o) => o.toFixed(4)).join(' and ')} m, tilted ${tilts.map((t) => t.toFixed(4)).join(' and ')} rad`,
      )
      expect(Math.abs(y - restHeight)).toBeLessThan(0.005)
      expect(Math.abs(y - 11)).toBeLessThan(0.04)
      expect(lateFastest).toBeLessThan(0.01)
      for (const o of offsets) expect(o).toBeLessThan(0.05)
      for (const t of tilts) expect(t).toBeLessThan(0.01)
    })
  }
})

describe('deep overlap', () => {
  it('two boxes created 50 % overlapping on the ground part at no more than the push-out speed, then rest', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody(groundDef())
    const a = world.createBody({ position: { x: 0, y: 0.5 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 0.5, y: 0.5 }, shape: box(0.5, 0.5) })
    let fastestApart = 0
    let last = 0.5
    for (let i = 0; i < 300; i++) {
      world.step()
      const gap = world.getPosition(b).x - world.getPosition(a).x
      fastestApart = Math.max(fastestApart, (gap - last) / STEP_SECONDS)
      last = gap
    }
    console.log(
      `50 % overlap: separated to ${last.toFixed(4)} m, fastest parting ${fastestApart.toFixed(3)} m/s`,
    )
    expect(last).toBeGreaterThan(1 - 0.02) // apart, within the speculative distance
    expect(fastestApart).toBeLessThanOrEqual(PUSH_SPEED * 1.0001)
    expect(speed(world, a) + speed(world, b)).toBeLessThan(SLEEP_SPEED) // parted, then still
    expect(world.getPosition(a).y).toBeCloseTo(0.5, 2) // and still on the ground, not thrown up
  })

  for (const overlap of [0.25, 0.5]) {
    it(`a base-4 pyramid built with ${overlap * 100} % overlap ends at its true height (Solver2D overlap recovery)`, () => {
      const world = createWorld({ enableSleep: false })
      world.createBody(groundDef())
      const ids: number[] = []
      const fraction = 1 - overlap
      for (let row = 0; row < 4; row++) {
        for (let i = 0; i < 4 - row; i++) {
          const x = (i - (3 - row) / 2) * fraction
          ids.push(world.createBody({ position: { x, y: 0.5 + row * fraction }, shape: box(0.5, 0.5) }))
        }
      }
      const fastest = runTracking(world, ids, 600)
      const top = world.getPosition(ids[ids.length - 1])
      console.log(
        `overlap ${overlap}: top at ${top.y.toFixed(4)} m (true 3.5), fastest ${fastest.toFixed(3)} m/s`,
      )
      // Four rows of 1 m boxes: the top centre rests at 3.5 m, within 2 slops per contact below it.
      expect(Math.abs(top.y - 3.5)).toBeLessThan(0.05)
      // Each box is pushed out of at most two neighbours at the push-out speed each.
      expect(fastest).toBeLessThan(2 * PUSH_SPEED)
      for (const id of ids) expect(speed(world, id)).toBeLessThan(SLEEP_SPEED)
    })
  }
})

describe('overlap recovery on a segment ground (issue 27)', () => {
  // Box2D's OverlapRecovery sample: a base-4 pyramid of 1 m boxes built overlapping on a segment
  // (-40, 0)-(40, 0). The push-out cap (maxContactPushSpeed, 3 m/s) bounds each contact's bias, not
  // the speed at which its points part: Gauss-Seidel adds the pushes of neighbouring contacts and the
  // boxes turn, so corners part faster. Measure: relative normal velocity at each manifold point
  // after each step, 600 steps; Box2D v3 is box2d3-wasm 5.2.0 on the same scene at its defaults.
  // At 25 % overlap the cap hardly acts (0.25 m x massScale x biasRate = 3.2 m/s at 45 Hz): Box2D
  // parts points at 5.2157 m/s, this engine at 5.2603 (5.3484 with no cap at all). At 50 % it does:
  // Box2D 5.4101 m/s (manifold centres 4.7644, fastest body 3.9748, top 3.4982 m), this engine
  // 5.1026 (10.5627 without the cap, the pyramid knocked down). The bound is Box2D's figure + 5 %.
  const BOX2D_POINT_PARTING = 5.4101
  it('parts its contact points no faster than Box2D v3 (+5 %) and ends at its true height', () => {
    const world = createWorld({ enableSleep: false })
    const ground = world.createBody({ type: 'static', shape: segment({ x: -40, y: 0 }, { x: 40, y: 0 }) })
    const ids: number[] = []
    for (let row = 0; row < 4; row++) {
      for (let i = 0; i < 4 - row; i++) {
        const position = { x: (i - (3 - row) / 2) * 0.5, y: 0.5 + row * 0.5 }
        ids.push(world.createBody({ position, shape: box(0.5, 0.5) }))
      }
    }
    const pointVelocity = (id: number, x: number, y: number): Vec2 => {
      if (id === ground) return { x: 0, y: 0 }
      const v = world.getLinearVelocity(id)
      const w = world.getAngularVelocity(id)
      const c = world.getPosition(id)
      return { x: v.x - w * (y - c.y), y: v.y + w * (x - c.x) }
    }
    let parting = 0
    for (let i = 0; i < 600; i++) {
      world.step()
      for (const c of world.contacts()) {
        for (const p of c.points) {
          const a = pointVelocity(c.bodyA, p.point.x, p.point.y)
          const b = pointVelocity(c.bodyB, p.point.x, p.point.y)
          parting = Math.max(parting, (b.x - a.x) * c.normal.x + (b.y - a.y) * c.normal.y)
        }
      }
    }
    const top = world.getPosition(ids[ids.length - 1])
    console.log(
      `overlap 0.5 on a segment: fastest point parting ${parting.toFixed(4)} m/s (Box2D v3 ${BOX2D_POINT_PARTING}), top at ${top.y.toFixed(4)} m`,
    )
    expect(parting).toBeLessThan(1.05 * BOX2D_POINT_PARTING)
    expect(Math.abs(top.y - 3.5)).toBeLessThan(0.05)
    for (const id of ids) expect(speed(world, id)).toBeLessThan(SLEEP_SPEED)
  })
})

describe('thin shapes', () => {
  it('a card house (2 mm x 0.4 m cards at 25 degrees, friction 0.7) stands 10 s with sleeping off', () => {
    const scene = cardHouseScene(4)
    const world = createWorld({ enableSleep: false })
    const ids = buildScene(world, scene)
    const starts = scene.bodies.map((d) => d.position ?? { x: 0, y: 0 })
    for (let i = 0; i < 600; i++) world.step()
    const drift = worstDrift(world, ids.slice(1), starts.slice(1))
    console.log(`card house: worst card drift ${drift.toFixed(4)} m after 10 s`)
    expect(drift).toBeLessThan(0.05) // a fallen card moves by its own height, 0.4 m
  })

  for (const [name, hw, hh] of [
    ['planks (2 m x 4 cm)', 1, 0.02],
    ['rods (8 m x 10 cm)', 4, 0.05],
  ] as const) {
    it(`ten ${name} stacked flat stand at their true heights for 10 s`, () => {
      const world = createWorld({ enableSleep: false })
      world.createBody(groundDef())
      const ids: number[] = []
      for (let i = 0; i < 10; i++) {
        ids.push(world.createBody({ position: { x: (i % 2) * 0.1, y: hh + 2 * hh * i }, shape: box(hw, hh) }))
      }
      for (let i = 0; i < 600; i++) world.step()
      const top = world.getPosition(ids[9])
      const trueTop = hh + 18 * hh
      console.log(`${name}: top at ${top.y.toFixed(4)} m (true ${trueTop}), x ${top.x.toFixed(4)}`)
      expect(Math.abs(top.y - trueTop)).toBeLessThan(10 * 2 * 0.005)
      expect(Math.abs(top.x - 0.1)).toBeLessThan(0.01)
      for (const id of ids) expect(speed(world, id)).toBeLessThan(SLEEP_SPEED)
    })
  }
})

describe('tall stacks', () => {
  it('a 15-box stack dropped with 10 cm gaps stands for 60 s', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody(groundDef())
    const ids: number[] = []
    for (let i = 0; i < 15; i++)
      ids.push(world.createBody({ position: { x: 0, y: 0.5 + 1.1 * i }, shape: box(0.5, 0.5) }))
    let worst = 0
    for (let step = 1; step <= 3600; step++) {
      world.step()
      if (step % 600 === 0) {
        for (let i = 0; i < 15; i++) {
          const p = world.getPosition(ids[i])
          worst = Math.max(worst, Math.abs(p.x), Math.abs(p.y - (0.5 + i)))
        }
      }
    }
    console.log(`15-box dropped stack: worst offset from the true column over 60 s ${worst.toFixed(4)} m`)
    expect(worst).toBeLessThan(0.05)
    expect(speed(world, ids[14])).toBeLessThan(SLEEP_SPEED)
  })

  it('a 20-box tower with boxes alternately offset by 5 cm stands still for 10 s (Box2D v3: down by 10 s)', () => {
    // 1 m boxes at x = 0, 0.05, 0, ... (friction 0.6, as towerScene): every interface's load is
    // centred on its 0.95 m overlap, so rigid boxes stand forever. On soft contacts a face contact is
    // a rotational spring and the weight above pushes the column over: at 45 Hz the springs would
    // have to be 1.34 times stiffer (tests/engine/README.md "Robustness"; before contact-columns.ts the
    // tower was 0.24 m off at 10 s and down at about 17 s). "Stands still": every box within 2 cm of
    // its start x at every step of the 10 s (a falling column keeps going, a fallen box moves by
    // metres), and over the last 2 s every box slower than 0.01 m/s, a fifth of the sleep threshold.
    const world = createWorld({ enableSleep: false })
    world.createBody(groundDef())
    const starts: number[] = []
    const ids: number[] = []
    for (let i = 0; i < 20; i++) {
      starts.push((i % 2) * 0.05)
      ids.push(
        world.createBody({ position: { x: starts[i], y: 0.5 + i }, shape: box(0.5, 0.5), friction: 0.6 }),
      )
    }
    let worstX = 0
    let lateFastest = 0
    for (let step = 1; step <= 600; step++) {
      world.step()
      ids.forEach((id, i) => {
        worstX = Math.max(worstX, Math.abs(world.getPosition(id).x - starts[i]))
        if (step > 480) lateFastest = Math.max(lateFastest, speed(world, id))
      })
    }
    console.log(
      `alternating 20-box tower: worst sideways offset over 10 s ${worstX.toFixed(4)} m, fastest over the last 2 s ${lateFastest.toFixed(4)} m/s`,
    )
    expect(worstX).toBeLessThan(0.02)
    expect(lateFastest).toBeLessThan(SLEEP_SPEED / 5)
  })

  for (const [name, halfWidth, halfHeight, topDensity] of [
    ['boxes 0.4 m wide and 1 m tall', 0.2, 0.5, 1],
    ['1 m boxes, the top five 20 times denser', 0.5, 0.5, 20],
  ] as const) {
    it(`a 20-box column of ${name} stands still for 20 s (column stiffness from load and lever)`, () => {
      // At the 1 m boxes' 90 Hz these columns buckle (down at about 18 s and 10 s): a narrower
      // interface turns on a shorter lever, a heavier top pushes harder. extra-sweeps.ts weighs
      // each column and stiffens it as a column of 1 m boxes equally close to buckling.
      const world = createWorld({ enableSleep: false })
      world.createBody(groundDef())
      const ids: number[] = []
      for (let i = 0; i < 20; i++) {
        const density = i >= 15 ? topDensity : 1
        const position = { x: 0, y: halfHeight * (1 + 2 * i) }
        ids.push(world.createBody({ position, shape: box(halfWidth, halfHeight), density }))
      }
      let worstX = 0
      let lateFastest = 0
      for (let step = 1; step <= 1200; step++) {
        world.step()
        for (const id of ids) {
          worstX = Math.max(worstX, Math.abs(world.getPosition(id).x))
          if (step > 1080) lateFastest = Math.max(lateFastest, speed(world, id))
        }
      }
      console.log(
        `20-box column of ${name}: worst sideways offset over 20 s ${worstX.toFixed(4)} m, fastest over the last 2 s ${lateFastest.toFixed(4)} m/s`,
      )
      expect(worstX).toBeLessThan(0.04)
      expect(lateFastest).toBeLessThan(SLEEP_SPEED / 5)
    })
  }

  it('a 50-box alternating tower stands still for 20 s (stiffer contacts for taller columns)', () => {
    // The buckling factor grows as n^3: at the 20-box tower's 90 Hz a 50-box column is 5.4 times past
    // its buckling load (down within 10 s); contact-columns.ts stiffens taller columns as (n / 20)^1.5
    // (356 Hz at 50) with more sweeps. Same "stands still" as the 20-box tower, over 20 s.
    const world = createWorld({ enableSleep: false })
    world.createBody(groundDef())
    const ids: number[] = []
    for (let i = 0; i < 50; i++)
      ids.push(world.createBody({ position: { x: (i % 2) * 0.05, y: 0.5 + i }, shape: box(0.5, 0.5) }))
    let worstX = 0
    let lateFastest = 0
    for (let step = 1; step <= 1200; step++) {
      world.step()
      ids.forEach((id, i) => {
        worstX = Math.max(worstX, Math.abs(world.getPosition(id).x - (i % 2) * 0.05))
        if (step > 1080) lateFastest = Math.max(lateFastest, speed(world, id))
      })
    }
    console.log(
      `alternating 50-box tower: worst sideways offset over 20 s ${worstX.toFixed(4)} m, fastest over the last 2 s ${lateFastest.toFixed(4)} m/s`,
    )
    expect(worstX).toBeLessThan(0.02)
    expect(lateFastest).toBeLessThan(SLEEP_SPEED / 5)
  })
})

describe('piles fall asleep, balls still roll', () => {
  it('the 500-body mixed pile (sleeping on) is fully asleep within 10 s', () => {
    const world = createWorld()
    buildScene(world, pileScene(500))
    let asleepAt = -1
    for (let i = 1; i <= 600 && asleepAt < 0; i++) {
      world.step()
      if (world.awakeBodyCount() === 0) asleepAt = i
    }
    console.log(`pile 500: asleep at ${(asleepAt * STEP_SECONDS).toFixed(2)} s`)
    expect(asleepAt).toBeGreaterThan(0)
  })

  it('a 200-body pile of compound bodies and decomposed concave outlines (sleeping on) settles and is fully asleep within 10 s', () => {
    // Five kinds, 40 of each: decompose()d L (2 pieces), U (3) and five-pointed star (4 or more), a
    // dumbbell (two discs on a bar) and a capsule with a fin. Dropped in 20 rows of 10 into a 16 m
    // wide bin with a segment floor, at random angles (seeded).
    const world = createWorld()
    world.createBody({
      type: 'static',
      shapes: [
        { shape: segment({ x: -8, y: 0 }, { x: 8, y: 0 }) },
        { shape: box(0.25, 10, { x: -8.25, y: 10 }) },
        { shape: box(0.25, 10, { x: 8.25, y: 10 }) },
      ],
    })
    const outline = (points: number[]): Vec2[] =>
      points.flatMap((v, i) => (i % 2 === 0 ? [{ x: v, y: points[i + 1] }] : []))
    const L = outline([-0.5, -0.5, 0.5, -0.5, 0.5, -0.2, -0.2, -0.2, -0.2, 0.5, -0.5, 0.5])
    const U = outline([
      -0.6, -0.3, 0.6, -0.3, 0.6, 0.3, 0.35, 0.3, 0.35, -0.05, -0.35, -0.05, -0.35, 0.3, -0.6, 0.3,
    ])
    const star: Vec2[] = []
    for (let k = 0; k < 10; k++) {
      const r = k % 2 === 0 ? 0.55 : 0.25
      star.push({ x: r * cos((k * PI) / 5), y: r * sin((k * PI) / 5) })
    }
    const pieces = (points: Vec2[]) => decompose(points).map((p) => ({ shape: polygon(p) }))
    const kinds = [
      pieces(L),
      pieces(U),
      pieces(star),
      [
        { shape: circle(0.25, { x: -0.5, y: 0 }) },
        { shape: box(0.5, 0.08) },
        { shape: circle(0.25, { x: 0.5, y: 0 }) },
      ],
      [
        { shape: capsule({ x: -0.4, y: 0 }, { x: 0.4, y: 0 }, 0.15) },
        { shape: box(0.08, 0.3, { x: 0, y: 0.3 }) },
      ],
    ]
    for (const kind of kinds) expect(kind.length).toBeGreaterThan(1) // every body is a compound
    const prng = new Prng(11)
    const ids: number[] = []
    for (let i = 0; i < 200; i++) {
      const position = { x: -6.5 + (i % 10) * 1.45, y: 1 + Math.floor(i / 10) * 1.3 }
      ids.push(world.createBody({ position, angle: prng.range(-PI, PI), shapes: kinds[i % kinds.length] }))
    }
    let asleepAt = -1
    for (let i = 1; i <= 600 && asleepAt < 0; i++) {
      world.step()
      if (world.awakeBodyCount() === 0) asleepAt = i
    }
    let highest = 0
    for (const id of ids) {
      const p = world.getPosition(id)
      highest = Math.max(highest, p.y)
      expect(Math.abs(p.x)).toBeLessThan(8) // inside the bin
      expect(p.y).toBeGreaterThan(0) // above the floor
    }
    console.log(
      `compound pile 200: asleep at ${asleepAt < 0 ? 'never (10 s)' : `${(asleepAt * STEP_SECONDS).toFixed(2)} s`}, highest body at ${highest.toFixed(2)} m, ${world.contacts().length} contacts`,
    )
    expect(asleepAt).toBeGreaterThan(0)
    // Settled, not frozen mid-fall: the pile rests as a heap well below the drop height (26 m).
    expect(highest).toBeLessThan(15)
  })

  it('a ball rolls down a 30 degree ramp by the textbook distance (a = 2/3 g sin theta)', () => {
    const theta = PI / 6
    const world = createWorld({ enableSleep: false })
    world.createBody({
      type: 'static',
      position: { x: 0, y: 0 },
      angle: -theta,
      shape: box(40, 0.5),
      friction: 0.6,
    })
    const r = 0.5
    // Resting on the ramp's top face: 0.5 + r along the ramp normal (sin, cos) from a point up the slope.
    const along = -15
    const start = {
      x: along * cos(theta) + (0.5 + r) * sin(theta),
      y: -along * sin(theta) + (0.5 + r) * cos(theta),
    }
    const ball = world.createBody({ position: start, shape: circle(r), friction: 0.6 })
    const seconds = 2
    for (let i = 0; i < seconds * 60; i++) world.step()
    const p = world.getPosition(ball)
    const travelled = Math.hypot(p.x - start.x, p.y - start.y)
    const textbook = 0.5 * ((2 / 3) * 10 * sin(theta)) * seconds * seconds
    console.log(`rolling ball: ${travelled.toFixed(4)} m in ${seconds} s, textbook ${textbook.toFixed(4)} m`)
    // Rolls without slipping (friction 0.6 > tan(theta) / 3): the solid-disc distance within 1 %.
    expect(Math.abs(travelled - textbook) / textbook).toBeLessThan(0.01)
  })
})

describe('speed limits', () => {
  it('absurd impulses leave every body finite and within the linear and angular speed caps', () => {
    const world = createWorld({ enableSleep: false })
    world.createBody(groundDef())
    const ids = [
      world.createBody({ position: { x: 0, y: 1 }, shape: box(0.5, 0.5), density: 1e-6 }),
      world.createBody({ position: { x: 3, y: 1 }, shape: circle(0.01), density: 1e-6 }),
      world.createBody({ position: { x: -3, y: 1 }, shape: box(2, 0.01) }),
    ]
    const maxW = world.maxAngularSpeed
    const huge = [1e308, -1e308, 1e300, 5e15]
    for (let round = 0; round < 20; round++) {
      for (const id of ids) {
        const p = world.getPosition(id)
        const a = huge[round % 4]
        const b = huge[(round + 1) % 4]
        world.applyLinearImpulse(id, { x: a, y: b }, { x: p.x + 1e300, y: p.y - 1e300 })
        for (const v of [world.getLinearVelocity(id)]) {
          expect(Math.hypot(v.x, v.y)).toBeLessThanOrEqual(MAX_LINEAR_SPEED * (1 + 1e-12))
        }
        expect(Math.abs(world.getAngularVelocity(id))).toBeLessThanOrEqual(maxW)
      }
      if (round % 5 === 4) world.setLinearVelocity(ids[0], { x: 1e308, y: 1e308 })
      for (let i = 0; i < 10; i++) {
        world.step()
        for (const id of ids) {
          const p = world.getPosition(id)
          const v = world.getLinearVelocity(id)
          const w = world.getAngularVelocity(id)
          expect([p.x, p.y, v.x, v.y, w, world.getAngle(id)].every(Number.isFinite)).toBe(true)
          expect(Math.hypot(v.x, v.y)).toBeLessThanOrEqual(MAX_LINEAR_SPEED * (1 + 1e-12))
          expect(Math.abs(w)).toBeLessThanOrEqual(maxW)
        }
      }
    }
    console.log(
      `speed caps: ${MAX_LINEAR_SPEED} m/s, ${maxW.toFixed(2)} rad/s held under impulses up to 1e308 N s`,
    )
  })
})
