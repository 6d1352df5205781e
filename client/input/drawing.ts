/*
 * Turning what a player draws into spawn commands (PROTOCOL.md, `spawn`): a stroke (freehand or
 * click by click) is simplified with Ramer-Douglas-Peucker (Ramer 1972; Douglas and Peucker 1973)
 * until it fits the wire's limits, then becomes an outline body (the server decomposes it with the
 * engine's decompose) or, for ground, static one-sided chains; a drag becomes a box, circle or
 * capsule. Shapes travel in the body frame within MAX_SHAPE_EXTENT of the body's origin, so a body
 * is placed at the middle of what was drawn. The outline is checked here with the same decompose
 * the server runs, so a self-intersecting drawing is refused in the page at once with the engine's
 * reason (the server would refuse it alike).
 */
import { decompose, MAX_OUTLINE_POINTS, type Vec2 } from '../../engine/index.ts'
import { MAX_SHAPE_EXTENT, MIN_SHAPE_EXTENT, type SpawnCommand } from '../../shared/index.ts'

/** What a drag with the Draw tool makes. */
export type DrawForm = 'outline' | 'rect' | 'circle' | 'capsule'
/** The Draw tool's forms, in the order the tool cycles through them. */
export const DRAW_FORMS: readonly DrawForm[] = ['outline', 'rect', 'circle', 'capsule']

/** Distance (m) from point p to the segment a-b. */
function distanceToSegment(p: Vec2, a: Vec2, b: Vec2): number {
  const dx = b.x - a.x
  const dy = b.y - a.y
  const l2 = dx * dx + dy * dy
  const t = l2 > 0 ? Math.max(0, Math.min(1, ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2)) : 0
  return Math.hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy))
}

/**
 * Ramer-Douglas-Peucker: the points of `points` (an open polyline) that keep every dropped point
 * within `tolerance` (m) of the simplified line; the first and last are always kept.
 */
export function simplify(points: readonly Vec2[], tolerance: number): Vec2[] {
  if (points.length <= 2) return points.slice()
  const keep = new Uint8Array(points.length)
  keep[0] = 1
  keep[points.length - 1] = 1
  const stack: Array<[number, number]> = [[0, points.length - 1]]
  while (stack.length > 0) {
    const [first, last] = stack.pop() as [number, number]
    let worst = -1
    let distance = tolerance
    for (let i = first + 1; i < last; i++) {
      const d = distanceToSegment(points[i], points[first], points[last])
      if (d > distance) {
        worst = i
        distance = d
      }
    }
    if (worst < 0) continue
    keep[worst] = 1
    stack.push([first, worst], [worst, last])
  }
  return points.filter((_, i) => keep[i] === 1)
}

/** Simplify with a tolerance that doubles from `tolerance` until at most `max` points remain. */
export function simplifyTo(points: readonly Vec2[], tolerance: number, max: number): Vec2[] {
  let t = tolerance
  let out = simplify(points, t)
  while (out.length > max && t < 100) {
    t *= 2
    out = simplify(points, t)
  }
  return out
}

/** A drawing turned into commands, or the reason it cannot be. */
export type Drawn = { ok: true; commands: SpawnCommand[] } | { ok: false; reason: string }

const round = (v: number): number => Math.round(v * 1e4) / 1e4
const middle = (points: readonly Vec2[]): Vec2 => {
  let [minX, minY, maxX, maxY] = [Infinity, Infinity, -Infinity, -Infinity]
  for (const p of points) {
    minX = Math.min(minX, p.x)
    minY = Math.min(minY, p.y)
    maxX = Math.max(maxX, p.x)
    maxY = Math.max(maxY, p.y)
  }
  return { x: (minX + maxX) / 2, y: (minY + maxY) / 2 }
}
const tooBig = `Too big: a drawn body fits in ${2 * MAX_SHAPE_EXTENT} x ${2 * MAX_SHAPE_EXTENT} m. Draw it smaller.`

/**
 * A closed outline (world m) as one body: simplified (tolerance `tolerance` m, at most
 * MAX_OUTLINE_POINTS points), placed at its middle, checked with the engine's decompose.
 */
export function outlineBody(stroke: readonly Vec2[], tolerance: number): Drawn {
  // A closed stroke: drop a last point that returns onto the first.
  const open = stroke.slice()
  while (open.length > 3 && Math.hypot(open[0].x - open.at(-1)!.x, open[0].y - open.at(-1)!.y) < tolerance)
    open.pop()
  const points = simplifyTo(open, tolerance, MAX_OUTLINE_POINTS)
  if (points.length < 3) return { ok: false, reason: 'Draw a shape with some area: at least three corners.' }
  const at = middle(points)
  const local = points.map((p) => ({ x: round(p.x - at.x), y: round(p.y - at.y) }))
  if (local.some((p) => Math.abs(p.x) > MAX_SHAPE_EXTENT || Math.abs(p.y) > MAX_SHAPE_EXTENT))
    return { ok: false, reason: tooBig }
  try {
    decompose(local)
  } catch (error) {
    return { ok: false, reason: `That outline cannot be a body: ${(error as Error).message}. Draw it again.` }
  }
  const outline: number[] = []
  for (const p of local) outline.push(p.x, p.y)
  return { ok: true, commands: [{ k: 'spawn', outline, x: round(at.x), y: round(at.y) }] }
}

/** Length (m) at most of the ghost edge a ground chain gets past each end of a run (its direction is what counts). */
const GHOST_REACH = 0.5

