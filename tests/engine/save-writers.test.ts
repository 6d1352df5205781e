/*
 * The save writers (engine/world/world-state.ts) name every field instead of looping over the field
 * lists (for speed); the readers loop over the lists. Here each writer's bytes are compared with
 * an independent writer that loops over the lists, on objects whose every listed field holds a
 * distinct value, so a field left out, written twice or out of order changes the bytes.
 */
import { describe, expect, it } from 'vitest'
import { box } from '../../engine/collision/shapes.ts'
import { Body, DYNAMIC } from '../../engine/dynamics/body.ts'
import { BodyShape } from '../../engine/dynamics/body-shape.ts'
import { Contact } from '../../engine/dynamics/contact.ts'
import { ContactStore } from '../../engine/dynamics/contact-record.ts'
import { Joint } from '../../engine/joints/joint.ts'
import { ByteWriter } from '../../engine/world/save-format.ts'
import {
  BODY_MATERIAL_FIELDS,
  BODY_STATE_FIELDS,
  JOINT_EXTRA_FIELDS,
  JOINT_FIELDS,
  POINT_FIELDS,
  SHAPE_FIELDS,
  writeBody,
  writeBodyShape,
  writeContact,
  writeJoint,
} from '../../engine/world/world-state.ts'

type Fields = Record<string, number>

/** Give every listed field a value of its own: 1.5, 2.5, 3.5 ... */
function distinct(target: object, fields: readonly string[], start: number): number {
  let v = start
  for (const f of fields) (target as Fields)[f] = v++ + 0.5
  return v
}

const bytesOf = (write: (w: ByteWriter) => void): number[] => {
  const w = new ByteWriter()
  write(w)
  return [...w.bytes.subarray(0, w.length)]
}

function makeBodies(): [Body, Body] {
  const a = new Body(3, DYNAMIC)
  const b = new Body(7, DYNAMIC)
  return [a, b]
}

function makeShapes(): [BodyShape, BodyShape] {
  const [a, b] = makeBodies()
  return [new BodyShape(4, a, box(0.5, 0.25)), new BodyShape(9, b, box(1, 2))]
}

describe('save writers follow the field lists', () => {
  it('writeBody writes the material and state fields in list order', () => {
    const [body] = makeBodies()
    const next = distinct(body, BODY_MATERIAL_FIELDS, 0)
    distinct(body, BODY_STATE_FIELDS, next)
    body.enableSleep = true
    body.awake = true
    const fast = bytesOf((w) => writeBody(w, body))
    const oracle = bytesOf((w) => {
      w.f64(body.id)
      w.u8(body.type)
      for (const f of BODY_MATERIAL_FIELDS) w.f64(body[f])
      w.u8(2 | 8)
      for (const f of BODY_STATE_FIELDS) w.f64(body[f])
    })
    expect(fast).toEqual(oracle)
  })

  it('writeBodyShape writes the geometry, then the shape fields in list order, then the flags', () => {
    const [shape] = makeShapes()
    distinct(shape, SHAPE_FIELDS, 50)
    shape.sensor = true
    shape.enableHitEvents = true
    const fast = bytesOf((w) => writeBodyShape(w, shape))
    const oracle = bytesOf((w) => {
      w.f64(shape.id)
      // box shape: kind 1, half width, half height
      w.u8(1)
      w.f64(0.5)
      w.f64(0.25)
      for (const f of SHAPE_FIELDS) w.f64(shape[f])
      w.u8(1 | 2 | 4 | 8)
    })
    expect(fast).toEqual(oracle)
  })

  it('writeContact writes each point field in list order, for 0, 1 and 2 points', () => {
    const [a, b] = makeShapes()
    for (const points of [0, 1, 2]) {
      const c = new Contact(a, b, new ContactStore())
      const next = distinct(c, POINT_FIELDS[0], 100)
      distinct(c, POINT_FIELDS[1], next)
      c.normalX = 0.6
      c.normalY = -0.8
      c.touching = points > 0
      c.pointCount = points
      const fast = bytesOf((w) => writeContact(w, c))
      const oracle = bytesOf((w) => {
        w.f64(a.id)
        w.f64(b.id)
        w.u8(points > 0 ? 1 : 0)
        w.u8(points)
        w.f64(0.6)
        w.f64(-0.8)
        for (let j = 0; j < points; j++) for (const f of POINT_FIELDS[j]) w.f64((c as unknown as Fields)[f])
      })
      expect(fast, `${points} points`).toEqual(oracle)
    }
  })

  it('writeJoint writes the joint fields in list order', () => {
    const [a, b] = makeBodies()
    const j = new Joint(11, 1, a, b)
    distinct(j, JOINT_FIELDS, 200)
    j.enableMotor = true
    const fast = bytesOf((w) => writeJoint(w, j))
    const oracle = bytesOf((w) => {
      w.f64(11)
      w.u8(1)
      w.f64(a.id)
      w.f64(b.id)
      w.u8(2)
      for (const f of JOINT_FIELDS) w.f64(j[f])
    })
    expect(fast).toEqual(oracle)
  })

  it('writeJoint writes the format-2 fields (flag bit 3) in list order for a new kind', () => {
    const [a, b] = makeBodies()
    const j = new Joint(12, 4, a, b)
    const next = distinct(j, JOINT_FIELDS, 300)
    distinct(j, JOINT_EXTRA_FIELDS, next)
    j.enableSpring = true
    const fast = bytesOf((w) => writeJoint(w, j))
    const oracle = bytesOf((w) => {
      w.f64(12)
      w.u8(4)
      w.f64(a.id)
      w.f64(b.id)
      w.u8(8 | 16)
      for (const f of JOINT_FIELDS) w.f64(j[f])
      for (const f of JOINT_EXTRA_FIELDS) w.f64(j[f])
    })
    expect(fast).toEqual(oracle)
  })

  it('writeJoint leaves the format-2 fields out while every one is at its default (a format-1 joint)', () => {
    const [a, b] = makeBodies()
    const plain = new Joint(13, 0, a, b)
    const size = bytesOf((w) => writeJoint(w, plain)).length
    expect(size).toBe(8 + 1 + 8 + 8 + 1 + 8 * JOINT_FIELDS.length)
    for (const f of JOINT_EXTRA_FIELDS) {
      const j = new Joint(13, 0, a, b)
      ;(j as unknown as Record<string, number>)[f] = 0.25
      expect(bytesOf((w) => writeJoint(w, j)).length, f).toBe(size + 8 * JOINT_EXTRA_FIELDS.length)
    }
  })
})
