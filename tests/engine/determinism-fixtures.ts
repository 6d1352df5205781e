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
  capsule,
  cardHouseScene,
  chain,
  circle,
  cos,
  createWorld,
  decompose,
  machinesScene,
  pileScene,
  polygon,
  segment,
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

/** Steps of the vocabulary scene's cross-engine run (50 s). */
export const VOCABULARY_STEPS = 3000

/** Where the vocabulary scene's setup takes its sines from (the engine's; a deliberate break passes Math.sin). */
export type Sine = (x: number) => number

/** Ids the vocabulary scene's inputs need. */
export interface VocabularyHandles {
  /** Shapes of the bodies whose filter changes at step 1000 (start colliding with the "ghost" category). */
  refiltered: number[]
  /** A rolling disc pushed at step 500. */
  disc: number
}

/**
 * The vocabulary scene (issue 27): every shape kind the engine has beyond circles, boxes and convex
 * polygons, with their settings, in one container:
 * - static: a V of two conveyor segments (tangent speed +0.8 and -0.5 m/s), box walls, a sensor box
 *   in the middle, a one-sided chain ramp (3 segments) and a kinematic body spinning a capsule sensor;
 * - 36 dynamic bodies in six kinds: dumbbells (two circles on a box: compound), capsules,
 *   rounded triangles, decompose()d L outlines, decompose()d 5-pointed stars and a compound of a
 *   capsule and a rounded box; every other body has rolling resistance 0.08, every third asks for
 *   hit events, the sixth kind is sensor-blind (enableSensorEvents false);
 * - filters: dumbbells share the negative group -3 (they never touch each other); capsules are in
 *   category 2 and do not collide with category 4 ("ghosts": the decompose()d stars) until step
 *   1000, when setFilter gives them every mask bit;
 * - slender shapes (extra solver sweeps): two thin capsule rods in the container and a two-storey
 *   card house of 2 mm x 0.4 m cards on its own floor.
 * Initial angles come from `sine` (the engine's sin: the same bits everywhere; V8's Math.sin differs
 * from it by an ulp on one of the 36 arguments, i = 31, so a setup that used Math.sin is caught).
 */
