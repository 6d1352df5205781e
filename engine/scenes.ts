/*
 * Scenes, built in one place and reused by tests, benchmarks, the server and the client (Box2D
 * keeps shared/benchmarks.c for the same reason).
 *
 * A scene is a blueprint: plain body definitions (and later joint definitions) that any engine can
 * build. Concord's world builds it with buildScene(); the benchmark builds the very same list in
 * the peer engines, so every engine simulates identical geometry.
 */
import { cos, PI, sin, type Vec2 } from './math.ts'
import { Prng } from './prng.ts'
import { box, circle, polygon, type Shape } from './shapes.ts'
import type { BodyDef, BodyId } from './types.ts'

/** A scene as data: gravity and body definitions in creation order. */
export interface SceneBlueprint {
  name: string
  gravity: Vec2
  bodies: BodyDef[]
}

/** Anything that can create bodies (Concord's World). */
export interface BodyFactory {
  createBody(def: BodyDef): BodyId
  setGravity(g: Vec2): void
}

/** Ground: a static box whose top surface is y = 0, 200 m wide. */
export function groundDef(halfWidth = 100): BodyDef {
  return { type: 'static', position: { x: 0, y: -1 }, shape: box(halfWidth, 1), friction: 0.6 }
}

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

/** Builds a blueprint in a world; returns the created body ids in blueprint order. */
export function buildScene(world: BodyFactory, scene: SceneBlueprint): BodyId[] {
  world.setGravity(scene.gravity)
  const ids: BodyId[] = []
  for (const def of scene.bodies) ids.push(world.createBody(def))
  return ids
}

/** Scenes a user can pick by name, with the parameters the sandbox uses. */
export const SCENES: Readonly<Record<string, { description: string; make: () => SceneBlueprint }>> = {
  empty: { description: 'Only the ground', make: emptyScene },
  pyramid: { description: 'A 20-row pyramid of 210 boxes', make: () => pyramidScene(20) },
  pile: { description: '300 mixed shapes in a container', make: () => pileScene(300) },
  tower: { description: 'A staggered tower of 20 boxes', make: () => towerScene(20, true) },
  ramp: { description: 'A box resting on a 20 degree ramp', make: () => rampScene() },
  'heavy-on-light': { description: 'A 400:1 mass ratio stack', make: heavyOnLightScene },
}
