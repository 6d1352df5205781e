/*
 * Input tools for mouse, pen and touch, all through Pointer Events (one code path; the canvas has
 * `touch-action: none` so the browser does not scroll or zoom the page). One pointer drives the
 * active tool; a second pointer turns the gesture into a pinch (zoom about the midpoint, pan with
 * it) and cancels what the first pointer was doing. Pressing on empty space pans in every tool
 * that needs a body; the wheel zooms about the cursor.
 *
 * Tools produce protocol commands only; the sandbox applies them locally or sends them. The
 * player's own cursor, grab line and previews are drawn from local pointer state at once, so the
 * tool never feels late even though the body follows the server a few ticks behind.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { WireShape } from '../../shared/index.ts'
import type { Camera, ToolOverlay } from '../draw/index.ts'
import type { Sandbox, ViewBody, ViewJoint } from '../modes/index.ts'
import { pickBody, pickJoint, toLocal, toWorld } from './picking.ts'
import { SPAWN_DEFAULTS, type SpawnSettings } from './spawn-settings.ts'

/** The tools, in toolbar order. */
export const TOOLS = [
  'grab',
  'circle',
  'box',
  'polygon',
  'delete',
  'pin',
  'rope',
  'cut',
  'inspect',
  'explode',
] as const
/** A tool name. */
export type ToolName = (typeof TOOLS)[number]

/** Throw speed per metre of drag (1/s), and the largest throw speed (m/s). */
const THROW_GAIN = 4
const MAX_THROW = 40
/** A press that moves less than this (CSS px) is a click. */
const CLICK_SLOP = 6
/** The cut tool takes the joint within this distance of the pointer (CSS px). */
const CUT_REACH = 12
/** The explode tool's blast radius (m; it fades to nothing at twice this) and impulse per metre of width (N s/m). */
export const EXPLODE_RADIUS = 2
export const EXPLODE_IMPULSE = 8
/** Cursor updates while not grabbing are sent at most this often (ms). */
const HOVER_INTERVAL = 50

type Action =
  | { kind: 'none' }
  | { kind: 'pan'; moved: number; clickBody: ViewBody | null }
  | { kind: 'grab'; body: number; lx: number; ly: number }
  | { kind: 'spawn'; at: Vec2; shape: WireShape }
  | { kind: 'rope'; a: number; anchor: Vec2 }
  | { kind: 'pinch'; distance: number; mid: Vec2 }
  | { kind: 'explode' }

const dynamic = (b: ViewBody): boolean => b.kind === 2
const isSpawnTool = (tool: ToolName): boolean => tool === 'circle' || tool === 'box' || tool === 'polygon'
/** The preview body's fixed fields. */
const GHOST: ViewBody = {
  id: 0,
  kind: 2,
  shape: { type: 'circle', radius: 0.5 },
  x: 0,
  y: 0,
  angle: 0,
  awake: true,
  grabColor: null,
}

