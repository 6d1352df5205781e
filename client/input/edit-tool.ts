/*
 * The Edit tool (issue 31): select bodies and joints, move, turn, scale, duplicate and delete
 * them. A click on a body selects it; dragging it moves it (a faint copy shows where it goes, one
 * `transform` is sent on release); Shift+drag turns it about its origin, Shift+wheel turns it by
 * 15 degrees a notch. A press on empty space drags a selection rectangle: on release the editable
 * bodies whose origin lies inside are selected (a click there selects the joint within reach, or
 * nothing). Delete or Backspace, or the panel's Delete, removes the selection with one
 * `deleteMany` (a selected joint with `unjoint`). The panel (edit-panel.ts) changes material,
 * colour, layer, static state and scale, and turns the selection 15 degrees a press (touch has no Shift).
 *
 * Editable bodies are the room's rule (games/sandbox/edit-commands.ts): every body that is not
 * static, and static bodies with a colour (players' own); the scene's static scenery is skipped
 * here so a rectangle over the ground does not select it. Mouse, pen and touch alike (the tool
 * controller's Pointer Events): a finger drags a body or a rectangle the same way.
 */
import type { Vec2 } from '../../engine/index.ts'
import type { PlainData } from '../../shared/index.ts'
import type { Camera, ToolOverlay } from '../draw/index.ts'
import type { Sandbox, ViewBody, ViewJoint } from '../modes/index.ts'
import { bodyRadius, pickBody, pickJoint } from './picking.ts'

/** A press that moves less than this (CSS px) is a click. */
const CLICK_SLOP = 6
/** A click takes the joint within this distance of the pointer (CSS px). */
const JOINT_REACH = 12
/** Shift+wheel turns the selected body by this much per notch (rad). */
const WHEEL_TURN = Math.PI / 12
/** The largest selection a deleteMany carries (the room's MAX_DELETE_MANY). */
const MAX_SELECTION = 256

/** Whether players may edit this body (see the file comment). */
export const editable = (b: ViewBody): boolean => b.kind !== 0 || b.color !== null

/** An angle in [-pi, pi] (the transform command's range). */
function wrapAngle(a: number): number {
  return Math.atan2(Math.sin(a), Math.cos(a))
}

type Drag =
  | { kind: 'none' }
  | { kind: 'move'; body: number; from: Vec2; moved: number; turn: boolean; start: ViewBody }
  | { kind: 'box'; from: Vec2; moved: number }

/** The Edit tool's selection and drags (see the file comment). */
export class EditTool {
  /** Selected body ids (ascending), and the selected joint (0 when none). */
  selection: number[] = []
  joint = 0
  private drag: Drag = { kind: 'none' }
  private cursor: Vec2 | null = null

  constructor(
    private readonly camera: Camera,
    private readonly sandbox: () => Sandbox,
  ) {}

  /** The selected bodies as drawn this frame (a body gone since is dropped from the selection). */
  bodies(): ViewBody[] {
    const byId = new Map(
      this.sandbox()
        .bodies()
        .map((b) => [b.id, b]),
    )
    this.selection = this.selection.filter((id) => byId.has(id))
    return this.selection.map((id) => byId.get(id) as ViewBody)
  }

  /** The selected joint as drawn this frame, or null. */
  selectedJoint(): ViewJoint | null {
    const j = this.joint
      ? (this.sandbox()
          .joints()
          .find((v) => v.id === this.joint) ?? null)
      : null
    if (!j) this.joint = 0
    return j
  }

  /** A press at a world point (Shift held: turn instead of move). */
  press(w: Vec2, shift: boolean): void {
    this.cursor = w
    const hit = pickBody(this.sandbox().bodies(), w, editable)
    if (!hit) {
      this.drag = { kind: 'box', from: w, moved: 0 }
      return
    }
    if (!this.selection.includes(hit.id)) this.selection = [hit.id]
    this.joint = 0
    this.drag = { kind: 'move', body: hit.id, from: w, moved: 0, turn: shift, start: { ...hit } }
  }

  /** The pointer moved while pressed. */
  move(w: Vec2): void {
    const d = this.drag
    if (d.kind !== 'none' && this.cursor)
      d.moved += Math.hypot(w.x - this.cursor.x, w.y - this.cursor.y) * this.camera.scale
    this.cursor = w
  }

