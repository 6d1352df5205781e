/*
 * Drawing joints by kind, in world space (the renderer's y-up transform is set; `px` turns CSS
 * pixels into metres at the current zoom):
 *   rod     a solid bar between the anchors
 *   rope    taut: a straight cord; slack: a cord sagging under its spare length (a parabola whose
 *           arc length is the rope's, sag = sqrt(3 d (L - d) / 8) for span d and length L),
 *           lying along a level static box's top where the curve would pass through it
 *   spring  a zigzag of COILS coils between short straight ends, drawn across the current length
 *   pin     a pivot ring at the anchor and thin arms to both bodies' centres (Box2D's samples draw
 *           revolute joints the same way); a motor adds a curved arrow turning the way it drives;
 *           a limit adds the allowed arc [lower, upper] around the pivot and a tick at the angle
 *   weld    a small square at the anchor, turned with body b, and thin arms to both centres
 *   slider  the track along the axis through a's anchor (from lower to upper with stops when
 *           limited, else 1 m each way), a carriage at b's anchor, a motor arrow along the axis
 *   wheel   the suspension: the axis from a's anchor through the wheel's travel, a coil from a's
 *           anchor to the hub, the hub with a spoke turning with the wheel, the motor's arrow
 *   motor   a dashed line from body b's centre of mass to the pose it is driven to, and a cross there
 * The joints debug layer adds each anchor as a square and the reaction force on body b as an arrow
 * from its anchor (2 m per 100 N, at most 4 m) with its size in newtons.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { ViewBody, ViewJoint } from '../modes/index.ts'

/** Joint colours by kind (stroke). */
export const JOINT_COLORS = {
  rod: '#e8e8e8',
  rope: '#e0c080',
  spring: '#7fd8a0',
  pin: '#f0f0f0',
  weld: '#c9a0ff',
  slider: '#80c8ff',
  wheel: '#f0f0f0',
  drive: '#ffd080',
  motor: '#ffb347',
  limit: '#ff7f7f',
  anchor: '#ff40ff',
  force: '#ff40ff',
} as const

/** Coils in a drawn spring. */
const COILS = 8
/** Reaction arrows: metres per newton, and the longest arrow (m). */
const FORCE_SCALE = 0.02
const MAX_FORCE_ARROW = 4

/** Sag (m) of a slack rope of length `length` spanning `span` (parabola of the same arc length). */
export function ropeSag(span: number, length: number): number {
  if (length <= span) return 0
  return Math.sqrt((3 * span * (length - span)) / 8)
}

/** The flat top of a level static box (m): from x0 to x1 at height top. */
export interface Floor {
  x0: number
  x1: number
  top: number
}

/** The flat tops of the level static boxes among `bodies` (the ground, shelves), into `out`. */
export function floorsOf(bodies: readonly ViewBody[], out: Floor[] = []): Floor[] {
  out.length = 0
  for (const b of bodies) {
    const shape = b.shapes.length === 1 ? b.shapes[0] : null
    if (b.kind !== 0 || shape?.type !== 'box' || Math.abs(b.angle) > 1e-3) continue
    out.push({ x0: b.x - shape.hw, x1: b.x + shape.hw, top: b.y + shape.hh })
  }
  return out
}

/** Points along a slack rope's curve, one per ROPE_SEGMENTS, before any floor is applied. */
const ROPE_SEGMENTS = 24

/**
 * The drawn path of a slack rope (x, y pairs, m): the sagging parabola from anchor a to anchor b,
 * lying on a floor it would pass through instead (a floor counts when both anchors are above it),
 * so a slack rope between bodies on the ground is drawn along the ground, not under it.
 */
export function ropePath(
  ax: number,
  ay: number,
  bx: number,
  by: number,
  sag: number,
  floors: readonly Floor[],
): number[] {
  const cx = (ax + bx) / 2
  const cy = (ay + by) / 2 - 2 * sag
  const lowEnd = Math.min(ay, by)
  const path: number[] = []
  for (let i = 0; i <= ROPE_SEGMENTS; i++) {
    const t = i / ROPE_SEGMENTS
    const u = 1 - t
    const x = u * u * ax + 2 * u * t * cx + t * t * bx
    let y = u * u * ay + 2 * u * t * cy + t * t * by
    for (const f of floors) if (x >= f.x0 && x <= f.x1 && f.top <= lowEnd + 1e-6 && y < f.top) y = f.top
    path.push(x, y)
  }
  return path
}

