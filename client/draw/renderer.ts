/*
 * The canvas renderer. The backing store is sized in device pixels (HiDPI) and the world is drawn
 * with one transform that maps metres, y up, onto it, so shapes are plain world coordinates. To
 * stay fast with a thousand bodies, bodies are batched by style: one path per style (static,
 * awake, asleep, kinematic) holding every visible shape, filled and stroked once; only grabbed
 * bodies (in their player's colour) and overlays are drawn one by one. Sensor shapes (the wire's
 * `sensor: true`) are left out of those paths and drawn after them in one path of their own,
 * translucent with a dashed outline; so are gates (shapeStyle: static or kinematic shapes whose
 * collision filter lets some bodies through), faint with a dashed outline in GATE_COLOR. Text
 * (names, ids) is drawn
 * in screen space so it is never mirrored by the y-up transform.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { WireShape } from '../../shared/index.ts'
import { bodyRadius, shapeVertices, toWorld } from '../input/index.ts'
import type { LabContact, ViewBody, ViewCursor, ViewJoint } from '../modes/index.ts'
import type { Camera } from './camera.ts'
import { drawJoints, type Floor, floorsOf } from './joint-drawing.ts'
import { drawFreeBody, type FreeBody } from './lab.ts'

/** Which debug layers are on. */
export interface DebugLayers {
  contacts: boolean
  joints: boolean
  aabbs: boolean
  ids: boolean
}

/** What the tools want drawn on top: own cursor, grab line, previews. */
export interface ToolOverlay {
  cursor: Vec2 | null
  color: string
  /** Own grab: world point on the body the line ends at. */
  grabAnchor: Vec2 | null
  /** Spawn preview: a ghost body (drawn at ghostAlpha opacity) and a throw vector. */
  ghost: ViewBody | null
  ghostAlpha: number
  throwTo: Vec2 | null
  /** Rope preview from a world point to the cursor. */
  ropeFrom: Vec2 | null
  /** The joint the cut tool would remove here, marked. */
  cutJoint: ViewJoint | null
  /** Draw and Ground preview: the points so far (world m), closed for an outline. */
  stroke: readonly Vec2[] | null
  strokeClosed: boolean
  /** The joint a joint tool would make here (drawn faint, as the joint will be drawn). */
  joint: ViewJoint | null
  /** The explode tool's blast: full within `radius` (m), fading to nothing at twice it. */
  blast?: { x: number; y: number; radius: number } | null
  /** The Edit tool's selected bodies, outlined as the lab's selection is. */
  highlight?: readonly ViewBody[] | null
}

/** Everything one frame shows. */
export interface DrawFrame {
  bodies: readonly ViewBody[]
  joints: readonly ViewJoint[]
  cursors: readonly ViewCursor[]
  contacts: readonly LabContact[] | null
  layers: DebugLayers
  overlay: ToolOverlay
  selected: ViewBody | null
  freeBody: FreeBody | null
}

const STYLE = {
  background: '#161a22',
  grid: '#1f2530',
  static: ['#3c4350', '#596274'],
  awake: ['#4f86c6', '#9cc3f0'],
  asleep: ['#2c4360', '#4f6a8c'],
  kinematic: ['#7a5cc4', '#b7a0f0'],
} as const

/**
 * Sensor shapes (they detect overlap and never push: the goal game's goals, the marble run's bin
 * floor) are filled in this colour at SENSOR_FILL_ALPHA over whatever is under them, and outlined
 * with a dashed line in it, so they never look solid.
 */
export const SENSOR_COLOR = '#4fc3f7'
export const SENSOR_FILL_ALPHA = 0.15
/**
 * Gates (shapeStyle 'gate': static or kinematic shapes that let some bodies through, such as the
 * goal game's goal lines, which stop the discs and let the ball pass) are filled at GATE_FILL_ALPHA
 * in the body's colour, or in this one for a body without a colour (a scene's), and outlined with
 * a dashed line in this colour: visibly not a wall for everything.
 */
export const GATE_COLOR = '#e0b050'
export const GATE_FILL_ALPHA = 0.2

