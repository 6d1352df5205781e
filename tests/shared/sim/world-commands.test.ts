/*
 * The world-level command functions shared by the server's rooms and the offline sandbox, each run
 * on a real engine World. Expected values come from the protocol constants and hand computation
 * (world square, speed caps, rope length, grab force = min(1e7 N, 1000 N/kg * mass)), and the
 * effects are read back through the engine's own getters, never through the functions under test.
 */
import { describe, expect, it } from 'vitest'
import { box, circle, createWorld, type World } from '../../../engine/index.ts'
import {
  ANCHOR_MARGIN,
  MAX_ROPE_LENGTH,
  MAX_SPAWN_SPEED,
  WORLD_HALF_EXTENT,
} from '../../../shared/protocol/constants.ts'
import {
  addUserJoint,
  clampToWorld,
  deleteBody,
  GRAB_FORCE_PER_KG,
  grabBody,
  isMovable,
  MAX_GRAB_FORCE,
  moveGrab,
  removeJoint,
  setWorldGravity,
  spawnBody,
  type WorldResult,
} from '../../../shared/sim/world-commands.ts'

const zeroG = (): World => createWorld({ gravity: { x: 0, y: 0 } })
const unwrap = <T>(r: WorldResult<T>): T => {
  if (!r.ok) throw new Error(`unexpected refusal: ${r.reason}`)
  return r.value
}
const reasonOf = <T>(r: WorldResult<T>): string => (r.ok ? 'accepted' : r.reason)

describe('clampToWorld', () => {
  it('keeps points inside the world square and leaves inner points exact', () => {
    expect(clampToWorld(1e9, -1e9)).toEqual({ x: WORLD_HALF_EXTENT, y: -WORLD_HALF_EXTENT })
    expect(clampToWorld(-3.25, 7.5)).toEqual({ x: -3.25, y: 7.5 })
  })
})

describe('spawnBody', () => {
  it('creates a dynamic body with the wire shape, clamped position and clamped speeds', () => {
    const w = zeroG()
    const id = unwrap(
      spawnBody(w, {
        k: 'spawn',
        shape: { type: 'box', hw: 0.5, hh: 0.25 },
        x: 2 * WORLD_HALF_EXTENT,
        y: 3,
        angle: 0.5,
        vx: 1e6,
        vy: -1e6,
        w: -1e6,
      }),
    )
    expect(w.getBodyType(id)).toBe('dynamic')
    expect(w.getPosition(id)).toEqual({ x: WORLD_HALF_EXTENT, y: 3 })
    expect(w.getAngle(id)).toBeCloseTo(0.5, 12)
    expect(w.getLinearVelocity(id)).toEqual({ x: MAX_SPAWN_SPEED, y: -MAX_SPAWN_SPEED })
    expect(w.getAngularVelocity(id)).toBe(-MAX_SPAWN_SPEED)
    // A 1 m x 0.5 m box of density 1 weighs 0.5 kg.
    expect(w.getMass(id)).toBeCloseTo(0.5, 12)
  })

  it('keeps speeds under the cap unchanged and defaults angle and velocities to zero', () => {
    const w = zeroG()
    const a = unwrap(spawnBody(w, { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, vx: 7 }))
    expect(w.getLinearVelocity(a)).toEqual({ x: 7, y: 0 })
    expect(w.getAngle(a)).toBe(0)
    expect(w.getAngularVelocity(a)).toBe(0)
  })

  it('refuses a degenerate shape with a reason instead of throwing', () => {
    const w = zeroG()
    const r = spawnBody(w, { k: 'spawn', shape: { type: 'polygon', v: [0, 0, 1, 0, 2, 0] }, x: 0, y: 0 })
    expect(reasonOf(r)).toMatch(/^spawn refused: /)
    expect(w.bodyCount).toBe(0)
  })
})

