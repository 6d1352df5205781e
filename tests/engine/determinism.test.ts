/*
 * Determinism: the property the server, lockstep clients and replays rely on.
 *
 * - Two runs of the 600-step mixed scene (determinism-fixtures.ts: every shape kind, joints,
 *   sleeping, scripted inputs) are bit-identical: every body's position, angle, velocities and
 *   awake flag, compared with Object.is, and the state hash at every step.
 * - A golden hash of that scene at step 600 is pinned. If an engine change moves it on purpose,
 *   the failure message prints the new value to paste into GOLDEN_HASH.
 * - Save at step N, loadWorld, continue: the hashes agree at every later step, also for bytes
 *   saved while some islands sleep and others do not, while sleep timers run, and while a mouse
 *   joint and revolute joints are active. Broken bytes throw WorldLoadError with a clear message.
 * - The fixed stepper turns 30, 60, 144 fps and an uneven frame sequence into exactly the steps
 *   that integer arithmetic predicts, and the same steps give the same hash as plain stepping.
 */
import { beforeAll, describe, expect, it } from 'vitest'
import {
  box,
  buildScene,
  capsule,
  circle,
  createWorld,
  FixedStepper,
  loadWorld,
  polygon,
  SAVE_FORMAT_VERSION,
  segment,
  towerScene,
  type World,
  WorldLoadError,
} from '../../engine/index.ts'
import {
  buildMachines,
  buildMixedScene,
  driveMachines,
  GOLDEN_HASH,
  GOLDEN_STEPS,
  hex,
  type MixedHandles,
  runMixedScene,
} from './determinism-fixtures.ts'

interface BodyState {
  id: number
  x: number
  y: number
  angle: number
  c: number
  s: number
  vx: number
  vy: number
  w: number
  awake: boolean
}

function bodyStates(world: World): BodyState[] {
  return world.bodyIds().map((id) => {
    const p = world.getPosition(id)
    const v = world.getLinearVelocity(id)
    const q = world.getRotation(id)
    const awake = world.isAwake(id)
    return {
      id,
      x: p.x,
      y: p.y,
      angle: world.getAngle(id),
      c: q.c,
      s: q.s,
      vx: v.x,
      vy: v.y,
      w: world.getAngularVelocity(id),
      awake,
    }
  })
}

/** The first field that differs bit for bit between two state lists, or null. */
function firstDifference(a: BodyState[], b: BodyState[]): string | null {
  if (a.length !== b.length) return `${a.length} bodies vs ${b.length}`
  for (let i = 0; i < a.length; i++) {
    for (const key of Object.keys(a[i]) as (keyof BodyState)[]) {
      if (!Object.is(a[i][key], b[i][key])) return `body ${a[i].id} ${key}: ${a[i][key]} vs ${b[i][key]}`
    }
  }
  return null
}

interface Run {
  hashes: number[]
  states: BodyState[]
  saves: Map<number, { bytes: Uint8Array; handles: MixedHandles; awake: number; bodies: number }>
}

/** Runs the mixed scene for 600 steps, recording the hash after every step and saves at `saveAt`. */
function runMixed(saveAt: number[] = []): Run {
  const world = createWorld()
  const handles = buildMixedScene(world)
  const hashes = [world.hash()]
  const saves: Run['saves'] = new Map()
  while (world.tick < GOLDEN_STEPS) {
    runMixedScene(world, handles, world.tick + 1)
    hashes.push(world.hash())
    if (saveAt.includes(world.tick)) {
      saves.set(world.tick, {
        bytes: world.save(),
        handles: { ...handles },
        awake: world.awakeBodyCount(),
        bodies: world.bodyCount,
      })
    }
  }
  return { hashes, states: bodyStates(world), saves }
}

