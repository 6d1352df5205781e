/*
 * World.setJointSettings: a joint's settings changed after creation.
 *
 * Oracles that do not come from the solver:
 * - Bit identity where physics says so: a pendulum hanging straight down at rest is inside a limit
 *   of +-0.5 rad (a speculative limit applies no impulse then), and a motor that is off or a break
 *   force it does not reach exert nothing, so setting them at tick N leaves its future exactly that
 *   of a pendulum built with them (engine hash at every step); settings set at tick 0 always do. (A
 *   zero-speed motor is not such a setting: it damps the 1e-17 rad/s of round-off the pin leaves.)
 * - Statics of a hinge motor holding a horizontal arm (mass m, centre r from the pin): the load's
 *   torque is m g r; a zero-speed motor with maxMotorTorque above it holds the arm, below it does
 *   not. Raising or lowering the cap at tick N switches between the two.
 * - A limit [0, 0.2] rad set while a pendulum swings keeps it within the limit from then on (the
 *   unlimited copy swings to about 0.6 rad).
 * - A spring's period is 1 / hertz (a body on a distance spring from the world, anchor at its
 *   centre, so the axial mass is the body's mass): changing the hertz mid-run changes the period
 *   measured from zero crossings, within 2 %.
 * - A rope carrying a weight m g breaks at the first step after its breakForce is set below m g.
 * Plus: errors naming the field, a refused call changing nothing, save/load continuing bit for bit
 * after a setter, and a setter call allocating nothing once warm.
 */
import { dirname } from 'node:path'
import { fileURLToPath } from 'node:url'
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, type JointSettings, loadWorld, type World } from '../../engine/index.ts'
import { measureAllocation } from '../support/measure-allocation.ts'

const G = 10

/** A box pendulum hanging from a pin at (0, 5), its centre `r` below (or beside, `side`) the pin. */
function pendulum(settings: Partial<JointSettings> = {}, side = false) {
  const world = createWorld({ enableSleep: false, gravity: { x: 0, y: -G } })
  const r = 1
  const b = world.createBody({
    position: side ? { x: r, y: 5 } : { x: 0, y: 5 - r },
    shape: side ? box(r, 0.1) : box(0.1, r),
    density: 2,
  })
  const j = world.createJoint({
    type: 'revolute',
    bodyA: null,
    bodyB: b,
    anchor: { x: 0, y: 5 },
    ...(settings as object),
  })
  return { world, b, j, r, m: world.getMass(b) }
}

const HELD: JointSettings = {
  enableLimit: true,
  lowerAngle: -0.5,
  upperAngle: 0.5,
  enableMotor: true,
  motorSpeed: 0,
  maxMotorTorque: 3,
  breakForce: 1e6,
}

/** Settings that exert nothing on a pendulum at rest: a limit it is inside, a motor left off, a break force. */
const AT_REST: JointSettings = {
  enableLimit: true,
  lowerAngle: -0.5,
  upperAngle: 0.5,
  motorSpeed: 2,
  maxMotorTorque: 3,
  breakForce: 1e6,
}

describe('setJointSettings: bit identity where physics says so', () => {
  it('settings given at tick 0 equal the same settings in the definition, at every step', () => {
    const a = pendulum({}, true)
    const b = pendulum(HELD, true)
    a.world.setJointSettings(a.j, HELD)
    expect(a.world.hash()).toBe(b.world.hash())
    for (let i = 0; i < 300; i++) {
      a.world.step()
      b.world.step()
      expect(a.world.hash(), `step ${i + 1}`).toBe(b.world.hash())
    }
  })

  it('a pendulum at rest given a limit it is inside, motor settings (motor off) and a break force at tick 120 continues as one built with them', () => {
    const a = pendulum()
    const b = pendulum(AT_REST)
    for (let i = 0; i < 120; i++) {
      a.world.step()
      b.world.step()
    }
    a.world.setJointSettings(a.j, AT_REST)
    expect(a.world.hash()).toBe(b.world.hash())
    for (let i = 0; i < 300; i++) {
      a.world.step()
      b.world.step()
      expect(a.world.hash(), `step ${121 + i}`).toBe(b.world.hash())
    }
    expect(a.world.getJointDef(a.j)).toEqual(b.world.getJointDef(b.j))
  })

  it('setting a value to what it already is keeps the warm-start impulses (the hash of an untouched world)', () => {
    const a = pendulum({ enableMotor: true, motorSpeed: 1, maxMotorTorque: 4 }, true)
    const b = pendulum({ enableMotor: true, motorSpeed: 1, maxMotorTorque: 4 }, true)
    for (let i = 0; i < 30; i++) {
      a.world.step()
      b.world.step()
      // b's motor impulse is kept through the call (Box2D keeps it: b2RevoluteJoint_SetMaxMotorTorque).
      b.world.setJointSettings(b.j, { maxMotorTorque: 4, enableMotor: true, lowerAngle: 0, upperAngle: 0 })
      expect(a.world.hash(), `step ${i + 1}`).toBe(b.world.hash())
    }
  })
})

