/*
 * The Ground tool's line is a one-sided chain (client/input/drawing.ts groundBodies; issue 31):
 * a box sliding along a drawn 20-point ground never catches on a join. The line has 1 mm kinks
 * at every point (a hand's wobble that the simplifier keeps at this tolerance): with plain
 * segments a box's corner meets the next segment's end at each join (Box2D's "ghost collision");
 * on a chain with ghost vertices it slides on. The oracle is Coulomb friction: on level ground the
 * speed falls by at most mu times the normal impulse per step (mu = 0.6 for both shapes, g = 10:
 * 0.1 m/s per step on level ground, plus mu times what the 1 mm kinks take of the vertical speed).
 * The commands go through the wire's validation and the room's spawnShapeDefs, as a room builds them.
 */
import { describe, expect, it } from 'vitest'
import { groundBodies } from '../../../client/input/drawing.ts'
import { box, createWorld } from '../../../engine/index.ts'
import { type SpawnCommand, spawnShapeDefs, validateClientMessage } from '../../../shared/index.ts'

/** The 20 points a player drew from left to right: x = -8.55 ... 8.55, 0.9 m apart, y alternating 0 and 1 mm. */
const STROKE = Array.from({ length: 20 }, (_, i) => ({ x: -8.55 + 0.9 * i, y: i % 2 === 0 ? 0 : 0.001 }))

/** 45 points over 39.6 m: more than one chain can hold within the wire's 10 m of its middle. */
const LONG_STROKE = Array.from({ length: 45 }, (_, i) => ({ x: -19.8 + 0.9 * i, y: i % 2 === 0 ? 0 : 0.001 }))

/** A world with the ground the Ground tool sends for `stroke` (tolerance 0.1 mm keeps every point). */
function groundWorld(stroke = STROKE): { world: ReturnType<typeof createWorld>; commands: SpawnCommand[] } {
  const drawn = groundBodies(stroke, 0.0001)
  if (!drawn.ok) throw new Error(drawn.reason)
  const world = createWorld({ gravity: { x: 0, y: -10 } })
  for (const cmd of drawn.commands as SpawnCommand[]) {
    const checked = validateClientMessage({ t: 'input', seq: 1, cmd })
    if (!checked.ok) throw new Error(checked.reason)
    world.createBody({ type: 'static', position: { x: cmd.x, y: cmd.y }, shapes: spawnShapeDefs(cmd) })
  }
  return { world, commands: drawn.commands as SpawnCommand[] }
}

describe('Ground draws chains', () => {
  it('sends one static chain over all 20 points, its top side the one that collides', () => {
    const { world, commands } = groundWorld()
    expect(commands).toHaveLength(1)
    const shape = commands[0].shape
    expect(shape?.type).toBe('chain')
    // 20 points and a ghost at each end; run right to left (the collision side is the right of travel).
    const v = shape?.type === 'chain' ? shape.v : []
    expect(v.length / 2).toBe(22)
    expect(v[2] + commands[0].x).toBeCloseTo(8.55, 3)
    expect(world.bodyShapes(world.bodyIds()[0]).length).toBe(19)
    // A ball dropped on it stays on top.
    const ball = world.createBody({ position: { x: 0.3, y: 2 }, shape: box(0.2, 0.2) })
    for (let i = 0; i < 120; i++) world.step()
    expect(world.getPosition(ball).y).toBeCloseTo(0.2, 1)
  })

  it.each([
    ['a 20-point line (one chain)', STROKE, -8.3],
    ['a 45-point line (chains joined end to end)', LONG_STROKE, -4],
  ] as const)('a box slides along %s and slows only as friction says (Coulomb)', (_, stroke, start) => {
    const { world, commands } = groundWorld(stroke)
    if (stroke === LONG_STROKE) {
      expect(commands.length).toBeGreaterThan(1)
      // The box crosses from one chain to the next (their shared point is in its path).
      const ends = commands.map((c) => (c.shape?.type === 'chain' ? c.shape.v[2] + c.x : 0))
      expect(ends.some((x) => x > start && x < start + 6.75)).toBe(true)
    }
    const slider = world.createBody({
      position: { x: start, y: 0.25 + 0.001 },
      linearVelocity: { x: 9, y: 0 },
      shape: box(0.25, 0.25),
    })
    const v = { x: 0, y: 0 }
    let before = 9
    let beforeY = 0
    let worstDrop = 0
    let steps = 0
    while ((v.x > 0.05 || steps === 0) && steps < 600) {
      world.step()
      steps++
      world.getLinearVelocity(slider, v)
      // Coulomb: the friction impulse is at most mu times the normal impulse, which on level ground
      // is g dt plus what stops the box's vertical motion (the 1 mm kinks): per unit mass.
      const limit = 0.6 * (10 / 60 + Math.max(0, v.y - beforeY))
      worstDrop = Math.max(worstDrop, before - v.x - limit)
      before = v.x
      beforeY = v.y
      expect(Math.abs(v.y), `vertical speed at step ${steps}`).toBeLessThan(0.1)
      expect(Math.abs(world.getAngle(slider)), `tilt at step ${steps}`).toBeLessThan(0.01)
    }
    // It crossed the whole line (17.5 m: from 9 m/s at 6 m/s^2 it would stop after 6.75 m: so it
    // got at least that far at full friction, and no join stopped it sooner).
    const x = world.getPosition(slider).x
    expect(x).toBeGreaterThan(start + 6.75 - 0.1)
    // Never more than Coulomb allows (1 mm/s of slack for the solver's rounding).
    expect(worstDrop).toBeLessThan(0.001)
    // Where it stopped: v^2 / (2 mu g) from where it started, within 2 cm.
    expect(x - start).toBeCloseTo((9 * 9) / (2 * 0.6 * 10), 1)
  })
})
