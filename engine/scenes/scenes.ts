/*
 * Scenes, built in one place and reused by tests, benchmarks, the server and the client (Box2D
 * keeps shared/benchmarks.c for the same reason).
 *
 * A scene is a blueprint: plain body definitions and joint definitions that any engine can build.
 * Concord's world builds it with buildScene(); the benchmark builds the very same list in the peer
 * engines, so every engine simulates identical geometry. A joint's bodies are indices into the
 * blueprint's `bodies` (null is the fixed world frame), resolved to ids when the scene is built.
 */

import { box, capsule, chain, circle, polygon, type Shape } from '../collision/index.ts'
import { cos, PI, sin, type Vec2 } from '../math.ts'
import { Prng } from '../prng.ts'
import type { BodyDef, BodyId, CompoundBodyDef, JointDef, JointId } from '../types.ts'
import { groundDef } from './ground.ts'

/** A scene as data: gravity, body definitions in creation order, and joints between them. */
export interface SceneBlueprint {
  name: string
  gravity: Vec2
  bodies: BodyDef[]
  /**
   * Bodies of several shapes or with a chain, created after `bodies` (their indices continue
   * `bodies`' for joints); engines that only take one shape per body (the benchmark's peers) never
   * see a scene with them.
   */
  compoundBodies?: CompoundBodyDef[]
  /** Joints created after the bodies; their body fields are indices into `bodies` (null: the world). */
  joints?: JointDef[]
}

/** Anything that can create bodies (Concord's World); createJoint is needed for scenes with joints. */
export interface BodyFactory {
  createBody(def: BodyDef | CompoundBodyDef): BodyId
  setGravity(g: Vec2): void
  createJoint?(def: JointDef): JointId
}

export { groundDef }

/** Only the ground. */
export function emptyScene(): SceneBlueprint {
  return { name: 'empty', gravity: { x: 0, y: -10 }, bodies: [groundDef()] }
}

/** A pyramid of `rows` rows of touching 1 m boxes on the ground (rows = 20 gives 210 boxes). */
export function pyramidScene(rows: number): SceneBlueprint {
  const bodies = [groundDef(Math.max(100, rows))]
  const shape = box(0.5, 0.5)
  for (let row = 0; row < rows; row++) {
    const count = rows - row
    for (let i = 0; i < count; i++) {
      const x = i - (count - 1) / 2
      bodies.push({ position: { x, y: 0.5 + row }, shape, friction: 0.6 })
    }
  }
  return { name: `pyramid-${rows}`, gravity: { x: 0, y: -10 }, bodies }
}

/** A tower of `count` 1 m boxes resting on each other; staggered towers shift every other box 0.2 m. */
export function towerScene(count: number, staggered: boolean, gap = 0): SceneBlueprint {
  const bodies = [groundDef()]
  const shape = box(0.5, 0.5)
  for (let i = 0; i < count; i++) {
    const x = staggered ? (i % 2) * 0.2 - 0.1 : 0
    bodies.push({ position: { x, y: 0.5 + i * (1 + gap) }, shape, friction: 0.6 })
  }
  return { name: `tower-${count}${staggered ? '-staggered' : ''}`, gravity: { x: 0, y: -10 }, bodies }
}

/** A regular polygon of n vertices and circumradius r. */
export function regularPolygon(n: number, r: number): Shape {
  const points: Vec2[] = []
  for (let i = 0; i < n; i++) {
    const a = (2 * PI * i) / n
    points.push({ x: r * cos(a), y: r * sin(a) })
  }
  return polygon(points)
}

/**
 * A pile: `count` mixed circles, boxes and polygons (3-8 sides) dropped from a seeded grid layout
 * into a walled container. The container is about 1.25 sqrt(count) m wide.
 */