/** How a shape is drawn: see shapeStyle. */
export type ShapeStyle = 'solid' | 'sensor' | 'gate'

/**
 * How the renderer draws a shape of a body of `kind` (0 static, 1 kinematic, 2 dynamic), from its
 * wire settings: 'sensor' for a sensor; 'gate' for a shape of a static or kinematic body whose
 * filter (`[categoryBits, maskBits, groupIndex]`, absent: the default `[1, 0xffffffff, 0]`) lets
 * some bodies through: maskBits not every bit, or a negative group (its members pass each other);
 * else 'solid'. Moving bodies with filters (the goal game's ball and discs, sandbox layers) are
 * drawn solid: what they pass through is the gate.
 */
export function shapeStyle(kind: number, shape: WireShape): ShapeStyle {
  if (shape.sensor === true) return 'sensor'
  const f = shape.filter
  if (kind !== 2 && f !== undefined && (f[1] !== 0xffffffff || f[2] < 0)) return 'gate'
  return 'solid'
}

/** Segment shapes (lines, drawn ground) are stroked in this colour. */
const SEGMENT_COLOR = '#8a94a8'
/** The explode tool's blast preview. */
const BLAST_COLOR = '#ff5a36'

/** The mark on the joint the cut tool points at. */
export const CUT_MARK = '#ff3b30'

/** Name labels: font, plate colour and padding (CSS px). */
const LABEL_FONT = '12px system-ui, sans-serif'
/** The plate behind a player's name: near-black, so every player colour reads on it. */
export const LABEL_PLATE = 'rgba(10, 12, 16, 0.85)'
/** Name text colour. */
export const LABEL_TEXT = '#ffffff'
const LABEL_PAD = 4

/** Where a cursor's name label goes (CSS px): up and to the right of the cursor at (x, y). */
export function labelBox(x: number, y: number, textWidth: number) {
  return { x: x + 8, y: y - 24, width: textWidth + 2 * LABEL_PAD + 2, height: 18 }
}

/** Draws frames on one canvas. */
export class Renderer {
  readonly ctx: CanvasRenderingContext2D
  private dpr = 1
  private readonly byId = new Map<number, ViewBody>()
  /** Coloured bodies by colour for this frame (reused). */
  private readonly coloured = new Map<string, ViewBody[]>()
  /** Level static box tops for this frame (ropes lie on them), reused. */
  private readonly floors: Floor[] = []

  constructor(
    readonly canvas: HTMLCanvasElement,
    readonly camera: Camera,
  ) {
    const ctx = canvas.getContext('2d', { alpha: false })
    if (!ctx) throw new Error('canvas 2D is not available in this browser')
    this.ctx = ctx
  }

