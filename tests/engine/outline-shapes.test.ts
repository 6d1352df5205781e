/*
 * The issue-27 shape makers for outlines, against closed forms:
 * - polygon(points) is the convex hull of its points (3 to 64 points, 3 to 8 vertices after the
 *   hull): hand-worked hulls of concave, collinear, self-intersecting and cloud inputs; a strictly
 *   convex list is kept exactly (as convexPolygon); bad input names the problem;
 * - decompose(outline) gives shapes that one body takes, and that body's mass is the shoelace area
 *   times the density, its centre of mass the polygon centroid and its inertia the polygon's second
 *   moment (closed forms over the outline, not over the pieces), for an L and a ten-point star on
 *   a moved, turned body.
 */
import { describe, expect, it } from 'vitest'
import {
  convexPolygon,
  cos,
  createWorld,
  decompose,
  type PolygonShape,
  polygon,
  sin,
  type Vec2,
} from '../../engine/index.ts'

/** Shoelace area, centroid and second moment about the origin of a simple polygon (either winding). */
function outlineMoments(ps: readonly Vec2[]): { area: number; cx: number; cy: number; io: number } {
  let a2 = 0
  let cx = 0
  let cy = 0
  let io = 0
  for (let i = 0; i < ps.length; i++) {
    const p = ps[i]
    const q = ps[(i + 1) % ps.length]
    const cross = p.x * q.y - q.x * p.y
    a2 += cross
    cx += (p.x + q.x) * cross
    cy += (p.y + q.y) * cross
    io += cross * (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y)
  }
  // Signs cancel in the ratios; the area and moment take the absolute value.
  return { area: Math.abs(a2) / 2, cx: cx / (3 * a2), cy: cy / (3 * a2), io: Math.abs(io) / 12 }
}

/** The vertex set of a shape, sorted, for comparison with a hand-worked hull. */
function vertexSet(shape: PolygonShape): Array<[number, number]> {
  return shape.vertices.map((v): [number, number] => [v.x, v.y]).sort((a, b) => a[0] - b[0] || a[1] - b[1])
}

function signedArea(shape: PolygonShape): number {
  let a2 = 0
  for (let i = 0; i < shape.count; i++) {
    const p = shape.vertices[i]
    const q = shape.vertices[(i + 1) % shape.count]
    a2 += p.x * q.y - q.x * p.y
  }
  return a2 / 2
}

describe('polygon(points) is the convex hull of its points', () => {
  it('a concave vertex is dropped: the hull of a notched square is the square', () => {
    const shape = polygon([
      { x: 0, y: 0 },
      { x: 2, y: 0 },
      { x: 1, y: 0.5 },
      { x: 2, y: 2 },
      { x: 0, y: 2 },
    ])
    expect(vertexSet(shape)).toEqual([
      [0, 0],
      [0, 2],
      [2, 0],
      [2, 2],
    ])
    expect(signedArea(shape)).toBeCloseTo(4, 14)
  })

  it('a collinear point is dropped, and a self-intersecting star order becomes the pentagon', () => {
    expect(
      vertexSet(
        polygon([
          { x: 0, y: 0 },
          { x: 1, y: 0 },
          { x: 2, y: 0 },
          { x: 1, y: 1 },
        ]),
      ),
    ).toEqual([
      [0, 0],
      [1, 1],
      [2, 0],
    ])
    const star = [0, 2, 4, 1, 3].map((k) => ({
      x: cos((2 * Math.PI * k) / 5),
      y: sin((2 * Math.PI * k) / 5),
    }))
    const pentagon = polygon(star)
    expect(pentagon.count).toBe(5)
    // A regular pentagon of circumradius 1: (5 / 2) sin(72 degrees), counter-clockwise.
    expect(signedArea(pentagon)).toBeCloseTo(2.5 * Math.sin((2 * Math.PI) / 5), 12)
  })

  it('a cloud of 40 points inside a hexagon gives the hexagon; more than 8 points are accepted', () => {
    const hexagon = Array.from({ length: 6 }, (_, i) => ({
      x: 3 * Math.cos((i * Math.PI) / 3),
      y: 3 * Math.sin((i * Math.PI) / 3),
    }))
    const inside = Array.from({ length: 34 }, (_, i) => ({
      x: 2 * Math.cos(i * 0.7) * ((i % 5) / 5),
      y: 2 * Math.sin(i * 1.3) * ((i % 7) / 7),
    }))
    const points = [...inside.slice(0, 17), ...hexagon, ...inside.slice(17)]
    const shape = polygon(points)
    expect(vertexSet(shape)).toEqual(
      hexagon.map((v): [number, number] => [v.x, v.y]).sort((a, b) => a[0] - b[0] || a[1] - b[1]),
    )
    expect(polygon(points)).toEqual(shape)
  })

  it('a strictly convex list is kept exactly as given (counter-clockwise), as convexPolygon keeps it', () => {
    const cw = [
      { x: 0.3, y: 0.1 },
      { x: 0.1, y: 1.7 },
      { x: 1.9, y: 1.2 },
      { x: 2.2, y: 0.004 },
    ]
    expect(polygon(cw)).toEqual(convexPolygon(cw))
    expect(polygon(cw).vertices).toEqual([...cw].reverse())
    expect(polygon(cw, 0.05)).toEqual(convexPolygon(cw, 0.05))
  })

  it.each([
    [
      'two points',
      [
        { x: 0, y: 0 },
        { x: 1, y: 0 },
      ],
      /polygon needs 3 to 64 points, got 2/,
    ],
    ['65 points', Array.from({ length: 65 }, (_, i) => ({ x: cos(i / 10), y: sin(i / 10) })), /got 65/],
    [
      'a NaN point',
      [
        { x: 0, y: 0 },
        { x: Number.NaN, y: 0 },
        { x: 1, y: 1 },
      ],
      /vertex 1 is not a finite point/,
    ],
    [
      'points that weld together',
      [
        { x: 0, y: 0 },
        { x: 0.001, y: 0 },
        { x: 0, y: 0.001 },
        { x: 0.01, y: 0.01 },
      ],
      /polygon: hull is degenerate.*weld/,
    ],
    [
      'points along one line',
      [
        { x: 0, y: 0 },
        { x: 1, y: 0.001 },
        { x: 2, y: 0 },
        { x: 3, y: 0.002 },
      ],
      /polygon: hull is degenerate.*one line/,
    ],
    [
      'a hull of nine vertices',
      Array.from({ length: 9 }, (_, i) => ({ x: cos((2 * Math.PI * i) / 9), y: sin((2 * Math.PI * i) / 9) })),
      /polygon: hull has 9 vertices, more than 8/,
    ],
  ])('polygon() refuses %s with a message naming it', (_name, points, message) => {
    expect(() => polygon(points)).toThrow(RangeError)
    expect(() => polygon(points)).toThrow(message)
  })
})