/** Draw every joint; `bodies` by id gives pins their arms, `debug` adds anchors and reaction forces. */
export function drawJoints(
  ctx: CanvasRenderingContext2D,
  joints: readonly ViewJoint[],
  body: (id: number) => ViewBody | undefined,
  px: number,
  debug: boolean,
  floors: readonly Floor[] = [],
): void {
  ctx.lineCap = 'round'
  for (const j of joints) {
    switch (j.kind) {
      case 'rod':
        line(ctx, j.ax, j.ay, j.bx, j.by, JOINT_COLORS.rod, 3 * px)
        dots(ctx, j, JOINT_COLORS.rod, 3 * px)
        break
      case 'rope':
        drawRope(ctx, j, px, floors)
        break
      case 'spring':
        drawSpring(ctx, j, px)
        break
      case 'pin':
        drawPin(ctx, j, body, px)
        break
      case 'weld':
        drawWeld(ctx, j, body, px)
        break
      case 'slider':
        drawSlider(ctx, j, px)
        break
      case 'wheel':
        drawWheel(ctx, j, px)
        break
      case 'motor':
        drawDrive(ctx, j, px)
        break
    }
  }
  ctx.lineCap = 'butt'
  if (debug) for (const j of joints) drawDebug(ctx, j, px)
}

function line(
  ctx: CanvasRenderingContext2D,
  x0: number,
  y0: number,
  x1: number,
  y1: number,
  color: string,
  width: number,
) {
  ctx.strokeStyle = color
  ctx.lineWidth = width
  ctx.beginPath()
  ctx.moveTo(x0, y0)
  ctx.lineTo(x1, y1)
  ctx.stroke()
}

function dots(ctx: CanvasRenderingContext2D, j: ViewJoint, color: string, r: number): void {
  ctx.fillStyle = color
  ctx.beginPath()
  ctx.arc(j.ax, j.ay, r, 0, 2 * Math.PI)
  ctx.moveTo(j.bx + r, j.by)
  ctx.arc(j.bx, j.by, r, 0, 2 * Math.PI)
  ctx.fill()
}

function drawRope(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number, floors: readonly Floor[]): void {
  const dx = j.bx - j.ax
  const dy = j.by - j.ay
  const span = Math.sqrt(dx * dx + dy * dy)
  // Slack below a centimetre is drawn taut (the solver keeps a taut rope within millimetres).
  const sag = j.spec.max - span > 0.01 ? ropeSag(span, j.spec.max) : 0
  ctx.strokeStyle = JOINT_COLORS.rope
  ctx.lineWidth = 2 * px
  ctx.beginPath()
  ctx.moveTo(j.ax, j.ay)
  // A quadratic curve's control point twice the sag below the chord's middle puts its lowest point
  // at the sag; where that passes through a floor, the rope lies on the floor (ropePath).
  if (sag > 0) {
    const path = ropePath(j.ax, j.ay, j.bx, j.by, sag, floors)
    for (let i = 2; i < path.length; i += 2) ctx.lineTo(path[i], path[i + 1])
  } else ctx.lineTo(j.bx, j.by)
  ctx.stroke()
  dots(ctx, j, JOINT_COLORS.rope, 2.5 * px)
}

function drawSpring(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number): void {
  const dx = j.bx - j.ax
  const dy = j.by - j.ay
  const len = Math.sqrt(dx * dx + dy * dy)
  if (len < 1e-6) return
  const ux = dx / len
  const uy = dy / len
  // The coils are as wide as a fifth of the rest length, at least 6 px, so they read at any zoom.
  const width = Math.max(6 * px, 0.1 * j.spec.length)
  const end = Math.min(0.15 * len, 0.25)
  ctx.strokeStyle = JOINT_COLORS.spring
  ctx.lineWidth = 2 * px
  ctx.beginPath()
  ctx.moveTo(j.ax, j.ay)
  ctx.lineTo(j.ax + ux * end, j.ay + uy * end)
  const body = len - 2 * end
  const n = COILS * 2
  for (let i = 1; i < n; i++) {
    const t = end + (body * i) / n
    const side = i % 2 === 1 ? width : -width
    ctx.lineTo(j.ax + ux * t - uy * side, j.ay + uy * t + ux * side)
  }
  ctx.lineTo(j.bx - ux * end, j.by - uy * end)
  ctx.lineTo(j.bx, j.by)
  ctx.stroke()
  dots(ctx, j, JOINT_COLORS.spring, 2.5 * px)
}

