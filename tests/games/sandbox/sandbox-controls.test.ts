/*
 * The sandbox's explode, slow-motion and control-lock commands (docs/games.md, "The sandbox's
 * commands"), on a real RoomSimulation. Oracles: a free-falling body's height after n steps of
 * semi-implicit Euler (hand formula), the explosion impulse per unit width times a circle's width
 * (Box2D v3.1's rule) divided by its mass, and the lock rule as written in the guide.
 */
import { describe, expect, it } from 'vitest'
import { circle } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import type { PlainData, SimCommand } from '../../../shared/index.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { cloneSimulation, encodeSyncPayload, restoreSyncPayload } from '../../../shared/sim/sync-payload.ts'

const options = { game: sandbox, name: 'unit', scene: 'empty', maxBodies: 100, controls: true }
const cmd = (kind: string, a: { [key: string]: PlainData }): SimCommand => ({ k: 'cmd', kind, a })

/** A sandbox room on the empty scene, zero gravity unless asked, with one ball; returns the ball id. */
function room(gravityY = 0): { sim: RoomSimulation; ball: number } {
  const sim = new RoomSimulation(options)
  sim.join(1, 'ada', '#ff0000')
  sim.join(2, 'bob', '#00ff00')
  expect(sim.apply(1, { k: 'gravity', x: 0, y: gravityY })).toBeNull()
  const ball = sim.world.createBody({
    type: 'dynamic',
    position: { x: 0, y: 50 },
    shape: circle(0.5),
    density: 1,
  })
  return { sim, ball }
}

describe('sandbox slow motion', () => {
  it('steps the world on every 2nd or 4th room tick only, so a falling body falls as far as in half or a quarter of the ticks', () => {
    for (const every of [1, 2, 4]) {
      const { sim, ball } = room(-10)
      expect(sim.apply(2, cmd('slow', { every }))).toBeNull()
      const steps0 = sim.world.tick
      for (let i = 0; i < 120; i++) sim.runTick()
      const n = 120 / every
      expect(sim.world.tick - steps0).toBe(n)
      // Semi-implicit Euler from rest over N = 4n sub-steps of h = 1/240 s (the engine's default
      // 4 sub-steps per step, as Box2D v3): y = y0 - g h^2 N (N + 1) / 2.
      const h = 1 / 240
      const N = 4 * n
      expect(sim.world.getPosition(ball).y).toBeCloseTo(50 - (10 * h * h * N * (N + 1)) / 2, 9)
    }
  })

  it('refuses a factor other than 1, 2 or 4, naming the field', () => {
    const { sim } = room()
    expect(sim.apply(1, cmd('slow', { every: 3 }))).toMatch(/^slow refused: .*every/)
    expect(sim.apply(1, cmd('slow', {}))).toMatch(/^slow refused: .*every/)
    expect(sim.slowMotion).toBe(1)
  })

  it('travels in the sync payload and in a clone, so a lockstep client steps on the same ticks', () => {
    const { sim } = room(-10)
    sim.apply(1, cmd('slow', { every: 4 }))
    sim.runTick()
    const restored = restoreSyncPayload(encodeSyncPayload(sim), { ...options, games: () => sandbox })
    if (!restored.ok) throw new Error(restored.reason)
    const clone = cloneSimulation(sim, options)
    for (let i = 0; i < 37; i++) {
      sim.runTick()
      restored.sim.runTick()
      clone.runTick()
      expect(restored.sim.hash()).toBe(sim.hash())
      expect(clone.hash()).toBe(sim.hash())
    }
    expect(restored.sim.slowMotion).toBe(4)
    expect(sim.saveState().slowMotion).toBe(4)
  })
})

describe('sandbox explode', () => {
  it('gives a circle inside the radius the impulse per length times its diameter, away from the blast', () => {
    const { sim, ball } = room()
    const mass = Math.PI * 0.5 * 0.5 // density 1, radius 0.5
    expect(sim.apply(2, cmd('explode', { x: -2, y: 50, radius: 3, impulse: 4 }))).toBeNull()
    const v = sim.world.getLinearVelocity(ball)
    expect(v.x).toBeCloseTo((4 * 1) / mass, 9)
    expect(v.y).toBeCloseTo(0, 12)
  })

  it('fades linearly to nothing over a second radius, and leaves bodies beyond it alone', () => {
    const { sim, ball } = room()
    const mass = Math.PI * 0.25
    // Nearest point 4.5 m away, radius 3, falloff 3: scale (6 - 4.5) / 3 = 0.5.
    sim.apply(1, cmd('explode', { x: -5, y: 50, radius: 3, impulse: 4 }))
    expect(sim.world.getLinearVelocity(ball).x).toBeCloseTo((0.5 * 4) / mass, 9)
    const far = room()
    far.sim.apply(1, cmd('explode', { x: -7, y: 50, radius: 3, impulse: 4 }))
    expect(far.sim.world.getLinearVelocity(far.ball).x).toBe(0)
  })

  it('refuses bad arguments naming the field', () => {
    const { sim } = room()
    expect(sim.apply(1, cmd('explode', { x: 0, y: 0, radius: 0, impulse: 1 }))).toMatch(
      /^explode refused: .*radius/,
    )
    expect(sim.apply(1, cmd('explode', { x: 0, y: 0, radius: 1, impulse: 1000 }))).toMatch(
      /^explode refused: .*impulse/,
    )
    expect(sim.apply(1, cmd('explode', { x: 600, y: 0, radius: 1, impulse: 1 }))).toMatch(
      /^explode refused: .*x/,
    )
  })
})

describe('sandbox control lock', () => {
  it("lets only the room's creator lock the controls, refuses others' controls while locked, and frees them when it leaves", () => {
    const { sim } = room()
    expect(sim.creator).toBe(1)
    expect(sim.apply(2, cmd('lock', { locked: true }))).toMatch(/only the room's creator \(player 1\)/)
    expect(sim.apply(1, cmd('lock', { locked: true }))).toBeNull()
    expect(sim.apply(2, { k: 'pause', paused: true })).toMatch(/locked by the room's creator \(player 1\)/)
    expect(sim.apply(2, cmd('slow', { every: 2 }))).toMatch(/locked/)
    expect(sim.apply(2, { k: 'reset' })).toMatch(/locked/)
    // Not controls: still everyone's.
    expect(sim.apply(2, cmd('explode', { x: 0, y: 0, radius: 1, impulse: 1 }))).toBeNull()
    expect(sim.apply(2, { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 5 })).toBeNull()
    expect(sim.apply(1, { k: 'pause', paused: true })).toBeNull()
    expect(sim.paused).toBe(true)
    sim.leave(1)
    expect(sim.controlsLocked).toBe(false)
    expect(sim.apply(2, { k: 'pause', paused: false })).toBeNull()
    // The creator stays the first joiner: player 2 cannot take the lock.
    expect(sim.apply(2, cmd('lock', { locked: true }))).toMatch(/only the room's creator/)
  })
})
