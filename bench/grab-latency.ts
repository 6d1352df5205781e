/*
 * The time from a pointer move to the grabbed body moving on screen, measured inside a sandbox
 * page (snapshot, lockstep or predict mode) driven by playwright-core with real mouse input.
 *
 * Set-up: the empty scene with gravity off and one 1 m box, grabbed at its centre with the grab
 * tool and held. Each trial waits until the drawn box is at rest (under 0.1 CSS px of motion for
 * 20 frames), then moves the pointer 60 CSS px (2 m at the usual 30 px/m) left or right in one
 * pointermove. A requestAnimationFrame watcher, registered after the page's own frame callback so
 * it reads what that frame drew, stops at the first frame whose drawn box is 1 CSS px or more from
 * where it rested. The latency is that moment (performance.now()) minus the pointermove event's
 * timeStamp, both on the page's clock; the frames between them are counted too.
 */
import type { Page } from 'playwright-core'
import { pickTool, screenOf } from '../tests/support/client-harness.ts'
import { median, p95 } from './summary.ts'

/** One mode's trials (ms and animation frames). */
export interface GrabLatency {
  trials: number
  medianMs: number
  p95Ms: number
  minMs: number
  maxMs: number
  medianFrames: number
  samplesMs: number[]
}

/*
 * The in-page half, as source text: functions passed to page.evaluate from a tsx-compiled file
 * would carry esbuild's __name helper, which the page does not have (as in client-bench.ts).
 * window.grabBench.box() is the grabbed box's drawn centre in CSS px.
 */
const PAGE_SCRIPT = `(id) => {
  const box = () => {
    const b = window.concord.sandbox.bodies().find((v) => v.id === id)
    return b ? window.concord.camera.toScreen(b.x, b.y, { x: 0, y: 0 }) : null
  }
  const waitForRest = () => new Promise((resolve, reject) => {
    let last = box()
    let still = 0
    let frames = 0
    const watch = () => {
      const now = box()
      if (!now || !last) return reject(new Error('the grabbed box is gone from the page'))
      still = Math.hypot(now.x - last.x, now.y - last.y) < 0.1 ? still + 1 : 0
      last = now
      if (still >= 20) return resolve()
      if (++frames > 1200) return reject(new Error('the grabbed box did not come to rest in 1,200 frames'))
      requestAnimationFrame(watch)
    }
    requestAnimationFrame(watch)
  })
  const arm = () => {
    const start = box()
    window.grabBench.result = null
    let movedAt = -1
    let frames = 0
    window.addEventListener('pointermove', (e) => { movedAt = e.timeStamp; frames = 0 }, { once: true })
    const watch = () => {
      frames++
      const now = box()
      if (movedAt >= 0 && now && start && Math.hypot(now.x - start.x, now.y - start.y) >= 1) {
        window.grabBench.result = { ms: performance.now() - movedAt, frames }
        return
      }
      if (frames < 3000) requestAnimationFrame(watch)
    }
    requestAnimationFrame(watch)
  }
  window.grabBench = { box, waitForRest, arm, result: null }
}`

/** Prepare the page: empty scene, no gravity, one box; grab it and hold. Returns its body id. */
async function grabOneBox(page: Page): Promise<number> {
  await page.evaluate(`window.concord.sandbox.send({ k: 'scene', name: 'empty' })`)
  await page.waitForFunction(`window.concord.sandbox.scene() === 'empty'`, null, { timeout: 60_000 })
  await page.evaluate(`(() => {
    const s = window.concord.sandbox
    s.send({ k: 'gravity', x: 0, y: 0 })
    s.send({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 6 })
  })()`)
  await page.waitForFunction(`window.concord.sandbox.bodies().some((b) => b.kind === 2)`, null, {
    timeout: 60_000,
  })
  const box = (await page.evaluate(`(() => {
    const b = window.concord.sandbox.bodies().find((v) => v.kind === 2)
    return { id: b.id, x: b.x, y: b.y }
  })()`)) as { id: number; x: number; y: number }
  await pickTool(page, 'grab')
  const at = await screenOf(page, box.x, box.y)
  await page.mouse.move(at.x, at.y)
  await page.mouse.down()
  await page.evaluate(`(${PAGE_SCRIPT})(${box.id})`)
  return box.id
}

/** Run `trials` pointer moves on a page already showing the sandbox; the mouse is released after. */
export async function measureGrabLatency(page: Page, trials: number): Promise<GrabLatency> {
  const id = await grabOneBox(page)
  const ms: number[] = []
  const frames: number[] = []
  let dx = 60
  for (let i = 0; i < trials; i++) {
    await page.evaluate('window.grabBench.waitForRest()')
    const at = (await page.evaluate('window.grabBench.box()')) as { x: number; y: number } | null
    if (!at) throw new Error(`body ${id} is gone from the page`)
    const rect = (await page.evaluate(
      `(() => { const r = window.concord.renderer.canvas.getBoundingClientRect(); return { x: r.left, y: r.top } })()`,
    )) as { x: number; y: number }
    await page.evaluate('window.grabBench.arm()')
    await page.mouse.move(rect.x + at.x + dx, rect.y + at.y)
    await page.waitForFunction('window.grabBench.result !== null', null, { timeout: 60_000 })
    const r = (await page.evaluate('window.grabBench.result')) as { ms: number; frames: number }
    ms.push(r.ms)
    frames.push(r.frames)
    dx = -dx
  }
  await page.mouse.up()
  return {
    trials,
    medianMs: median(ms),
    p95Ms: p95(ms),
    minMs: Math.min(...ms),
    maxMs: Math.max(...ms),
    medianFrames: median(frames),
    samplesMs: ms.map((v) => Math.round(v * 10) / 10),
  }
}