describe('the mixed scene', () => {
  const saveTicks = [100, 250, 520]
  let first: Run
  let second: Run
  beforeAll(() => {
    first = runMixed()
    second = runMixed(saveTicks)
  })

  it('two runs are bit-identical at every step and in every body state at step 600', () => {
    expect(second.hashes.length).toBe(GOLDEN_STEPS + 1)
    const diverged = first.hashes.findIndex((h, i) => h !== second.hashes[i])
    expect(diverged, `hashes diverge at step ${diverged}`).toBe(-1)
    expect(firstDifference(first.states, second.states)).toBeNull()
    expect(first.states.some((s) => s.awake)).toBe(true)
    expect(first.states.some((s) => !s.awake)).toBe(true)
  })

  it('matches the pinned golden hash at step 600', () => {
    const actual = first.hashes[GOLDEN_STEPS]
    if (actual !== GOLDEN_HASH)
      console.log(`golden hash changed: actual ${hex(actual)}, pinned ${hex(GOLDEN_HASH)}`)
    expect(hex(actual), `golden hash changed: set GOLDEN_HASH = ${hex(actual)} if intended`).toBe(
      hex(GOLDEN_HASH),
    )
  })

  for (const tick of saveTicks) {
    it(`save at step ${tick}, load, continue: the hash agrees at every later step`, () => {
      const save = second.saves.get(tick)!
      const world = loadWorld(save.bytes)
      expect(world.tick).toBe(tick)
      expect(world.hash()).toBe(first.hashes[tick])
      expect(world.save()).toEqual(save.bytes)
      const handles = { ...save.handles }
      while (world.tick < GOLDEN_STEPS) {
        runMixedScene(world, handles, world.tick + 1)
        expect(world.hash(), `step ${world.tick}`).toBe(first.hashes[world.tick])
      }
      expect(firstDifference(bodyStates(world), first.states)).toBeNull()
    })
  }

  it('the saves cover an active mouse joint (100), revolute joints (all) and a half-asleep world (520)', () => {
    const s100 = second.saves.get(100)!
    expect(s100.handles.mouse).toBeGreaterThan(0)
    expect(loadWorld(s100.bytes).jointIds()).toContain(s100.handles.mouse)
    const s520 = second.saves.get(520)!
    expect(s520.awake).toBeGreaterThan(0)
    expect(s520.awake).toBeLessThan(s520.bodies - 3) // the statics never count as awake
    const loaded = loadWorld(s520.bytes)
    expect(loaded.awakeBodyCount()).toBe(s520.awake)
  })
})

describe('save and load around sleep', () => {
  function tower(): World {
    const world = createWorld()
    buildScene(world, towerScene(10, false))
    return world
  }

  /** Steps both worlds `n` times; returns the step at which `a` fell asleep (or -1) after checking hashes. */
  function stepBoth(a: World, b: World, n: number): number {
    let asleepAt = -1
    for (let i = 0; i < n; i++) {
      a.step()
      b.step()
      expect(b.hash(), `step ${a.tick}`).toBe(a.hash())
      expect(b.awakeBodyCount()).toBe(a.awakeBodyCount())
      if (asleepAt < 0 && a.awakeBodyCount() === 0) asleepAt = a.tick
    }
    return asleepAt
  }

  it('bytes saved while sleep timers run (tower not yet asleep) fall asleep at the same step', () => {
    const original = tower()
    for (let i = 0; i < 35; i++) original.step()
    expect(original.awakeBodyCount()).toBeGreaterThan(0)
    const copy = loadWorld(original.save())
    expect(stepBoth(original, copy, 60)).toBeGreaterThan(35)
    expect(original.awakeBodyCount()).toBe(0)
  })

  it('bytes saved while asleep wake identically when pushed', () => {
    const original = tower()
    for (let i = 0; i < 120; i++) original.step()
    expect(original.awakeBodyCount()).toBe(0)
    const copy = loadWorld(original.save())
    const ids = original.bodyIds()
    for (const w of [original, copy]) w.applyLinearImpulse(ids[9], { x: 4, y: 0 }, { x: 0, y: 9.9 })
    expect(copy.awakeBodyCount()).toBe(original.awakeBodyCount())
    expect(original.awakeBodyCount()).toBe(10)
    stepBoth(original, copy, 120)
  })
})

describe('save and load of a tall column', () => {
  it('a 40-box staggered tower (stiffened column contacts, extra sweeps) saved mid-run continues bit for bit', () => {
    // The column stiffness is derived state (contact-columns.ts, from the settings and the contact
    // graph of each step), not saved: a loaded world must rebuild it exactly.
    const original = createWorld({ enableSleep: false })
    buildScene(original, towerScene(40, true))
    for (let i = 0; i < 300; i++) original.step()
    const copy = loadWorld(original.save())
    for (let i = 0; i < 600; i++) {
      original.step()
      copy.step()
      expect(copy.hash(), `step ${original.tick}`).toBe(original.hash())
    }
    // Still a standing column at the end (so the stiffened path ran): the top box within 5 cm.
    const top = original.bodyIds()[40]
    expect(Math.abs(original.getPosition(top).x - 0.1)).toBeLessThan(0.05)
  })
})

