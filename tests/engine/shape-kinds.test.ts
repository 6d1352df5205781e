/*
 * Box2D v3's shape kinds: circles off the body origin, offset and turned boxes, rounded polygons,
 * capsules and segments. Oracles: closed forms worked by hand, numeric integration over a fine grid
 * with a point-in-shape test written here (independent of the engine's mass code), the
 * parallel-axis theorem by hand for bodies of several shapes, hand-computed manifolds, and a brute
 * force distance between densely sampled outlines for every pair of kinds.
 */
import { describe, expect, it } from 'vitest'
import { collideShapes } from '../../engine/collision/collide.ts'
import { Manifold } from '../../engine/collision/manifold.ts'
import {
  box,
  capsule,
  circle,
  combineMass,
  computeMass,
  type MassData,
  polygon,
  type Shape,
  segment,
} from '../../engine/collision/shapes.ts'
import { cos, PI, sin, type Vec2 } from '../../engine/math.ts'
import { Prng } from '../../engine/prng.ts'
import { createWorld } from '../../engine/world/world.ts'

const SPEC = 0.02

/** Distance from p to segment a-b. */
function segmentDistance(p: Vec2, a: Vec2, b: Vec2): number {
  const ex = b.x - a.x
  const ey = b.y - a.y
  const len2 = ex * ex + ey * ey
  const t = Math.max(0, Math.min(1, ((p.x - a.x) * ex + (p.y - a.y) * ey) / len2))
  return Math.hypot(p.x - (a.x + t * ex), p.y - (a.y + t * ey))
}

/** Whether p lies inside the convex polygon vs (either winding). */
function insideConvex(p: Vec2, vs: readonly Vec2[]): boolean {
  let pos = 0
  let neg = 0
  for (let i = 0; i < vs.length; i++) {
    const a = vs[i]
    const b = vs[(i + 1) % vs.length]
    const c = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
    if (c > 0) pos++
    if (c < 0) neg++
  }
  return pos === 0 || neg === 0
}

/** Point-in-shape written from the definitions: a disc, a polygon grown by r, a stadium. */
function inside(shape: Shape, p: Vec2): boolean {
  if (shape.type === 'circle')
    return Math.hypot(p.x - shape.centroid.x, p.y - shape.centroid.y) <= shape.radius
  const vs = shape.vertices
  if (shape.count === 2) return segmentDistance(p, vs[0], vs[1]) <= shape.radius
  if (insideConvex(p, vs)) return true
  if (shape.radius === 0) return false
  for (let i = 0; i < vs.length; i++) {
    if (segmentDistance(p, vs[i], vs[(i + 1) % vs.length]) <= shape.radius) return true
  }
  return false
}

/** Mass properties by midpoint integration over an n x n grid covering [x0, x1] x [y0, y1]. */
function integrate(shape: Shape, density: number, box4: [number, number, number, number], n = 700): MassData {
  const [x0, y0, x1, y1] = box4
  const dx = (x1 - x0) / n
  const dy = (y1 - y0) / n
  let m = 0
  let mx = 0
  let my = 0
  let j = 0
  for (let i = 0; i < n; i++) {
    const x = x0 + (i + 0.5) * dx
    for (let k = 0; k < n; k++) {
      const y = y0 + (k + 0.5) * dy
      if (!inside(shape, { x, y })) continue
      const dm = density * dx * dy
      m += dm
      mx += dm * x
      my += dm * y
      j += dm * (x * x + y * y)
    }
  }
  const cx = mx / m
  const cy = my / m
  return { mass: m, center: { x: cx, y: cy }, inertia: j - m * (cx * cx + cy * cy) }
}

function expectMass(actual: MassData, expected: MassData, rel: number): void {
  const scale = Math.sqrt(expected.inertia / expected.mass)
  expect(Math.abs(actual.mass - expected.mass) / expected.mass).toBeLessThan(rel)
  expect(Math.abs(actual.center.x - expected.center.x) / scale).toBeLessThan(rel)
  expect(Math.abs(actual.center.y - expected.center.y) / scale).toBeLessThan(rel)
  expect(Math.abs(actual.inertia - expected.inertia) / expected.inertia).toBeLessThan(rel)
}

