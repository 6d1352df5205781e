/*
 * World queries over chain segments: a ray from the solid side (the right of travel) hits a chain
 * floor at the hand-computed point, one from behind passes through (Box2D v3's one-sided chain
 * ray cast); overlaps and shape casts see the segment as its two-sided line.
 */
import { describe, expect, it } from 'vitest'
import { box, chain, circle, createWorld, type World } from '../../engine/index.ts'

/** A static floor y = 0 from x = 10 to x = -10 (right to left, so its solid side faces up), ghosts beyond. */
function floorWorld(): { world: World; first: number } {
  const world = createWorld({ gravity: { x: 0, y: -10 } })
  const body = world.createBody({
    type: 'static',
    shapes: [
      {
        shape: chain([
          { x: 12, y: 0 },
          { x: 10, y: 0 },
          { x: 0, y: 0 },
          { x: -10, y: 0 },
          { x: -12, y: 0 },
        ]),
      },
    ],
  })
  return { world, first: world.bodyShapes(body)[0] as unknown as number }
}

describe('world queries over a chain', () => {
  it('a ray from above hits the floor at the hand-computed point and normal; one from below passes', () => {
    const { world } = floorWorld()
    const down = world.castRayClosest({ x: 3, y: 4 }, { x: 0, y: -8 })
    expect(down).not.toBeNull()
    expect(down!.fraction).toBeCloseTo(0.5, 12)
    expect(down!.point.x).toBeCloseTo(3, 12)
    expect(down!.point.y).toBeCloseTo(0, 12)
    expect(down!.normal.y).toBeCloseTo(1, 12)
    expect(world.castRayClosest({ x: 3, y: -4 }, { x: 0, y: 8 })).toBeNull()
    expect(world.castRay({ x: -5, y: 1 }, { x: 0, y: -2 })).toHaveLength(1)
  })

  it('overlaps and shape casts see the chain segment', () => {
    const { world } = floorWorld()
    expect(world.overlapAABB({ minX: 2, minY: -0.1, maxX: 4, maxY: 0.1 })).toHaveLength(1)
    expect(world.overlapAABB({ minX: 2, minY: 0.1, maxX: 4, maxY: 1 })).toHaveLength(0)
    expect(world.overlapShape(circle(0.5), { position: { x: 5, y: 0.4 }, angle: 0 })).toHaveLength(1)
    const hit = world.castShape(box(0.5, 0.5), { position: { x: 5, y: 3 }, angle: 0 }, { x: 0, y: -5 })
    expect(hit).not.toBeNull()
    expect(hit!.fraction).toBeCloseTo(2.5 / 5, 2)
  })
})