/** Pointer, wheel and pinch handling for the canvas. */
export class ToolController {
  tool: ToolName = 'grab'
  /** The inspected body (lab), 0 when none. */
  selected = 0
  private action: Action = { kind: 'none' }
  private readonly pointers = new Map<number, Vec2>()
  private cursor: Vec2 | null = null
  private lastHover = 0
  private polygonSides = 3
  private preview: { key: string; shape: WireShape } | null = null

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly camera: Camera,
    private readonly sandbox: () => Sandbox,
    /** Size and material of spawned shapes (the spawn panel's sliders). */
    private readonly spawn: SpawnSettings = { ...SPAWN_DEFAULTS },
  ) {
    canvas.addEventListener('pointerdown', (e) => this.down(e))
    canvas.addEventListener('pointermove', (e) => this.move(e))
    canvas.addEventListener('pointerup', (e) => this.up(e, false))
    canvas.addEventListener('pointercancel', (e) => this.up(e, true))
    canvas.addEventListener('pointerleave', (e) => {
      if (e.pointerType === 'mouse' && !this.pointers.size) this.cursor = null
    })
    canvas.addEventListener('wheel', (e) => this.wheel(e), { passive: false })
    canvas.addEventListener('contextmenu', (e) => e.preventDefault())
  }

  private local(e: PointerEvent | WheelEvent): Vec2 {
    const r = this.canvas.getBoundingClientRect()
    return { x: e.clientX - r.left, y: e.clientY - r.top }
  }

  private down(e: PointerEvent): void {
    e.preventDefault()
    this.canvas.setPointerCapture?.(e.pointerId)
    const p = this.local(e)
    this.pointers.set(e.pointerId, p)
    if (this.pointers.size === 2) {
      this.cancel()
      const [a, b] = [...this.pointers.values()]
      this.action = { kind: 'pinch', distance: Math.hypot(a.x - b.x, a.y - b.y), mid: mid(a, b) }
      return
    }
    if (this.pointers.size > 2 || e.button > 0) {
      if (e.button > 0) this.action = { kind: 'pan', moved: 0, clickBody: null }
      return
    }
    const w = this.camera.toWorld(p.x, p.y)
    this.cursor = w
    this.begin(w)
  }

  private begin(w: Vec2): void {
    const sandbox = this.sandbox()
    const bodies = sandbox.bodies()
    const hit = pickBody(bodies, w, dynamic)
    switch (this.tool) {
      case 'grab':
        if (!hit) break
        {
          const l = toLocal(hit, w)
          sandbox.send({ k: 'grab', body: hit.id, lx: l.x, ly: l.y })
          sandbox.send({ k: 'move', x: w.x, y: w.y })
          this.action = { kind: 'grab', body: hit.id, lx: l.x, ly: l.y }
        }
        return
      case 'circle':
      case 'box':
      case 'polygon':
        this.action = { kind: 'spawn', at: w, shape: this.spawnShape() }
        return
      case 'delete':
        if (!hit) break
        sandbox.send({ k: 'delete', body: hit.id })
        if (this.selected === hit.id) this.selected = 0
        return
      case 'pin':
        if (!hit) break
        {
          const under = pickBody(bodies, w, () => true, hit.id)
          sandbox.send({ k: 'pin', a: under ? under.id : 0, b: hit.id, x: w.x, y: w.y })
        }
        return
      case 'rope': {
        const any = pickBody(bodies, w)
        this.action = { kind: 'rope', a: any ? any.id : 0, anchor: w }
        return
      }
      case 'cut': {
        const joint = this.jointAt(w)
        if (!joint) break
        sandbox.send({ k: 'unjoint', joint: joint.id })
        return
      }
      case 'inspect':
        this.action = { kind: 'pan', moved: 0, clickBody: hit ?? pickBody(bodies, w) }
        return
      case 'explode':
        // Press to see the blast (a finger too), move to aim, release to explode there.
        this.action = { kind: 'explode' }
        return
    }
    this.action = { kind: 'pan', moved: 0, clickBody: null }
  }

  /** The pin, rope, rod or spring the cut tool would remove at a world point, or null. */
  private jointAt(w: Vec2): ViewJoint | null {
    return pickJoint(this.sandbox().joints(), w, CUT_REACH / this.camera.scale)
  }

  /**
   * The shape the active spawn tool drops next, scaled by the spawn settings' size (polygons: the
   * side count cycles 3 to 8 per drop).
   */
  spawnShape(): WireShape {
    const k = this.spawn.size
    const r3 = (v: number): number => Math.round(v * 1000) / 1000
    if (this.tool === 'circle') return { type: 'circle', radius: r3(0.5 * k) }
    if (this.tool === 'box') return { type: 'box', hw: r3(0.5 * k), hh: r3(0.5 * k) }
    const n = this.polygonSides
    const v: number[] = []
    for (let i = 0; i < n; i++) {
      const a = (2 * Math.PI * i) / n + Math.PI / 2
      v.push(r3(0.6 * k * Math.cos(a)), r3(0.6 * k * Math.sin(a)))
    }
    return { type: 'polygon', v }
  }

  private move(e: PointerEvent): void {
    const p = this.local(e)
    const previous = this.pointers.get(e.pointerId)
    if (previous) this.pointers.set(e.pointerId, p)
    const a = this.action
    if (a.kind === 'pinch') {
      if (this.pointers.size < 2) return
      const [p0, p1] = [...this.pointers.values()]
      const distance = Math.hypot(p0.x - p1.x, p0.y - p1.y)
      const m = mid(p0, p1)
      this.camera.pan(m.x - a.mid.x, m.y - a.mid.y)
      if (a.distance > 0 && distance > 0) this.camera.zoomAt(m.x, m.y, distance / a.distance)
      a.distance = distance
      a.mid = m
      return
    }
    if (a.kind === 'pan' && previous) {
      a.moved += Math.abs(p.x - previous.x) + Math.abs(p.y - previous.y)
      this.camera.pan(p.x - previous.x, p.y - previous.y)
      return
    }
    const w = this.camera.toWorld(p.x, p.y)
    this.cursor = w
    const now = performance.now()
    if (a.kind === 'grab') this.sandbox().send({ k: 'move', x: w.x, y: w.y })
    else if (this.sandbox().mode === 'online' && now - this.lastHover > HOVER_INTERVAL) {
      this.lastHover = now
      this.sandbox().send({ k: 'move', x: w.x, y: w.y })
    }
  }

  private up(e: PointerEvent, cancelled: boolean): void {
    const had = this.pointers.delete(e.pointerId)
    if (!had) return
    const a = this.action
    if (a.kind === 'pinch') {
      if (this.pointers.size === 0) this.action = { kind: 'none' }
      return
    }
    if (e.pointerType !== 'mouse') this.cursor = null
    const p = this.local(e)
    const w = this.camera.toWorld(p.x, p.y)
    this.action = { kind: 'none' }
    if (cancelled) {
      if (a.kind === 'grab') this.sandbox().send({ k: 'release' })
      return
    }
    this.finish(a, w)
  }

  private finish(a: Action, w: Vec2): void {
    const sandbox = this.sandbox()
    if (a.kind === 'grab') sandbox.send({ k: 'release' })
    else if (a.kind === 'spawn') {
      const drag = Math.hypot(w.x - a.at.x, w.y - a.at.y) * this.camera.scale
      const v = drag < CLICK_SLOP ? { x: 0, y: 0 } : throwVelocity(a.at, w)
      const { density, friction, restitution } = this.spawn
      sandbox.send({
        k: 'spawn',
        shape: a.shape,
        x: a.at.x,
        y: a.at.y,
        vx: v.x,
        vy: v.y,
        density,
        friction,
        restitution,
      })
      if (a.shape.type === 'polygon') this.polygonSides = this.polygonSides >= 8 ? 3 : this.polygonSides + 1
    } else if (a.kind === 'rope') this.tieRope(a, w)
    else if (a.kind === 'explode')
      sandbox.sendGame?.('explode', { x: w.x, y: w.y, radius: EXPLODE_RADIUS, impulse: EXPLODE_IMPULSE })
    else if (a.kind === 'pan' && a.moved < CLICK_SLOP && this.tool === 'inspect') {
      this.selected = a.clickBody && a.clickBody.kind === 2 ? a.clickBody.id : 0
    }
  }

  private tieRope(a: { a: number; anchor: Vec2 }, w: Vec2): void {
    const bodies = this.sandbox().bodies()
    const end = pickBody(bodies, w)
    let first = { id: a.a, p: a.anchor }
    let second = { id: end ? end.id : 0, p: w }
    const isDynamic = (id: number): boolean => bodies.some((b) => b.id === id && b.kind === 2)
    if (!isDynamic(second.id)) [first, second] = [second, first]
    if (!isDynamic(second.id) || first.id === second.id) return
    if (Math.hypot(w.x - a.anchor.x, w.y - a.anchor.y) < 0.05) return
    // A static body as the first end is the same as the world: anchor it in world space.
    const firstId = first.id && isDynamic(first.id) ? first.id : 0
    this.sandbox().send({
      k: 'rope',
      a: firstId,
      b: second.id,
      ax: first.p.x,
      ay: first.p.y,
      bx: second.p.x,
      by: second.p.y,
    })
  }

  /** Abandon the current action (a second finger arrived, the tool changed, focus was lost). */
  cancel(): void {
    if (this.action.kind === 'grab') this.sandbox().send({ k: 'release' })
    this.action = { kind: 'none' }
  }

  private wheel(e: WheelEvent): void {
    e.preventDefault()
    const p = this.local(e)
    this.camera.zoomAt(p.x, p.y, Math.exp(-e.deltaY * 0.0015))
  }

  /** What to draw for the tools this frame. */
  overlay(color: string): ToolOverlay {
    const a = this.action
    const o: ToolOverlay = {
      cursor: this.cursor,
      color,
      grabAnchor: null,
      ghost: null,
      throwTo: null,
      ropeFrom: null,
      cutJoint: null,
      ghostAlpha: 0.5,
    }
    if (a.kind === 'grab') {
      const body = this.sandbox()
        .bodies()
        .find((b) => b.id === a.body)
      if (body) o.grabAnchor = toWorld(body, a.lx, a.ly)
      else this.action = { kind: 'none' }
    } else if (a.kind === 'spawn') {
      o.ghost = { ...GHOST, shape: a.shape, x: a.at.x, y: a.at.y }
      o.throwTo = this.cursor
    } else if (a.kind === 'none' && this.cursor && isSpawnTool(this.tool)) {
      // Hovering with a spawn tool: the shape the next click drops, faint, at the pointer.
      o.ghost = { ...GHOST, shape: this.previewShape(), x: this.cursor.x, y: this.cursor.y }
      o.ghostAlpha = 0.25
    } else if (a.kind === 'rope') o.ropeFrom = a.anchor
    else if (this.tool === 'cut' && this.cursor) o.cutJoint = this.jointAt(this.cursor)
    if (this.tool === 'explode' && this.cursor)
      o.blast = { x: this.cursor.x, y: this.cursor.y, radius: EXPLODE_RADIUS }
    return o
  }

  /** The next spawn shape, rebuilt only when it changes (the preview is drawn every frame). */
  private previewShape(): WireShape {
    const key = `${this.tool}:${this.polygonSides}:${this.spawn.size}`
    if (this.preview?.key !== key) this.preview = { key, shape: this.spawnShape() }
    return this.preview.shape
  }

  /** Where the pointer is (world m), null when it is not over the canvas. */
  get pointer(): Vec2 | null {
    return this.cursor
  }

  /** The body grabbed by this player, 0 when none. */
  get grabbing(): number {
    return this.action.kind === 'grab' ? this.action.body : 0
  }
}

function mid(a: Vec2, b: Vec2): Vec2 {
  return { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2 }
}

/** Throw velocity (m/s) for a spawn dragged from `from` to `to`: along the drag, capped. */
export function throwVelocity(from: Vec2, to: Vec2): Vec2 {
  let vx = (to.x - from.x) * THROW_GAIN
  let vy = (to.y - from.y) * THROW_GAIN
  const speed = Math.hypot(vx, vy)
  if (speed > MAX_THROW) {
    vx *= MAX_THROW / speed
    vy *= MAX_THROW / speed
  }
  return { x: vx, y: vy }
}