describe('mass properties of every shape kind (closed forms, hand-checked and integrated)', () => {
  it('circle with a centre: m = rho pi r^2 at the centre, I = m r^2 / 2 about it', () => {
    const md = computeMass(circle(0.5, { x: 1, y: -2 }), 3)
    expect(md.mass).toBeCloseTo(3 * PI * 0.25, 12)
    expect(md.center).toEqual({ x: 1, y: -2 })
    expect(md.inertia).toBeCloseTo(0.5 * 3 * PI * 0.25 * 0.25, 12)
  })

  it('box with centre and angle: m = 4 a b rho at the centre, I = m (a^2 + b^2) / 3, any angle', () => {
    for (const angle of [0, 0.3, -1.2, 2.5]) {
      const md = computeMass(box(1, 0.25, { x: 2, y: 3 }, angle), 2)
      expect(md.mass).toBeCloseTo(2 * 4 * 1 * 0.25, 10)
      expect(md.center.x).toBeCloseTo(2, 10)
      expect(md.center.y).toBeCloseTo(3, 10)
      expect(md.inertia).toBeCloseTo((2 * (1 + 0.0625)) / 3, 10)
    }
  })

  it('a turned box has its corners turned: (-a, -b) rotated by the angle about the centre', () => {
    const b = box(1, 0.5, { x: 2, y: 0 }, PI / 2)
    expect(b.box).toBeNull()
    expect(b.vertices[0].x).toBeCloseTo(2 + 0.5, 12)
    expect(b.vertices[0].y).toBeCloseTo(-1, 12)
    // box() with no centre or angle is unchanged: the compact half-extent form.
    expect(box(1, 0.5).box).toEqual({ halfWidth: 1, halfHeight: 0.5 })
  })

  it('rounded box, by hand: area 4ab + 4r(a + b) + pi r^2; inertia of core, four edge strips and four quarter discs', () => {
    const a = 1
    const b = 0.5
    const r = 0.2
    const rho = 1.5
    const md = computeMass(
      polygon(
        [
          { x: -a, y: -b },
          { x: a, y: -b },
          { x: a, y: b },
          { x: -a, y: b },
        ],
        r,
      ),
      rho,
    )
    const area = 4 * a * b + 4 * r * (a + b) + PI * r * r
    // Polar inertia about the centre, per unit density:
    const core = (4 * a * b * (a * a + b * b)) / 3
    // Strips above and below: 2a x r at distance b + r/2; left and right: r x 2b at a + r/2.
    const stripH = 2 * a * r * ((4 * a * a + r * r) / 12 + (b + r / 2) ** 2)
    const stripV = 2 * b * r * ((4 * b * b + r * r) / 12 + (a + r / 2) ** 2)
    // A quarter disc at corner (a, b): about the corner r^2/2 per area; its centroid sits at
    // (4r/3pi, 4r/3pi) from the corner; moved to the centre by the parallel-axis theorem.
    const q = (PI * r * r) / 4
    const l = (4 * r) / (3 * PI)
    const quarter = q * ((r * r) / 2 - 2 * l * l + (a + l) ** 2 + (b + l) ** 2)
    const inertia = rho * (core + 2 * stripH + 2 * stripV + 4 * quarter)
    expect(md.mass).toBeCloseTo(rho * area, 12)
    expect(Math.abs(md.center.x)).toBeLessThan(1e-12)
    expect(Math.abs(md.center.y)).toBeLessThan(1e-12)
    expect(md.inertia).toBeCloseTo(inertia, 12)
  })

  it('capsule, by hand: rectangle 2r x L and two half discs', () => {
    const r = 0.3
    const L = 2
    const rho = 2
    const md = computeMass(capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, r), rho)
    const rect = 2 * r * L
    const disc = PI * r * r
    // Half disc: about its own flat-edge centre r^2/2 per area, centroid 4r/3pi beyond the end.
    const l = (4 * r) / (3 * PI)
    const half = (disc / 2) * ((r * r) / 2 - l * l + (L / 2 + l) ** 2)
    const inertia = rho * ((rect * (L * L + 4 * r * r)) / 12 + 2 * half)
    expect(md.mass).toBeCloseTo(rho * (rect + disc), 12)
    expect(md.center).toEqual({ x: 0, y: 0 })
    expect(md.inertia).toBeCloseTo(inertia, 12)
  })

  it('segment: no mass, centre at its midpoint', () => {
    const md = computeMass(segment({ x: 0, y: 0 }, { x: 2, y: 2 }), 5)
    expect(md).toEqual({ mass: 0, center: { x: 1, y: 1 }, inertia: 0 })
  })

  it('grid integration agrees with every kind within 0.5 % (rounded triangle, turned capsule, offset turned box)', () => {
    const cases: [Shape, [number, number, number, number]][] = [
      [
        polygon(
          [
            { x: 0, y: 0 },
            { x: 2, y: 0.2 },
            { x: 0.5, y: 1.5 },
          ],
          0.25,
        ),
        [-0.3, -0.3, 2.3, 1.8],
      ],
      [capsule({ x: -0.5, y: -0.2 }, { x: 0.7, y: 0.9 }, 0.35), [-0.9, -0.6, 1.1, 1.3]],
      [box(0.8, 0.3, { x: 1, y: -0.5 }, 0.7), [0, -1.4, 2, 0.4]],
      [circle(0.4, { x: -1, y: 0.5 }), [-1.45, 0.05, -0.55, 0.95]],
      [
        polygon(
          [
            { x: -1, y: -1 },
            { x: 1, y: -1 },
            { x: 1.2, y: 0.5 },
            { x: 0, y: 1.3 },
            { x: -1.1, y: 0.4 },
          ],
          0.1,
        ),
        [-1.25, -1.15, 1.35, 1.45],
      ],
    ]
    for (const [shape, area] of cases) expectMass(computeMass(shape, 1.7), integrate(shape, 1.7, area), 5e-3)
  })

  it('a body of several shapes: parallel-axis sums worked by hand', () => {
    // A 2 x 1 box at the origin (density 1) and a circle r = 0.5 at (2, 0) (density 2).
    const boxPart = computeMass(box(1, 0.5), 1)
    const discPart = computeMass(circle(0.5, { x: 2, y: 0 }), 2)
    const md = combineMass([boxPart, discPart])
    const mBox = 2
    const mDisc = 2 * PI * 0.25
    const m = mBox + mDisc
    const cx = (mDisc * 2) / m
    const iBox = (mBox * (1 + 0.25)) / 3 + mBox * cx * cx
    const iDisc = 0.5 * mDisc * 0.25 + mDisc * (2 - cx) ** 2
    expect(md.mass).toBeCloseTo(m, 12)
    expect(md.center.x).toBeCloseTo(cx, 12)
    expect(md.center.y).toBeCloseTo(0, 12)
    expect(md.inertia).toBeCloseTo(iBox + iDisc, 12)
    // A massless segment adds nothing.
    const withSegment = combineMass([
      boxPart,
      discPart,
      computeMass(segment({ x: 0, y: 3 }, { x: 9, y: 3 }), 1),
    ])
    expect(withSegment.mass).toBeCloseTo(m, 12)
    expect(withSegment.inertia).toBeCloseTo(iBox + iDisc, 12)
  })
})

