/*
 * The camera: maps world metres (y up) to CSS pixels on the canvas (y down) and back. It holds a
 * centre in world space and a scale in CSS pixels per metre; the renderer multiplies by the device
 * pixel ratio only when it sets the canvas transform, so every input path (mouse, touch, wheel)
 * works in CSS pixels. Zooming keeps the world point under the cursor (or the pinch centre) fixed.
 */
import type { Vec2 } from '../../engine/index.ts'

/** Smallest and largest zoom (CSS px per metre). */
const MIN_SCALE = 2
const MAX_SCALE = 400

/** A 2D camera over the world. */
export class Camera {
  /** World point at the centre of the view (m). */
  x = 0
  y = 8
  /** CSS pixels per metre, usually 30. */
  scale = 30
  /** Viewport size in CSS pixels. */
  width = 800
  height = 600

  /** Set the viewport size (CSS px). */
  resize(width: number, height: number): void {
    this.width = Math.max(1, width)
    this.height = Math.max(1, height)
  }

  /** Screen point (CSS px) to world point (m). */
  toWorld(sx: number, sy: number, out: Vec2 = { x: 0, y: 0 }): Vec2 {
    out.x = this.x + (sx - this.width / 2) / this.scale
    out.y = this.y - (sy - this.height / 2) / this.scale
    return out
  }

  /** World point (m) to screen point (CSS px). */
  toScreen(wx: number, wy: number, out: Vec2 = { x: 0, y: 0 }): Vec2 {
    out.x = (wx - this.x) * this.scale + this.width / 2
    out.y = this.height / 2 - (wy - this.y) * this.scale
    return out
  }

  /** Move the view by a screen drag of (dx, dy) CSS px: the world follows the pointer. */
  pan(dx: number, dy: number): void {
    this.x -= dx / this.scale
    this.y += dy / this.scale
  }

  /** Multiply the zoom by `factor`, keeping the world point under screen point (sx, sy) fixed. */
  zoomAt(sx: number, sy: number, factor: number): void {
    const before = this.toWorld(sx, sy)
    this.scale = Math.min(MAX_SCALE, Math.max(MIN_SCALE, this.scale * factor))
    const after = this.toWorld(sx, sy)
    this.x += before.x - after.x
    this.y += before.y - after.y
  }

  /**
   * Frame a world rectangle (m) with a margin, e.g. a scene's bodies, between a band of `insetTop`
   * CSS px (the toolbar) and one of `insetBottom` (the replay controls) that it should not hide
   * behind.
   */
  fit(
    minX: number,
    minY: number,
    maxX: number,
    maxY: number,
    insetTop = 0,
    insetBottom = 0,
    margin = 1.15,
  ): void {
    const w = Math.max(4, (maxX - minX) * margin)
    const h = Math.max(4, (maxY - minY) * margin)
    const usable = Math.max(1, this.height - insetTop - insetBottom)
    this.scale = Math.min(MAX_SCALE, Math.max(MIN_SCALE, Math.min(this.width / w, usable / h)))
    this.x = (minX + maxX) / 2
    this.y = (minY + maxY) / 2 + (insetTop - insetBottom) / 2 / this.scale
  }

  /** The visible world rectangle (m), for culling. */
  visibleBounds(): { minX: number; minY: number; maxX: number; maxY: number } {
    const hw = this.width / 2 / this.scale
    const hh = this.height / 2 / this.scale
    return { minX: this.x - hw, minY: this.y - hh, maxX: this.x + hw, maxY: this.y + hh }
  }
}
