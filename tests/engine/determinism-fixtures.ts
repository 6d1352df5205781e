/*
 * Fixtures shared by the determinism tests in Node (tests/engine/determinism.test.ts) and in
 * headless Chromium (tests/browser/engine-determinism.test.ts), so both run the very same code:
 *
 * - The mixed scene: a seeded pile of 200 circles, boxes and polygons (3-8 sides) in a walled
 *   container, plus a ramp with a sliding box and a rolling circle, a revolute pendulum chain with
 *   a limit, a motorized wheel, a rope and a soft spring, a spinning kinematic paddle and a bullet.
 *   Sleeping is on, so by step 600 the pile sleeps while the joints keep moving.
 * - A scripted input schedule applied by world.tick (as a server applies commands at a tick): a
 *   mouse joint grabs the ramp box and drags it along a sine path, impulses, a body destroyed,
 *   a body spawned, the bullet fired, a joint destroyed.
 * - Trig inputs and a digest of the exact bits of a function's results over them.
 *
 * Nothing here may use Node APIs: the browser test bundles this file with esbuild.
 */
import {
  box,
  buildScene,
  circle,
  machinesScene,
  pileScene,
  polygon,
  sin,
  type World,
} from '../../engine/index.ts'

/** Steps of the golden run (10 s). */
export const GOLDEN_STEPS = 600
/**
 * The mixed scene's world.hash() at step 600, in Node and in Chromium. Update it deliberately,
 * with the value the failing test prints, when an engine change is meant to change the simulation.
 */
export const GOLDEN_HASH = 0xbbdb8699

/** Ids the input schedule needs; a plain object, copied along with a saved world. */
export interface MixedHandles {
  rampBox: number
  pileBody: number
  doomed: number
  bullet: number
  rope: number
  mouse: number
}

/** Builds the mixed scene in an empty world (sleeping on) and returns the ids the schedule uses. */
export function buildMixedScene(world: World): MixedHandles {
  const ids = buildScene(world, pileScene(200, 7))
  // A ramp with a sliding box and a rolling circle, right of the pile (the pile's walls are at x = +-10).
  world.createBody({ type: 'static', position: { x: 25, y: 4 }, angle: -0.3, shape: box(6, 0.25) })
  const rampBox = world.createBody({
    position: { x: 21, y: 6.5 },
    angle: -0.3,
    shape: box(0.4, 0.3),
    friction: 0.2,
  })
  world.createBody({ position: { x: 22.5, y: 6 }, shape: circle(0.35), friction: 0.8, restitution: 0.3 })
  // A pendulum chain of 5 boxes on revolute joints, hanging from the world at (40, 14).
  let previous: number | null = null
  for (let i = 0; i < 5; i++) {
    const link = world.createBody({ position: { x: 40.5 + i, y: 14 }, shape: box(0.5, 0.1), density: 2 })
    world.createJoint({
      type: 'revolute',
      bodyA: previous,
      bodyB: link,
      anchor: { x: 40 + i, y: 14 },
      enableLimit: i === 2,
      lowerAngle: -0.8,
      upperAngle: 0.8,
    })
    previous = link
  }
  // A motorized wheel on a pin, a rope and a soft spring hanging from it.
  const wheel = world.createBody({ position: { x: 50, y: 8 }, shape: polygon(hexagon(1)), friction: 0.9 })
  world.createJoint({
    type: 'revolute',
    bodyA: null,
    bodyB: wheel,
    anchor: { x: 50, y: 8 },
    enableMotor: true,
    motorSpeed: 2,
    maxMotorTorque: 50,
  })
  const weight = world.createBody({ position: { x: 51, y: 5 }, shape: circle(0.3) })
  const rope = world.createJoint({
    type: 'distance',
    bodyA: wheel,
    bodyB: weight,
    anchorA: { x: 51, y: 8 },
    anchorB: { x: 51, y: 5 },
    minLength: 0,
  })
  const bob = world.createBody({ position: { x: 49, y: 5 }, shape: box(0.3, 0.3) })
  world.createJoint({
    type: 'distance',
    bodyA: wheel,
    bodyB: bob,
    anchorA: { x: 49, y: 8 },
    anchorB: { x: 49, y: 5.3 },
    hertz: 3,
    dampingRatio: 0.3,
  })
  // A spinning kinematic paddle and a bullet aimed at a wall of boxes.
  world.createBody({
    type: 'kinematic',
    position: { x: 60, y: 2 },
    angularVelocity: 1.5,
    shape: box(1.5, 0.1),
  })
  for (let i = 0; i < 6; i++) world.createBody({ position: { x: 75, y: 0.5 + i }, shape: box(0.25, 0.5) })
  const bullet = world.createBody({
    position: { x: 65, y: 3 },
    shape: circle(0.1),
    bullet: true,
    awake: false,
  })
  return { rampBox, pileBody: ids[40], doomed: ids[120], bullet, rope, mouse: 0 }
}

