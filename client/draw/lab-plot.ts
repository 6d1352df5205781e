/*
 * The lab's plot: the selected body's speed (m/s) and kinetic energy (J) over the last
 * PLOT_SECONDS of simulated time, one sample per room tick that the page saw (samples are keyed by
 * tick, not by frame, so a slow page plots the same curve with fewer points, and a paused room
 * stops the plot). Each curve is scaled to its own maximum, written beside it.
 */
import type { FreeBody } from './lab.ts'

/** Simulated seconds shown. */
export const PLOT_SECONDS = 5
/** Curve colours: speed, kinetic energy. */
export const PLOT_COLORS = { speed: '#4ecdc4', kinetic: '#ff9f1c' } as const

/** One sample: room tick, speed (m/s), kinetic energy (J). */
export interface PlotSample {
  tick: number
  speed: number
  kinetic: number
}

/** The samples of one body, oldest first. */
export class LabPlot {
  readonly samples: PlotSample[] = []
  private body = 0

  constructor(private readonly tickRate: number) {}

  /** Record the diagram of `bodyId` at room tick `tick`; another body starts a new plot. */
  add(bodyId: number, tick: number, fb: FreeBody): void {
    if (bodyId !== this.body) {
      this.body = bodyId
      this.samples.length = 0
    }
    const last = this.samples[this.samples.length - 1]
    if (last && tick <= last.tick) {
      // A new world restarts the ticks: start over; the same tick again adds nothing.
      if (tick < last.tick) this.samples.length = 0
      else return
    }
    const v = fb.velocity
    this.samples.push({ tick, speed: Math.sqrt(v.x * v.x + v.y * v.y), kinetic: fb.kinetic })
    const oldest = tick - PLOT_SECONDS * this.tickRate
    let drop = 0
    while (drop < this.samples.length && this.samples[drop].tick < oldest) drop++
    if (drop > 0) this.samples.splice(0, drop)
  }

  /** Forget the plot (nothing selected). */
  clear(): void {
    this.body = 0
    this.samples.length = 0
  }

  /** Draw both curves on a canvas (CSS size of the element, device pixels for the backing store). */
  draw(canvas: HTMLCanvasElement): void {
    const dpr = window.devicePixelRatio || 1
    const w = canvas.clientWidth
    const h = canvas.clientHeight
    if (canvas.width !== Math.round(w * dpr)) canvas.width = Math.round(w * dpr)
    if (canvas.height !== Math.round(h * dpr)) canvas.height = Math.round(h * dpr)
    const ctx = canvas.getContext('2d')
    if (!ctx || w === 0) return
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0)
    ctx.clearRect(0, 0, w, h)
    ctx.strokeStyle = '#2e3644'
    ctx.strokeRect(0.5, 0.5, w - 1, h - 1)
    const s = this.samples
    if (s.length === 0) return
    const end = s[s.length - 1].tick
    const span = PLOT_SECONDS * this.tickRate
    const top = 14
    const x = (tick: number): number => w - 2 - ((end - tick) / span) * (w - 4)
    ctx.font = '10px ui-monospace, monospace'
    ctx.textBaseline = 'top'
    const curves = [
      ['speed', 'm/s', 4],
      ['kinetic', 'J', w / 2],
    ] as const
    for (const [key, unit, labelX] of curves) {
      let max = 0
      for (const p of s) max = Math.max(max, p[key])
      const scale = max > 0 ? (h - top - 3) / max : 0
      ctx.strokeStyle = PLOT_COLORS[key]
      ctx.lineWidth = 1.5
      ctx.beginPath()
      for (let i = 0; i < s.length; i++) {
        const px = x(s[i].tick)
        const py = h - 2 - s[i][key] * scale
        if (i === 0) ctx.moveTo(px, py)
        else ctx.lineTo(px, py)
      }
      ctx.stroke()
      ctx.fillStyle = PLOT_COLORS[key]
      ctx.fillText(`${key === 'speed' ? 'speed' : 'kinetic'} max ${max.toFixed(2)} ${unit}`, labelX, 2)
    }
  }
}
