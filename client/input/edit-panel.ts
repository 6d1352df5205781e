/*
 * The Edit tool's panel, under the toolbar while the tool is active: what is selected (a body, a
 * number of bodies, or a joint), its material (density, friction, restitution sliders), colour,
 * collision layer (0-7: games/sandbox/edit-commands.ts), a static toggle, scale buttons (x0.8,
 * x1.25), turn buttons (15 degrees either way), Duplicate and Delete. It shows the first selected body's values as they travel (its
 * shapes' settings and filter); a change is sent for every selected body when the control is let
 * go (the sandbox's `edit` command; scale a `transform`). A selected joint shows its kind and
 * one control per setting its kind has (games/sandbox's EDITABLE_JOINT_SETTINGS: check boxes for
 * limit, motor and spring, number fields for the rest, in the wire's units and the command's
 * bounds); a change is sent when the field is committed (the sandbox's `editJoint`), and the
 * controls are rewritten when the joint comes back changed.
 */
import { EDITABLE_JOINT_SETTINGS, filterLayer, MAX_LAYER } from '../../games/index.ts'
import { cssColor, type WireJoint } from '../../shared/index.ts'
import type { ViewBody, ViewJoint } from '../modes/index.ts'
import type { EditTool } from './edit-tool.ts'

type Material = 'density' | 'friction' | 'restitution'

/** Slider ranges: [min, max, step], inside the edit command's bounds (PROTOCOL.md). */
const RANGES: Record<Material, readonly [number, number, number]> = {
  density: [0.05, 100, 0.05],
  friction: [0, 2, 0.05],
  restitution: [0, 1, 0.05],
}
/** Defaults of a shape setting that does not travel (PROTOCOL.md, Shape). */
const DEFAULTS: Record<Material, number> = { density: 1, friction: 0.6, restitution: 0 }

/**
 * A joint setting's control: its bounds [min, max, step] (editJoint's, PROTOCOL.md; a pin's angles
 * within +-pi), its unit, and a label; a boolean has none.
 */
function jointField(
  kind: WireJoint['kind'],
  key: string,
): { range: readonly [number, number, number]; unit: string } | null {
  const pin = kind === 'pin'
  switch (key) {
    case 'limit':
    case 'motor':
    case 'spring':
      return null
    case 'lower':
    case 'upper':
    case 'target':
      return pin ? { range: [-Math.PI, Math.PI, 0.05], unit: 'rad' } : { range: [-100, 100, 0.05], unit: 'm' }
    case 'speed':
      return { range: [-50, 50, 0.5], unit: kind === 'pin' || kind === 'wheel' ? 'rad/s' : 'm/s' }
    case 'torque':
      return { range: [0, 1e6, 1], unit: 'N m' }
    case 'force':
      return { range: [0, 1e6, 1], unit: 'N' }
    case 'hz':
    case 'ahz':
      return { range: [0, 60, 0.5], unit: 'Hz' }
    case 'damping':
    case 'adamping':
      return { range: [0, 10, 0.1], unit: '' }
    case 'length':
    case 'max':
      return { range: [0.001, 100, 0.1], unit: 'm' }
    case 'min':
      return { range: [0, 100, 0.1], unit: 'm' }
    case 'correction':
      return { range: [0, 1, 0.05], unit: '' }
    case 'breakForce':
      return { range: [0, 1e9, 10], unit: 'N (0 never)' }
    default:
      return { range: [0, 1e9, 10], unit: 'N m (0 never)' } // breakTorque
  }
}

/** The Edit panel (see the file comment). */
export class EditPanel {
  private readonly title = document.createElement('span')
  private readonly inputs = new Map<string, HTMLInputElement | HTMLSelectElement>()
  private readonly values = new Map<Material, HTMLSpanElement>()
  private readonly controls = document.createElement('div')
  /** The selected joint's controls (rewritten when the joint or its settings change). */
  private readonly jointControls = document.createElement('div')
  /** What the panel shows now (so it is rewritten only when that changes). */
  private shown = 'nothing yet'

  /** A key of what the panel shows (changes when it is rewritten). */
  get key(): string {
    return this.shown
  }

  constructor(
    private readonly panel: HTMLElement,
    private readonly tool: EditTool,
  ) {
    this.title.className = 'edit-title'
    this.title.dataset.edit = 'title'
    panel.append(this.title, this.controls, this.jointControls)
    this.controls.className = 'edit-controls'
    this.jointControls.className = 'edit-controls'
    this.jointControls.dataset.edit = 'joint'
    this.jointControls.hidden = true
    for (const key of Object.keys(RANGES) as Material[]) {
      const [min, max, step] = RANGES[key]
      const input = this.field(key, 'range')
      Object.assign(input, { min: String(min), max: String(max), step: String(step) })
      const value = document.createElement('span')
      this.values.set(key, value)
      input.addEventListener('input', () => {
        value.textContent = input.value
      })
      input.addEventListener('change', () => this.tool.edit({ [key]: clamp(Number(input.value), min, max) }))
      input.parentElement?.append(value)
    }
    const color = this.field('color', 'color')
    color.addEventListener('change', () =>
      this.tool.edit({ color: Number.parseInt(color.value.slice(1), 16) }),
    )
    const layer = document.createElement('select')
    for (let l = 0; l <= MAX_LAYER; l++) layer.append(new Option(l === 0 ? '0 (all)' : String(l), String(l)))
    this.label('layer', layer)
    layer.addEventListener('change', () => this.tool.edit({ layer: Number(layer.value) }))
    const fixed = this.field('static', 'checkbox')
    fixed.addEventListener('change', () => this.tool.edit({ static: fixed.checked }))
    this.button('smaller', '−', 'Scale down (×0.8)', () => this.tool.scale(0.8))
    this.button('bigger', '+', 'Scale up (×1.25)', () => this.tool.scale(1.25))
    this.button('turn-left', '⟲', 'Turn 15° counter-clockwise (Shift+wheel)', () => this.tool.turn(1))
    this.button('turn-right', '⟳', 'Turn 15° clockwise (Shift+wheel)', () => this.tool.turn(-1))
    this.button('duplicate', 'Duplicate', 'Copy beside itself', () => this.tool.duplicate())
    this.button('delete', 'Delete', 'Delete the selection (Delete key)', () => this.tool.deleteSelection())
  }