describe('grabBody', () => {
  it('refuses static and missing bodies', () => {
    const w = zeroG()
    const ground = w.createBody({ type: 'static', shape: box(5, 1) })
    expect(reasonOf(grabBody(w, ground, 0, 0))).toBe(`body ${ground} cannot be grabbed`)
    expect(reasonOf(grabBody(w, 99, 0, 0))).toBe('body 99 cannot be grabbed')
    expect(w.jointIds()).toEqual([])
  })

  it('starts the target at the anchor and pulls a far anchor in to the shape reach', () => {
    const w = zeroG()
    const id = w.createBody({ shape: circle(0.5), position: { x: 10, y: 20 } })
    expect(unwrap(grabBody(w, id, 0.3, 0)).target).toEqual({ x: 10.3, y: 20 })
    // (30, 40) is 50 m out; the circle's reach is 0.5 m, so the anchor is (0.3, 0.4).
    const far = unwrap(grabBody(w, id, 30, 40)).target
    expect(far.x).toBeCloseTo(10.3, 12)
    expect(far.y).toBeCloseTo(20.4, 12)
  })

  it('caps the force at 1000 N per kg for a light body', () => {
    const w = zeroG()
    const id = w.createBody({ shape: box(0.5, 0.5) }) // 1 kg
    const { joint } = unwrap(grabBody(w, id, 0, 0))
    moveGrab(w, joint, 400, 0)
    w.step()
    const force = w.joints()[0].force
    expect(Math.hypot(force.x, force.y)).toBeCloseTo(GRAB_FORCE_PER_KG * 1, 6)
  })

  it('caps the force at 1e7 N for a body heavier than 10 t', () => {
    const w = zeroG()
    const id = w.createBody({ shape: box(100, 100) }) // 40,000 kg: 1000 N/kg would allow 4e7 N
    expect(w.getMass(id)).toBeCloseTo(40000, 6)
    const { joint } = unwrap(grabBody(w, id, 0, 0))
    moveGrab(w, joint, 400, 0)
    w.step()
    const force = w.joints()[0].force
    expect(Math.hypot(force.x, force.y) / MAX_GRAB_FORCE).toBeCloseTo(1, 6)
  })
})

describe('moveGrab', () => {
  it('moves the target clamped to the world and returns the clamped point', () => {
    const w = zeroG()
    const id = w.createBody({ shape: circle(0.5) })
    const { joint } = unwrap(grabBody(w, id, 0, 0))
    expect(moveGrab(w, joint, -1e9, 3)).toEqual({ x: -WORLD_HALF_EXTENT, y: 3 })
    expect(w.joints()[0].anchorA).toEqual({ x: -WORLD_HALF_EXTENT, y: 3 })
  })

  it('only clamps when there is no grab or the joint is gone', () => {
    const w = zeroG()
    expect(moveGrab(w, null, 1e9, 0)).toEqual({ x: WORLD_HALF_EXTENT, y: 0 })
    expect(moveGrab(w, 42, 1, 2)).toEqual({ x: 1, y: 2 })
  })
})

describe('deleteBody and removeJoint', () => {
  it('deletes a dynamic body with its joints and refuses static or missing bodies', () => {
    const w = zeroG()
    const ground = w.createBody({ type: 'static', shape: box(5, 1) })
    const id = w.createBody({ shape: circle(0.5), position: { x: 0, y: 3 } })
    unwrap(addUserJoint(w, { k: 'pin', a: 0, b: id, x: 0, y: 3 }))
    expect(deleteBody(w, ground)).toBe(`body ${ground} does not exist or is static`)
    expect(deleteBody(w, 77)).toBe('body 77 does not exist or is static')
    expect(deleteBody(w, id)).toBeNull()
    expect(w.hasBody(id)).toBe(false)
    expect(w.jointIds()).toEqual([])
    expect(isMovable(w, id)).toBe(false)
  })

  it('removes a joint once and ignores one that no longer exists', () => {
    const w = zeroG()
    const id = w.createBody({ shape: circle(0.5) })
    const { joint } = unwrap(grabBody(w, id, 0, 0))
    removeJoint(w, joint)
    expect(w.hasJoint(joint)).toBe(false)
    removeJoint(w, joint)
    expect(w.jointIds()).toEqual([])
  })
})