  /** The press ended (cancelled: a second finger, the tool changed): a move, a turn or a selection. */
  release(w: Vec2, cancelled: boolean): void {
    const d = this.drag
    this.drag = { kind: 'none' }
    if (cancelled || d.kind === 'none') return
    if (d.kind === 'move') {
      if (d.moved < CLICK_SLOP) return
      const pose = this.dragPose(d, w)
      this.transform(d.body, pose.x, pose.y, pose.angle)
      return
    }
    if (d.moved < CLICK_SLOP) {
      // A click on empty space: the joint within reach, or nothing.
      const j = pickJoint(this.sandbox().joints(), w, JOINT_REACH / this.camera.scale)
      this.selection = []
      this.joint = j ? j.id : 0
      return
    }
    const [x0, x1] = [Math.min(d.from.x, w.x), Math.max(d.from.x, w.x)]
    const [y0, y1] = [Math.min(d.from.y, w.y), Math.max(d.from.y, w.y)]
    this.joint = 0
    this.selection = this.sandbox()
      .bodies()
      .filter((b) => editable(b) && b.x >= x0 && b.x <= x1 && b.y >= y0 && b.y <= y1)
      .map((b) => b.id)
      .sort((a, b) => a - b)
      .slice(0, MAX_SELECTION)
  }

  /** Where a dragged body goes: moved with the pointer, or turned about its origin (Shift). */
  private dragPose(d: Extract<Drag, { kind: 'move' }>, w: Vec2): { x: number; y: number; angle: number } {
    const s = d.start
    if (!d.turn) return { x: s.x + w.x - d.from.x, y: s.y + w.y - d.from.y, angle: s.angle }
    const turn = Math.atan2(w.y - s.y, w.x - s.x) - Math.atan2(d.from.y - s.y, d.from.x - s.x)
    return { x: s.x, y: s.y, angle: wrapAngle(s.angle + turn) }
  }

  /** Shift+wheel over the tool: turn the one selected body; false when there is none to turn. */
  wheel(deltaY: number): boolean {
    if (this.selection.length !== 1) return false
    this.turn(deltaY < 0 ? 1 : -1)
    return true
  }

  /** Turn every selected body about its origin by 15 degrees, counter-clockwise (1) or clockwise (-1). */
  turn(direction: 1 | -1): void {
    // Only the angle: the room keeps each body's position exactly (the drawn one may lag).
    for (const b of this.bodies())
      this.sandbox().sendGame('transform', { body: b.id, angle: wrapAngle(b.angle + direction * WHEEL_TURN) })
  }

  /** Send one transform (x, y in m, angle in rad). */
  transform(body: number, x: number, y: number, angle: number): void {
    this.sandbox().sendGame('transform', { body, x, y, angle: wrapAngle(angle) })
  }

  /** Scale every selected body by k about its origin, where it is (the panel's - and + buttons). */
  scale(k: number): void {
    for (const id of this.selection) this.sandbox().sendGame('transform', { body: id, scale: k })
  }

  /** Set fields of every selected body (the panel: material, colour, layer, static). */
  edit(fields: { [key: string]: PlainData }): void {
    for (const id of this.selection) this.sandbox().sendGame('edit', { body: id, ...fields })
  }

  /** Change settings of the selected joint (the panel's joint controls: the sandbox's `editJoint`). */
  editJoint(fields: { [key: string]: PlainData }): void {
    if (this.joint) this.sandbox().sendGame('editJoint', { joint: this.joint, ...fields })
  }

  /** Copy every selected body beside itself (to the right, clear of it). */
  duplicate(): void {
    for (const b of this.bodies()) {
      const dx = Math.min(100, Math.round((2 * bodyRadius(b) + 0.1) * 1000) / 1000)
      this.sandbox().sendGame('duplicate', { body: b.id, dx, dy: 0 })
    }
  }

  /** Remove the selection: the bodies with one deleteMany, or the selected joint. */
  deleteSelection(): void {
    if (this.selection.length > 0) this.sandbox().sendGame('deleteMany', { bodies: [...this.selection] })
    else if (this.joint) this.sandbox().send({ k: 'unjoint', joint: this.joint })
    this.selection = []
    this.joint = 0
  }

  /** Forget the selection and any drag (Escape, another tool). */
  clear(): void {
    this.selection = []
    this.joint = 0
    this.drag = { kind: 'none' }
  }

  /** Draw the tool: the selection outlined, the dragged body where it would go, the rectangle. */
  decorate(o: ToolOverlay): void {
    o.highlight = this.bodies()
    const j = this.selectedJoint()
    if (j) o.cutJoint = j
    const d = this.drag
    const at = this.cursor
    if (!at) return
    if (d.kind === 'move' && d.moved >= CLICK_SLOP) {
      const pose = this.dragPose(d, at)
      o.ghost = { ...d.start, ...pose, color: null, grabColor: null }
      o.ghostAlpha = 0.45
    } else if (d.kind === 'box' && d.moved >= CLICK_SLOP) {
      o.stroke = [d.from, { x: at.x, y: d.from.y }, at, { x: d.from.x, y: at.y }]
      o.strokeClosed = true
    }
  }
}