  private label(key: string, input: HTMLInputElement | HTMLSelectElement): void {
    const label = document.createElement('label')
    input.dataset.edit = key
    input.setAttribute('aria-label', key)
    label.append(`${key} `, input)
    this.controls.append(label)
    this.inputs.set(key, input)
  }

  private field(key: string, type: string): HTMLInputElement {
    const input = document.createElement('input')
    input.type = type
    this.label(key, input)
    return input
  }

  private button(key: string, text: string, title: string, click: () => void): void {
    const b = document.createElement('button')
    b.type = 'button'
    b.textContent = text
    b.title = title
    b.dataset.editAction = key
    b.addEventListener('click', click)
    this.panel.append(b)
  }

  /** Show the panel while the Edit tool is active. */
  show(visible: boolean): void {
    this.panel.hidden = !visible
  }

  /** Show the selection (called every frame; rewrites the controls only when it changed). */
  refresh(bodies: readonly ViewBody[], joint: ViewJoint | null): void {
    const first = bodies[0]
    const key = first
      ? `${bodies.map((b) => b.id).join(',')}:${first.kind}:${first.color}:${JSON.stringify(first.shapes[0])}`
      : joint
        ? `j${joint.id}:${JSON.stringify(joint.spec)}`
        : ''
    if (key === this.shown) return
    this.shown = key
    this.controls.hidden = !first
    this.jointControls.hidden = first !== undefined || joint === null
    for (const b of this.panel.querySelectorAll<HTMLButtonElement>('button'))
      b.disabled = !first && !(joint && b.dataset.editAction === 'delete')
    if (!first) {
      this.title.textContent = joint
        ? `joint ${joint.id}: ${joint.kind}${jointSettings(joint)}`
        : 'Click a body or a joint, or drag a box around bodies'
      if (joint) this.showJoint(joint.spec)
      return
    }
    this.title.textContent = bodies.length === 1 ? `body ${first.id}` : `${bodies.length} bodies`
    const shape = first.shapes[0]
    for (const m of Object.keys(RANGES) as Material[]) {
      const v = shape[m] ?? DEFAULTS[m]
      ;(this.inputs.get(m) as HTMLInputElement).value = String(v)
      ;(this.values.get(m) as HTMLSpanElement).textContent = String(v)
    }
    ;(this.inputs.get('color') as HTMLInputElement).value = first.color ?? cssColor(0x888888)!
    const filter = shape.filter ?? [1, 0xffffffff, 0]
    this.inputs.get('layer')!.value = String(filterLayer({ categoryBits: filter[0], maskBits: filter[1] }))
    ;(this.inputs.get('static') as HTMLInputElement).checked = first.kind === 0
  }
  /** One control per setting of the joint's kind, each sending editJoint when committed. */
  private showJoint(spec: WireJoint): void {
    this.jointControls.replaceChildren()
    const values = spec as unknown as Record<string, number | boolean>
    for (const key of EDITABLE_JOINT_SETTINGS[spec.kind]) {
      const label = document.createElement('label')
      const input = document.createElement('input')
      input.dataset.jointEdit = key
      input.setAttribute('aria-label', `joint ${key}`)
      const field = jointField(spec.kind, key)
      if (field === null) {
        input.type = 'checkbox'
        input.checked = values[key] === true
        input.addEventListener('change', () => this.tool.editJoint({ [key]: input.checked }))
        label.append(`${key} `, input)
      } else {
        const [min, max, step] = field.range
        input.type = 'number'
        input.inputMode = 'decimal'
        Object.assign(input, { min: String(min), max: String(max), step: String(step) })
        input.value = String(values[key])
        input.addEventListener('change', () => {
          const v = Number(input.value)
          if (input.value.trim() === '' || !Number.isFinite(v)) return
          this.tool.editJoint({ [key]: clamp(v, min, max) })
        })
        const unit = document.createElement('span')
        unit.textContent = field.unit
        label.append(`${key} `, input, unit)
      }
      this.jointControls.append(label)
    }
  }
}

const clamp = (v: number, lo: number, hi: number): number => Math.min(hi, Math.max(lo, v))

/** A joint's settings worth showing (motor, limit, spring, breaking force). */
function jointSettings(j: ViewJoint): string {
  const s = j.spec
  const parts: string[] = []
  if (s.motor) parts.push(`motor ${s.speed} at most ${s.torque || s.force}`)
  if (s.limit) parts.push(`limit ${s.lower.toFixed(2)}..${s.upper.toFixed(2)}`)
  if (s.hz > 0 && (s.kind === 'spring' || s.kind === 'wheel' || s.spring)) parts.push(`spring ${s.hz} Hz`)
  if (s.breakForce > 0) parts.push(`breaks at ${s.breakForce} N`)
  return parts.length > 0 ? ` (${parts.join(', ')})` : ''
}