export function buildVocabularyScene(world: World, sine: Sine = sin): VocabularyHandles {
  world.createBody({
    type: 'static',
    shapes: [
      { shape: segment({ x: -10, y: 3 }, { x: 0, y: 0 }), tangentSpeed: 0.8 },
      { shape: segment({ x: 0, y: 0 }, { x: 10, y: 3 }), tangentSpeed: -0.5 },
      { shape: box(0.25, 8, { x: -10.25, y: 10 }) },
      { shape: box(0.25, 8, { x: 10.25, y: 10 }) },
      { shape: box(2, 1, { x: -3, y: 4 }), sensor: true },
      // A one-sided chain ramp, run right to left so its solid side faces up, ghosts at both ends.
      {
        shape: chain([
          { x: 9.5, y: 7.4 },
          { x: 9, y: 7 },
          { x: 7, y: 6.2 },
          { x: 5, y: 5.7 },
          { x: 3, y: 5.5 },
          { x: 2.5, y: 5.6 },
        ]),
      },
    ],
  })
  world.createBody({
    type: 'kinematic',
    position: { x: 4, y: 5 },
    angularVelocity: 0.7,
    shapes: [{ shape: capsule({ x: -1.5, y: 0 }, { x: 1.5, y: 0 }, 0.3), sensor: true }],
  })
  const outlineL = [
    { x: -0.4, y: -0.4 },
    { x: 0.4, y: -0.4 },
    { x: 0.4, y: -0.15 },
    { x: -0.15, y: -0.15 },
    { x: -0.15, y: 0.4 },
    { x: -0.4, y: 0.4 },
  ]
  const star: { x: number; y: number }[] = []
  for (let k = 0; k < 10; k++) {
    // Exact corners: the engine's trig on a fixed grid of angles.
    const r = k % 2 === 0 ? 0.5 : 0.22
    star.push({ x: r * cos((k * Math.PI) / 5 + 0.1), y: r * sin((k * Math.PI) / 5 + 0.1) })
  }
  const lPieces = decompose(outlineL)
  const starPieces = decompose(star)
  const handles: VocabularyHandles = { refiltered: [], disc: 0 }
  for (let i = 0; i < 36; i++) {
    const kind = i % 6
    const position = { x: -8 + (i % 9) * 2, y: 7 + Math.floor(i / 9) * 1.6 }
    const angle = 3 * sine(0.37 * i + 0.3)
    const rollingResistance = i % 2 === 1 ? 0.08 : 0
    const enableHitEvents = i % 3 === 0
    const shapes =
      kind === 0
        ? [
            {
              shape: circle(0.25, { x: -0.5, y: 0 }),
              filter: { categoryBits: 1, maskBits: 0xffffffff, groupIndex: -3 },
            },
            { shape: box(0.5, 0.08), filter: { categoryBits: 1, maskBits: 0xffffffff, groupIndex: -3 } },
            {
              shape: circle(0.25, { x: 0.5, y: 0 }),
              filter: { categoryBits: 1, maskBits: 0xffffffff, groupIndex: -3 },
            },
          ]
        : kind === 1
          ? [
              {
                shape: capsule({ x: -0.35, y: 0 }, { x: 0.35, y: 0 }, 0.2),
                filter: { categoryBits: 2, maskBits: 0xfffffffb, groupIndex: 0 },
              },
            ]
          : kind === 2
            ? [
                {
                  shape: polygon(
                    [
                      { x: -0.3, y: -0.25 },
                      { x: 0.3, y: -0.25 },
                      { x: 0, y: 0.3 },
                    ],
                    0.06,
                  ),
                },
              ]
            : kind === 3
              ? lPieces.map((shape) => ({ shape }))
              : kind === 4
                ? starPieces.map((shape) => ({
                    shape,
                    filter: { categoryBits: 4, maskBits: 0xffffffff, groupIndex: 0 },
                  }))
                : [
                    { shape: capsule({ x: 0, y: -0.3 }, { x: 0, y: 0.3 }, 0.15), enableSensorEvents: false },
                    { shape: polygon(hexagon(0.25), 0.04), enableSensorEvents: false },
                  ]
    const body = world.createBody({
      position,
      angle,
      shapes: shapes.map((d) => ({
        ...d,
        rollingResistance,
        enableHitEvents,
        restitution: i % 4 === 0 ? 0.3 : 0,
      })),
    })
    if (kind === 1) handles.refiltered.push(...world.bodyShapes(body))
  }
  handles.disc = world.createBody({
    position: { x: 8, y: 6 },
    shapes: [{ shape: circle(0.35), rollingResistance: 0.05 }],
  })
  // Slender shapes (their contacts get extra sweeps): two thin rods dropped into the container, and
  // a two-storey card house of 2 mm cards on its own floor at x = 30.
  for (const x of [-2, 2]) {
    world.createBody({
      position: { x, y: 14 },
      angle: x * 0.2,
      shape: capsule({ x: -0.8, y: 0 }, { x: 0.8, y: 0 }, 0.03),
    })
  }
  world.createBody({ type: 'static', position: { x: 30, y: -1 }, shape: box(3, 1), friction: 0.7 })
  for (const card of cardHouseScene(2).bodies.slice(1)) {
    world.createBody({ ...card, position: { x: 29.5 + (card.position?.x ?? 0), y: card.position?.y ?? 0 } })
  }
  return handles
}

/** Folds numbers into a 32-bit FNV-1a hash by their exact bits (as world.hash() folds the state). */
export class HashStream {
  private readonly f = new Float64Array(1)
  private readonly u = new Uint32Array(this.f.buffer)
  hash = 0x811c9dc5

  /** Folds one number's 64 bits. */
  add(x: number): void {
    this.f[0] = x
    this.word(this.u[0])
    this.word(this.u[1])
  }

  private word(w: number): void {
    let h = this.hash
    for (let k = 0; k < 32; k += 8) {
      h ^= (w >>> k) & 0xff
      h = Math.imul(h, 0x01000193)
    }
    this.hash = h >>> 0
  }
}

/** The vocabulary scene's inputs before the step (world.tick steps taken). */
export function driveVocabularyScene(world: World, h: VocabularyHandles): void {
  const t = world.tick
  if (t === 500) world.applyLinearImpulse(h.disc, { x: -2, y: 0 }, world.getWorldCenter(h.disc))
  if (t === 1000)
    for (const s of h.refiltered) world.setFilter(s, { categoryBits: 2, maskBits: 0xffffffff, groupIndex: 0 })
  if (t === 1500 || t === 2500)
    world.explode({ position: { x: 0, y: 0.5 }, radius: 3, falloff: 4, impulsePerLength: 6 })
}