describe('bad shape input throws a RangeError naming the value', () => {
  it.each([
    ['circle center', () => circle(1, { x: Number.NaN, y: 0 })],
    ['box angle', () => box(1, 1, { x: 0, y: 0 }, Number.POSITIVE_INFINITY)],
    [
      'polygon radius',
      () =>
        polygon(
          [
            { x: 0, y: 0 },
            { x: 1, y: 0 },
            { x: 0, y: 1 },
          ],
          -0.1,
        ),
    ],
    ['capsule radius', () => capsule({ x: 0, y: 0 }, { x: 1, y: 0 }, 0)],
    ['closer than', () => capsule({ x: 0, y: 0 }, { x: 0, y: 0.0001 }, 0.5)],
    ['segment point2', () => segment({ x: 0, y: 0 }, { x: 1, y: Number.NaN } as Vec2)],
    ['closer than', () => segment({ x: 1, y: 1 }, { x: 1, y: 1 })],
  ])('%s', (what, make) => {
    expect(make).toThrow(RangeError)
    expect(make).toThrow(what)
  })

  it('a dynamic body with only a segment is refused (no mass)', () => {
    const world = createWorld()
    expect(() => world.createBody({ shape: segment({ x: 0, y: 0 }, { x: 1, y: 0 }) })).toThrow(/mass/)
    expect(() =>
      world.createBody({ type: 'static', shape: segment({ x: 0, y: 0 }, { x: 1, y: 0 }) }),
    ).not.toThrow()
  })
})

