/*
 * Input tools for mouse, pen and touch, all through Pointer Events (one code path; the canvas has
 * `touch-action: none` so the browser does not scroll or zoom the page). One pointer drives the
 * active tool; a second pointer turns the gesture into a pinch (zoom about the midpoint, pan with
 * it) and cancels what the first pointer was doing. Pressing on empty space pans in every tool
 * that needs a body; the wheel zooms about the cursor.
 *
 * In a room whose game's client module has pointer bindings (docs/games.md, "Client modules"), a
 * press is offered to the game first: when its `down` returns a command, the whole gesture (press,
 * drag, release, or a cancel such as a second finger) is the game's, and the tool never sees it.
 *
 * Tools produce protocol commands only; the sandbox applies them locally or sends them. The
 * player's own cursor, grab line and previews are drawn from local pointer state at once, so the
 * tool never feels late even though the body follows the server a few ticks behind.
 */
import type { Vec2 } from '../../engine/index.ts'
import {
  type GameClient,
  POINTER_MOVE_INTERVAL,
  type PointerBindings,
  type PointerInput,
} from '../../games/index.ts'
import type { PlainData, SpawnCommand, WireJoint, WireJointKind, WireShape } from '../../shared/index.ts'
import type { Camera, ToolOverlay } from '../draw/index.ts'
import type { Sandbox, ViewBody, ViewJoint } from '../modes/index.ts'
import { DRAW_FORMS, type DrawForm, type Drawn, dragBody, groundBodies, outlineBody } from './drawing.ts'
import { EditTool } from './edit-tool.ts'
import { JOINT_DEFAULTS, type JointSettings } from './joint-settings.ts'
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
  'draw',
  'ground',
  'weld',
  'hinge',
  'spring',
  'slider',
  'wheel',
  'explode',
  'edit',
] as const
/** A tool name. */
export type ToolName = (typeof TOOLS)[number]

/**
 * The command each tool sends (a built-in `input` kind or a game `cmd` kind; the Lab reads and
 * sends nothing the game must list): a page offers a tool only when the room's game lists it
 * (rules.builtins, rules.commands).
 */
export const TOOL_COMMANDS: Readonly<Record<ToolName, string | null>> = {
  grab: 'grab',
  circle: 'spawn',
  box: 'spawn',
  polygon: 'spawn',
  delete: 'delete',
  pin: 'pin',
  rope: 'rope',
  cut: 'unjoint',
  inspect: null,
  draw: 'spawn',
  ground: 'spawn',
  weld: 'weld',
  hinge: 'hinge',
  spring: 'spring',
  slider: 'slider',
  wheel: 'wheel',
  explode: 'explode',
  edit: 'edit',
}

/** Throw speed per metre of drag (1/s), and the largest throw speed (m/s). */
const THROW_GAIN = 4
const MAX_THROW = 40
/** A press that moves less than this (CSS px) is a click. */
const CLICK_SLOP = 6
/** The cut tool takes the joint within this distance of the pointer (CSS px). */
const CUT_REACH = 12
/** A drawn stroke takes a point every this many CSS px, and is simplified to within half that. */
const STROKE_STEP = 4
/** A click this close (CSS px) to the first point closes a clicked outline (the last point: ends a clicked ground line). */
const CLOSE_REACH = 12
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
  | { kind: 'spring'; a: number; anchor: Vec2 }
  | { kind: 'slider'; a: number; b: number; anchor: Vec2 }
  | { kind: 'pinch'; distance: number; mid: Vec2 }
  | { kind: 'stroke'; points: Vec2[]; moved: number }
  | { kind: 'drag'; from: Vec2 }
  | { kind: 'explode' }
  | { kind: 'edit' }
  | {
      kind: 'game'
      pointer: PointerBindings
      last: Vec2
      sent: string
      timer: ReturnType<typeof setInterval> | null
    }

