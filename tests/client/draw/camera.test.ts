/*
 * The camera's mapping: world y up is screen y down, the two maps are inverses, zooming keeps the
 * point under the cursor fixed, and a pan moves the world with the pointer.
 */
import { describe, expect, it } from 'vitest'
import { Camera } from '../../../client/draw/camera.ts'

describe('Camera', () => {
  const camera = (): Camera => {
    const c = new Camera()
    c.resize(800, 600)
    c.x = 3
    c.y = 5
    c.scale = 40
    return c
  }

  it('draws y up: a point above the centre is higher on the screen', () => {
    const c = camera()
    expect(c.toScreen(3, 5)).toEqual({ x: 400, y: 300 })
    expect(c.toScreen(3, 6).y).toBe(260)
    expect(c.toScreen(4, 5).x).toBe(440)
  })

  it('maps screen to world and back exactly', () => {
    const c = camera()
    for (const [sx, sy] of [
      [0, 0],
      [123.5, 456.25],
      [800, 600],
    ]) {
      const w = c.toWorld(sx, sy)
      const s = c.toScreen(w.x, w.y)
      expect(s.x).toBeCloseTo(sx, 9)
      expect(s.y).toBeCloseTo(sy, 9)
    }
  })

  it('keeps the world point under the cursor fixed while zooming', () => {
    const c = camera()
    const before = c.toWorld(100, 500)
    c.zoomAt(100, 500, 2.5)
    const after = c.toWorld(100, 500)
    expect(c.scale).toBe(100)
    expect(after.x).toBeCloseTo(before.x, 9)
    expect(after.y).toBeCloseTo(before.y, 9)
  })

  it('pans so that the world follows the pointer', () => {
    const c = camera()
    const grabbed = c.toWorld(200, 200)
    c.pan(50, -30)
    const s = c.toScreen(grabbed.x, grabbed.y)
    expect(s.x).toBeCloseTo(250, 9)
    expect(s.y).toBeCloseTo(170, 9)
  })
})
