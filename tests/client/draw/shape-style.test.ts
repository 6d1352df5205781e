/*
 * How the renderer draws a shape (client/draw/renderer.ts shapeStyle), case by case from Box2D's
 * filter rule (two shapes touch when each one's category is in the other's mask, and never when
 * they share a negative group): a static or kinematic shape whose mask leaves out any category, or
 * whose group is negative, lets some bodies through and is a gate; a category alone excludes
 * nothing; sensors are sensors whatever their filter; moving bodies are drawn solid.
 */
import { describe, expect, it } from 'vitest'
import { shapeStyle } from '../../../client/draw/renderer.ts'
import type { WireShape } from '../../../shared/index.ts'

const box = (extra: Partial<WireShape> = {}): WireShape =>
  ({ type: 'box', hw: 1, hh: 1, ...extra }) as WireShape
const ALL = 0xffffffff

describe('shapeStyle', () => {
  it('static and kinematic shapes that let some bodies through are gates', () => {
    // The goal game's goal lines: category 8, colliding with discs (2) only.
    expect(shapeStyle(0, box({ filter: [8, 2, 0] }))).toBe('gate')
    expect(shapeStyle(1, box({ filter: [8, 2, 0] }))).toBe('gate')
    // Everything but one bit; nothing at all; a negative group (its members pass each other).
    expect(shapeStyle(0, box({ filter: [1, ALL - 1, 0] }))).toBe('gate')
    expect(shapeStyle(0, box({ filter: [1, 0, 0] }))).toBe('gate')
    expect(shapeStyle(0, box({ filter: [1, ALL, -3] }))).toBe('gate')
    // A sandbox layer (category 1 << 2, mask 1 + (1 << 2)) made static.
    expect(shapeStyle(0, box({ filter: [4, 5, 0] }))).toBe('gate')
    const segment: WireShape = { type: 'segment', v: [0, 0, 1, 0], filter: [1, 2, 0] }
    expect(shapeStyle(0, segment)).toBe('gate')
  })

  it('a default filter, a category alone or a positive group excludes nothing: solid', () => {
    expect(shapeStyle(0, box())).toBe('solid')
    expect(shapeStyle(0, box({ filter: [1, ALL, 0] }))).toBe('solid')
    expect(shapeStyle(0, box({ filter: [16, ALL, 0] }))).toBe('solid')
    expect(shapeStyle(0, box({ filter: [1, ALL, 5] }))).toBe('solid')
  })

  it('sensors are sensors, whatever their filter; dynamic bodies are solid, whatever theirs', () => {
    expect(shapeStyle(0, box({ sensor: true }))).toBe('sensor')
    expect(shapeStyle(0, box({ sensor: true, filter: [8, 2, 0] }))).toBe('sensor')
    expect(shapeStyle(2, box({ sensor: true }))).toBe('sensor')
    // The goal game's ball (category 4, mask walls | discs | ball = 7) and a disc.
    expect(shapeStyle(2, box({ filter: [4, 7, 0] }))).toBe('solid')
    expect(shapeStyle(2, box({ filter: [2, 15, -1] }))).toBe('solid')
  })
})