export function pileScene(count: number, seed = 1): SceneBlueprint {
  const prng = new Prng(seed)
  const columns = Math.max(4, Math.ceil(Math.sqrt(count) * 1.25))
  const rows = Math.ceil(count / columns)
  const inner = columns + 1
  const wallHalfHeight = (rows + 4) / 2
  const bodies: BodyDef[] = [groundDef()]
  for (const side of [-1, 1]) {
    bodies.push({
      type: 'static',
      position: { x: side * (inner / 2 + 0.5), y: wallHalfHeight },
      shape: box(0.5, wallHalfHeight),
      friction: 0.6,
    })
  }
  for (let i = 0; i < count; i++) {
    const column = i % columns
    const row = Math.floor(i / columns)
    const kind = prng.int(3)
    let shape: Shape
    if (kind === 0) shape = circle(prng.range(0.25, 0.45))
    else if (kind === 1) shape = box(prng.range(0.2, 0.45), prng.range(0.2, 0.45))
    else shape = regularPolygon(3 + prng.int(6), prng.range(0.3, 0.45))
    const x = -inner / 2 + 1 + column + prng.range(-0.05, 0.05)
    const y = 1 + row
    bodies.push({ position: { x, y }, angle: prng.range(0, 2 * PI), shape, friction: 0.6 })
  }
  return { name: `pile-${count}`, gravity: { x: 0, y: -10 }, bodies }
}

/**
 * A ramp: a static plane inclined by `angle` (rad) with a 1 m box resting on it, plus the ground.
 * The box is body index 2 of the blueprint.
 */
export function rampScene(angle = (20 * PI) / 180, friction = 0.6): SceneBlueprint {
  const c = cos(angle)
  const s = sin(angle)
  const rampCenter = { x: 0, y: 6 }
  // The box sits on the ramp's top face, centre 0.5 + 0.5 m along the ramp normal (-s, c).
  const boxCenter = { x: rampCenter.x - s * 1, y: rampCenter.y + c * 1 }
  return {
    name: 'ramp',
    gravity: { x: 0, y: -10 },
    bodies: [
      groundDef(),
      { type: 'static', position: rampCenter, angle, shape: box(10, 0.5), friction },
      { position: boxCenter, angle, shape: box(0.5, 0.5), friction },
    ],
  }
}

/** A 20 x 20 m box (density 1) resting on two 1 m boxes: a 400:1 mass ratio. */
export function heavyOnLightScene(): SceneBlueprint {
  const small = box(0.5, 0.5)
  return {
    name: 'heavy-on-light',
    gravity: { x: 0, y: -10 },
    bodies: [
      groundDef(),
      { position: { x: -9, y: 0.5 }, shape: small, friction: 0.6 },
      { position: { x: 9, y: 0.5 }, shape: small, friction: 0.6 },
      { position: { x: 0, y: 11 }, shape: box(10, 10), friction: 0.6 },
    ],
  }
}

/**
 * Joints at work: a paddle turned by a motor (revolute, motor) that bats falling boxes, an arm
 * hinged at one end that drops onto its lower limit (revolute, limits), and a ball bobbing on a
 * soft spring (distance, 1.5 Hz, damping 0.1). Body 1 is the paddle, 2 the arm, 3 the ball.
 */
export function jointsScene(): SceneBlueprint {
  const bodies: BodyDef[] = [
    groundDef(),
    { position: { x: -6, y: 3 }, shape: box(2, 0.15) },
    { position: { x: 1, y: 5 }, shape: box(1, 0.1) },
    { position: { x: 6, y: 5 }, shape: circle(0.4) },
  ]
  for (let i = 0; i < 6; i++) {
    bodies.push({ position: { x: -7 + (i % 3), y: 6 + Math.floor(i / 3) }, shape: box(0.25, 0.25) })
  }
  bodies.push({ position: { x: 1.6, y: 7 }, shape: circle(0.3) })
  const joints: JointDef[] = [
    {
      type: 'revolute',
      bodyA: null,
      bodyB: 1,
      anchor: { x: -6, y: 3 },
      enableMotor: true,
      motorSpeed: 1.5,
      maxMotorTorque: 200,
    },
    {
      type: 'revolute',
      bodyA: null,
      bodyB: 2,
      anchor: { x: 0, y: 5 },
      enableLimit: true,
      lowerAngle: -PI / 4,
      upperAngle: PI / 6,
    },
    {
      type: 'distance',
      bodyA: null,
      bodyB: 3,
      anchorA: { x: 6, y: 8 },
      anchorB: { x: 6, y: 5 },
      length: 2,
      hertz: 1.5,
      dampingRatio: 0.1,
    },
  ]
  return { name: 'joints', gravity: { x: 0, y: -10 }, bodies, joints }
}