function drawPin(
  ctx: CanvasRenderingContext2D,
  j: ViewJoint,
  body: (id: number) => ViewBody | undefined,
  px: number,
): void {
  const a = j.spec.a ? body(j.spec.a) : undefined
  const b = body(j.spec.b)
  ctx.globalAlpha = 0.6
  if (a) line(ctx, a.x, a.y, j.ax, j.ay, JOINT_COLORS.pin, 1.5 * px)
  if (b) line(ctx, b.x, b.y, j.bx, j.by, JOINT_COLORS.pin, 1.5 * px)
  ctx.globalAlpha = 1
  const r = 5 * px
  if (j.spec.limit) drawLimit(ctx, j, 4 * r, px)
  if (j.spec.motor && j.spec.speed !== 0) drawMotor(ctx, j, 2.6 * r, px)
  ctx.fillStyle = '#161a22'
  ctx.strokeStyle = JOINT_COLORS.pin
  ctx.lineWidth = 2 * px
  ctx.beginPath()
  ctx.arc(j.bx, j.by, r, 0, 2 * Math.PI)
  ctx.fill()
  ctx.stroke()
  ctx.fillStyle = JOINT_COLORS.pin
  ctx.beginPath()
  ctx.arc(j.bx, j.by, 1.5 * px, 0, 2 * Math.PI)
  ctx.fill()
}

/** The allowed arc [lower, upper] around the pivot, measured from body a's frame, and where body b is now. */
function drawLimit(ctx: CanvasRenderingContext2D, j: ViewJoint, r: number, px: number): void {
  const base = j.angleA + j.spec.ref
  ctx.strokeStyle = JOINT_COLORS.limit
  ctx.fillStyle = 'rgba(255, 127, 127, 0.18)'
  ctx.lineWidth = 1.5 * px
  ctx.beginPath()
  ctx.moveTo(j.bx, j.by)
  ctx.arc(j.bx, j.by, r, base + j.spec.lower, base + j.spec.upper)
  ctx.closePath()
  ctx.fill()
  ctx.stroke()
  const now = base + j.angle
  line(
    ctx,
    j.bx,
    j.by,
    j.bx + Math.cos(now) * r * 1.15,
    j.by + Math.sin(now) * r * 1.15,
    JOINT_COLORS.limit,
    2 * px,
  )
}

/** A three-quarter circular arrow around the pivot, turning the way the motor drives body b. */
function drawMotor(ctx: CanvasRenderingContext2D, j: ViewJoint, r: number, px: number): void {
  const dir = Math.sign(j.spec.speed)
  const start = j.angleA + j.angle
  const end = start + dir * 1.5 * Math.PI
  ctx.strokeStyle = JOINT_COLORS.motor
  ctx.fillStyle = JOINT_COLORS.motor
  ctx.lineWidth = 2 * px
  ctx.beginPath()
  ctx.arc(j.bx, j.by, r, start, end, dir < 0)
  ctx.stroke()
  const tip = { x: j.bx + Math.cos(end) * r, y: j.by + Math.sin(end) * r }
  const tx = -Math.sin(end) * dir
  const ty = Math.cos(end) * dir
  const h = 6 * px
  ctx.beginPath()
  ctx.moveTo(tip.x + tx * h, tip.y + ty * h)
  ctx.lineTo(tip.x - ty * h * 0.6, tip.y + tx * h * 0.6)
  ctx.lineTo(tip.x + ty * h * 0.6, tip.y - tx * h * 0.6)
  ctx.closePath()
  ctx.fill()
}

