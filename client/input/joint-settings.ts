/*
 * What the joint tools make: a motor torque (hinges and wheels, N m; a slider's force is ten times
 * it in N; 0 makes no motor), a hinge's angle limit (+- degrees; 0 none), a spring's and a wheel's
 * stiffness (Hz) and a breaking force (N; 0 never). A small panel of sliders under the toolbar,
 * shown while a joint tool is active; the values go into the sandbox's joint commands (PROTOCOL.md,
 * "The sandbox's joint commands"), inside their ranges.
 *
 * Motors are driven from the keyboard by the player who made them (the room refuses anyone else):
 * the arrow keys turn your wheels and hinges (right: clockwise, which drives a car to the right)
 * and push your sliders (up: along the axis), and stop them when released.
 */
import type { WireJoint } from '../../shared/index.ts'

/** The joint tools' settings. */
export interface JointSettings {
  /** Motor torque (N m) for hinges and wheels (slider force: 10x, N); 0: no motor. */
  torque: number
  /** A hinge's limit, +- this many degrees; 0: none. */
  limit: number
  /** A spring's and a wheel suspension's stiffness (Hz). */
  hz: number
  /** Breaking force (N) of every joint made; 0: never breaks. */
  breakForce: number
}

/** Defaults: a 5 N m motor (drives a 1 m box on two of its wheels at 2.5 m/s without tipping it over), a 4 Hz suspension, unbreakable. */
export const JOINT_DEFAULTS: JointSettings = { torque: 5, limit: 0, hz: 4, breakForce: 0 }

/** Motor speeds the arrow keys ask for: rad/s for wheels and hinges, m/s for sliders. */
export const DRIVE_SPEED = { turn: 10, slide: 2 } as const

type Key = keyof JointSettings

const RANGES: Record<Key, readonly [number, number, number]> = {
  torque: [0, 500, 5],
  limit: [0, 180, 5],
  hz: [0.5, 20, 0.5],
  breakForce: [0, 5000, 50],
}
const LABELS: Record<Key, string> = { torque: 'motor', limit: 'limit', hz: 'spring', breakForce: 'break' }
const UNITS: Record<Key, string> = { torque: 'N m', limit: '°', hz: 'Hz', breakForce: 'N' }

/** The panel's sliders, bound to a settings object that the tools read. */
export class JointPanel {
  readonly settings: JointSettings = { ...JOINT_DEFAULTS }

  constructor(private readonly panel: HTMLElement) {
    for (const key of Object.keys(RANGES) as Key[]) {
      const [min, max, step] = RANGES[key]
      const label = document.createElement('label')
      const input = document.createElement('input')
      const value = document.createElement('span')
      input.type = 'range'
      input.min = String(min)
      input.max = String(max)
      input.step = String(step)
      input.value = String(this.settings[key])
      input.dataset.joint = key
      input.setAttribute('aria-label', LABELS[key])
      const show = (): void => {
        const v = this.settings[key]
        value.textContent =
          v === 0 && key !== 'hz' ? (key === 'breakForce' ? 'never' : 'off') : `${v} ${UNITS[key]}`
      }
      input.addEventListener('input', () => {
        this.settings[key] = Math.min(max, Math.max(min, Number(input.value)))
        show()
      })
      show()
      label.append(`${LABELS[key]} `, input, value)
      panel.append(label)
    }
  }

  /** Show the panel while a joint tool is active. */
  show(visible: boolean): void {
    this.panel.hidden = !visible
  }
}

/** The motor speed an arrow key asks of one of your joints (undefined: the key does not drive it). */
export function driveSpeed(j: WireJoint, key: string): number | undefined {
  if (!j.motor) return undefined
  if (j.kind === 'wheel' || j.kind === 'pin') {
    if (key === 'ArrowRight') return -DRIVE_SPEED.turn
    if (key === 'ArrowLeft') return DRIVE_SPEED.turn
  } else if (j.kind === 'slider') {
    if (key === 'ArrowUp') return DRIVE_SPEED.slide
    if (key === 'ArrowDown') return -DRIVE_SPEED.slide
  }
  return undefined
}