/**
 * A 2 x 8 tower of 1 m boxes and a 0.75 m steel-dense ball (density 5) on an 8 m rope anchored
 * above, released from level with the anchor: it swings down and hits the tower low. The rope
 * (minLength 0) only pulls. Body 1 is the ball.
 */
export function wreckingBallScene(): SceneBlueprint {
  const bodies: BodyDef[] = [
    groundDef(),
    { position: { x: -12, y: 10 }, shape: circle(0.75), density: 5, friction: 0.4 },
  ]
  const shape = box(0.5, 0.5)
  for (let row = 0; row < 8; row++) {
    for (let column = 0; column < 2; column++) {
      bodies.push({ position: { x: -2.5 + column, y: 0.5 + row }, shape, friction: 0.6 })
    }
  }
  const joints: JointDef[] = [
    {
      type: 'distance',
      bodyA: null,
      bodyB: 1,
      anchorA: { x: -4, y: 10 },
      anchorB: { x: -12, y: 10 },
      minLength: 0,
      maxLength: 8,
    },
  ]
  return { name: 'wrecking-ball', gravity: { x: 0, y: -10 }, bodies, joints }
}

/**
 * Newton's cradle: five 0.5 m balls (restitution 1, no friction) on 4 m rods, 6 cm apart; the
 * leftmost is raised 30 degrees and let go. The gap is wider than a ball travels in one step
 * (3.3 m/s at the bottom, 5.5 cm per step), so every impact is a separate two-body collision with
 * an approach speed above the restitution threshold: resting balls pressed together would instead
 * share one inelastic solve. Bodies 1-5 are the balls, left to right.
 */
export function newtonsCradleScene(count = 5): SceneBlueprint {
  const r = 0.5
  const gap = 0.06
  const L = 4
  const top = 6
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  for (let i = 0; i < count; i++) {
    const x = (i - (count - 1) / 2) * (2 * r + gap)
    const raised = i === 0 ? PI / 6 : 0
    const p = { x: x - L * sin(raised), y: top - L * cos(raised) }
    bodies.push({ position: p, shape: circle(r), friction: 0, restitution: 1 })
    joints.push({ type: 'distance', bodyA: null, bodyB: i + 1, anchorA: { x, y: top }, anchorB: p })
  }
  return { name: 'newtons-cradle', gravity: { x: 0, y: -10 }, bodies, joints }
}

/**
 * A chain bridge: `planks` planks 1 m long pinned end to end by revolute joints, both ends pinned
 * to the world 5 m above the ground; a few boxes and balls fall on it. Bodies 1..planks are planks.
 */
export function chainBridgeScene(planks = 20): SceneBlueprint {
  const y = 5
  const x0 = -planks / 2
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  const plank = box(0.5, 0.1)
  for (let i = 0; i < planks; i++) {
    bodies.push({ position: { x: x0 + 0.5 + i, y }, shape: plank, friction: 0.6 })
    joints.push({ type: 'revolute', bodyA: i === 0 ? null : i, bodyB: i + 1, anchor: { x: x0 + i, y } })
  }
  joints.push({ type: 'revolute', bodyA: null, bodyB: planks, anchor: { x: -x0, y } })
  for (let i = 0; i < 6; i++) {
    const x = -planks / 4 + (i * planks) / 10
    bodies.push({ position: { x, y: y + 2 + (i % 2) }, shape: i % 2 === 0 ? box(0.4, 0.4) : circle(0.4) })
  }
  return { name: 'chain-bridge', gravity: { x: 0, y: -10 }, bodies, joints }
}