/**
 * A ground line (world m) as static bodies, each one one-sided chain (engine chain(): Box2D v3's,
 * with ghost vertices, so a body sliding along it never catches on a join): simplified, then cut
 * into runs that each fit within MAX_SHAPE_EXTENT of their middle and the wire's chain length
 * (MAX_OUTLINE_POINTS points with the ghosts). The line is run from right to left (reversed when
 * drawn the other way), so its upper side is the one that collides: ground is stood on. Each run's
 * ghosts point at the line's neighbouring points (past the line's ends: straight on), so the joins
 * between runs are smooth too. Points closer than 1 cm to the one before are dropped.
 */
export function groundBodies(stroke: readonly Vec2[], tolerance: number): Drawn {
  const points: Vec2[] = []
  for (const p of simplify(stroke, tolerance)) {
    const last = points.at(-1)
    if (!last || Math.hypot(p.x - last.x, p.y - last.y) >= 0.01) points.push(p)
  }
  if (
    points.length < 2 ||
    Math.hypot(points[1].x - points[0].x, points[1].y - points[0].y) < MIN_SHAPE_EXTENT
  )
    return { ok: false, reason: 'Drag to draw a ground line.' }
  if (points[points.length - 1].x > points[0].x) points.reverse()
  // Long edges are cut so that every run fits the extent.
  const line: Vec2[] = [points[0]]
  for (let i = 1; i < points.length; i++) {
    const [a, b] = [points[i - 1], points[i]]
    const pieces = Math.max(1, Math.ceil(Math.hypot(b.x - a.x, b.y - a.y) / (2 * MAX_SHAPE_EXTENT - 2)))
    for (let k = 1; k <= pieces; k++)
      line.push({ x: a.x + ((b.x - a.x) * k) / pieces, y: a.y + ((b.y - a.y) * k) / pieces })
  }
  // A ghost: toward `to` from `from`, GHOST_REACH at most (straight on past an end of the line).
  const ghost = (from: Vec2, to: Vec2): Vec2 => {
    const d = Math.hypot(to.x - from.x, to.y - from.y)
    const f = Math.min(1, GHOST_REACH / d)
    return { x: from.x + (to.x - from.x) * f, y: from.y + (to.y - from.y) * f }
  }
  const commands: SpawnCommand[] = []
  const fits = (run: readonly Vec2[]): boolean => {
    const m = middle(run)
    const room = MAX_SHAPE_EXTENT - GHOST_REACH - 0.01
    return run.every((q) => Math.abs(q.x - m.x) < room && Math.abs(q.y - m.y) < room)
  }
  let first = 0
  while (first < line.length - 1) {
    let last = first + 1
    while (
      last + 1 < line.length &&
      last + 1 - first + 3 <= MAX_OUTLINE_POINTS &&
      fits(line.slice(first, last + 2))
    )
      last++
    const run = line.slice(first, last + 1)
    const before =
      first > 0 ? line[first - 1] : { x: 2 * line[0].x - line[1].x, y: 2 * line[0].y - line[1].y }
    const n = line.length - 1
    const after =
      last < n ? line[last + 1] : { x: 2 * line[n].x - line[n - 1].x, y: 2 * line[n].y - line[n - 1].y }
    const chain = [ghost(run[0], before), ...run, ghost(run[run.length - 1], after)]
    const at = middle(run)
    const v: number[] = []
    for (const p of chain) v.push(round(p.x - at.x), round(p.y - at.y))
    commands.push({ k: 'spawn', shape: { type: 'chain', v }, x: round(at.x), y: round(at.y), static: true })
    first = last
  }
  return { ok: true, commands }
}

/**
 * A drag from `a` to `b` (world m) as a rectangle (the drag is its diagonal), a circle (centre a,
 * radius |b - a|) or a capsule (from a to b, radius `capsuleRadius`).
 */
export function dragBody(form: Exclude<DrawForm, 'outline'>, a: Vec2, b: Vec2, capsuleRadius: number): Drawn {
  const small = 'Drag further to draw it bigger.'
  const big = tooBig
  if (form === 'rect') {
    const hw = round(Math.abs(b.x - a.x) / 2)
    const hh = round(Math.abs(b.y - a.y) / 2)
    if (hw < 0.05 || hh < 0.05) return { ok: false, reason: small }
    if (hw > MAX_SHAPE_EXTENT || hh > MAX_SHAPE_EXTENT) return { ok: false, reason: big }
    return {
      ok: true,
      commands: [
        { k: 'spawn', shape: { type: 'box', hw, hh }, x: round((a.x + b.x) / 2), y: round((a.y + b.y) / 2) },
      ],
    }
  }
  if (form === 'circle') {
    const radius = round(Math.hypot(b.x - a.x, b.y - a.y))
    if (radius < 0.05) return { ok: false, reason: small }
    if (radius > MAX_SHAPE_EXTENT) return { ok: false, reason: big }
    return {
      ok: true,
      commands: [{ k: 'spawn', shape: { type: 'circle', radius }, x: round(a.x), y: round(a.y) }],
    }
  }
  const hx = round((b.x - a.x) / 2)
  const hy = round((b.y - a.y) / 2)
  if (Math.hypot(hx, hy) < 0.05) return { ok: false, reason: small }
  if (Math.abs(hx) + capsuleRadius > MAX_SHAPE_EXTENT || Math.abs(hy) + capsuleRadius > MAX_SHAPE_EXTENT)
    return { ok: false, reason: big }
  return {
    ok: true,
    commands: [
      {
        k: 'spawn',
        shape: { type: 'capsule', v: [-hx, -hy, hx, hy], radius: capsuleRadius },
        x: round((a.x + b.x) / 2),
        y: round((a.y + b.y) / 2),
      },
    ],
  }
}
