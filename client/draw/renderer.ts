/*
 * The canvas renderer. The backing store is sized in device pixels (HiDPI) and the world is drawn
 * with one transform that maps metres, y up, onto it, so shapes are plain world coordinates. To
 * stay fast with a thousand bodies, bodies are batched by style: one path per style (static,
 * awake, asleep, kinematic) holding every visible shape, filled and stroked once; only grabbed
 * bodies (in their player's colour) and overlays are drawn one by one. Text (names, ids) is drawn
 * in screen space so it is never mirrored by the y-up transform.
 */
import type { Vec2 } from '../../engine/index.ts'
import { shapeRadius, shapeVertices, toWorld } from '../input/index.ts'
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
  /** The explode tool's blast: full within `radius` (m), fading to nothing at twice it. */
  blast?: { x: number; y: number; radius: number } | null
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
      [STYLE.static, (v) => v.kind === 0],
      [STYLE.kinematic, (v) => v.kind === 1],
      [STYLE.asleep, (v) => v.kind === 2 && !v.awake],
      [STYLE.awake, (v) => v.kind === 2 && v.awake],
    ]
    const ctx = this.ctx
    ctx.lineWidth = this.lineWidth(1.25)
    ctx.lineJoin = 'miter'
    // Stroking outlines costs as much raster work as filling. With many bodies on screen, shapes
    // are filled shrunk by one pixel instead, so the background shows between touching bodies.
    const outline = this.camera.scale >= 40 || bodies.length < 400
    const inset = outline ? 0 : 1 / this.camera.scale
    for (const [style, accept] of groups) {
      ctx.beginPath()
      let any = false
      for (const v of bodies) {
        if (v.grabColor || !accept(v)) continue
        const r = shapeRadius(v.shape)
        if (v.x + r < b.minX || v.x - r > b.maxX || v.y + r < b.minY || v.y - r > b.maxY) continue
        this.traceBody(v, inset > 0 ? Math.max(0.2, 1 - inset / r) : 1)
        any = true
      }
      if (!any) continue
      ctx.fillStyle = style[0]
      ctx.fill()
      if (!outline) continue
      ctx.strokeStyle = style[1]
      ctx.stroke()
    }
    for (const v of bodies) {
      if (!v.grabColor) continue
      ctx.beginPath()
      this.traceBody(v)
      ctx.fillStyle = v.grabColor
      ctx.fill()
      ctx.strokeStyle = '#ffffff'
      ctx.stroke()
    }
  }

  /**
   * Add a body's outline to the current path, scaled by `shrink` about its origin; circles get a
   * radius line to show rotation.
   */
  private traceBody(v: ViewBody, shrink = 1): void {
    const ctx = this.ctx
    if (v.shape.type === 'circle') {
      const r = v.shape.radius * shrink
      const c = Math.cos(v.angle)
      const s = Math.sin(v.angle)
      ctx.moveTo(v.x + r * c, v.y + r * s)
      ctx.arc(v.x, v.y, r, v.angle, v.angle + 2 * Math.PI)
      ctx.lineTo(v.x, v.y)
      return
    }
    const verts = shapeVertices(v.shape)
    const c = Math.cos(v.angle) * shrink
    const s = Math.sin(v.angle) * shrink
    for (let i = 0; i < verts.length; i++) {
      const p = verts[i]
      const x = v.x + c * p.x - s * p.y
      const y = v.y + s * p.x + c * p.y
      if (i === 0) ctx.moveTo(x, y)
      else ctx.lineTo(x, y)
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
      if (v.shape.type === 'circle') {
        const r = v.shape.radius
        ;[minX, minY, maxX, maxY] = [v.x - r, v.y - r, v.x + r, v.y + r]
      } else {
        for (const p of shapeVertices(v.shape)) {
          const w = toWorld(v, p.x, p.y)
          minX = Math.min(minX, w.x)
          minY = Math.min(minY, w.y)
          maxX = Math.max(maxX, w.x)
          maxY = Math.max(maxY, w.y)
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