/**
 * Folds the step's events and the scene's queries into `stream`: contact begin/end/hit and sensor
 * begin/end (in the engine's order), then a closest ray cast and an all-hits ray cast sweeping across
 * the container, a capsule cast falling from above, overlapAABB, overlapPoint and overlapShape (a
 * rounded hexagon) at points moving with the step, one of them filtered to category 2.
 */
export function foldVocabularyStep(world: World, stream: HashStream): void {
  const t = world.tick
  const contacts = world.contactEvents()
  stream.add(contacts.begin.length)
  for (const e of contacts.begin) stream.add(e.shapeA * 65536 + e.shapeB)
  stream.add(contacts.end.length)
  for (const e of contacts.end) stream.add(e.shapeA * 65536 + e.shapeB)
  stream.add(contacts.hit.length)
  for (const e of contacts.hit) {
    stream.add(e.shapeA * 65536 + e.shapeB)
    stream.add(e.point.x)
    stream.add(e.point.y)
    stream.add(e.normal.x)
    stream.add(e.normal.y)
    stream.add(e.approachSpeed)
  }
  const sensors = world.sensorEvents()
  stream.add(sensors.begin.length)
  for (const e of sensors.begin) stream.add(e.sensor * 65536 + e.visitor)
  stream.add(sensors.end.length)
  for (const e of sensors.end) stream.add(e.sensor * 65536 + e.visitor)
  const u = (t % 200) / 200
  const closest = world.castRayClosest({ x: -9.5, y: 12 }, { x: 19, y: -12 + 10 * u })
  if (closest === null) stream.add(-1)
  else foldHit(stream, closest)
  const all = world.castRay({ x: -9.9 + 19.8 * u, y: 14 }, { x: 0.5, y: -14 }, { maskBits: 0xfffffffb })
  stream.add(all.length)
  for (const hit of all) foldHit(stream, hit)
  const cast = world.castShape(
    capsule({ x: -0.3, y: 0 }, { x: 0.3, y: 0 }, 0.15),
    { position: { x: 9 - 18 * u, y: 13 }, angle: u },
    { x: 0, y: -13 },
  )
  if (cast === null) stream.add(-1)
  else foldHit(stream, cast)
  const x = -8 + 16 * u
  for (const id of world.overlapAABB({ minX: x - 1, minY: 0, maxX: x + 1, maxY: 3 })) stream.add(id)
  for (const id of world.overlapPoint({ x, y: 1 + u })) stream.add(id)
  const hexShape = VOCABULARY_HEXAGON
  for (const id of world.overlapShape(
    hexShape,
    { position: { x: -x, y: 1.5 }, angle: 2 * u },
    { categoryBits: 2, maskBits: 0xffffffff },
  ))
    stream.add(id)
}

const VOCABULARY_HEXAGON = polygon(hexagon(0.6), 0.1)

function foldHit(
  stream: HashStream,
  hit: {
    shape: number
    body: number
    point: { x: number; y: number }
    normal: { x: number; y: number }
    fraction: number
  },
): void {
  stream.add(hit.shape)
  stream.add(hit.body)
  stream.add(hit.point.x)
  stream.add(hit.point.y)
  stream.add(hit.normal.x)
  stream.add(hit.normal.y)
  stream.add(hit.fraction)
}

/**
 * runVocabulary's hashes in Node, Chromium and Firefox (world, then stream, at steps 500, 1000, ...,
 * 3000). Pinned so a change to what the new shape kinds do (an off-origin circle of a dumbbell, a
 * chain's ghost vertices, a sensor's overlap) shows even where no other test looks; update them
 * deliberately, with the values the failing test prints.
 */
export const VOCABULARY_GOLDEN: readonly number[] = [
  0xcb1beb02, 0xfc5380b4, 0xbaf5813c, 0xa3c333a4, 0x5a85309c, 0xc49418bb, 0x739c90f7, 0xaf072222, 0x758a6e10,
  0x8add1d5c, 0x86df226a, 0xb0291487,
]

/**
 * Runs the vocabulary scene VOCABULARY_STEPS steps; every 500 steps returns the world's hash and the
 * stream's (events and queries of every step so far).
 */
export function runVocabulary(sine: Sine = sin): number[] {
  const world = createWorld()
  const handles = buildVocabularyScene(world, sine)
  const stream = new HashStream()
  const out: number[] = []
  for (let i = 1; i <= VOCABULARY_STEPS; i++) {
    driveVocabularyScene(world, handles)
    world.step()
    foldVocabularyStep(world, stream)
    if (i % 500 === 0) out.push(world.hash(), stream.hash)
  }
  return out
}
