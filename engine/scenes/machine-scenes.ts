/*
 * The "machines" scene (issue 28): every joint kind at work, as a blueprint like scenes.ts (joint
 * bodies are indices into `bodies`, null is the world). From left to right on a 200 m ground:
 * - a car: a 2 m x 0.5 m chassis on two wheel joints (sprung suspension, travel limits, motors)
 *   driving right over low bumps;
 * - a piston: a block on a vertical prismatic joint with a spring, limits and a motor pushing up;
 * - a welded crane: a static mast with a boom of four welded boxes, a rope (distance joint with
 *   a motor reeling it in) from the boom's tip to a hanging load, and a counterweight on a sprung
 *   pin;
 * - a bridge of eight planks pinned end to end between two static piers, each pin breaking above
 *   400 N, with a heavy crate dropped on its middle: it breaks;
 * - a platform driven by a motor joint toward an offset above its start.
 */

import { box, circle } from '../collision/index.ts'
import { PI } from '../math.ts'
import type { BodyDef, JointDef } from '../types.ts'
import { groundDef } from './ground.ts'
import type { SceneBlueprint } from './scenes.ts'

/** Where the machines scene puts things (x of each machine's centre, m). */
export const MACHINES_LAYOUT = { car: -30, piston: -10, crane: 5, bridge: 25, platform: 45 } as const

/** Every joint kind working: a car, a piston, a welded crane, a bridge that breaks, a driven platform. */
export function machinesScene(): SceneBlueprint {
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  const add = (def: BodyDef): number => bodies.push(def) - 1
  const L = MACHINES_LAYOUT
  // Bumps for the car (static, low).
  for (let i = 0; i < 4; i++)
    add({ type: 'static', position: { x: L.car + 6 + 4 * i, y: 0 }, angle: PI / 4, shape: box(0.15, 0.15) })
  // Car.
  const chassis = add({ position: { x: L.car, y: 1.4 }, shape: box(1, 0.25), density: 2 })
  for (const side of [-1, 1]) {
    const at = { x: L.car + 0.8 * side, y: 0.45 }
    const wheel = add({ position: at, shape: circle(0.4), friction: 0.9 })
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
      motorSpeed: -6,
      maxMotorTorque: 20,
    })
  }
  // Piston.
  const block = add({ position: { x: L.piston, y: 1 }, shape: box(0.5, 0.5), density: 2 })
  joints.push({
    type: 'prismatic',
    bodyA: null,
    bodyB: block,
    anchor: { x: L.piston, y: 1 },
    axis: { x: 0, y: 1 },
    enableLimit: true,
    lower: -0.4,
    upper: 2,
    enableSpring: true,
    hertz: 1.5,
    dampingRatio: 0.1,
    targetTranslation: 1,
    enableMotor: true,
    motorSpeed: 0.5,
    maxMotorForce: 5,
  })
  // Welded crane: mast (static), boom of four 1 m boxes welded end to end, a reeling rope and a load.
  const mast = add({ type: 'static', position: { x: L.crane, y: 3 }, shape: box(0.25, 3) })
  let previous = mast
  for (let i = 0; i < 4; i++) {
    const boom = add({ position: { x: L.crane + 0.75 + i, y: 5.75 }, shape: box(0.5, 0.15) })
    joints.push({ type: 'weld', bodyA: previous, bodyB: boom, anchor: { x: L.crane + 0.25 + i, y: 5.75 } })
    previous = boom
  }
  const load = add({ position: { x: L.crane + 4, y: 2 }, shape: box(0.3, 0.3), density: 3 })
  joints.push({
    type: 'distance',
    bodyA: previous,
    bodyB: load,
    anchorA: { x: L.crane + 4, y: 5.6 },
    anchorB: { x: L.crane + 4, y: 2.3 },
    minLength: 0,
    maxLength: 3.3,
    enableMotor: true,
    motorSpeed: -0.2,
    maxMotorForce: 40,
  })
  const counterweight = add({ position: { x: L.crane - 1, y: 5 }, shape: box(0.2, 0.5), density: 4 })
  joints.push({
    type: 'revolute',
    bodyA: mast,
    bodyB: counterweight,
    anchor: { x: L.crane - 1, y: 5.5 },
    enableSpring: true,
    hertz: 1,
    dampingRatio: 0.3,
    targetAngle: 0.3,
  })
  // Bridge between two piers, pins breaking above 400 N, and a crate dropped on it.
  const left = add({ type: 'static', position: { x: L.bridge - 4.5, y: 1.5 }, shape: box(0.5, 1.5) })
  const right = add({ type: 'static', position: { x: L.bridge + 4.5, y: 1.5 }, shape: box(0.5, 1.5) })
  previous = left
  for (let i = 0; i < 8; i++) {
    const plank = add({ position: { x: L.bridge - 3.5 + i, y: 3 }, shape: box(0.5, 0.05), density: 2 })
    joints.push({
      type: 'revolute',
      bodyA: previous,
      bodyB: plank,
      anchor: { x: L.bridge - 4 + i, y: 3 },
      breakForce: 400,
    })
    previous = plank
  }
  joints.push({
    type: 'revolute',
    bodyA: previous,
    bodyB: right,
    anchor: { x: L.bridge + 4, y: 3 },
    breakForce: 400,
  })
  add({ position: { x: L.bridge, y: 6 }, shape: box(0.5, 0.5), density: 60 })
  // A platform driven up toward an offset 2 m above its start by a motor joint.
  const platform = add({ position: { x: L.platform, y: 1 }, shape: box(1.5, 0.1) })
  joints.push({
    type: 'motor',
    bodyA: null,
    bodyB: platform,
    linearOffset: { x: L.platform, y: 3 },
    angularOffset: 0,
    maxForce: 200,
    maxTorque: 200,
  })
  return { name: 'machines', gravity: { x: 0, y: -10 }, bodies, joints }
}
