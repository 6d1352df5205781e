/*
 * What the spawn tools drop: a size (a scale on the tool's 1 m shape) and a material (density,
 * friction, restitution). A small panel of sliders under the toolbar, shown while a spawn tool is
 * active; the values go into every spawn command (the protocol's optional material fields, in
 * SPAWN_MATERIAL's ranges), and offline the same command builds the body.
 */
import { SPAWN_MATERIAL } from '../../shared/index.ts'

/** Size scale range (1 = the default 1 m shapes). */
export const SIZE_RANGE = [0.25, 4] as const
/** Defaults: the engine's own (density 1 kg/m^2, friction 0.6, restitution 0). */
export const SPAWN_DEFAULTS = { size: 1, density: 1, friction: 0.6, restitution: 0 } as const

/** The spawn tools' current size and material. */
export interface SpawnSettings {
  size: number
  density: number
  friction: number
  restitution: number
}

type Key = keyof SpawnSettings

const RANGES: Record<Key, readonly [number, number]> = {
  size: SIZE_RANGE,
  density: [0.1, 20],
  friction: SPAWN_MATERIAL.friction,
  restitution: SPAWN_MATERIAL.restitution,
}
const UNITS: Record<Key, string> = { size: 'x', density: 'kg/m²', friction: '', restitution: '' }

/** The panel's sliders, bound to a settings object that the tools read. */
export class SpawnPanel {
  readonly settings: SpawnSettings = { ...SPAWN_DEFAULTS }

  constructor(private readonly panel: HTMLElement) {
    for (const key of Object.keys(RANGES) as Key[]) {
      const [min, max] = RANGES[key]
      const label = document.createElement('label')
      const input = document.createElement('input')
      const value = document.createElement('span')
      input.type = 'range'
      input.min = String(min)
      input.max = String(max)
      input.step = key === 'density' ? '0.1' : '0.05'
      input.value = String(this.settings[key])
      input.dataset.spawn = key
      input.setAttribute('aria-label', key)
      const show = (): void => {
        value.textContent = `${this.settings[key].toFixed(2)}${UNITS[key] ? ` ${UNITS[key]}` : ''}`
      }
      input.addEventListener('input', () => {
        this.settings[key] = Math.min(max, Math.max(min, Number(input.value)))
        show()
      })
      show()
      label.append(`${key} `, input, value)
      panel.append(label)
    }
  }

  /** Show the panel while a spawn tool is active. */
  show(visible: boolean): void {
    this.panel.hidden = !visible
  }
}