/**
 * A card house of `storeys` storeys (Box2D v3's card-house benchmark geometry): cards 0.4 m tall
 * and 2 mm thick lean in pairs at +-25 degrees, with flat cards across neighbouring pairs; the
 * bottom storey has `storeys` pairs, each storey one fewer (five by default: 40 cards). Friction 0.7.
 */
export function cardHouseScene(storeys = 5): SceneBlueprint {
  const halfHeight = 0.2
  const card = box(0.001, halfHeight)
  const lean = (25 * PI) / 180
  const bodies: BodyDef[] = [groundDef()]
  const add = (x: number, y: number, angle: number): void => {
    bodies.push({ position: { x, y }, angle, shape: card, friction: 0.7 })
  }
  let y = halfHeight - 0.02
  let z0 = 0
  for (let pairs = storeys; pairs > 0; pairs--) {
    let z = z0
    for (let i = 0; i < pairs; i++) {
      if (i !== pairs - 1) add(z + 0.25, y + halfHeight - 0.015, PI / 2)
      add(z, y, -lean)
      z += 0.175
      add(z, y, lean)
      z += 0.175
    }
    y += 2 * halfHeight - 0.03
    z0 += 0.175
  }
  return { name: 'card-house', gravity: { x: 0, y: -10 }, bodies }
}

/*
 * The "marble run" (issue 27): balls and capsules roll and slide down four zig-zag chain tracks into
 * a bin whose floor is a sensor that counts arrivals. Each track is one open chain on its own static
 * body: a straight ramp of 0.5 m segments falling 15 degrees toward its open end, and at its high end
 * a curved wall (a quarter circle of radius 2 m, then 4 m straight up) that catches the marbles
 * falling off the track above and turns them around. The chains run so that their collision side
 * (the right of travel) faces the marbles: the ramp's top and the wall's inside. Track 0's wall is
 * on the left, track 1's on the right, and so on; the last track drops the marbles into the bin.
 */

/** Where the marble run puts things (m). */
export const MARBLE_RUN_LAYOUT = {
  /** Height of track k's high end: HIGH_END - k * TRACK_SPACING. */
  highEnd: 22,
  trackSpacing: 5,
  tracks: 4,
  /** Half the horizontal length of a ramp. */
  rampHalfLength: 7,
  /** The sensor box in the bin: x from binLeft to binRight, y from 0 to sensorTop. */
  binLeft: -20,
  binRight: -6,
  sensorTop: 2,
} as const

/** Marbles in the scene: balls then capsules. */
export const MARBLE_RUN_BALLS = 12
export const MARBLE_RUN_CAPSULES = 6

/** Ramp slope (rad): 15 degrees. */
const SLOPE = PI / 12

/**
 * The points of a track whose wall is on the left (x < 0), high end at (-L, h), right to left so
 * that the collision side is up (and inside the wall); the first and last points are ghosts.
 */
function leftWallTrack(h: number, L: number): Vec2[] {
  const drop = (2 * L * sin(SLOPE)) / cos(SLOPE)
  const points: Vec2[] = []
  // Ghost beyond the open (low) end, then the ramp from x = L to x = -L.
  const step = 0.5
  const n = Math.round((2 * L) / step)
  points.push({ x: L + step, y: h - drop - (step * drop) / (2 * L) })
  for (let i = 0; i <= n; i++) {
    const x = L - i * step
    points.push({ x, y: h - (drop * (x + L)) / (2 * L) })
  }
  // The wall: a quarter circle of radius 2 about (-L, h + 2) from its bottom to its left point,
  // starting tangent to the ramp's direction, then straight up.
  const r = 2
  for (let k = 1; k <= 12; k++) {
    const a = -PI / 2 - (k * PI) / 24
    points.push({ x: -L + r * cos(a), y: h + r + r * sin(a) })
  }
  for (let k = 1; k <= 4; k++) points.push({ x: -L - r, y: h + r + k })
  // Ghost above the wall's top.
  points.push({ x: -L - r, y: h + r + 5 })
  return points
}

