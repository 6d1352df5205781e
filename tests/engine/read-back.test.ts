/*
 * The definition read-backs (getBodyDef, getShapeDef, getJointDef): a body or joint recreated from
 * its read-back in a second world reads back the same definition, bit for bit, though the first
 * world has stepped since its joints were made (exact rotations and joint frames), and the values
 * read back are the ones given (hand-set).
 */
import { describe, expect, it } from 'vitest'
import { box, buildScene, circle, createWorld, type JointDef, machinesScene } from '../../engine/index.ts'

describe('definition read-back', () => {
  it('recreates every body and joint of a stepped machines world exactly', () => {
    const world = createWorld()
    buildScene(world, machinesScene())
    for (let i = 0; i < 150; i++) world.step()
    const copy = createWorld()
    const ids = new Map<number, number>()
    for (const id of world.bodyIds()) ids.set(id, copy.createBody(world.getBodyDef(id)))
    const remap = (def: JointDef): JointDef => {
      if (def.type === 'mouse') return { ...def, body: ids.get(def.body) as number }
      return {
        ...def,
        bodyA: def.bodyA === null ? null : (ids.get(def.bodyA) as number),
        bodyB: ids.get(def.bodyB) as number,
      }
    }
    const jointIds = new Map<number, number>()
    for (const id of world.jointIds()) jointIds.set(id, copy.createJoint(remap(world.getJointDef(id))))
    for (const [a, b] of ids) {
      const original = world.getBodyDef(a)
      // Creating a joint wakes its bodies; everything else must match.
      expect({ ...copy.getBodyDef(b), awake: original.awake }).toEqual(original)
    }
    for (const [a, b] of jointIds) expect(copy.getJointDef(b)).toEqual(remap(world.getJointDef(a)))
  })

  it('reads back the values given, with the exact rotation and frames', () => {
    const world = createWorld()
    const a = world.createBody({
      position: { x: 1, y: 2 },
      angle: 0.25,
      shape: box(1, 0.5),
      density: 3,
      friction: 0.1,
    })
    const b = world.createBody({ position: { x: 3, y: 2 }, shape: circle(0.5), restitution: 0.5 })
    const j = world.createJoint({
      type: 'revolute',
      bodyA: a,
      bodyB: b,
      anchor: { x: 2, y: 2 },
      enableMotor: true,
      motorSpeed: 4,
      maxMotorTorque: 9,
    })
    const def = world.getBodyDef(a)
    expect(def.position).toEqual({ x: 1, y: 2 })
    expect(def.rotation).toEqual(world.getRotation(a))
    expect(def.shapes[0].density).toBe(3)
    expect(def.shapes[0].friction).toBe(0.1)
    expect(world.getShapeDef(world.bodyShapes(b)[0]).restitution).toBe(0.5)
    const jd = world.getJointDef(j)
    if (jd.type !== 'revolute') throw new Error('not a revolute joint')
    expect([jd.enableMotor, jd.motorSpeed, jd.maxMotorTorque]).toEqual([true, 4, 9])
    // The anchor (2, 2) in A's frame: rotate (1, 0) by -0.25 rad; in B's: (-1, 0).
    expect(jd.frames?.localAnchorA.x).toBeCloseTo(Math.cos(0.25), 12)
    expect(jd.frames?.localAnchorA.y).toBeCloseTo(-Math.sin(0.25), 12)
    expect(jd.frames?.localAnchorB).toEqual({ x: -1, y: 0 })
    expect(jd.frames?.referenceAngle).toBeCloseTo(-0.25, 12)
  })

  it('refuses a rotation that is not unit and a frames axis that is not unit, naming them', () => {
    const world = createWorld()
    expect(() => world.createBody({ rotation: { c: 1, s: 1 }, shape: box(1, 1) })).toThrow(
      /rotation must have length 1/,
    )
    const a = world.createBody({ shape: box(1, 1) })
    const frames = {
      localAnchorA: { x: 0, y: 0 },
      localAnchorB: { x: 0, y: 0 },
      referenceAngle: 0,
      localAxisA: { x: 2, y: 0 },
    }
    expect(() =>
      world.createJoint({
        type: 'prismatic',
        bodyA: null,
        bodyB: a,
        anchor: { x: 0, y: 0 },
        axis: { x: 1, y: 0 },
        frames,
      }),
    ).toThrow(/frames.localAxisA must be a unit vector/)
  })
})
