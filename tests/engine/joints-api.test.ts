/*
 * The joint setters and getters of issue 28: each refuses a joint kind it does not apply to with
 * an error naming the joint and its kind, and the read-back of joints() carries what a renderer
 * needs for every kind (checked against the geometry the test built).
 */
import { describe, expect, it } from 'vitest'
import { box, createWorld } from '../../engine/index.ts'

function world3() {
  const world = createWorld({ gravity: { x: 0, y: 0 } })
  const a = world.createBody({ position: { x: 0, y: 0 }, shape: box(0.5, 0.5) })
  const b = world.createBody({ position: { x: 2, y: 0 }, shape: box(0.5, 0.5) })
  return { world, a, b }
}

describe('joint setters and getters', () => {
  it('refuse the kinds they do not apply to, naming the joint and its kind', () => {
    const { world, a, b } = world3()
    const weld = world.createJoint({ type: 'weld', bodyA: a, bodyB: b, anchor: { x: 1, y: 0 } })
    const motor = world.createJoint({ type: 'motor', bodyA: a, bodyB: b })
    expect(() => world.setJointMotorSpeed(weld, 1)).toThrow(
      `joint ${weld} is a weld joint, which has no motor`,
    )
    expect(() => world.setJointTarget(weld, 1)).toThrow(`joint ${weld} is a weld joint, which has no target`)
    expect(() => world.getJointTranslation(weld)).toThrow(
      `joint ${weld} is a weld joint, which has no translation`,
    )
    expect(() => world.getJointSpeed(motor)).toThrow(`joint ${motor} is a motor joint, which has no speed`)
    expect(() => world.setJointTarget(motor, 3)).toThrow(/motor joint's target must be a point/)
    expect(() => world.setJointTarget(motor, { x: Number.NaN, y: 0 })).toThrow(/target/)
    const rope = world.createJoint({
      type: 'distance',
      bodyA: a,
      bodyB: b,
      anchorA: { x: 0, y: 0 },
      anchorB: { x: 2, y: 0 },
    })
    expect(() => world.getJointAngle(rope)).toThrow(`joint ${rope} is a distance joint, which has no angle`)
    expect(() => world.setJointMotorSpeed(rope, Number.POSITIVE_INFINITY)).toThrow(/motorSpeed/)
  })

  it('joints() reports axis, limits, translation and angle for a renderer', () => {
    const { world, a, b } = world3()
    const slider = world.createJoint({
      type: 'prismatic',
      bodyA: a,
      bodyB: b,
      anchor: { x: 1, y: 0 },
      axis: { x: 3, y: 4 },
      enableLimit: true,
      lower: -1,
      upper: 2,
    })
    const wheel = world.createJoint({
      type: 'wheel',
      bodyA: a,
      bodyB: b,
      anchor: { x: 2, y: 0 },
      axis: { x: 0, y: 2 },
    })
    const pin = world.createJoint({
      type: 'revolute',
      bodyA: a,
      bodyB: b,
      anchor: { x: 1, y: 0 },
      enableLimit: true,
      lowerAngle: -0.5,
      upperAngle: 0.25,
    })
    // Move B 0.3 m along (0.6, 0.8) and turn it 0.1 rad: translation 0.3 on the slider, 0.24 on the wheel's (0, 1) axis.
    world.setTransform(b, { x: 2 + 0.18, y: 0.24 }, 0.1)
    const info = new Map(world.joints().map((j) => [j.id, j]))
    const s = info.get(slider)
    expect(s?.axis?.x).toBeCloseTo(0.6, 12)
    expect(s?.axis?.y).toBeCloseTo(0.8, 12)
    expect(s?.lower).toBe(-1)
    expect(s?.upper).toBe(2)
    // The anchors moved with B by its turn too: the translation is (anchorB - anchorA) . axis.
    const d = { x: (s?.anchorB.x ?? 0) - (s?.anchorA.x ?? 0), y: (s?.anchorB.y ?? 0) - (s?.anchorA.y ?? 0) }
    expect(s?.translation).toBeCloseTo(d.x * 0.6 + d.y * 0.8, 12)
    expect(world.getJointTranslation(slider)).toBe(s?.translation)
    expect(s?.angle).toBeCloseTo(0.1, 12)
    const w = info.get(wheel)
    expect(w?.translation).toBeCloseTo(0.24, 12)
    expect(w?.lower).toBeUndefined()
    const p = info.get(pin)
    expect(p?.lower).toBe(-0.5)
    expect(p?.upper).toBe(0.25)
    expect(p?.angle).toBeCloseTo(0.1, 12)
    expect(world.getJointAngle(pin)).toBeCloseTo(0.1, 12)
  })
})