describe('setJointSettings: oracles', () => {
  /** Angle change of the arm over `steps` steps. */
  function run(world: World, j: number, steps: number): number {
    const before = world.getJointAngle(j)
    for (let i = 0; i < steps; i++) world.step()
    return world.getJointAngle(j) - before
  }

  it('a hinge motor above the load torque m g r holds a horizontal arm, below it lets it fall; changing the cap switches', () => {
    const { world, j, r, m } = pendulum({ enableMotor: true, motorSpeed: 0 }, true)
    const load = m * G * r
    world.setJointSettings(j, { maxMotorTorque: 1.05 * load })
    const held = run(world, j, 60)
    world.setJointSettings(j, { maxMotorTorque: 0.95 * load })
    const fell = run(world, j, 30)
    world.setJointSettings(j, { maxMotorTorque: 1.05 * load })
    run(world, j, 30) // stops the fall
    const heldAgain = run(world, j, 60)
    console.log(
      `motor hold: m g r = ${load.toFixed(3)} N m; at 1.05 m g r moved ${held.toExponential(2)} rad in 1 s, at 0.95 m g r fell ${fell.toFixed(4)} rad in 0.5 s, raised again moved ${heldAgain.toExponential(2)} rad in 1 s`,
    )
    // Held: only the pin's soft correction sags (about a millimetre at the 1 m arm's end).
    expect(Math.abs(held)).toBeLessThan(3e-3)
    expect(fell).toBeLessThan(-0.03)
    expect(Math.abs(heldAgain)).toBeLessThan(3e-3)
    expect(Math.abs(world.getJointSpeed(j))).toBeLessThan(1e-3)
    const def = world.getJointDef(j)
    expect(def.type === 'revolute' && def.maxMotorTorque).toBe(1.05 * load)
  })

  it('a motor raised above m g r lifts the arm at its speed; a copy left below sags', () => {
    const a = pendulum({ enableMotor: true, motorSpeed: 1, maxMotorTorque: 0 }, true)
    const load = a.m * G * a.r
    a.world.setJointSettings(a.j, { maxMotorTorque: 0.9 * load })
    run(a.world, a.j, 20)
    const copy = loadWorld(a.world.save())
    a.world.setJointSettings(a.j, { maxMotorTorque: 1.3 * load })
    const lifted = run(a.world, a.j, 120)
    const sagged = run(copy, a.j, 120)
    console.log(
      `motor lift: raised cap moved ${lifted.toFixed(3)} rad in 2 s (w ${a.world.getJointSpeed(a.j).toFixed(4)} rad/s); copy ${sagged.toFixed(3)} rad`,
    )
    expect(a.world.getJointAngle(a.j)).toBeGreaterThan(0.5)
    expect(a.world.getJointSpeed(a.j)).toBeCloseTo(1, 3)
    // Below the load the arm never rises above horizontal: its lowest equilibrium is -acos(0.9).
    expect(copy.getJointAngle(a.j)).toBeLessThan(0)
  })

  it('a limit [0, 0.2] rad set while a pendulum swings keeps it within the limit', () => {
    const a = pendulum()
    // 3 rad/s about the pin: the centre, 1 m below it, moves at 3 m/s along +x.
    a.world.setAngularVelocity(a.b, 3)
    a.world.setLinearVelocity(a.b, { x: 3, y: 0 })
    let steps = 0
    while (a.world.getJointAngle(a.j) < 0.1) {
      a.world.step()
      steps++
    }
    const copy = loadWorld(a.world.save())
    a.world.setJointSettings(a.j, { enableLimit: true, lowerAngle: 0, upperAngle: 0.2 })
    let lo = Number.POSITIVE_INFINITY
    let hi = Number.NEGATIVE_INFINITY
    let free = 0
    for (let i = 0; i < 600; i++) {
      a.world.step()
      copy.step()
      const angle = a.world.getJointAngle(a.j)
      lo = Math.min(lo, angle)
      hi = Math.max(hi, angle)
      free = Math.max(free, copy.getJointAngle(a.j))
    }
    console.log(
      `limit: set at step ${steps}; angle within [${lo.toFixed(4)}, ${hi.toFixed(4)}] rad over 10 s; unlimited copy reached ${free.toFixed(3)} rad`,
    )
    expect(free).toBeGreaterThan(0.4)
    expect(lo).toBeGreaterThan(-0.01)
    expect(hi).toBeLessThan(0.21)
  })

  it("a spring's period follows its hertz when the hertz changes mid-run (1 Hz, then 2 Hz, within 2 %)", () => {
    const world = createWorld({ enableSleep: false, gravity: { x: 0, y: 0 } })
    const b = world.createBody({ position: { x: 1.2, y: 0 }, shape: circle(0.2) })
    const j = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: 1.2, y: 0 },
      length: 1,
      hertz: 1,
      dampingRatio: 0,
    })
    /** Mean period from upward zero crossings of length - 1 over `steps` steps (linear interpolation). */
    function period(steps: number): number {
      const crossings: number[] = []
      let prev = world.getJointTranslation(j) - 1
      for (let i = 1; i <= steps; i++) {
        world.step()
        const x = world.getJointTranslation(j) - 1
        if (prev < 0 && x >= 0) crossings.push(i - 1 + prev / (prev - x))
        prev = x
      }
      return (crossings[crossings.length - 1] - crossings[0]) / (crossings.length - 1) / 60
    }
    const before = period(300)
    world.setJointSettings(j, { hertz: 2 })
    world.step()
    const after = period(300)
    console.log(`spring period: ${before.toFixed(4)} s at 1 Hz, ${after.toFixed(4)} s after setting 2 Hz`)
    expect(Math.abs(before - 1)).toBeLessThan(0.02)
    expect(Math.abs(after - 0.5)).toBeLessThan(0.01)
  })

  it('a rope carrying m g breaks at the first step after its breakForce is set below m g, not before', () => {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.2, 0.2) })
    const j = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 5 },
      anchorB: { x: 0, y: 3 },
      maxLength: 2,
    })
    const weight = world.getMass(b) * G
    for (let i = 0; i < 60; i++) world.step()
    world.setJointSettings(j, { breakForce: 1.1 * weight })
    for (let i = 0; i < 60; i++) {
      world.step()
      expect(world.jointEvents().broken).toEqual([])
    }
    world.setJointSettings(j, { breakForce: 0.9 * weight })
    world.step()
    expect(world.jointEvents().broken).toEqual([j])
    expect(world.hasJoint(j)).toBe(false)
  })
})