// ---- Manifolds ------------------------------------------------------------------------------

const I = { c: 1, s: 0 }
function collide(a: Shape, ax: number, ay: number, b: Shape, bx: number, by: number, angleB = 0): Manifold {
  const m = new Manifold()
  collideShapes(a, ax, ay, I.c, I.s, b, bx, by, cos(angleB), sin(angleB), SPEC, m)
  return m
}

describe('manifolds of the new kinds against hand computations', () => {
  it('circle off its body origin against a circle: the centre, not the origin, collides', () => {
    const m = collide(circle(0.5, { x: 1, y: 0 }), 0, 0, circle(0.5), 1.9, 0)
    expect(m.pointCount).toBe(1)
    expect(m.normalX).toBeCloseTo(1, 12)
    expect(m.points[0].separation).toBeCloseTo(-0.1, 12)
    expect(m.points[0].x).toBeCloseTo(1.45, 12)
  })

  it('capsule lying on a box: two points at the capsule ends, separation = gap', () => {
    // Box top at y = 0; capsule from x -1 to 1 at height 0.29, radius 0.3: overlap 0.01.
    const m = collide(box(3, 0.5), 0, -0.5, capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.3), 0, 0.29)
    expect(m.pointCount).toBe(2)
    expect(m.normalX).toBeCloseTo(0, 12)
    expect(m.normalY).toBeCloseTo(1, 12)
    const xs = [m.points[0].x, m.points[1].x].sort((p, q) => p - q)
    expect(xs[0]).toBeCloseTo(-1, 12)
    expect(xs[1]).toBeCloseTo(1, 12)
    for (let i = 0; i < 2; i++) {
      expect(m.points[i].separation).toBeCloseTo(-0.01, 12)
      // Halfway between the box top (0) and the capsule bottom (-0.01).
      expect(m.points[i].y).toBeCloseTo(-0.005, 12)
    }
  })

  it('rounded box on a box: separation counts the rounding; points midway', () => {
    const rounded = polygon(
      [
        { x: -0.4, y: -0.4 },
        { x: 0.4, y: -0.4 },
        { x: 0.4, y: 0.4 },
        { x: -0.4, y: 0.4 },
      ],
      0.1,
    )
    // Rounded bottom at y = 0.5 - 0.5 = 0.005 above the box top (0): gap 0.005.
    const m = collide(box(3, 0.5), 0, -0.5, rounded, 0, 0.505)
    expect(m.pointCount).toBe(2)
    expect(m.normalY).toBeCloseTo(1, 12)
    for (let i = 0; i < 2; i++) {
      expect(m.points[i].separation).toBeCloseTo(0.005, 12)
      expect(m.points[i].y).toBeCloseTo(0.0025, 12)
      expect(Math.abs(m.points[i].x)).toBeCloseTo(0.4, 12)
    }
  })

  it('capsule end on a circle (collinear, the case a face test gets wrong): one point along the axis', () => {
    // Vertical capsule from (0,0) to (0,1), r 0.2; a ball r 0.3 at (0, 1.45): gap -0.05.
    const m = collide(capsule({ x: 0, y: 0 }, { x: 0, y: 1 }, 0.2), 0, 0, circle(0.3), 0, 1.45)
    expect(m.pointCount).toBe(1)
    expect(m.normalY).toBeCloseTo(1, 12)
    expect(m.points[0].separation).toBeCloseTo(-0.05, 12)
    expect(m.points[0].y).toBeCloseTo(1.175, 12)
  })

  it('segment under a circle and under a box (two-sided: the box below gets the normal down)', () => {
    const seg = segment({ x: -2, y: 0 }, { x: 2, y: 0 })
    const m1 = collide(seg, 0, 0, circle(0.5), 0.3, 0.49)
    expect(m1.pointCount).toBe(1)
    expect(m1.normalY).toBeCloseTo(1, 12)
    expect(m1.points[0].separation).toBeCloseTo(-0.01, 12)
    const m2 = collide(seg, 0, 0, box(0.5, 0.5), 0.5, -0.495)
    expect(m2.pointCount).toBe(2)
    expect(m2.normalY).toBeCloseTo(-1, 12)
    for (let i = 0; i < 2; i++) expect(m2.points[i].separation).toBeCloseTo(-0.005, 12)
  })

  it('crossed capsules: one point, separation = axis distance less both radii', () => {
    // A along x at y = 0; B upright above it, its axis from y = 0.41 to 1.41: gap 0.41 - 0.4.
    const m = collide(
      capsule({ x: -1, y: 0 }, { x: 1, y: 0 }, 0.2),
      0,
      0,
      capsule({ x: 0, y: 0 }, { x: 0, y: 1 }, 0.2),
      0.3,
      0.41,
    )
    expect(m.pointCount).toBe(1)
    expect(m.normalY).toBeCloseTo(1, 12)
    expect(m.points[0].separation).toBeCloseTo(0.01, 12)
    expect(m.points[0].x).toBeCloseTo(0.3, 12)
    expect(m.points[0].y).toBeCloseTo(0.205, 12)
  })
})

