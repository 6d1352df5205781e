/*
 * World.hash() is cached until the world changes (a room and its recorder hash the same tick).
 * After every public method that changes the world, the cached hash must equal a hash computed
 * from scratch (hashWorld with a fresh writer: the independent oracle) and differ from the value
 * before the change. A method that forgot to mark the world changed would return the old value.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, type World } from '../../engine/index.ts'
import { ByteWriter } from '../../engine/world/save-format.ts'
import { hashWorld } from '../../engine/world/world-state.ts'

const fresh = (world: World): number => hashWorld(new ByteWriter(), world)

interface Setup {
  world: World
  ground: number
  ball: number
  crate: number
  mouse: number
  pin: number
}

function setup(): Setup {
  const world = createWorld()
  const ground = world.createBody({ type: 'static', shape: box(10, 0.5), position: { x: 0, y: -0.5 } })
  const ball = world.createBody({ shape: circle(0.5), position: { x: 0, y: 2 } })
  const crate = world.createBody({ shape: box(0.5, 0.5), position: { x: 2, y: 0.5 } })
  const mouse = world.createJoint({ type: 'mouse', body: crate, target: { x: 2, y: 0.5 } })
  const pin = world.createJoint({ type: 'revolute', bodyA: null, bodyB: ball, anchor: { x: 0, y: 2.5 } })
  for (let i = 0; i < 30; i++) world.step()
  return { world, ground, ball, crate, mouse, pin }
}

const changes: Array<[string, (s: Setup) => void]> = [
  ['step', (s) => s.world.step()],
  ['createBody', (s) => s.world.createBody({ shape: circle(0.25), position: { x: -3, y: 3 } })],
  ['destroyBody', (s) => s.world.destroyBody(s.crate)],
  ['setTransform', (s) => s.world.setTransform(s.crate, { x: 3, y: 1 }, 0.5)],
  ['setLinearVelocity', (s) => s.world.setLinearVelocity(s.crate, { x: 1, y: 2 })],
  ['setAngularVelocity', (s) => s.world.setAngularVelocity(s.crate, 3)],
  ['setAwake', (s) => s.world.setAwake(s.ball, false)],
  ['applyLinearImpulse', (s) => s.world.applyLinearImpulse(s.crate, { x: 1, y: 0 }, { x: 2, y: 1 })],
  ['setGravity', (s) => s.world.setGravity({ x: 1, y: -5 })],
  [
    'createJoint',
    (s) =>
      s.world.createJoint({
        type: 'distance',
        bodyA: s.ball,
        bodyB: s.crate,
        anchorA: { x: 0, y: 2 },
        anchorB: { x: 2, y: 0.5 },
      }),
  ],
  ['destroyJoint', (s) => s.world.destroyJoint(s.pin)],
  ['setJointTarget', (s) => s.world.setJointTarget(s.mouse, { x: 2.5, y: 1 })],
]

describe('World.hash() cache', () => {
  it('returns the from-scratch hash when nothing changed, also when asked twice', () => {
    const { world } = setup()
    expect(world.hash()).toBe(fresh(world))
    expect(world.hash()).toBe(fresh(world))
  })

  for (const [name, change] of changes) {
    it(`is recomputed after ${name}`, () => {
      const s = setup()
      const before = s.world.hash()
      change(s)
      const after = s.world.hash()
      expect(after).toBe(fresh(s.world))
      expect(after).not.toBe(before)
    })
  }

  it('save() and hash() in any order agree with the from-scratch hash', () => {
    const { world } = setup()
    world.hash()
    const saved = world.save()
    // Bytes 12-15 of a save hold the same FNV-1a as the hash (PROTOCOL.md).
    const view = new DataView(saved.buffer, saved.byteOffset, saved.byteLength)
    expect(view.getUint32(12, true)).toBe(world.hash())
    world.step()
    expect(world.hash()).toBe(fresh(world))
  })
})