describe('setJointSettings: warm starting as Box2D v3.1 leaves it (the reaction reads the accumulated impulses)', () => {
  it('a cap change keeps the motor impulse, a motor toggle zeroes it; a limit change zeroes the limit impulse, a spring change does not', () => {
    const { world, j, r, m } = pendulum({ enableMotor: true, motorSpeed: 0 }, true)
    const load = m * G * r
    world.setJointSettings(j, { maxMotorTorque: 1.05 * load })
    for (let i = 0; i < 60; i++) world.step()
    const held = world.getJointReaction(j).torque
    expect(held).toBeCloseTo(load, 1)
    world.setJointSettings(j, { maxMotorTorque: 2 * load, breakTorque: 1e6 })
    expect(world.getJointReaction(j).torque).toBe(held)
    world.setJointSettings(j, { enableMotor: false })
    world.setJointSettings(j, { enableMotor: true })
    expect(world.getJointReaction(j).torque).toBe(0)
    // Rest the arm on a lower limit (motor off): the limit carries m g r.
    world.setJointSettings(j, { enableMotor: false, enableLimit: true, lowerAngle: -0.2, upperAngle: 0.5 })
    for (let i = 0; i < 120; i++) world.step()
    const resting = world.getJointReaction(j).torque
    expect(resting).toBeGreaterThan(0.9 * load)
    world.setJointSettings(j, { hertz: 3 }) // the spring is off: its settings leave the limit alone
    expect(world.getJointReaction(j).torque).toBe(resting)
    world.setJointSettings(j, { lowerAngle: -0.25 })
    expect(world.getJointReaction(j).torque).toBe(0)
  })

  it("a distance joint's length change zeroes its axial impulse, a break force change does not", () => {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.2, 0.2) })
    const j = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 5 },
      anchorB: { x: 0, y: 3 },
    })
    for (let i = 0; i < 60; i++) world.step()
    const pull = world.getJointReaction(j).force.y
    expect(pull).toBeCloseTo(world.getMass(b) * G, 1)
    world.setJointSettings(j, { breakForce: 1e6 })
    expect(world.getJointReaction(j).force.y).toBe(pull)
    world.setJointSettings(j, { length: 2.1 })
    expect(Math.abs(world.getJointReaction(j).force.y)).toBe(0)
  })
})