  /** Match the backing store to the element's CSS size and the device pixel ratio. */
  resize(): void {
    const rect = this.canvas.getBoundingClientRect()
    this.dpr = window.devicePixelRatio || 1
    const w = Math.max(1, Math.round(rect.width * this.dpr))
    const h = Math.max(1, Math.round(rect.height * this.dpr))
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w
      this.canvas.height = h
    }
    this.camera.resize(rect.width, rect.height)
  }

  private worldTransform(): void {
    const c = this.camera
    const s = c.scale * this.dpr
    this.ctx.setTransform(
      s,
      0,
      0,
      -s,
      this.dpr * (c.width / 2) - c.x * s,
      this.dpr * (c.height / 2) + c.y * s,
    )
  }

  private screenTransform(): void {
    this.ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0)
  }

  /** Draw one frame. */
  draw(frame: DrawFrame): void {
    const ctx = this.ctx
    this.screenTransform()
    ctx.fillStyle = STYLE.background
    ctx.fillRect(0, 0, this.camera.width, this.camera.height)
    this.worldTransform()
    this.drawGrid()
    this.drawBodies(frame.bodies)
    const byId = this.bodyLookup(frame.bodies)
    const floors = frame.joints.length > 0 ? floorsOf(frame.bodies, this.floors) : this.floors
    drawJoints(this.ctx, frame.joints, byId, this.lineWidth(1), frame.layers.joints, floors)
    if (frame.layers.aabbs) this.drawAabbs(frame.bodies)
    if (frame.layers.contacts && frame.contacts) this.drawContacts(frame.contacts)
    if (frame.selected) this.drawSelection(frame.selected)
    if (frame.selected && frame.freeBody) {
      drawFreeBody(ctx, frame.selected, frame.freeBody, this.camera.scale)
    }
    this.drawCursorsWorld(frame)
    this.drawOverlayWorld(frame.overlay)
    this.screenTransform()
    if (frame.layers.ids) this.drawIds(frame.bodies)
    this.drawCursorLabels(frame.cursors)
  }

  /** Bodies by id for this frame (reused map). */
  private bodyLookup(bodies: readonly ViewBody[]): (id: number) => ViewBody | undefined {
    const map = this.byId
    map.clear()
    for (const v of bodies) map.set(v.id, v)
    return (id) => map.get(id)
  }

  private lineWidth(px: number): number {
    return px / this.camera.scale
  }

  private drawGrid(): void {
    const ctx = this.ctx
    const b = this.camera.visibleBounds()
    const step = this.camera.scale < 8 ? 10 : this.camera.scale < 40 ? 1 : 0.5
    const count = (b.maxX - b.minX) / step + (b.maxY - b.minY) / step
    if (count > 400) return
    ctx.strokeStyle = STYLE.grid
    ctx.lineWidth = this.lineWidth(1)
    ctx.beginPath()
    for (let x = Math.floor(b.minX / step) * step; x <= b.maxX; x += step) {
      ctx.moveTo(x, b.minY)
      ctx.lineTo(x, b.maxY)
    }
    for (let y = Math.floor(b.minY / step) * step; y <= b.maxY; y += step) {
      ctx.moveTo(b.minX, y)
      ctx.lineTo(b.maxX, y)
    }
    ctx.stroke()
  }

  private drawBodies(bodies: readonly ViewBody[]): void {
    const b = this.camera.visibleBounds()
    const groups: Array<[readonly [string, string], (v: ViewBody) => boolean]> = [
      [STYLE.static, (v) => v.kind === 0 && v.color === null],
      [STYLE.kinematic, (v) => v.kind === 1 && v.color === null],
      [STYLE.asleep, (v) => v.kind === 2 && !v.awake && v.color === null],
      [STYLE.awake, (v) => v.kind === 2 && v.awake && v.color === null],
    ]
    const ctx = this.ctx
    ctx.lineWidth = this.lineWidth(1.25)
    ctx.lineJoin = 'miter'
    // Stroking outlines costs as much raster work as filling. With many bodies on screen, shapes
    // are filled shrunk by one pixel instead, so the background shows between touching bodies.
    const outline = this.camera.scale >= 40 || bodies.length < 400
    const inset = outline ? 0 : 1 / this.camera.scale
    const visible = (v: ViewBody): boolean => {
      const r = bodyRadius(v)
      return !(v.x + r < b.minX || v.x - r > b.maxX || v.y + r < b.minY || v.y - r > b.maxY)
    }
    const shrinkOf = (v: ViewBody): number => (inset > 0 ? Math.max(0.2, 1 - inset / bodyRadius(v)) : 1)
    for (const [style, accept] of groups) {
      ctx.beginPath()
      let any = false
      for (const v of bodies) {
        if (v.grabColor || !accept(v) || !visible(v)) continue
        if (this.traceBody(v, shrinkOf(v), true)) any = true
      }
      if (!any) continue
      ctx.fillStyle = style[0]
      ctx.fill()
      if (!outline) continue
      ctx.strokeStyle = style[1]
      ctx.stroke()
    }
    // Coloured bodies (players' own), one path per colour and state: asleep ones darker.
    const coloured = this.coloured
    coloured.clear()
    for (const v of bodies) {
      if (v.grabColor || v.color === null || !visible(v)) continue
      const key = v.kind === 2 && !v.awake ? `${v.color}.` : v.color
      const list = coloured.get(key)
      if (list) list.push(v)
      else coloured.set(key, [v])
    }
    for (const [key, list] of coloured) {
      ctx.beginPath()
      for (const v of list) this.traceBody(v, shrinkOf(v), true)
      const asleep = key.endsWith('.')
      ctx.globalAlpha = asleep ? 0.55 : 1
      ctx.fillStyle = asleep ? key.slice(0, -1) : key
      ctx.fill()
      ctx.globalAlpha = 1
      if (!outline) continue
      ctx.strokeStyle = asleep ? '#5a6272' : '#e8edf5'
      ctx.stroke()
    }
    for (const v of bodies) {
      if (!v.grabColor) continue
      ctx.beginPath()
      this.traceBody(v, 1, true)
      ctx.fillStyle = v.grabColor
      ctx.fill()
      ctx.strokeStyle = '#ffffff'
      ctx.stroke()
    }
    this.drawSensors(bodies, visible)
    this.drawGates(bodies, visible)
    // Segments have no area: stroke them (lines and drawn ground) at least 3 px wide, always.
    ctx.beginPath()
    let segments = false
    for (const v of bodies) {
      if (!visible(v)) continue
      for (const shape of v.shapes) {
        if (shape.type !== 'segment' || shapeStyle(v.kind, shape) === 'gate') continue
        const [p, q] = shapeVertices(shape)
        const a = toWorld(v, p.x, p.y)
        const c = toWorld(v, q.x, q.y)
        ctx.moveTo(a.x, a.y)
        ctx.lineTo(c.x, c.y)
        segments = true
      }
    }
    if (segments) {
      ctx.lineWidth = this.lineWidth(3)
      ctx.lineCap = 'round'
      ctx.strokeStyle = SEGMENT_COLOR
      ctx.stroke()
      ctx.lineCap = 'butt'
    }
  }

  /** Sensor shapes of the visible bodies: translucent fill, dashed outline (SENSOR_COLOR). */
  private drawSensors(bodies: readonly ViewBody[], visible: (v: ViewBody) => boolean): void {
    const ctx = this.ctx
    ctx.beginPath()
    let any = false
    for (const v of bodies) {
      if (!visible(v)) continue
      for (const shape of v.shapes) {
        if (shape.sensor !== true || shape.type === 'segment') continue
        this.traceShape(v, shape, 1)
        any = true
      }
    }
    if (!any) return
    ctx.globalAlpha = SENSOR_FILL_ALPHA
    ctx.fillStyle = SENSOR_COLOR
    ctx.fill()
    ctx.globalAlpha = 1
    ctx.lineWidth = this.lineWidth(1.25)
    ctx.setLineDash([this.lineWidth(6), this.lineWidth(4)])
    ctx.strokeStyle = SENSOR_COLOR
    ctx.stroke()
    ctx.setLineDash([])
  }

  /**
   * Gate shapes of the visible bodies (shapeStyle 'gate'): faint fill in the body's colour (else
   * GATE_COLOR), dashed outline in GATE_COLOR.
   */
  private drawGates(bodies: readonly ViewBody[], visible: (v: ViewBody) => boolean): void {
    const ctx = this.ctx
    let any = false
    // Each gate body filled faintly in its own colour (a player's static body on a layer keeps
    // it), or GATE_COLOR for a body without one (a scene's, such as the goal lines).
    ctx.globalAlpha = GATE_FILL_ALPHA
    for (const v of bodies) {
      if (v.kind === 2 || !visible(v)) continue
      ctx.beginPath()
      if (!this.traceGates(v)) continue
      ctx.fillStyle = v.color ?? GATE_COLOR
      ctx.fill()
      any = true
    }
    ctx.globalAlpha = 1
    if (!any) return
    // Then every gate's outline, dashed in GATE_COLOR.
    ctx.beginPath()
    for (const v of bodies) if (v.kind !== 2 && visible(v)) this.traceGates(v)
    ctx.lineWidth = this.lineWidth(1.5)
    ctx.setLineDash([this.lineWidth(4), this.lineWidth(4)])
    ctx.strokeStyle = GATE_COLOR
    ctx.stroke()
    ctx.setLineDash([])
  }

  /** Add a body's gate shapes (shapeStyle 'gate'; segments as lines) to the current path; whether it had any. */
  private traceGates(v: ViewBody): boolean {
    const ctx = this.ctx
    let any = false
    for (const shape of v.shapes) {
      if (shapeStyle(v.kind, shape) !== 'gate') continue
      if (shape.type === 'segment') {
        const [p, q] = shapeVertices(shape)
        const a = toWorld(v, p.x, p.y)
        const c = toWorld(v, q.x, q.y)
        ctx.moveTo(a.x, a.y)
        ctx.lineTo(c.x, c.y)
      } else this.traceShape(v, shape, 1)
      any = true
    }
    return any
  }

  /**
   * Add a body's outline (every shape; with `solid`, only its solid shapes: drawSensors and
   * drawGates draw the others) to the current path, scaled by `shrink` about its origin; circles get a
   * radius line to show rotation. Segments add nothing (drawBodies strokes them). Returns whether
   * it added anything.
   */
  private traceBody(v: ViewBody, shrink = 1, solid = false): boolean {
    let any = false
    for (const shape of v.shapes) {
      if (solid && shapeStyle(v.kind, shape) !== 'solid') continue
      this.traceShape(v, shape, shrink)
      any = true
    }
    return any
  }

  private traceShape(v: ViewBody, shape: WireShape, shrink: number): void {
    const ctx = this.ctx
    const c = Math.cos(v.angle) * shrink
    const s = Math.sin(v.angle) * shrink
    const wx = (x: number, y: number): number => v.x + c * x - s * y
    const wy = (x: number, y: number): number => v.y + s * x + c * y
    if (shape.type === 'segment') return
    if (shape.type === 'circle') {
      const r = shape.radius * shrink
      const cx = wx(shape.x ?? 0, shape.y ?? 0)
      const cy = wy(shape.x ?? 0, shape.y ?? 0)
      ctx.moveTo(cx + r * Math.cos(v.angle), cy + r * Math.sin(v.angle))
      ctx.arc(cx, cy, r, v.angle, v.angle + 2 * Math.PI)
      ctx.lineTo(cx, cy)
      return
    }
    const verts = shapeVertices(shape)
    const r = (shape.type === 'polygon' || shape.type === 'capsule' ? (shape.radius ?? 0) : 0) * shrink
    if (r === 0) {
      for (let i = 0; i < verts.length; i++) {
        const p = verts[i]
        if (i === 0) ctx.moveTo(wx(p.x, p.y), wy(p.x, p.y))
        else ctx.lineTo(wx(p.x, p.y), wy(p.x, p.y))
      }
      ctx.closePath()
      return
    }
    // Rounded (a capsule is a two-vertex polygon): around each vertex, an arc of radius r from the
    // outward normal of the edge before it to that of the edge after it (counter-clockwise).
    const n = verts.length
    for (let i = 0; i < n; i++) {
      const prev = verts[(i + n - 1) % n]
      const p = verts[i]
      const next = verts[(i + 1) % n]
      const from = Math.atan2(-(p.x - prev.x), p.y - prev.y) + v.angle
      let to = Math.atan2(-(next.x - p.x), next.y - p.y) + v.angle
      if (to < from) to += 2 * Math.PI
      const x = wx(p.x, p.y)
      const y = wy(p.x, p.y)
      if (i === 0) ctx.moveTo(x + r * Math.cos(from), y + r * Math.sin(from))
      ctx.arc(x, y, r, from, to)
    }
    ctx.closePath()
  }

  private drawAabbs(bodies: readonly ViewBody[]): void {
    const ctx = this.ctx
    ctx.strokeStyle = '#d0a040'
    ctx.lineWidth = this.lineWidth(1)
    ctx.beginPath()
    for (const v of bodies) {
      let minX = Infinity
      let minY = Infinity
      let maxX = -Infinity
      let maxY = -Infinity
      for (const shape of v.shapes) {
        const r =
          shape.type === 'circle' || shape.type === 'capsule' || shape.type === 'polygon'
            ? (shape.radius ?? 0)
            : 0
        const points = shape.type === 'circle' ? [{ x: shape.x ?? 0, y: shape.y ?? 0 }] : shapeVertices(shape)
        for (const p of points) {
          const w = toWorld(v, p.x, p.y)
          minX = Math.min(minX, w.x - r)
          minY = Math.min(minY, w.y - r)
          maxX = Math.max(maxX, w.x + r)
          maxY = Math.max(maxY, w.y + r)
        }
      }
      ctx.rect(minX, minY, maxX - minX, maxY - minY)
    }
    ctx.stroke()
  }

  private drawContacts(contacts: readonly LabContact[]): void {
    const ctx = this.ctx
    const size = this.lineWidth(4)
    ctx.fillStyle = '#ff5050'
    ctx.strokeStyle = '#50ff80'
    ctx.lineWidth = this.lineWidth(1.5)
    ctx.beginPath()
    for (const c of contacts) {
      for (const p of c.points) {
        ctx.fillRect(p.point.x - size / 2, p.point.y - size / 2, size, size)
        ctx.moveTo(p.point.x, p.point.y)
        ctx.lineTo(p.point.x + c.normal.x * 0.3, p.point.y + c.normal.y * 0.3)
      }
    }
    ctx.stroke()
  }

  private drawSelection(v: ViewBody): void {
    const ctx = this.ctx
    ctx.beginPath()
    this.traceBody(v)
    ctx.strokeStyle = '#ffe066'
    ctx.lineWidth = this.lineWidth(3)
    ctx.stroke()
  }

  private drawCursorsWorld(frame: DrawFrame): void {
    const ctx = this.ctx
    const byId = new Map<number, ViewBody>()
    for (const c of frame.cursors) if (c.body) byId.set(c.body, null as unknown as ViewBody)
    if (byId.size) for (const v of frame.bodies) if (byId.has(v.id)) byId.set(v.id, v)
    for (const c of frame.cursors) {
      const body = c.body ? byId.get(c.body) : null
      ctx.strokeStyle = c.color
      ctx.fillStyle = c.color
      ctx.lineWidth = this.lineWidth(2)
      if (body) {
        ctx.beginPath()
        ctx.moveTo(c.x, c.y)
        ctx.lineTo(body.x, body.y)
        ctx.stroke()
      }
      ctx.beginPath()
      ctx.arc(c.x, c.y, this.lineWidth(5), 0, 2 * Math.PI)
      ctx.fill()
    }
  }

  private drawOverlayWorld(o: ToolOverlay): void {
    const ctx = this.ctx
    for (const v of o.highlight ?? []) this.drawSelection(v)
    ctx.lineWidth = this.lineWidth(2)
    ctx.strokeStyle = o.color
    if (o.ghost) {
      ctx.globalAlpha = o.ghostAlpha
      ctx.beginPath()
      this.traceBody(o.ghost)
      ctx.fillStyle = o.color
      ctx.fill()
      ctx.globalAlpha = 1
      if (o.throwTo) {
        ctx.beginPath()
        ctx.moveTo(o.ghost.x, o.ghost.y)
        ctx.lineTo(o.throwTo.x, o.throwTo.y)
        ctx.stroke()
      }
    }
    if (o.stroke && o.stroke.length > 1) {
      ctx.beginPath()
      ctx.moveTo(o.stroke[0].x, o.stroke[0].y)
      for (const p of o.stroke) ctx.lineTo(p.x, p.y)
      if (o.strokeClosed) {
        ctx.closePath()
        ctx.globalAlpha = 0.25
        ctx.fillStyle = o.color
        ctx.fill()
        ctx.globalAlpha = 1
      }
      ctx.stroke()
    }
    if (o.blast) {
      const b = o.blast
      ctx.globalAlpha = 0.18
      ctx.fillStyle = BLAST_COLOR
      ctx.beginPath()
      ctx.arc(b.x, b.y, b.radius, 0, 2 * Math.PI)
      ctx.fill()
      ctx.globalAlpha = 1
      ctx.strokeStyle = BLAST_COLOR
      ctx.beginPath()
      ctx.arc(b.x, b.y, b.radius, 0, 2 * Math.PI)
      ctx.stroke()
      ctx.setLineDash([this.lineWidth(6), this.lineWidth(4)])
      ctx.beginPath()
      ctx.arc(b.x, b.y, 2 * b.radius, 0, 2 * Math.PI)
      ctx.stroke()
      ctx.setLineDash([])
      ctx.strokeStyle = o.color
    }
    if (o.ropeFrom && o.cursor) {
      ctx.setLineDash([this.lineWidth(6), this.lineWidth(4)])
      ctx.beginPath()
      ctx.moveTo(o.ropeFrom.x, o.ropeFrom.y)
      ctx.lineTo(o.cursor.x, o.cursor.y)
      ctx.stroke()
      ctx.setLineDash([])
    }
    if (o.joint) {
      ctx.globalAlpha = 0.55
      drawJoints(ctx, [o.joint], () => undefined, this.lineWidth(1), false)
      ctx.globalAlpha = 1
      ctx.lineWidth = this.lineWidth(2)
      ctx.strokeStyle = o.color
    }
    if (o.cutJoint) {
      const j = o.cutJoint
      ctx.strokeStyle = CUT_MARK
      ctx.lineWidth = this.lineWidth(5)
      ctx.beginPath()
      ctx.moveTo(j.ax, j.ay)
      ctx.lineTo(j.bx, j.by)
      ctx.stroke()
      ctx.beginPath()
      ctx.arc(j.bx, j.by, this.lineWidth(7), 0, 2 * Math.PI)
      ctx.stroke()
      ctx.lineWidth = this.lineWidth(2)
      ctx.strokeStyle = o.color
    }
    if (o.grabAnchor && o.cursor) {
      ctx.beginPath()
      ctx.moveTo(o.cursor.x, o.cursor.y)
      ctx.lineTo(o.grabAnchor.x, o.grabAnchor.y)
      ctx.stroke()
      ctx.fillStyle = o.color
      ctx.beginPath()
      ctx.arc(o.grabAnchor.x, o.grabAnchor.y, this.lineWidth(3), 0, 2 * Math.PI)
      ctx.fill()
    }
    if (o.cursor) {
      ctx.beginPath()
      ctx.arc(o.cursor.x, o.cursor.y, this.lineWidth(6), 0, 2 * Math.PI)
      ctx.stroke()
    }
  }

  private drawIds(bodies: readonly ViewBody[]): void {
    const ctx = this.ctx
    if (this.camera.scale < 12) return
    ctx.fillStyle = '#ffffff'
    ctx.font = '10px system-ui, sans-serif'
    ctx.textAlign = 'center'
    ctx.textBaseline = 'middle'
    const b = this.camera.visibleBounds()
    const p = { x: 0, y: 0 }
    for (const v of bodies) {
      if (v.x < b.minX || v.x > b.maxX || v.y < b.minY || v.y > b.maxY) continue
      this.camera.toScreen(v.x, v.y, p)
      ctx.fillText(String(v.id), p.x, p.y)
    }
  }

  /**
   * Players' names beside their cursors: white on a dark plate edged in the player's colour. The
   * label reads over anything (white on the plate is about 17:1), including a body drawn in the
   * player's own colour (the one it holds); the colour still says whose cursor it is.
   */
  private drawCursorLabels(cursors: readonly ViewCursor[]): void {
    const ctx = this.ctx
    ctx.font = LABEL_FONT
    ctx.textAlign = 'left'
    ctx.textBaseline = 'middle'
    const p = { x: 0, y: 0 }
    for (const c of cursors) {
      this.camera.toScreen(c.x, c.y, p)
      const box = labelBox(p.x, p.y, ctx.measureText(c.name).width)
      ctx.fillStyle = LABEL_PLATE
      ctx.beginPath()
      ctx.roundRect(box.x, box.y, box.width, box.height, 4)
      ctx.fill()
      ctx.fillStyle = c.color
      ctx.fillRect(box.x, box.y + 2, 3, box.height - 4)
      ctx.fillStyle = LABEL_TEXT
      ctx.fillText(c.name, box.x + LABEL_PAD + 2, box.y + box.height / 2)
    }
  }
}