describe('save and load of every joint kind (the machines scene)', () => {
  /**
   * Every joint kind with its springs, motors and limits, a bridge that breaks at step 44, and
   * scripted setter calls (motor speeds, a motor joint's moving offset, a slider's and a sprung
   * pin's targets) applied by tick, so the saved setter state matters too.
   */
  function machines(): World {
    const world = createWorld()
    buildMachines(world)
    return world
  }
  const drive = driveMachines

  it('two runs are bit-identical, the bridge breaks the same, and saves at 30, 44, 45, 150 and 400 continue bit for bit', () => {
    const a = machines()
    const b = machines()
    const copies: World[] = []
    const brokenA: number[] = []
    for (let i = 0; i < 700; i++) {
      drive(a)
      drive(b)
      for (const c of copies) drive(c)
      a.step()
      b.step()
      for (const c of copies) c.step()
      brokenA.push(...a.jointEvents().broken)
      expect(b.hash(), `step ${a.tick}`).toBe(a.hash())
      expect(b.jointEvents().broken).toEqual(a.jointEvents().broken)
      for (const c of copies) {
        expect(c.hash(), `copy, step ${a.tick}`).toBe(a.hash())
        expect(c.jointEvents().broken).toEqual(a.jointEvents().broken)
      }
      if ([30, 44, 45, 150, 400].includes(a.tick)) copies.push(loadWorld(a.save()))
    }
    expect(brokenA.length).toBeGreaterThan(0)
    const kinds = new Set(a.joints().map((j) => j.type))
    for (const kind of ['revolute', 'distance', 'weld', 'prismatic', 'wheel', 'motor'])
      expect(kinds.has(kind as never)).toBe(true)
  })

  it('a mouse joint with a break threshold and a revolute spring survive save and load', () => {
    const a = machines()
    const ids = a.bodyIds()
    const grab = a.createJoint({ type: 'mouse', body: ids[5], target: { x: -30, y: 3 }, breakForce: 1e6 })
    for (let i = 0; i < 60; i++) a.step()
    const b = loadWorld(a.save())
    for (let i = 0; i < 120; i++) {
      a.setJointTarget(grab, { x: -30 + 0.01 * i, y: 3 })
      b.setJointTarget(grab, { x: -30 + 0.01 * i, y: 3 })
      a.step()
      b.step()
      expect(b.hash()).toBe(a.hash())
    }
  })

  it('settings changed by setJointSettings on every joint kind at step 60 are saved: a copy saved at 61 continues bit for bit', () => {
    const a = machines()
    let copy: World | null = null
    for (let i = 0; i < 300; i++) {
      drive(a)
      if (copy) drive(copy)
      if (a.tick === 60) {
        for (const j of a.joints()) {
          if (j.type === 'revolute')
            a.setJointSettings(j.id, {
              enableLimit: true,
              lowerAngle: -0.4,
              upperAngle: 0.3,
              maxMotorTorque: 7,
            })
          else if (j.type === 'distance')
            a.setJointSettings(j.id, { hertz: 3, dampingRatio: 0.2, breakForce: 1e5 })
          else if (j.type === 'weld') a.setJointSettings(j.id, { angularHertz: 4, linearHertz: 6 })
          else if (j.type === 'prismatic')
            a.setJointSettings(j.id, { enableLimit: true, lower: -0.5, upper: 0.5, maxMotorForce: 40 })
          else if (j.type === 'wheel')
            a.setJointSettings(j.id, {
              hertz: 3,
              maxMotorTorque: 20,
              enableLimit: true,
              lower: -0.2,
              upper: 0.2,
            })
          else if (j.type === 'motor')
            a.setJointSettings(j.id, { maxForce: 50, maxTorque: 5, correctionFactor: 0.5 })
        }
      }
      a.step()
      if (copy) {
        copy.step()
        expect(copy.hash(), `copy, step ${a.tick}`).toBe(a.hash())
      }
      if (a.tick === 61) {
        copy = loadWorld(a.save())
        for (const j of a.joints()) expect(copy.getJointDef(j.id)).toEqual(a.getJointDef(j.id))
      }
    }
  })

  it('a save of format 1, 2 or 3 is refused naming both versions', () => {
    expect(SAVE_FORMAT_VERSION).toBe(4)
    for (const version of [1, 2, 3]) {
      const bytes = createWorld().save()
      new DataView(bytes.buffer, bytes.byteOffset).setUint16(4, version, true)
      let message = ''
      try {
        loadWorld(bytes)
      } catch (error) {
        expect(error).toBeInstanceOf(WorldLoadError)
        message = (error as Error).message
      }
      expect(message).toBe(`saved world has format version ${version}; this engine reads version 4`)
    }
  })
})