const dynamic = (b: ViewBody): boolean => b.kind === 2
/** A body the wheel tool takes as a wheel: one circle. */
const isWheel = (b: ViewBody): boolean => b.shapes.length === 1 && b.shapes[0].type === 'circle'
const isSpawnTool = (tool: ToolName): boolean => tool === 'circle' || tool === 'box' || tool === 'polygon'
/** The preview body's fixed fields. */
const GHOST: ViewBody = {
  id: 0,
  kind: 2,
  shapes: [{ type: 'circle', radius: 0.5 }],
  color: null,
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
  private preview: { key: string; shapes: WireShape[] } | null = null
  /** What a drag with the Draw tool makes. */
  drawForm: DrawForm = 'outline'
  /** The static toggle: what the Draw and spawn tools make is static. */
  makeStatic = false
  /** Points clicked one by one for an outline (Draw) or a ground line (Ground), world m. */
  private pending: Vec2[] = []
  /** Tells the player why a drawing was refused (the page's notice). */
  onNotice: (text: string) => void = () => {}
  /** The Edit tool (edit-tool.ts): selection, move, turn, box selection. */
  readonly edit: EditTool
  /** Whether Shift was held at the last press (the Edit tool turns instead of moving). */
  private shift = false
  /** The room's game's client module (set by the page), offered each press before the tool. */
  gameClient: () => GameClient | undefined = () => undefined

  /**
   * Whether the room's game lists a command kind (set by the page from rules.builtins and
   * rules.commands; everything, offline and before the welcome). Hover cursors go as `move`, so a
   * game without `move` gets none.
   */
  allows: (kind: string) => boolean = () => true

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly camera: Camera,
    private readonly sandbox: () => Sandbox,
    /** Size and material of spawned shapes (the spawn panel's sliders). */
    private readonly spawn: SpawnSettings = { ...SPAWN_DEFAULTS },
    /** Motor, limit, spring and breaking force of the joints made (the joint panel's sliders). */
    private readonly joints: JointSettings = { ...JOINT_DEFAULTS },
  ) {
    this.edit = new EditTool(camera, sandbox)
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
    this.shift = e.shiftKey
    if (this.gameDown(w)) return
    this.begin(w)
  }

  /** Offer a press to the game's pointer bindings; true when its `down` sent a command. */
  private gameDown(w: Vec2): boolean {
    const pointer = this.gameClient()?.pointer
    const cmd = pointer?.down?.(this.pointerInput(w))
    if (!pointer || !cmd) return false
    this.sandbox().sendGame(cmd.kind, cmd.args)
    const action: Action = { kind: 'game', pointer, last: w, sent: JSON.stringify(cmd), timer: null }
    // While held, `move` is asked every interval (the pointer may stay put while the world moves).
    if (pointer.move) action.timer = setInterval(() => this.gameHeld(action), POINTER_MOVE_INTERVAL)
    this.action = action
    return true
  }

  /** A game gesture still held: send what `move` returns for the pointer now, when it changed. */
  private gameHeld(a: Extract<Action, { kind: 'game' }>): void {
    if (this.action !== a) return
    const cmd = a.pointer.move?.(this.pointerInput(a.last))
    if (!cmd) return
    const text = JSON.stringify(cmd)
    if (text === a.sent) return
    a.sent = text
    this.sandbox().sendGame(cmd.kind, cmd.args)
  }

  /** The game's pointer gesture ended (lifted or cancelled): send what its `up` returns. */
  private gameUp(a: Extract<Action, { kind: 'game' }>, w: Vec2): void {
    if (a.timer !== null) clearInterval(a.timer)
    const cmd = a.pointer.up?.(this.pointerInput(w))
    if (cmd) this.sandbox().sendGame(cmd.kind, cmd.args)
  }

  private pointerInput(w: Vec2): PointerInput {
    const sandbox = this.sandbox()
    return {
      state: sandbox.gameState?.() ?? null,
      me: sandbox.playerId(),
      x: w.x,
      y: w.y,
      position: (id) => {
        const b = sandbox.bodies().find((body) => body.id === id)
        return b ? { x: b.x, y: b.y } : null
      },
    }
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
      case 'draw':
        this.action =
          this.drawForm === 'outline' ? { kind: 'stroke', points: [w], moved: 0 } : { kind: 'drag', from: w }
        return
      case 'ground':
        this.action = { kind: 'stroke', points: [w], moved: 0 }
        return
      case 'weld':
      case 'hinge':
      case 'wheel': {
        const made = this.clickJoint(this.tool, w)
        if (!made) break
        sandbox.sendGame(this.tool, made)
        return
      }
      case 'spring': {
        const any = pickBody(bodies, w)
        this.action = { kind: 'spring', a: any ? any.id : 0, anchor: w }
        return
      }
      case 'slider':
        if (!hit) break
        {
          const under = pickBody(bodies, w, () => true, hit.id)
          this.action = { kind: 'slider', a: under ? under.id : 0, b: hit.id, anchor: w }
        }
        return
      case 'explode':
        // Press to see the blast (a finger too), move to aim, release to explode there.
        this.action = { kind: 'explode' }
        return
      case 'edit':
        this.edit.press(w, this.shift)
        this.action = { kind: 'edit' }
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
    if (a.kind === 'edit' && previous) this.edit.move(w)
    if (a.kind === 'stroke' && previous) {
      a.moved += Math.hypot(p.x - previous.x, p.y - previous.y)
      const last = a.points[a.points.length - 1]
      if (Math.hypot(w.x - last.x, w.y - last.y) * this.camera.scale >= STROKE_STEP) a.points.push(w)
    }
    const now = performance.now()
    if (a.kind === 'game' && previous) a.last = w
    if (a.kind === 'grab') this.sandbox().send({ k: 'move', x: w.x, y: w.y })
    else if (
      this.sandbox().mode === 'online' &&
      now - this.lastHover > HOVER_INTERVAL &&
      this.allows('move')
    ) {
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
      if (a.kind === 'game') this.gameUp(a, a.last)
      if (a.kind === 'grab') this.sandbox().send({ k: 'release' })
      if (a.kind === 'edit') this.edit.release(w, true)
      return
    }
    this.finish(a, w)
  }

  private finish(a: Action, w: Vec2): void {
    const sandbox = this.sandbox()
    if (a.kind === 'grab') sandbox.send({ k: 'release' })
    else if (a.kind === 'game') this.gameUp(a, w)
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
        ...(this.makeStatic ? { static: true } : {}),
      })
      if (a.shape.type === 'polygon') this.polygonSides = this.polygonSides >= 8 ? 3 : this.polygonSides + 1
    } else if (a.kind === 'stroke') this.finishStroke(a, w)
    else if (a.kind === 'drag' && this.drawForm !== 'outline') {
      this.commit(dragBody(this.drawForm, a.from, w, this.capsuleRadius()))
    } else if (a.kind === 'rope') this.tieRope(a, w)
    else if (a.kind === 'spring') this.hangSpring(a, w)
    else if (a.kind === 'slider') this.laySlider(a, w)
    else if (a.kind === 'edit') this.edit.release(w, false)
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

  /**
   * A stroke ended: a drag is a freehand outline (Draw) or line (Ground); a click adds a point to
   * the one being clicked, and a click on its first point (Draw) or its last (Ground) finishes it.
   */
  private finishStroke(a: { points: Vec2[]; moved: number }, w: Vec2): void {
    if (a.moved >= CLICK_SLOP) {
      this.pending = []
      a.points.push(w)
      this.commitStroke(a.points)
      return
    }
    const near = (p: Vec2 | undefined): boolean =>
      p !== undefined && Math.hypot(p.x - w.x, p.y - w.y) * this.camera.scale <= CLOSE_REACH
    const ends =
      this.tool === 'draw'
        ? this.pending.length >= 3 && near(this.pending[0])
        : this.pending.length >= 2 && near(this.pending.at(-1))
    if (ends) this.finishPending()
    else this.pending.push(w)
  }

  /** Finish the outline or ground line clicked point by point (Enter, or a click on its end). */
  finishPending(): void {
    const points = this.pending
    this.pending = []
    if (points.length >= 2) this.commitStroke(points)
  }

  private commitStroke(points: Vec2[]): void {
    const tolerance = STROKE_STEP / 2 / this.camera.scale
    this.commit(this.tool === 'ground' ? groundBodies(points, tolerance) : outlineBody(points, tolerance))
  }

  /** Send what was drawn (static when the toggle is on; with the spawn panel's material), or say why not. */
  private commit(drawn: Drawn): void {
    if (!drawn.ok) {
      this.onNotice(drawn.reason)
      return
    }
    const { density, friction, restitution } = this.spawn
    for (const cmd of drawn.commands) {
      const out: SpawnCommand = cmd.static ? cmd : { ...cmd, density, friction, restitution }
      if (this.makeStatic) out.static = true
      this.sandbox().send(out)
    }
  }

  /** A dragged capsule's radius (m): a quarter of the spawn size's 1 m. */
  private capsuleRadius(): number {
    return Math.round(250 * this.spawn.size) / 1000
  }

  /** The Draw tool's next form (outline, rectangle, circle, capsule, outline ...). */
  cycleDrawForm(): DrawForm {
    this.drawForm = DRAW_FORMS[(DRAW_FORMS.indexOf(this.drawForm) + 1) % DRAW_FORMS.length]
    return this.drawForm
  }

  /** Breaking force and motor arguments every joint command shares, from the joint settings. */
  private jointExtras(motor: 'torque' | 'force' | null): { [key: string]: PlainData } {
    const out: { [key: string]: PlainData } = {}
    const s = this.joints
    if (s.breakForce > 0) out.breakForce = s.breakForce
    if (motor === 'torque' && s.torque > 0) out.torque = s.torque
    if (motor === 'force' && s.torque > 0) out.force = 10 * s.torque
    return out
  }

  /**
   * The arguments of a weld, hinge or wheel made by a click at `w`, or null when there is nothing
   * to join: a weld or hinge joins the dynamic body under the pointer to what lies under it (or the
   * background); the wheel tool joins a circle lying over another body to it as its wheel, and on
   * any other body (a chassis) makes a new wheel there.
   */
  private clickJoint(tool: 'weld' | 'hinge' | 'wheel', w: Vec2): { [key: string]: PlainData } | null {
    const bodies = this.sandbox().bodies()
    const hit = pickBody(bodies, w, dynamic)
    if (!hit) return null
    const under = pickBody(bodies, w, () => true, hit.id)
    const s = this.joints
    if (tool === 'weld')
      return { a: under ? under.id : 0, b: hit.id, x: w.x, y: w.y, ...this.jointExtras(null) }
    if (tool === 'hinge') {
      const limit: { [key: string]: PlainData } =
        s.limit > 0 ? { lower: (-s.limit * Math.PI) / 180, upper: (s.limit * Math.PI) / 180 } : {}
      return { a: under ? under.id : 0, b: hit.id, x: w.x, y: w.y, ...limit, ...this.jointExtras('torque') }
    }
    const wheel = { hz: s.hz, ...this.jointExtras('torque') }
    if (isWheel(hit) && under && under.kind === 2) return { a: under.id, b: hit.id, ...wheel }
    return { a: hit.id, radius: this.wheelRadius(), x: w.x, y: w.y, ...wheel }
  }

  /** A new wheel's radius (m): a quarter of the box tool's side (0.25 m at the spawn panel's size 1x). */
  private wheelRadius(): number {
    return Math.round(250 * this.spawn.size) / 1000
  }

  private hangSpring(a: { a: number; anchor: Vec2 }, w: Vec2): void {
    const bodies = this.sandbox().bodies()
    const end = pickBody(bodies, w)
    let first = { id: a.a, p: a.anchor }
    let second = { id: end ? end.id : 0, p: w }
    const isDynamic = (id: number): boolean => bodies.some((b) => b.id === id && b.kind === 2)
    if (!isDynamic(second.id)) [first, second] = [second, first]
    if (!isDynamic(second.id) || first.id === second.id) return
    if (Math.hypot(w.x - a.anchor.x, w.y - a.anchor.y) < 0.05) return
    const firstId = first.id && isDynamic(first.id) ? first.id : 0
    this.sandbox().sendGame('spring', {
      ...{ a: firstId, b: second.id, ax: first.p.x, ay: first.p.y, bx: second.p.x, by: second.p.y },
      hz: this.joints.hz,
      ...this.jointExtras(null),
    })
  }

  /** A slider through the press point, along the drag, free to travel the drag's length each way. */
  private laySlider(a: { a: number; b: number; anchor: Vec2 }, w: Vec2): void {
    const dx = w.x - a.anchor.x
    const dy = w.y - a.anchor.y
    const length = Math.hypot(dx, dy)
    if (length * this.camera.scale < CLICK_SLOP) return
    const travel = Math.min(100, Math.round(length * 1000) / 1000)
    this.sandbox().sendGame('slider', {
      ...{ a: a.a, b: a.b, x: a.anchor.x, y: a.anchor.y, dx, dy, lower: -travel, upper: travel },
      ...this.jointExtras('force'),
    })
  }

  /** The joint the active joint tool would make now, for the preview (null when none). */
  private jointPreview(): ViewJoint | null {
    const a = this.action
    const at = this.cursor
    if (!at) return null
    if (a.kind === 'spring') return previewJoint('spring', a.anchor, at, 0)
    if (a.kind === 'slider')
      return previewJoint('slider', a.anchor, at, Math.hypot(at.x - a.anchor.x, at.y - a.anchor.y))
    if (a.kind !== 'none') return null
    if (this.tool === 'weld' || this.tool === 'hinge' || this.tool === 'wheel') {
      if (!pickBody(this.sandbox().bodies(), at, dynamic)) return null
      const kind = this.tool === 'hinge' ? 'pin' : this.tool
      const preview = previewJoint(kind, at, at, 0)
      if (this.tool === 'hinge' && this.joints.limit > 0) {
        preview.spec.limit = true
        preview.spec.lower = (-this.joints.limit * Math.PI) / 180
        preview.spec.upper = -preview.spec.lower
      }
      return preview
    }
    return null
  }

  /** Abandon the current action (a second finger arrived, the tool changed, focus was lost). */
  cancel(): void {
    if (this.action.kind === 'game') this.gameUp(this.action, this.action.last)
    if (this.action.kind === 'grab') this.sandbox().send({ k: 'release' })
    if (this.action.kind === 'edit') this.edit.release({ x: 0, y: 0 }, true)
    this.action = { kind: 'none' }
    this.pending = []
  }

  private wheel(e: WheelEvent): void {
    e.preventDefault()
    if (this.tool === 'edit' && e.shiftKey && this.edit.wheel(e.deltaY || e.deltaX)) return
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
      stroke: null,
      strokeClosed: false,
      joint: this.jointPreview(),
    }
    if (a.kind === 'grab') {
      const body = this.sandbox()
        .bodies()
        .find((b) => b.id === a.body)
      if (body) o.grabAnchor = toWorld(body, a.lx, a.ly)
      else this.action = { kind: 'none' }
    } else if (a.kind === 'spawn') {
      o.ghost = { ...GHOST, shapes: [a.shape], x: a.at.x, y: a.at.y }
      o.throwTo = this.cursor
    } else if (a.kind === 'none' && this.cursor && isSpawnTool(this.tool)) {
      // Hovering with a spawn tool: the shape the next click drops, faint, at the pointer.
      o.ghost = { ...GHOST, shapes: this.previewShapes(), x: this.cursor.x, y: this.cursor.y }
      o.ghostAlpha = 0.25
    } else if (a.kind === 'drag' && this.cursor && this.drawForm !== 'outline') {
      // Dragging out a rectangle, circle or capsule: the body it will be, where it will be.
      const drawn = dragBody(this.drawForm, a.from, this.cursor, this.capsuleRadius())
      const cmd = drawn.ok ? drawn.commands[0] : null
      if (cmd?.shape) o.ghost = { ...GHOST, shapes: [cmd.shape], x: cmd.x, y: cmd.y }
    } else if (
      (a.kind === 'stroke' || this.pending.length > 0) &&
      (this.tool === 'draw' || this.tool === 'ground')
    ) {
      // The outline or line so far: clicked points, the stroke being drawn, and the pointer.
      const points = [...this.pending, ...(a.kind === 'stroke' ? a.points : [])]
      if (this.cursor) points.push(this.cursor)
      o.stroke = points
      o.strokeClosed = this.tool === 'draw'
    } else if (a.kind === 'rope') o.ropeFrom = a.anchor
    else if (a.kind === 'none' && this.cursor && this.tool === 'wheel' && o.joint) {
      // The wheel tool over a chassis: the wheel a click makes (a circle already there is used instead).
      const bodies = this.sandbox().bodies()
      const hit = pickBody(bodies, this.cursor, dynamic)
      if (hit && !(isWheel(hit) && pickBody(bodies, this.cursor, dynamic, hit.id))) {
        const shape: WireShape = { type: 'circle', radius: this.wheelRadius() }
        o.ghost = { ...GHOST, shapes: [shape], x: this.cursor.x, y: this.cursor.y }
        o.ghostAlpha = 0.3
      }
    } else if (this.tool === 'cut' && this.cursor) o.cutJoint = this.jointAt(this.cursor)
    if (this.tool === 'explode' && this.cursor)
      o.blast = { x: this.cursor.x, y: this.cursor.y, radius: EXPLODE_RADIUS }
    if (this.tool === 'edit') this.edit.decorate(o)
    return o
  }

  /** The next spawn shape, rebuilt only when it changes (the preview is drawn every frame). */
  private previewShapes(): WireShape[] {
    const key = `${this.tool}:${this.polygonSides}:${this.spawn.size}`
    if (this.preview?.key !== key) this.preview = { key, shapes: [this.spawnShape()] }
    return this.preview.shapes
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

/** A joint of `kind` from `from` to `to` in world space, as a joint tool's preview draws it. */
function previewJoint(kind: WireJointKind, from: Vec2, to: Vec2, travel: number): ViewJoint {
  const dx = to.x - from.x
  const dy = to.y - from.y
  const length = Math.hypot(dx, dy)
  const ux = length > 1e-9 ? dx / length : 0
  const uy = length > 1e-9 ? dy / length : 1
  const spec: WireJoint = {
    ...{ id: 0, kind, a: 0, b: 0, ax: from.x, ay: from.y, bx: to.x, by: to.y },
    ...{ length, min: length, max: length, hz: 1, damping: 0, ref: 0 },
    ...{
      limit: travel > 0,
      lower: -travel,
      upper: travel,
      motor: false,
      speed: 0,
      torque: 0,
      collide: false,
    },
    ...{ force: 0, ux, uy, spring: false, target: 0, ahz: 0, adamping: 0, correction: 0 },
    ...{ breakForce: 0, breakTorque: 0, owner: 0 },
  }
  const slider = kind === 'slider'
  return {
    id: 0,
    kind,
    spec,
    ax: from.x,
    ay: from.y,
    bx: slider ? from.x : to.x,
    by: slider ? from.y : to.y,
    angleA: 0,
    angle: 0,
    axisX: ux,
    axisY: uy,
    translation: 0,
    force: null,
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