describe('decompose(outline) gives one body the mass of the outline', () => {
  const L = [
    { x: 0, y: 0 },
    { x: 3, y: 0 },
    { x: 3, y: 1 },
    { x: 1, y: 1 },
    { x: 1, y: 2 },
    { x: 0, y: 2 },
  ]
  const star = Array.from({ length: 10 }, (_, i) => {
    const r = i % 2 === 0 ? 2 : 0.8
    const a = (i * Math.PI) / 5 + 0.1
    return { x: 0.7 + r * Math.cos(a), y: -0.3 + r * Math.sin(a) }
  })

  it('the L by hand: area 4, centroid (5/4, 3/4); the shoelace closed forms agree', () => {
    const m = outlineMoments(L)
    expect(m.area).toBe(4)
    expect(m.cx).toBeCloseTo(5 / 4, 14)
    expect(m.cy).toBeCloseTo(3 / 4, 14)
  })

  it.each([
    ['an L', L],
    ['a ten-point star (clockwise)', [...star].reverse()],
  ])(
    '%s: mass = shoelace area x density, centre = polygon centroid, inertia = polygon second moment',
    (_name, outline) => {
      const density = 2.5
      const pieces = decompose(outline)
      expect(pieces.length).toBeGreaterThan(1)
      const world = createWorld()
      const angle = 0.4
      const position = { x: 5, y: 3 }
      const body = world.createBody({ position, angle, shapes: pieces.map((shape) => ({ shape, density })) })
      expect(world.bodyShapes(body).length).toBe(pieces.length)
      const m = outlineMoments(outline)
      const mass = world.getMass(body)
      expect(Math.abs(mass - m.area * density) / (m.area * density)).toBeLessThan(1e-12)
      const c = { x: cos(angle), y: sin(angle) }
      const expectedCenter = {
        x: position.x + c.x * m.cx - c.y * m.cy,
        y: position.y + c.y * m.cx + c.x * m.cy,
      }
      const center = world.getWorldCenter(body)
      expect(Math.abs(center.x - expectedCenter.x)).toBeLessThan(1e-12)
      expect(Math.abs(center.y - expectedCenter.y)).toBeLessThan(1e-12)
      // Parallel-axis theorem: the second moment about the centroid.
      const inertia = density * (m.io - m.area * (m.cx * m.cx + m.cy * m.cy))
      expect(Math.abs(world.getInertia(body) - inertia) / inertia).toBeLessThan(1e-12)
      // The body stands in a world and steps (the pieces collide as one body).
      world.createBody({
        type: 'static',
        position: { x: 0, y: -5 },
        shape: polygon([
          { x: -20, y: -1 },
          { x: 20, y: -1 },
          { x: 20, y: 0 },
          { x: -20, y: 0 },
        ]),
      })
      for (let i = 0; i < 240; i++) world.step()
      expect(world.getPosition(body).y).toBeLessThan(3)
      expect(world.getPosition(body).y).toBeGreaterThan(-6)
    },
  )
})
