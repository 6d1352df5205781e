/*
 * A slack rope is drawn as a parabola sagging under its spare length, but never through the
 * ground: where the curve would pass below a level static box's top (with both anchors above it),
 * the drawn rope lies on that top (issue 31, fix 9).
 */
import { describe, expect, it } from 'vitest'
import { floorsOf, ropePath, ropeSag } from '../../../client/draw/joint-drawing.ts'
import type { ViewBody } from '../../../client/modes/index.ts'

const body = (kind: 0 | 2, x: number, y: number, hw: number, hh: number, angle = 0): ViewBody => ({
  id: 1,
  kind,
  shapes: [{ type: 'box', hw, hh }],
  color: null,
  x,
  y,
  angle,
  awake: true,
  grabColor: null,
})

const lowest = (path: number[]): number => Math.min(...path.filter((_, i) => i % 2 === 1))

describe('slack rope drawing', () => {
  it('sags by sqrt(3 d (L - d) / 8) in the open', () => {
    // Span 4 m, length 10 m: sag = sqrt(3 * 4 * 6 / 8) = 3 m, below anchors at y = 5.
    expect(ropeSag(4, 10)).toBe(3)
    const path = ropePath(-2, 5, 2, 5, 3, [])
    expect(lowest(path)).toBeCloseTo(2, 9)
    expect(path.slice(0, 2)).toEqual([-2, 5])
    expect(path.slice(-2)).toEqual([2, 5])
  })

  it('lies on the ground instead of passing under it', () => {
    // The sandbox ground: a static box 100 m wide whose top is y = 0; two boxes on it tied by a
    // 10 m rope at anchors 0.5 m up. Unclamped, the curve would reach 0.5 - 3 = -2.5 m.
    const floors = floorsOf([body(0, 0, -1, 50, 1), body(2, -2, 0.5, 0.5, 0.5)])
    expect(floors).toEqual([{ x0: -50, x1: 50, top: 0 }])
    const path = ropePath(-2, 0.5, 2, 0.5, ropeSag(4, 10), floors)
    expect(lowest(path)).toBe(0)
    // The ends stay at the anchors, and the middle of the rope is on the ground.
    expect(path.slice(0, 2)).toEqual([-2, 0.5])
    expect(path[path.length / 2]).toBe(0)
  })

  it('ignores floors above an anchor, beside the span, or tilted', () => {
    // A shelf at y = 2 above the lower anchor (y = 1) does not hold the rope up; nor does a
    // floor beside the span, nor a tilted ramp (its box top is not its surface).
    const floors = floorsOf([body(0, 0, 1.5, 5, 0.5), body(0, 20, -1, 5, 1), body(0, 0, -1, 5, 1, 0.3)])
    expect(floors).toHaveLength(2)
    const path = ropePath(-2, 1, 2, 3, ropeSag(Math.hypot(4, 2), 10), floors)
    expect(lowest(path)).toBeLessThan(-1)
  })
})