/** Marbles rolling down four chain tracks into a bin whose floor sensor counts them. */
export function marbleRunScene(): SceneBlueprint {
  const M = MARBLE_RUN_LAYOUT
  const bodies: BodyDef[] = [groundDef()]
  const compoundBodies: CompoundBodyDef[] = []
  for (let k = 0; k < M.tracks; k++) {
    const points = leftWallTrack(M.highEnd - k * M.trackSpacing, M.rampHalfLength)
    // Odd tracks are mirrored (wall on the right): mirror x and reverse the order, so the
    // collision side stays on the right of travel.
    const track = k % 2 === 0 ? points : points.map((p) => ({ x: -p.x, y: p.y })).reverse()
    compoundBodies.push({ type: 'static', shapes: [{ shape: chain(track), friction: 0.4 }] })
  }
  // The bin: two walls and the sensor on one static body.
  const binWidth = M.binRight - M.binLeft
  compoundBodies.push({
    type: 'static',
    position: { x: 0.5 * (M.binLeft + M.binRight), y: 0 },
    shapes: [
      { shape: box(0.25, 1.5, { x: -0.5 * binWidth - 0.25, y: 1.5 }) },
      { shape: box(0.25, 1, { x: 0.5 * binWidth + 0.25, y: 1 }) },
      { shape: box(0.5 * binWidth, 0.5 * M.sensorTop, { x: 0, y: 0.5 * M.sensorTop }), sensor: true },
    ],
  })
  // The marbles, in a column above track 0's wall end.
  const startX = -M.rampHalfLength + 1
  const startY = M.highEnd + 1
  for (let i = 0; i < MARBLE_RUN_BALLS + MARBLE_RUN_CAPSULES; i++) {
    const position = { x: startX + 0.3 * (i % 3), y: startY + 0.9 * i }
    if (i % 3 === 2 && i < 3 * MARBLE_RUN_CAPSULES) {
      bodies.push({
        position,
        shape: capsule({ x: -0.3, y: 0 }, { x: 0.3, y: 0 }, 0.2),
        friction: 0.1,
        angle: 0.3,
      })
    } else {
      bodies.push({ position, shape: circle(0.25), friction: 0.6, restitution: 0.1 })
    }
  }
  return { name: 'marble-run', gravity: { x: 0, y: -10 }, bodies, compoundBodies }
}

/** Builds a blueprint in a world (bodies, then joints); returns the created body ids in blueprint order. */
export function buildScene(world: BodyFactory, scene: SceneBlueprint): BodyId[] {
  world.setGravity(scene.gravity)
  const ids: BodyId[] = []
  for (const def of scene.bodies) ids.push(world.createBody(def))
  for (const def of scene.compoundBodies ?? []) ids.push(world.createBody(def))
  for (const def of scene.joints ?? []) {
    if (world.createJoint === undefined)
      throw new Error(`scene ${scene.name} has joints; the factory cannot make them`)
    world.createJoint(resolveJoint(def, ids))
  }
  return ids
}

/** A blueprint joint with its body indices replaced by the created ids. */
function resolveJoint(def: JointDef, ids: BodyId[]): JointDef {
  const id = (index: number): BodyId => {
    if (!Number.isInteger(index) || index < 0 || index >= ids.length) {
      throw new RangeError(`scene joint refers to body index ${index} of ${ids.length}`)
    }
    return ids[index]
  }
  if (def.type === 'mouse') return { ...def, body: id(def.body) }
  return { ...def, bodyA: def.bodyA === null ? null : id(def.bodyA), bodyB: id(def.bodyB) }
}
