/*
 * The "playground" scene (issue 31): a starting scene that shows what can be built, with ready-made
 * machines made of the joints a player can make. From left to right on the 200 m ground:
 * - a car: a 2.4 m chassis on two sprung wheel joints whose motors brake (speed 0): push it;
 * - a seesaw: a plank on a pin at the top of a static wedge, a ball and a box on its ends;
 * - a lift: a platform on a vertical prismatic joint with a soft spring between travel limits,
 *   carrying a box;
 * - a windmill: two blades welded into a cross, pinned to the background and turned by a motor;
 * - a few loose boxes, balls and polygons to play with.
 * Only boxes, circles and polygons, so every client draws it today.
 */

import { box, circle } from '../collision/index.ts'
import { PI } from '../math.ts'
import type { BodyDef, JointDef } from '../types.ts'
import { groundDef, regularPolygon, type SceneBlueprint } from './scenes.ts'

/** Where the playground puts things (x of each machine's centre, m). */
export const PLAYGROUND_LAYOUT = { car: -12, seesaw: -4, lift: 3, windmill: 10, loose: 16 } as const

/** The playground: ground, a car, a seesaw, a lift, a windmill and loose shapes (see the file comment). */
export function playgroundScene(): SceneBlueprint {
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  const add = (def: BodyDef): number => bodies.push(def) - 1
  const L = PLAYGROUND_LAYOUT
  // Car: chassis and two wheels on sprung wheel joints; the motors hold the wheels (a brake).
  const chassis = add({ position: { x: L.car, y: 1.2 }, shape: box(1.2, 0.25), density: 2 })
  for (const side of [-1, 1]) {
    const at = { x: L.car + 0.9 * side, y: 0.45 }
    const wheel = add({ position: at, shape: circle(0.45), friction: 0.9 })
    joints.push({
      type: 'wheel',
      bodyA: chassis,
      bodyB: wheel,
      anchor: at,
      axis: { x: 0, y: 1 },
      hertz: 4,
      dampingRatio: 0.7,
      enableLimit: true,
      lower: -0.25,
      upper: 0.25,
      enableMotor: true,
      motorSpeed: 0,
      maxMotorTorque: 5,
    })
  }
  // Seesaw: a static wedge, a plank pinned at its top, a ball and a box on the ends.
  add({
    type: 'static',
    position: { x: L.seesaw, y: 0 },
    shape: regularPolygon(3, 0.9),
    angle: PI / 2,
  })
  const plank = add({ position: { x: L.seesaw, y: 1.0 }, shape: box(3, 0.1), friction: 0.8 })
  joints.push({ type: 'revolute', bodyA: null, bodyB: plank, anchor: { x: L.seesaw, y: 0.9 } })
  add({ position: { x: L.seesaw - 2.5, y: 1.6 }, shape: circle(0.4), density: 2 })
  add({ position: { x: L.seesaw + 2.5, y: 1.5 }, shape: box(0.4, 0.4) })
  // Lift: a platform on a vertical slider with a spring and limits, a box riding on it.
  const platform = add({ position: { x: L.lift, y: 1 }, shape: box(1.2, 0.1), friction: 0.8 })
  joints.push({
    type: 'prismatic',
    bodyA: null,
    bodyB: platform,
    anchor: { x: L.lift, y: 1 },
    axis: { x: 0, y: 1 },
    enableLimit: true,
    lower: -0.8,
    upper: 3,
    enableSpring: true,
    hertz: 1,
    dampingRatio: 0.2,
    targetTranslation: 1.5,
  })
  add({ position: { x: L.lift, y: 1.6 }, shape: box(0.5, 0.5) })
  // Windmill: two blades welded into a cross, pinned to the background, motor driven.
  const hub = { x: L.windmill, y: 4.5 }
  const bladeA = add({ position: hub, shape: box(2, 0.12) })
  const bladeB = add({ position: hub, shape: box(0.12, 2) })
  joints.push({ type: 'weld', bodyA: bladeA, bodyB: bladeB, anchor: hub })
  joints.push({
    type: 'revolute',
    bodyA: null,
    bodyB: bladeA,
    anchor: hub,
    enableMotor: true,
    motorSpeed: 1,
    maxMotorTorque: 500,
  })
  // Loose shapes.
  for (let i = 0; i < 3; i++) {
    add({ position: { x: L.loose + 1.2 * i, y: 0.5 }, shape: box(0.5, 0.5) })
    add({ position: { x: L.loose + 1.2 * i, y: 1.6 }, shape: circle(0.4), restitution: 0.3 })
  }
  add({ position: { x: L.loose + 0.6, y: 2.8 }, shape: regularPolygon(5, 0.5) })
  add({ position: { x: L.loose + 1.8, y: 2.8 }, shape: regularPolygon(6, 0.5) })
  return { name: 'playground', gravity: { x: 0, y: -10 }, bodies, joints }
}