function drawWeld(
  ctx: CanvasRenderingContext2D,
  j: ViewJoint,
  body: (id: number) => ViewBody | undefined,
  px: number,
): void {
  const a = j.spec.a ? body(j.spec.a) : undefined
  const b = body(j.spec.b)
  ctx.globalAlpha = 0.6
  if (a) line(ctx, a.x, a.y, j.ax, j.ay, JOINT_COLORS.weld, 1.5 * px)
  if (b) line(ctx, b.x, b.y, j.bx, j.by, JOINT_COLORS.weld, 1.5 * px)
  ctx.globalAlpha = 1
  // A square turned with body b (a + the relative angle + ref = b's angle).
  const turn = j.angleA + j.spec.ref + j.angle
  const r = 5 * px
  ctx.save()
  ctx.translate(j.bx, j.by)
  ctx.rotate(turn)
  ctx.fillStyle = JOINT_COLORS.weld
  ctx.fillRect(-r, -r, 2 * r, 2 * r)
  ctx.strokeStyle = '#161a22'
  ctx.lineWidth = 1.5 * px
  ctx.beginPath()
  ctx.moveTo(-r, -r)
  ctx.lineTo(r, r)
  ctx.moveTo(-r, r)
  ctx.lineTo(r, -r)
  ctx.stroke()
  ctx.restore()
}

/** The travel of a slider or wheel along its axis from a's anchor (m): its limits, or `free` each way. */
function travel(j: ViewJoint, free: number): [number, number] {
  return j.spec.limit ? [j.spec.lower, j.spec.upper] : [-free, free]
}

function drawSlider(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number): void {
  const ux = j.axisX
  const uy = j.axisY
  const [lo, hi] = travel(j, Math.max(1, Math.abs(j.translation) + 0.5))
  line(ctx, j.ax + ux * lo, j.ay + uy * lo, j.ax + ux * hi, j.ay + uy * hi, JOINT_COLORS.slider, 2 * px)
  if (j.spec.limit) {
    const s = 6 * px
    for (const t of [lo, hi])
      line(
        ctx,
        j.ax + ux * t - uy * s,
        j.ay + uy * t + ux * s,
        j.ax + ux * t + uy * s,
        j.ay + uy * t - ux * s,
        JOINT_COLORS.limit,
        2 * px,
      )
  }
  // The carriage: a box across the track at b's anchor.
  const w = 7 * px
  const h = 4 * px
  ctx.fillStyle = JOINT_COLORS.slider
  ctx.beginPath()
  ctx.moveTo(j.bx + ux * w - uy * h, j.by + uy * w + ux * h)
  ctx.lineTo(j.bx + ux * w + uy * h, j.by + uy * w - ux * h)
  ctx.lineTo(j.bx - ux * w + uy * h, j.by - uy * w - ux * h)
  ctx.lineTo(j.bx - ux * w - uy * h, j.by - uy * w + ux * h)
  ctx.closePath()
  ctx.fill()
  if (j.spec.motor && j.spec.speed !== 0) {
    const dir = Math.sign(j.spec.speed)
    arrow(ctx, j.bx, j.by, j.bx + ux * dir * 14 * px, j.by + uy * dir * 14 * px, JOINT_COLORS.motor, px)
  }
}

function drawWheel(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number): void {
  const ux = j.axisX
  const uy = j.axisY
  const [lo, hi] = travel(j, Math.max(0.25, Math.abs(j.translation)))
  ctx.globalAlpha = 0.6
  line(ctx, j.ax + ux * lo, j.ay + uy * lo, j.ax + ux * hi, j.ay + uy * hi, JOINT_COLORS.slider, 1.5 * px)
  ctx.globalAlpha = 1
  // The suspension: a short coil from a's anchor to the hub (straight when the hub is at the anchor).
  const dx = j.bx - j.ax
  const dy = j.by - j.ay
  const len = Math.sqrt(dx * dx + dy * dy)
  ctx.strokeStyle = JOINT_COLORS.spring
  ctx.lineWidth = 1.5 * px
  ctx.beginPath()
  ctx.moveTo(j.ax, j.ay)
  if (len > 1e-3) {
    const n = 8
    const w = 4 * px
    for (let i = 1; i < n; i++) {
      const side = i % 2 === 1 ? w : -w
      ctx.lineTo(j.ax + (dx * i) / n - (dy / len) * side, j.ay + (dy * i) / n + (dx / len) * side)
    }
  }
  ctx.lineTo(j.bx, j.by)
  ctx.stroke()
  const r = 5 * px
  if (j.spec.motor && j.spec.speed !== 0) drawMotor(ctx, j, 2.6 * r, px)
  // The hub, with a spoke turning with the wheel.
  ctx.fillStyle = '#161a22'
  ctx.strokeStyle = JOINT_COLORS.wheel
  ctx.lineWidth = 2 * px
  ctx.beginPath()
  ctx.arc(j.bx, j.by, r, 0, 2 * Math.PI)
  ctx.fill()
  ctx.stroke()
  const turn = j.angleA + j.spec.ref + j.angle
  line(ctx, j.bx, j.by, j.bx + Math.cos(turn) * r, j.by + Math.sin(turn) * r, JOINT_COLORS.wheel, 1.5 * px)
}

