/*
 * Scenes that stress joints: a pinned chain holding a much heavier box, and ragdolls (trees of
 * revolute joints with limits) dropped in a heap. Blueprints like scenes.ts (joint bodies are
 * indices into `bodies`, null is the world), reused by tests and benchmarks.
 */

import { box, circle } from '../collision/index.ts'
import { PI } from '../math.ts'
import type { BodyDef, JointDef } from '../types.ts'
import { groundDef, type SceneBlueprint } from './scenes.ts'

/** Top pin of the hanging chain: the world point the chain hangs from (m). */
export const CHAIN_TOP = { x: 0, y: 30 } as const
/** Length of one chain link between its pins (m). */
export const CHAIN_LINK_LENGTH = 0.5

/**
 * `links` links (0.5 x 0.1 m boxes, density 1, pinned end to end) hang straight down from the
 * world at CHAIN_TOP and hold a 0.5 m box `ratio` times heavier than a link, pinned at the middle of
 * its top edge. At rest the box's top edge is exactly links * 0.5 m below CHAIN_TOP. Bodies 1..links
 * are the links, top down; body links + 1 is the box.
 */
export function hangingChainScene(links = 20, ratio = 100): SceneBlueprint {
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  const L = CHAIN_LINK_LENGTH
  const linkMass = L * 0.1 // density 1
  for (let i = 0; i < links; i++) {
    const y = CHAIN_TOP.y - (i + 0.5) * L
    bodies.push({ position: { x: CHAIN_TOP.x, y }, shape: box(0.05, L / 2) })
    const anchor = { x: CHAIN_TOP.x, y: CHAIN_TOP.y - i * L }
    joints.push({ type: 'revolute', bodyA: i === 0 ? null : i, bodyB: i + 1, anchor })
  }
  const end = CHAIN_TOP.y - links * L
  // A 0.5 x 0.5 m box has area 0.25 m^2: density = ratio * linkMass / 0.25.
  bodies.push({
    position: { x: CHAIN_TOP.x, y: end - 0.25 },
    shape: box(0.25, 0.25),
    density: (ratio * linkMass) / 0.25,
  })
  joints.push({ type: 'revolute', bodyA: links, bodyB: links + 1, anchor: { x: CHAIN_TOP.x, y: end } })
  return { name: 'hanging-chain', gravity: { x: 0, y: -10 }, bodies, joints }
}

/** Parts of one ragdoll: body offsets from its feet (m) and shapes; see ragdoll(). */
const LIMB = PI / 2

/**
 * Appends one ragdoll standing with its feet at (x, y): torso, head, two two-part arms and two
 * two-part legs (10 bodies, 9 revolute joints, every joint limited like a human's). Heads and hands
 * weigh about a tenth of the torso.
 */
function ragdoll(bodies: BodyDef[], joints: JointDef[], x: number, y: number, angularVelocity: number): void {
  const first = bodies.length
  const part = (dx: number, dy: number, shape: BodyDef['shape']): number => {
    bodies.push({ position: { x: x + dx, y: y + dy }, shape, friction: 0.6, angularVelocity })
    return bodies.length - 1
  }
  const pin = (a: number, b: number, dx: number, dy: number, lower: number, upper: number): void => {
    const anchor = { x: x + dx, y: y + dy }
    joints.push({
      type: 'revolute',
      bodyA: a,
      bodyB: b,
      anchor,
      enableLimit: true,
      lowerAngle: lower,
      upperAngle: upper,
    })
  }
  const torso = part(0, 1.2, box(0.15, 0.3))
  const head = part(0, 1.64, circle(0.12))
  pin(torso, head, 0, 1.5, -0.5, 0.5)
  for (const side of [-1, 1]) {
    const upperArm = part(0.2 * side, 1.3, box(0.05, 0.15))
    pin(torso, upperArm, 0.2 * side, 1.45, -LIMB, LIMB)
    const lowerArm = part(0.2 * side, 1.0, box(0.045, 0.15))
    pin(upperArm, lowerArm, 0.2 * side, 1.15, side > 0 ? 0 : -2.5, side > 0 ? 2.5 : 0)
    const thigh = part(0.08 * side, 0.68, box(0.07, 0.22))
    pin(torso, thigh, 0.08 * side, 0.9, -1.5, 0.5)
    const shin = part(0.08 * side, 0.23, box(0.06, 0.22))
    pin(thigh, shin, 0.08 * side, 0.45, -2.4, 0)
  }
  if (bodies.length !== first + 10) throw new Error('a ragdoll has 10 parts')
}

/**
 * `count` ragdolls dropped from increasing heights, spinning, onto the ground and onto each other.
 * Bodies 1..10 are the first ragdoll (torso first), 11..20 the second, and so on.
 */
export function ragdollScene(count = 4): SceneBlueprint {
  const bodies: BodyDef[] = [groundDef()]
  const joints: JointDef[] = []
  for (let i = 0; i < count; i++)
    ragdoll(bodies, joints, 0.3 * (i % 3) - 0.3, 1 + 2.2 * i, i % 2 === 0 ? 2 : -3)
  return { name: 'ragdolls', gravity: { x: 0, y: -10 }, bodies, joints }
}