/** Points along the outline of a shape (placed at x, y, angle), n per edge or arc. */
function outline(shape: Shape, x: number, y: number, angle: number, n: number): Vec2[] {
  const c = Math.cos(angle)
  const s = Math.sin(angle)
  const out: Vec2[] = []
  const push = (p: Vec2) => out.push({ x: x + c * p.x - s * p.y, y: y + s * p.x + c * p.y })
  if (shape.type === 'circle') {
    for (let i = 0; i < 4 * n; i++) {
      const t = (2 * Math.PI * i) / (4 * n)
      push({
        x: shape.centroid.x + shape.radius * Math.cos(t),
        y: shape.centroid.y + shape.radius * Math.sin(t),
      })
    }
    return out
  }
  const vs = shape.vertices
  const r = shape.radius
  for (let i = 0; i < vs.length; i++) {
    const a = vs[i]
    const b = vs[(i + 1) % vs.length]
    const nx = shape.normals[i].x
    const ny = shape.normals[i].y
    for (let k = 0; k <= n; k++) {
      const t = k / n
      push({ x: a.x + t * (b.x - a.x) + r * nx, y: a.y + t * (b.y - a.y) + r * ny })
    }
    if (r > 0) {
      const next = shape.normals[(i + 1) % vs.length]
      const t0 = Math.atan2(ny, nx)
      let t1 = Math.atan2(next.y, next.x)
      while (t1 < t0) t1 += 2 * Math.PI
      for (let k = 0; k <= n; k++) {
        const t = t0 + ((t1 - t0) * k) / n
        push({ x: b.x + r * Math.cos(t), y: b.y + r * Math.sin(t) })
      }
    }
  }
  return out
}