describe('loadWorld on broken bytes', () => {
  let good: Uint8Array
  beforeAll(() => {
    const world = createWorld()
    buildScene(world, towerScene(3, true))
    world.createJoint({ type: 'revolute', bodyA: null, bodyB: world.bodyIds()[3], anchor: { x: 0, y: 3 } })
    for (let i = 0; i < 10; i++) world.step()
    good = world.save()
  })

  function loadError(bytes: Uint8Array): WorldLoadError {
    try {
      loadWorld(bytes)
    } catch (e) {
      expect(e).toBeInstanceOf(WorldLoadError)
      return e as WorldLoadError
    }
    throw new Error(`loadWorld accepted ${bytes.length} broken bytes`)
  }

  it('the intact bytes load', () => {
    expect(loadWorld(good).save()).toEqual(good)
  })

  it('empty bytes throw a clear WorldLoadError', () => {
    expect(loadError(new Uint8Array(0)).message).toMatch(/truncated/)
  })

  it('every truncation throws a clear WorldLoadError', () => {
    for (let n = 0; n < good.length; n++) {
      expect(loadError(good.subarray(0, n)).message, `truncated to ${n}`).toMatch(/truncated/)
    }
  })

  it('trailing bytes throw a clear WorldLoadError', () => {
    const longer = new Uint8Array(good.length + 3)
    longer.set(good)
    expect(loadError(longer).message).toMatch(/trailing/)
  })

  it('every single-bit flip in the magic, version, length, checksum or payload throws', () => {
    let flips = 0
    for (let i = 0; i < good.length; i++) {
      if (i === 6 || i === 7) continue // reserved, see below
      for (let bit = 0; bit < 8; bit++) {
        const bad = good.slice()
        bad[i] ^= 1 << bit
        expect(loadError(bad).message, `byte ${i} bit ${bit}`).toMatch(
          /magic|version|truncated|trailing|corrupt/,
        )
        flips++
      }
    }
    expect(flips).toBeGreaterThan(1000)
  })

  it('a flip in the reserved header bytes throws', () => {
    for (const i of [6, 7]) {
      const bad = good.slice()
      bad[i] ^= 1
      loadError(bad)
    }
  })

  it('another format version throws a WorldLoadError naming both versions', () => {
    const other = good.slice()
    new DataView(other.buffer).setUint16(4, SAVE_FORMAT_VERSION + 1, true)
    const message = loadError(other).message
    expect(message).toMatch(/version/)
    expect(message).toContain(String(SAVE_FORMAT_VERSION + 1))
    expect(message).toContain(String(SAVE_FORMAT_VERSION))
  })

  it('bytes that are not a saved world at all throw', () => {
    const text = new TextEncoder().encode('{"bodies": []} this is not a saved world')
    expect(loadError(text).message).toMatch(/magic|truncated/)
  })
})

describe('FixedStepper', () => {
  /** Steps a tower world as the stepper says for every frame; returns the world and step counts. */
  function drive(frames: number[]) {
    const stepper = new FixedStepper()
    const world = createWorld()
    buildScene(world, towerScene(5, true))
    const counts: number[] = []
    let total = 0
    for (const frame of frames) {
      const n = stepper.advance(frame)
      for (let i = 0; i < n; i++) world.step()
      total += n
      counts.push(total)
      expect(stepper.alpha).toBeGreaterThanOrEqual(0)
      expect(stepper.alpha).toBeLessThan(1)
    }
    return { world, counts }
  }

  function plainHash(steps: number): number {
    const world = createWorld()
    buildScene(world, towerScene(5, true))
    for (let i = 0; i < steps; i++) world.step()
    return world.hash()
  }

  for (const fps of [30, 60, 144]) {
    it(`${fps} fps for 5 s: after frame k exactly floor(k * 60 / ${fps}) steps, and plain stepping's hash`, () => {
      const frames = new Array(5 * fps).fill(1 / fps)
      const { world, counts } = drive(frames)
      for (let k = 0; k < counts.length; k++) {
        expect(counts[k], `frame ${k + 1}`).toBe(Math.floor(((k + 1) * 60) / fps))
      }
      expect(world.tick).toBe(300)
      expect(world.hash()).toBe(plainHash(300))
    })
  }

  it('an uneven frame sequence (whole milliseconds) gives floor(total ms * 60 / 1000) steps and the same hash', () => {
    const ms = [16, 17, 16, 33, 8, 50, 1, 16, 100, 7, 16, 16, 17, 34, 2, 3, 250, 16, 5, 60]
    const frames: number[] = []
    for (let i = 0; i < 12; i++) frames.push(...ms)
    const { world, counts } = drive(frames.map((m) => m / 1000))
    let totalMs = 0
    frames.forEach((m, k) => {
      totalMs += m
      expect(counts[k], `frame ${k + 1}`).toBe(Math.floor((totalMs * 60) / 1000))
    })
    expect(world.hash()).toBe(plainHash(world.tick))
  })

  it('caps catch-up at 0.25 s: a 5 s stall yields 15 steps, never a spiral', () => {
    const stepper = new FixedStepper()
    expect(stepper.advance(5)).toBe(15)
    expect(stepper.alpha).toBeGreaterThanOrEqual(0)
    expect(stepper.alpha).toBeLessThan(1)
    expect(stepper.advance(0.25)).toBeLessThanOrEqual(16)
    expect(stepper.advance(0)).toBe(0)
    expect(stepper.advance(-1)).toBe(0)
    expect(stepper.advance(Number.NaN)).toBe(0)
  })

  it('reports alpha in [0, 1) as the fraction of a step left over', () => {
    const stepper = new FixedStepper()
    expect(stepper.advance(0.5 / 60)).toBe(0)
    expect(Math.abs(stepper.alpha - 0.5)).toBeLessThan(1e-9)
    expect(stepper.advance(0.75 / 60)).toBe(1)
    expect(Math.abs(stepper.alpha - 0.25)).toBeLessThan(1e-9)
  })
})