describe('addUserJoint', () => {
  it('pins a body to the world at a clamped point, anchors in each frame', () => {
    const w = zeroG()
    const id = w.createBody({ shape: box(1, 1), position: { x: WORLD_HALF_EXTENT, y: 0 } })
    const pin = unwrap(addUserJoint(w, { k: 'pin', a: 0, b: id, x: 1e9, y: 0 }))
    expect(pin).toEqual({
      id: pin.id,
      kind: 'pin',
      a: 0,
      b: id,
      ax: WORLD_HALF_EXTENT,
      ay: 0,
      bx: 0,
      by: 0,
      length: 0,
      ...{ min: 0, max: 0, hz: 0, damping: 0, ref: 0, limit: false, lower: 0, upper: 0 },
      ...{ motor: false, speed: 0, torque: 0, collide: false },
      ...{ force: 0, ux: 0, uy: 0, spring: false, target: 0, ahz: 0, adamping: 0, correction: 0 },
      ...{ breakForce: 0, breakTorque: 0, owner: 0 },
    })
    expect(w.hasJoint(pin.id)).toBe(true)
  })

  it('ties a rope whose length is the distance between the clamped anchors', () => {
    const w = zeroG()
    const a = w.createBody({ shape: circle(0.5), position: { x: 0, y: 0 } })
    const b = w.createBody({ shape: circle(0.5), position: { x: 3, y: 4 } })
    const rope = unwrap(addUserJoint(w, { k: 'rope', a, b, ax: 0, ay: 0, bx: 3, by: 4 }))
    expect(rope.length).toBe(5)
    expect(rope.kind).toBe('rope')
    expect([rope.ax, rope.ay, rope.bx, rope.by]).toEqual([0, 0, 0, 0])
    const info = w.joints()[0]
    expect(info.type).toBe('distance')
    expect([info.bodyA, info.bodyB]).toEqual([a, b])
  })

  it('refuses a rope longer than MAX_ROPE_LENGTH and accepts one exactly that long', () => {
    const w = zeroG()
    const id = w.createBody({ shape: circle(0.5) })
    const long = addUserJoint(w, { k: 'rope', a: 0, b: id, ax: 0, ay: MAX_ROPE_LENGTH + 0.001, bx: 0, by: 0 })
    expect(reasonOf(long)).toBe(`rope longer than ${MAX_ROPE_LENGTH} m`)
    expect(w.jointIds()).toEqual([])
    const exact = unwrap(
      addUserJoint(w, { k: 'rope', a: 0, b: id, ax: 0, ay: MAX_ROPE_LENGTH, bx: 0, by: 0 }),
    )
    expect(exact.length).toBe(MAX_ROPE_LENGTH)
  })

  it('refuses a static or missing body b, a missing body a, and a = b, in that order', () => {
    const w = zeroG()
    const ground = w.createBody({ type: 'static', shape: box(5, 1) })
    const id = w.createBody({ shape: circle(0.5), position: { x: 0, y: 3 } })
    expect(reasonOf(addUserJoint(w, { k: 'pin', a: 0, b: ground, x: 0, y: 0 }))).toBe(
      `body ${ground} does not exist or is static`,
    )
    expect(reasonOf(addUserJoint(w, { k: 'pin', a: 50, b: 60, x: 0, y: 0 }))).toBe(
      'body 60 does not exist or is static',
    )
    expect(reasonOf(addUserJoint(w, { k: 'pin', a: 50, b: id, x: 0, y: 0 }))).toBe('body 50 does not exist')
    expect(reasonOf(addUserJoint(w, { k: 'rope', a: id, b: id, ax: 0, ay: 0, bx: 1, by: 1 }))).toBe(
      'a joint needs two different bodies',
    )
    expect(w.jointIds()).toEqual([])
  })
})

describe('setWorldGravity', () => {
  it('sets gravity and wakes sleeping dynamic bodies', () => {
    const w = zeroG()
    const id = w.createBody({ shape: circle(0.5) })
    w.setAwake(id, false)
    setWorldGravity(w, 1, -2)
    expect(w.getGravity()).toEqual({ x: 1, y: -2 })
    expect(w.isAwake(id)).toBe(true)
  })
})