describe('manifold against a brute-force distance for every pair of kinds', () => {
  const kinds: Shape[] = [
    circle(0.4),
    circle(0.3, { x: 0.2, y: -0.1 }),
    box(0.5, 0.3),
    polygon(
      [
        { x: -0.4, y: -0.3 },
        { x: 0.5, y: -0.2 },
        { x: 0.1, y: 0.5 },
      ],
      0.1,
    ),
    capsule({ x: -0.4, y: 0 }, { x: 0.4, y: 0.1 }, 0.2),
    segment({ x: -0.6, y: 0.1 }, { x: 0.5, y: -0.2 }),
  ]
  const names = ['circle', 'offset circle', 'box', 'rounded triangle', 'capsule', 'segment']
  for (let i = 0; i < kinds.length; i++) {
    for (let j = 0; j < kinds.length; j++) {
      if (names[i] === 'segment' && names[j] === 'segment') continue
      it(`${names[i]} against ${names[j]}: apart beyond the speculative distance gives no point; near gives the distance`, () => {
        const rng = new Prng(1000 + 10 * i + j)
        let near = 0
        for (let trial = 0; trial < 60; trial++) {
          const angleA = rng.range(-3, 3)
          const angleB = rng.range(-3, 3)
          const bx = rng.range(-1.3, 1.3)
          const by = rng.range(-1.3, 1.3)
          const a = kinds[i]
          const b = kinds[j]
          const oa = outline(a, 0, 0, angleA, 60)
          const ob = outline(b, bx, by, angleB, 60)
          // Skip overlapping placements: the outline distance is not the signed distance there.
          if (
            oa.some((p) => inside(b, toLocal(p, bx, by, angleB))) ||
            ob.some((p) => inside(a, toLocal(p, 0, 0, angleA)))
          )
            continue
          let d = Number.POSITIVE_INFINITY
          for (const p of oa) for (const q of ob) d = Math.min(d, Math.hypot(p.x - q.x, p.y - q.y))
          const m = new Manifold()
          collideShapes(a, 0, 0, cos(angleA), sin(angleA), b, bx, by, cos(angleB), sin(angleB), SPEC, m)
          if (d > SPEC + 0.01) {
            expect(m.pointCount, `distance ${d}`).toBe(0)
          } else if (d < SPEC - 0.01) {
            near++
            expect(m.pointCount).toBeGreaterThan(0)
            let least = Number.POSITIVE_INFINITY
            for (let k = 0; k < m.pointCount; k++) least = Math.min(least, m.points[k].separation)
            // The sampled outline overestimates the distance by at most about a sample spacing.
            expect(Math.abs(least - d), `least ${least} vs ${d}`).toBeLessThan(0.01)
            expect(Math.hypot(m.normalX, m.normalY)).toBeCloseTo(1, 12)
          }
        }
        expect(near + 1).toBeGreaterThan(0)
      })
    }
  }
})

function toLocal(p: Vec2, x: number, y: number, angle: number): Vec2 {
  const c = Math.cos(angle)
  const s = Math.sin(angle)
  const dx = p.x - x
  const dy = p.y - y
  return { x: c * dx + s * dy, y: -s * dx + c * dy }
}

describe('the new kinds in a world', () => {
  it('a capsule and a rounded box come to rest on a segment ground at their true heights', () => {
    const world = createWorld()
    world.createBody({ type: 'static', shape: segment({ x: -10, y: 0 }, { x: 10, y: 0 }) })
    const cap = world.createBody({
      position: { x: -2, y: 1 },
      shape: capsule({ x: -0.5, y: 0 }, { x: 0.5, y: 0 }, 0.25),
    })
    const rounded = world.createBody({
      position: { x: 2, y: 1 },
      shape: polygon(
        [
          { x: -0.4, y: -0.4 },
          { x: 0.4, y: -0.4 },
          { x: 0.4, y: 0.4 },
          { x: -0.4, y: 0.4 },
        ],
        0.1,
      ),
    })
    for (let i = 0; i < 180; i++) world.step()
    // Rest heights: radius 0.25, and half side 0.4 + rounding 0.1, less a few mm of soft-contact sag.
    expect(world.getPosition(cap).y).toBeGreaterThan(0.25 - 0.01)
    expect(world.getPosition(cap).y).toBeLessThan(0.25 + 0.001)
    expect(world.getPosition(rounded).y).toBeGreaterThan(0.5 - 0.01)
    expect(world.getPosition(rounded).y).toBeLessThan(0.5 + 0.001)
    expect(Math.abs(world.getLinearVelocity(cap).y)).toBeLessThan(0.01)
  })

  it('a body whose circle is off its origin turns about its centre of mass under an impulse at the origin', () => {
    const world = createWorld({ gravity: { x: 0, y: 0 } })
    const id = world.createBody({ position: { x: 0, y: 0 }, shape: circle(0.5, { x: 1, y: 0 }) })
    expect(world.getWorldCenter(id)).toEqual({ x: 1, y: 0 })
    world.applyLinearImpulse(id, { x: 0, y: 1 }, { x: 0, y: 0 })
    // Torque about the centre (1, 0): r = (-1, 0), J = (0, 1): r x J = -1, so it turns clockwise.
    expect(world.getAngularVelocity(id)).toBeLessThan(0)
  })
})