describe('save/load with every shape kind, compound bodies, filters, sensors and events', () => {
  /** A machine of every kind: segment floor, compound carts, capsules, rounded and offset shapes, two sensors. */
  function build(): World {
    const world = createWorld()
    world.createBody({
      type: 'static',
      shapes: [
        { shape: segment({ x: -8, y: 0 }, { x: 8, y: 0 }) },
        { shape: box(0.2, 3, { x: -8, y: 3 }) },
        { shape: box(0.2, 3, { x: 8, y: 3 }, 0.1) },
        { shape: box(2, 1, { x: 0, y: 1 }), sensor: true },
      ],
    })
    world.createBody({
      type: 'kinematic',
      position: { x: 3, y: 3 },
      angularVelocity: 2,
      shapes: [{ shape: capsule({ x: -1.5, y: 0 }, { x: 1.5, y: 0 }, 0.2), sensor: true }],
    })
    for (let i = 0; i < 24; i++) {
      const x = -6 + (i % 8) * 1.6
      const y = 1 + Math.floor(i / 8) * 1.5
      const filter = {
        categoryBits: 1 << (i % 3),
        maskBits: i % 5 === 0 ? 0xfffffffd : 0xffffffff,
        groupIndex: i % 7 === 0 ? -1 : 0,
      }
      const shapes =
        i % 4 === 0
          ? [
              { shape: circle(0.25, { x: -0.4, y: 0 }) },
              { shape: box(0.4, 0.1) },
              { shape: circle(0.25, { x: 0.4, y: 0 }) },
            ]
          : i % 4 === 1
            ? [{ shape: capsule({ x: -0.3, y: 0 }, { x: 0.3, y: 0.1 }, 0.2) }]
            : i % 4 === 2
              ? [
                  {
                    shape: polygon(
                      [
                        { x: -0.3, y: -0.3 },
                        { x: 0.3, y: -0.3 },
                        { x: 0, y: 0.3 },
                      ],
                      0.06,
                    ),
                  },
                ]
              : [
                  { shape: box(0.3, 0.2, { x: 0.1, y: 0 }, 0.3) },
                  { shape: segment({ x: -0.4, y: 0.3 }, { x: 0.4, y: 0.3 }) },
                ]
      world.createBody({
        position: { x, y },
        angle: 0.2 * i,
        shapes: shapes.map((s) => ({ ...s, filter, enableHitEvents: i % 2 === 0, restitution: 0.3 })),
      })
    }
    return world
  }
  const events = (world: World): string => JSON.stringify([world.contactEvents(), world.sensorEvents()])

  it('a saved world continues bit for bit, events included', () => {
    const world = build()
    for (let i = 0; i < 20; i++) world.step()
    const copy = loadWorld(world.save())
    expect(copy.hash()).toBe(world.hash())
    let eventSteps = 0
    for (let i = 0; i < 300; i++) {
      world.step()
      copy.step()
      expect(copy.hash(), `step ${i}`).toBe(world.hash())
      const e = events(world)
      expect(events(copy), `events at step ${i}`).toBe(e)
      if (e !== '[{"begin":[],"end":[],"hit":[]},{"begin":[],"end":[]}]') eventSteps++
    }
    expect(eventSteps).toBeGreaterThan(10)
  })
})
