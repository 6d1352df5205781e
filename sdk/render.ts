/*
 * The SDK's canvas renderer (docs/sdk.md): draws a Session's world with the Concord page's own
 * Renderer and Camera (HiDPI, y up), framing the room's bodies at first and following the canvas's
 * size. A separate entry (dist/sdk/render.js) so headless users of sdk/index.ts do not bundle it.
 */
import { Camera, Renderer, type ViewBody, viewJoints } from '../client/index.ts'
import type { Session } from './index.ts'

/** A running renderer: `stop()` ends its animation loop; `camera` may be moved and zoomed. */
export interface SessionRenderer {
  readonly camera: Camera
  /** Draw one frame now (the loop does this every animation frame). */
  draw(): void
  stop(): void
}

/** Options for createRenderer. */
export interface RenderOptions {
  /** Frame the bodies once they first arrive (default true); false keeps the camera where it is. */
  fit?: boolean
  /** Draw every animation frame (default true); false draws only when `draw()` is called. */
  loop?: boolean
}

/** Draw `session` on `canvas` every animation frame until `stop()` (see the file comment). */
export function createRenderer(
  canvas: HTMLCanvasElement,
  session: Session,
  options: RenderOptions = {},
): SessionRenderer {
  if (typeof HTMLCanvasElement === 'undefined' || !(canvas instanceof HTMLCanvasElement))
    throw new TypeError('createRenderer: canvas must be an HTMLCanvasElement')
  const camera = new Camera()
  const renderer = new Renderer(canvas, camera)
  let fitted = options.fit === false
  let frame = 0
  const layers = { contacts: false, joints: true, aabbs: false, ids: false }
  const overlay = {
    cursor: null,
    color: '#ffffff',
    grabAnchor: null,
    ghost: null,
    ghostAlpha: 0,
    throwTo: null,
    ropeFrom: null,
    cutJoint: null,
    stroke: null,
    strokeClosed: false,
    joint: null,
  }
  const draw = (): void => {
    renderer.resize()
    const bodies: ViewBody[] = session.bodies().map((b) => ({ ...b, grabColor: null }))
    if (!fitted && bodies.length > 0) {
      let minX = Number.POSITIVE_INFINITY
      let minY = Number.POSITIVE_INFINITY
      let maxX = Number.NEGATIVE_INFINITY
      let maxY = Number.NEGATIVE_INFINITY
      for (const b of bodies) {
        minX = Math.min(minX, b.x - 1)
        minY = Math.min(minY, b.y - 1)
        maxX = Math.max(maxX, b.x + 1)
        maxY = Math.max(maxY, b.y + 1)
      }
      camera.fit(minX, minY, maxX, maxY)
      fitted = true
    }
    const byId = new Map(bodies.map((b) => [b.id, b]))
    const joints = viewJoints(
      session.joints(),
      (id) => byId.get(id),
      () => null,
    )
    renderer.draw({
      bodies,
      joints,
      cursors: [],
      contacts: null,
      layers,
      overlay,
      selected: null,
      freeBody: null,
    })
  }
  const loop = (): void => {
    draw()
    frame = requestAnimationFrame(loop)
  }
  if (options.loop !== false) frame = requestAnimationFrame(loop)
  return {
    camera,
    draw,
    stop: () => cancelAnimationFrame(frame),
  }
}