describe('setJointSettings: waking', () => {
  it('a sleeping arm given a motor wakes and turns', () => {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    const b = world.createBody({ position: { x: 0, y: 4 }, shape: box(0.1, 1) })
    const j = world.createJoint({ type: 'revolute', bodyA: null, bodyB: b, anchor: { x: 0, y: 5 } })
    for (let i = 0; i < 300 && world.isAwake(b); i++) world.step()
    expect(world.isAwake(b)).toBe(false)
    world.setJointSettings(j, { enableMotor: true, motorSpeed: 1, maxMotorTorque: 100 })
    expect(world.isAwake(b)).toBe(true)
    for (let i = 0; i < 30; i++) world.step()
    expect(world.getJointAngle(j)).toBeGreaterThan(0.3)
  })
})

describe('setJointSettings: bad input', () => {
  it('names the field: a setting the kind lacks, out of range, out of order, not a boolean, an unknown joint', () => {
    const { world, j } = pendulum()
    expect(() => world.setJointSettings(j, { lower: 0 })).toThrow(
      /lower is not a setting of joint 1, a revolute joint/,
    )
    expect(() => world.setJointSettings(j, { maxMotorTorque: -1 })).toThrow(
      /maxMotorTorque must be in \[0, 1000000000000\]/,
    )
    expect(() => world.setJointSettings(j, { hertz: Number.NaN })).toThrow(/hertz must be a finite number/)
    expect(() => world.setJointSettings(j, { lowerAngle: 4 })).toThrow(/lowerAngle must be in/)
    expect(() => world.setJointSettings(j, { lowerAngle: 0.3, upperAngle: 0.1 })).toThrow(
      /upperAngle must be >= lowerAngle \(0.3\), got 0.1/,
    )
    expect(() => world.setJointSettings(j, { enableMotor: 1 as unknown as boolean })).toThrow(
      /enableMotor must be a boolean/,
    )
    expect(() => world.setJointSettings(j, { breakForce: -1 })).toThrow(/breakForce must be a number >= 0/)
    expect(() => world.setJointSettings(99, { hertz: 1 })).toThrow(RangeError)
    expect(() => world.setJointSettings(j, null as unknown as JointSettings)).toThrow(/must be an object/)
  })

  it('a distance joint checks min <= length <= max, and a rod stays a rod when only its length changes', () => {
    const world = createWorld({ gravity: { x: 0, y: -G } })
    const b = world.createBody({ position: { x: 0, y: 3 }, shape: box(0.2, 0.2) })
    const j = world.createJoint({
      type: 'distance',
      bodyA: null,
      bodyB: b,
      anchorA: { x: 0, y: 5 },
      anchorB: { x: 0, y: 3 },
    })
    world.setJointSettings(j, { length: 1.5 })
    const def = world.getJointDef(j)
    expect(def.type === 'distance' && [def.minLength, def.length, def.maxLength]).toEqual([1.5, 1.5, 1.5])
    expect(() => world.setJointSettings(j, { minLength: 2 })).toThrow(/minLength must be in \[0, 1.5\]/)
    expect(() => world.setJointSettings(j, { maxLength: 1 })).toThrow(/maxLength must be in \[1.5, 1000000\]/)
    expect(() => world.setJointSettings(j, { lowerAngle: 0 })).toThrow(
      /lowerAngle is not a setting of joint 1, a distance joint/,
    )
    expect(() => world.setJointSettings(j, { length: 0 })).toThrow(/length must be in \[0.001, 1000000\]/)
  })

  it('a weld takes its own spring names and refuses hertz', () => {
    const world = createWorld({})
    const a = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
    const b = world.createBody({ position: { x: 1, y: 0 }, shape: box(0.5, 0.5) })
    const j = world.createJoint({ type: 'weld', bodyA: a, bodyB: b, anchor: { x: 0.5, y: 0 } })
    world.setJointSettings(j, { linearHertz: 3, angularHertz: 2, angularDampingRatio: 0.5 })
    const def = world.getJointDef(j)
    expect(def.type === 'weld' && [def.linearHertz, def.angularHertz, def.angularDampingRatio]).toEqual([
      3, 2, 0.5,
    ])
    expect(() => world.setJointSettings(j, { hertz: 1 })).toThrow(
      /hertz is not a setting of joint 1, a weld joint/,
    )
    expect(() => world.setJointSettings(j, { linearHertz: -1 })).toThrow(/linearHertz must be in/)
  })

  it('a refused call changes nothing (same hash and same saved bytes), even when its other fields were good', () => {
    const { world, j } = pendulum({}, true)
    for (let i = 0; i < 10; i++) world.step()
    const bytes = world.save()
    const hash = world.hash()
    expect(() => world.setJointSettings(j, { maxMotorTorque: 5, enableMotor: true, upperAngle: 9 })).toThrow(
      /upperAngle/,
    )
    expect(world.hash()).toBe(hash)
    expect(world.save()).toEqual(bytes)
  })
})