describe('pin and rope anchors must lie on or near their bodies', () => {
  // A 1 x 1 m half-extent box reaches sqrt(2) m from its centre; the margin adds ANCHOR_MARGIN.
  const limit = Math.SQRT2 + ANCHOR_MARGIN

  it('accepts a pin just inside the reach plus margin and refuses one just outside, naming the distance', () => {
    const w = zeroG()
    const id = w.createBody({ shape: box(1, 1), position: { x: 2, y: 3 } })
    unwrap(addUserJoint(w, { k: 'pin', a: 0, b: id, x: 2 + limit - 1e-9, y: 3 }))
    const far = addUserJoint(w, { k: 'pin', a: 0, b: id, x: 2, y: 3 + limit + 1e-6 })
    expect(reasonOf(far)).toBe(
      `pin anchor (2.00, ${(3 + limit).toFixed(2)}) is ${limit.toFixed(2)} m from body ${id}; it must be within ${limit.toFixed(2)} m`,
    )
    expect(w.jointIds().length).toBe(1)
  })

  it('refuses the issue attack: a pin between two bodies anchored 400 m from both', () => {
    const w = zeroG()
    const a = w.createBody({ shape: box(1, 1), position: { x: 0, y: 0 } })
    const b = w.createBody({ shape: box(1, 1), position: { x: 3, y: 0 } })
    expect(reasonOf(addUserJoint(w, { k: 'pin', a, b, x: 400, y: 400 }))).toContain(`from body ${b}`)
    // Near b but far from a: refused for a.
    expect(reasonOf(addUserJoint(w, { k: 'pin', a, b, x: 3, y: 0 }))).toContain(`from body ${a}`)
    expect(w.jointIds()).toEqual([])
  })

  it('checks both rope ends against their bodies, but lets a world end (a = 0) lie anywhere', () => {
    const w = zeroG()
    const a = w.createBody({ shape: circle(0.5), position: { x: 0, y: 0 } })
    const b = w.createBody({ shape: circle(0.5), position: { x: 10, y: 0 } })
    expect(reasonOf(addUserJoint(w, { k: 'rope', a, b, ax: 0, ay: 0, bx: 50, by: 0 }))).toContain(
      `from body ${b}`,
    )
    expect(reasonOf(addUserJoint(w, { k: 'rope', a, b, ax: 0, ay: 40, bx: 10, by: 0 }))).toContain(
      `from body ${a}`,
    )
    const world = unwrap(addUserJoint(w, { k: 'rope', a: 0, b, ax: 60, ay: 40, bx: 10.9, by: 0 }))
    expect(world.length).toBeCloseTo(Math.hypot(60 - 10.9, 40), 9)
    expect(w.jointIds().length).toBe(1)
  })
})

describe('spawn material', () => {
  it('gives a spawned body the density asked for (mass = density x area), and 1 otherwise', () => {
    const world = zeroG()
    const made = spawnBody(world, {
      k: 'spawn',
      shape: { type: 'box', hw: 0.5, hh: 0.25 },
      x: 0,
      y: 0,
      density: 4,
    })
    const plain = spawnBody(world, { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.25 }, x: 3, y: 0 })
    if (!made.ok || !plain.ok) throw new Error('spawn refused')
    expect(world.getMass(made.value)).toBeCloseTo(4 * 0.5, 12)
    expect(world.getMass(plain.value)).toBeCloseTo(0.5, 12)
  })

  it('bounces a ball dropped at 5 m/s back at restitution x 5 m/s, and not at all by default', () => {
    const rebound = (restitution?: number): number => {
      const world = zeroG()
      world.createBody({ type: 'static', shape: box(5, 1), position: { x: 0, y: -1 } })
      const r = spawnBody(world, {
        k: 'spawn',
        shape: { type: 'circle', radius: 0.5 },
        x: 0,
        y: 2,
        vy: -5,
        restitution,
      })
      if (!r.ok) throw new Error(r.reason)
      let best = -Infinity
      for (let i = 0; i < 60; i++) {
        world.step()
        best = Math.max(best, world.getLinearVelocity(r.value).y)
      }
      return best
    }
    expect(rebound(0.8) / 5).toBeCloseTo(0.8, 1)
    expect(rebound()).toBeLessThan(0.1)
  })

  it('slides a box 6x farther on friction 0.1 than on the default 0.6 (distance v^2 / (2 mu g))', () => {
    const slide = (friction?: number): number => {
      const world = createWorld({ gravity: { x: 0, y: -10 } })
      world.createBody({ type: 'static', shape: box(100, 1), position: { x: 0, y: -1 }, friction: 1 })
      const r = spawnBody(world, {
        k: 'spawn',
        shape: { type: 'box', hw: 0.5, hh: 0.5 },
        x: 0,
        y: 0.5,
        vx: 4,
        friction,
      })
      if (!r.ok) throw new Error(r.reason)
      for (let i = 0; i < 600; i++) world.step()
      return world.getPosition(r.value).x
    }
    // Contacts mix friction as sqrt(f1 f2) with the ground's 1: mu = sqrt(0.1), sqrt(0.6).
    const low = slide(0.1)
    const plain = slide()
    expect(low / (16 / (2 * Math.sqrt(0.1) * 10))).toBeCloseTo(1, 1)
    expect(plain / (16 / (2 * Math.sqrt(0.6) * 10))).toBeCloseTo(1, 1)
  })
})
