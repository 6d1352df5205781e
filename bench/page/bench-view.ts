/*
 * Drawing for the benchmark page: one engine's scene, small, from the bodies' positions (every
 * engine reports the same thing: origin and velocity per body, so shapes are drawn unrotated:
 * circles as circles, polygons as discs of their mean vertex radius, static boxes as boxes), and a
 * live chart of step times per round.
 */
import type { BodyDef } from '../../engine/index.ts'

/** The world rectangle a scene's view shows (m). */
export interface ViewBounds {
  minX: number
  minY: number
  maxX: number
  maxY: number
}

function bodyRadius(def: BodyDef): number {
  const shape = def.shape
  if (shape.type === 'circle') return shape.radius
  let sum = 0
  for (const v of shape.vertices) sum += Math.hypot(v.x - shape.centroid.x, v.y - shape.centroid.y)
  return (sum / shape.vertices.length) * 0.9
}

/** The box around every dynamic body's start, with a margin, and the ground line in view. */
export function sceneBounds(bodies: readonly BodyDef[]): ViewBounds {
  const b = { minX: Number.POSITIVE_INFINITY, minY: -1, maxX: Number.NEGATIVE_INFINITY, maxY: 1 }
  for (const def of bodies) {
    if ((def.type ?? 'dynamic') === 'static') continue
    const p = def.position ?? { x: 0, y: 0 }
    const r = bodyRadius(def) + 1
    b.minX = Math.min(b.minX, p.x - r)
    b.maxX = Math.max(b.maxX, p.x + r)
    b.minY = Math.min(b.minY, p.y - r)
    b.maxY = Math.max(b.maxY, p.y + r)
  }
  if (!Number.isFinite(b.minX)) return { minX: -10, minY: -1, maxX: 10, maxY: 10 }
  return b
}

/** Draws the bodies (positions from readBodies, 4 numbers per body; bodies not yet arrived are skipped). */
export function drawScene(
  canvas: HTMLCanvasElement,
  bodies: readonly BodyDef[],
  state: Float64Array,
  bounds: ViewBounds,
): void {
  const g = canvas.getContext('2d')
  if (!g) return
  const w = canvas.width
  const h = canvas.height
  const scale = Math.min(w / (bounds.maxX - bounds.minX), h / (bounds.maxY - bounds.minY))
  const ox = w / 2 - ((bounds.minX + bounds.maxX) / 2) * scale
  const oy = h / 2 + ((bounds.minY + bounds.maxY) / 2) * scale
  g.fillStyle = '#12161d'
  g.fillRect(0, 0, w, h)
  const count = Math.min(bodies.length, state.length / 4)
  for (let i = 0; i < count; i++) {
    const def = bodies[i]
    const x = ox + state[4 * i] * scale
    const y = oy - state[4 * i + 1] * scale
    if ((def.type ?? 'dynamic') === 'static') {
      const box = def.shape.type === 'polygon' ? def.shape.box : null
      if (!box) continue
      g.fillStyle = '#3b4556'
      g.fillRect(
        x - box.halfWidth * scale,
        y - box.halfHeight * scale,
        2 * box.halfWidth * scale,
        2 * box.halfHeight * scale,
      )
      continue
    }
    g.fillStyle = def.shape.type === 'circle' ? '#8fc1ff' : '#ff9f1c'
    g.beginPath()
    g.arc(x, y, Math.max(0.8, bodyRadius(def) * scale), 0, 2 * Math.PI)
    g.fill()
  }
}

/** Draws step times (ms per round, one series per engine) as lines; `colors` by series. */
export function drawTimes(
  canvas: HTMLCanvasElement,
  series: readonly number[],
  maxMs: number,
  color: string,
): void {
  const g = canvas.getContext('2d')
  if (!g) return
  const w = canvas.width
  const h = canvas.height
  g.fillStyle = '#12161d'
  g.fillRect(0, 0, w, h)
  g.strokeStyle = '#2e3644'
  g.beginPath()
  for (let k = 1; k < 4; k++) {
    g.moveTo(0, (h * k) / 4)
    g.lineTo(w, (h * k) / 4)
  }
  g.stroke()
  if (series.length === 0 || !(maxMs > 0)) return
  g.strokeStyle = color
  g.lineWidth = 1.5
  g.beginPath()
  series.forEach((ms, i) => {
    const x = series.length === 1 ? w / 2 : (i / (series.length - 1)) * (w - 2) + 1
    const y = h - Math.min(1, ms / maxMs) * (h - 2) - 1
    if (i === 0) g.moveTo(x, y)
    else g.lineTo(x, y)
  })
  g.stroke()
  g.fillStyle = '#d8dee9'
  g.font = '10px ui-monospace, monospace'
  g.fillText(`${maxMs.toFixed(maxMs < 10 ? 1 : 0)} ms`, 3, 11)
}