function drawDrive(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number): void {
  ctx.setLineDash([4 * px, 3 * px])
  line(ctx, j.bx, j.by, j.ax, j.ay, JOINT_COLORS.drive, 1.5 * px)
  ctx.setLineDash([])
  const s = 5 * px
  line(ctx, j.ax - s, j.ay, j.ax + s, j.ay, JOINT_COLORS.drive, 2 * px)
  line(ctx, j.ax, j.ay - s, j.ax, j.ay + s, JOINT_COLORS.drive, 2 * px)
}

/** A straight arrow from (x0, y0) to (x1, y1). */
function arrow(
  ctx: CanvasRenderingContext2D,
  x0: number,
  y0: number,
  x1: number,
  y1: number,
  color: string,
  px: number,
): void {
  line(ctx, x0, y0, x1, y1, color, 2 * px)
  const dx = x1 - x0
  const dy = y1 - y0
  const n = Math.sqrt(dx * dx + dy * dy)
  if (n < 1e-9) return
  const ux = dx / n
  const uy = dy / n
  const h = 5 * px
  ctx.fillStyle = color
  ctx.beginPath()
  ctx.moveTo(x1 + ux * h, y1 + uy * h)
  ctx.lineTo(x1 - uy * h * 0.6, y1 + ux * h * 0.6)
  ctx.lineTo(x1 + uy * h * 0.6, y1 - ux * h * 0.6)
  ctx.closePath()
  ctx.fill()
}

function drawDebug(ctx: CanvasRenderingContext2D, j: ViewJoint, px: number): void {
  const s = 4 * px
  ctx.strokeStyle = JOINT_COLORS.anchor
  ctx.lineWidth = 1.5 * px
  ctx.strokeRect(j.ax - s, j.ay - s, 2 * s, 2 * s)
  ctx.strokeRect(j.bx - s, j.by - s, 2 * s, 2 * s)
  if (j.force) drawForce(ctx, { x: j.bx, y: j.by }, j.force, px)
}

/** An arrow for a force (N) acting at `at`, 2 m per 100 N and at most MAX_FORCE_ARROW long, labelled in newtons. */
export function drawForce(ctx: CanvasRenderingContext2D, at: Vec2, f: Vec2, px: number): void {
  const n = Math.sqrt(f.x * f.x + f.y * f.y)
  if (n < 1e-3) return
  const l = Math.min(n * FORCE_SCALE, MAX_FORCE_ARROW)
  const ux = f.x / n
  const uy = f.y / n
  const tx = at.x + ux * l
  const ty = at.y + uy * l
  line(ctx, at.x, at.y, tx, ty, JOINT_COLORS.force, 2 * px)
  const h = Math.min(7 * px, l * 0.4)
  ctx.fillStyle = JOINT_COLORS.force
  ctx.beginPath()
  ctx.moveTo(tx, ty)
  ctx.lineTo(tx - ux * h - uy * h * 0.5, ty - uy * h + ux * h * 0.5)
  ctx.lineTo(tx - ux * h + uy * h * 0.5, ty - uy * h - ux * h * 0.5)
  ctx.closePath()
  ctx.fill()
  // Text in world space would be mirrored by the y-up transform: flip it back locally.
  ctx.save()
  ctx.translate(tx, ty)
  ctx.scale(px, -px)
  ctx.font = '11px system-ui, sans-serif'
  ctx.textAlign = 'left'
  ctx.textBaseline = 'middle'
  ctx.fillText(`${n.toFixed(1)} N`, 6, 0)
  ctx.restore()
}