function hexagon(r: number) {
  const c = 0.5 * r
  const s = 0.8660254037844386 * r
  return [
    { x: r, y: 0 },
    { x: c, y: s },
    { x: -c, y: s },
    { x: -r, y: 0 },
    { x: -c, y: -s },
    { x: c, y: -s },
  ]
}

/** Applies the inputs scheduled for the coming step (world.tick is the number of steps taken). */
export function driveMixedScene(world: World, h: MixedHandles): void {
  const t = world.tick
  if (t === 60)
    h.mouse = world.createJoint({ type: 'mouse', body: h.rampBox, target: world.getPosition(h.rampBox) })
  if (t > 60 && t < 300) {
    // Drag the ramp box along a sine path (the engine's sin: the same bits everywhere).
    world.setJointTarget(h.mouse, { x: 21 + 0.01 * (t - 60), y: 7 + sin(t / 20) })
  }
  if (t === 300) world.destroyJoint(h.mouse)
  if (t === 90) world.applyLinearImpulse(h.pileBody, { x: 3, y: 6 }, world.getWorldCenter(h.pileBody))
  if (t === 150) world.setLinearVelocity(h.bullet, { x: 150, y: 0 })
  if (t === 200) world.destroyBody(h.doomed)
  if (t === 260) world.createBody({ position: { x: 0.3, y: 20 }, angle: 0.5, shape: box(0.4, 0.2) })
  if (t === 420) world.destroyJoint(h.rope)
}

/** Steps the mixed scene, inputs included, until world.tick reaches `tick`. */
export function runMixedScene(world: World, h: MixedHandles, tick: number): void {
  while (world.tick < tick) {
    driveMixedScene(world, h)
    world.step()
  }
}

/** Builds the machines scene (every joint kind, engine/scenes/machine-scenes.ts) in an empty world. */
export function buildMachines(world: World): void {
  buildScene(world, machinesScene())
}

/**
 * Before each step of the machines scene: the setter calls a game would make, by tick (motor
 * speeds, a motor joint's moving offset and angle, a slider's and a sprung pin's targets).
 */
export function driveMachines(world: World): void {
  const t = world.tick
  const joints = world.joints()
  const of = (type: string): number[] => joints.filter((j) => j.type === type).map((j) => j.id)
  if (t % 90 === 0) for (const j of of('wheel')) world.setJointMotorSpeed(j, t % 180 === 0 ? -6 : -3)
  if (t % 7 === 0) for (const j of of('motor')) world.setJointTarget(j, { x: 45 + 0.01 * t, y: 3 }, 0.001 * t)
  if (t === 200) for (const j of of('prismatic')) world.setJointTarget(j, 0.2)
  if (t === 250) for (const j of of('revolute')) world.setJointTarget(j, -0.2)
}

/** Hex form of a 32-bit hash, for messages. */
export function hex(hash: number): string {
  return `0x${hash.toString(16).padStart(8, '0')}`
}

/** `count` deterministic trig arguments: a grid over [-40, 40], small values and multiples of pi/4. */
export function trigInputs(count = 4000): Float64Array {
  const out = new Float64Array(count)
  let seed = 0x2545f491
  for (let i = 0; i < count; i++) {
    // xorshift32 for the mantissa-level jitter; exact integer operations only.
    seed ^= seed << 13
    seed ^= seed >>> 17
    seed ^= seed << 5
    const jitter = (seed >>> 0) / 4294967296
    if (i % 4 === 0) out[i] = -40 + (80 * i) / count + jitter * 1e-3
    else if (i % 4 === 1) out[i] = (jitter - 0.5) * powerOfHalf(i % 40)
    else if (i % 4 === 2) out[i] = ((i % 64) - 32) * (Math.PI / 4) * (1 + (jitter - 0.5) * 1e-12)
    else out[i] = (jitter - 0.5) * 8
  }
  return out
}

/** 2^-k, exactly, without Math.pow. */
function powerOfHalf(k: number): number {
  let x = 1
  for (let i = 0; i < k; i++) x *= 0.5
  return x
}

/** Results of f on every input (atan2 takes consecutive pairs as (y, x)). */
export function trigResults(inputs: Float64Array, f: (x: number) => number): Float64Array {
  const out = new Float64Array(inputs.length)
  for (let i = 0; i < inputs.length; i++) out[i] = f(inputs[i])
  return out
}

/** Results of atan2 on (inputs[i], inputs[(i * 7 + 3) % n]). */
export function atan2Results(inputs: Float64Array, f: (y: number, x: number) => number): Float64Array {
  const n = inputs.length
  const out = new Float64Array(n)
  for (let i = 0; i < n; i++) out[i] = f(inputs[i], inputs[(i * 7 + 3) % n])
  return out
}

/** FNV-1a over the exact bytes of a Float64Array. */
export function digest(values: Float64Array): number {
  const bytes = new Uint8Array(values.buffer, values.byteOffset, values.byteLength)
  let h = 0x811c9dc5
  for (let i = 0; i < bytes.length; i++) {
    h ^= bytes[i]
    h = Math.imul(h, 0x01000193)
  }
  return h >>> 0
}