describe('setJointSettings: save and load', () => {
  it('bytes saved after a setter continue bit for bit, with the new settings', () => {
    const { world, j } = pendulum({}, true)
    for (let i = 0; i < 30; i++) world.step()
    world.setJointSettings(j, {
      enableMotor: true,
      motorSpeed: 2,
      maxMotorTorque: 50,
      enableLimit: true,
      lowerAngle: -1,
      upperAngle: 0.3,
      breakForce: 1e5,
    })
    world.step()
    const copy = loadWorld(world.save())
    expect(copy.getJointDef(j)).toEqual(world.getJointDef(j))
    for (let i = 0; i < 300; i++) {
      world.step()
      copy.step()
      expect(copy.hash(), `step ${i}`).toBe(world.hash())
    }
  })
})

describe('setJointSettings: allocation', () => {
  it('a setter call allocates nothing once warm', async () => {
    const result = await measureAllocation({
      resolveDir: dirname(fileURLToPath(import.meta.url)),
      setup: `
import { box, createWorld } from '../../engine/index.ts'
const world = createWorld({ enableSleep: false })
const b = world.createBody({ position: { x: 1, y: 5 }, shape: box(1, 0.1) })
const j = world.createJoint({ type: 'revolute', bodyA: null, bodyB: b, anchor: { x: 0, y: 5 } })
const one = { enableMotor: true, maxMotorTorque: 10, enableLimit: true, lowerAngle: -0.5, upperAngle: 0.5 }
const two = { maxMotorTorque: 20, lowerAngle: -0.2, upperAngle: 0.2, breakForce: 1e6 }
let k = 0
`,
      unit: 'world.setJointSettings(j, (k++ & 1) === 0 ? one : two)',
      units: 20000,
      warmup: 20000,
      rounds: 3,
      reportAbove: 64,
    })
    console.log(
      `setter allocation: ${result.gcCount} collections, heap growth ${result.heapGrowth} bytes over ${result.units} calls` +
        (result.allocators.length ? `; allocating: ${JSON.stringify(result.allocators)}` : ''),
    )
    expect(result.gcCount, JSON.stringify(result.allocators)).toBe(0)
    expect(result.heapGrowth / result.units, JSON.stringify(result.allocators)).toBeLessThan(8)
  })
})
