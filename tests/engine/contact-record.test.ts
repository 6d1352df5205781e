/*
 * Contacts keep their numbers in a shared record array (engine/dynamics/contact-record.ts). The oracle is
 * a plain object per contact holding what was written through the named properties: every
 * property must read back its own value (no two properties share a slot, no two contacts share a
 * record), also after the array has grown, and the narrowphase's writes must be what the
 * properties read.
 */
import { describe, expect, it } from 'vitest'
import { box } from '../../engine/collision/shapes.ts'
import { SPECULATIVE_DISTANCE } from '../../engine/constants.ts'
import { Body, DYNAMIC, updateMassData } from '../../engine/dynamics/body.ts'
import { BodyShape } from '../../engine/dynamics/body-shape.ts'
import { CONTACT_POINT_FIELDS, Contact, updateContact } from '../../engine/dynamics/contact.ts'
import { CONTACT_STRIDE, ContactStore } from '../../engine/dynamics/contact-record.ts'

const NAMES = [
  'friction',
  'restitution',
  'normalX',
  'normalY',
  ...CONTACT_POINT_FIELDS.map((f) => `${f}0`),
  ...CONTACT_POINT_FIELDS.map((f) => `${f}1`),
]

type Fields = Record<string, number>

/** The one shape of a fresh dynamic unit box with id `id` (shape id = body id). */
function bodyAt(id: number, x: number, y: number, angle: number): BodyShape {
  const b = new Body(id, DYNAMIC)
  const s = new BodyShape(id, b, box(0.5, 0.5))
  s.friction = 0.25 * id
  s.restitution = 0.1 * id
  b.shapes.push(s)
  updateMassData(b)
  b.x = x
  b.y = y
  b.c = Math.cos(angle)
  b.s = Math.sin(angle)
  b.updateCenter()
  return s
}

describe('contact records', () => {
  it('every named property of every contact reads back its own value, before and after the store grows', () => {
    const store = new ContactStore()
    const a = bodyAt(1, 0, 0, 0)
    const b = bodyAt(2, 1, 0, 0)
    const contacts: Contact[] = []
    const expected: Fields[] = []
    let value = 1
    const write = (c: Contact, oracle: Fields): void => {
      for (const name of NAMES) {
        ;(c as unknown as Fields)[name] = value
        oracle[name] = value
        value += 0.5
      }
    }
    // 64 records fit the initial array; 300 contacts make it grow three times.
    for (let k = 0; k < 300; k++) {
      const c = new Contact(a, b, store)
      const oracle: Fields = {}
      write(c, oracle)
      contacts.push(c)
      expected.push(oracle)
    }
    expect(store.data.length).toBeGreaterThanOrEqual(300 * CONTACT_STRIDE)
    for (let k = 0; k < contacts.length; k++) {
      for (const name of NAMES) {
        expect((contacts[k] as unknown as Fields)[name], `contact ${k} ${name}`).toBe(expected[k][name])
      }
    }
    // A pooled contact reset for a new pair clears its impulses and takes the new pair's material.
    const c = contacts[7].reset(a, bodyAt(3, 2, 0, 0))
    expect(c.friction).toBe(Math.sqrt(0.25 * 0.75))
    expect(c.restitution).toBe(0.30000000000000004)
    for (const name of ['normalImpulse0', 'tangentImpulse1', 'totalNormalImpulse0', 'totalTangentImpulse1']) {
      expect((c as unknown as Fields)[name], name).toBe(0)
    }
    expect(contacts[8].anchorAx0).toBe(expected[8].anchorAx0)
  })

  it('updateContact writes the manifold the properties read, and inherits impulses by feature id', () => {
    const store = new ContactStore()
    // Box B resting on box A, slightly overlapping: two points, normal straight up.
    const a = bodyAt(1, 0, 0, 0)
    const b = bodyAt(2, 0.1, 0.99, 0)
    const c = new Contact(a, b, store)
    expect(updateContact(c, SPECULATIVE_DISTANCE)).toBe(true)
    expect(c.pointCount).toBe(2)
    expect(c.normalX).toBeCloseTo(0, 12)
    expect(c.normalY).toBeCloseTo(1, 12)
    for (const j of [0, 1]) {
      const f = c as unknown as Fields
      expect(f[`separation${j}`]).toBeCloseTo(-0.01, 12)
      // Each point lies halfway between the surfaces (y = 0.495) and its anchors are the point
      // minus each body's centre.
      expect(f[`py${j}`]).toBeCloseTo(0.495, 12)
      expect(f[`anchorAx${j}`]).toBe(f[`px${j}`] - a.body.cx)
      expect(f[`anchorBy${j}`]).toBe(f[`py${j}`] - b.body.cy)
    }
    // The two points are B's bottom corners clipped to A's top face: x from -0.4 to 0.5.
    expect([c.px0, c.px1].sort((p, q) => p - q)).toEqual([expect.closeTo(-0.4, 12), expect.closeTo(0.5, 12)])
    c.normalImpulse0 = 3
    c.tangentImpulse0 = -1
    c.normalImpulse1 = 5
    c.tangentImpulse1 = 2
    const ids = [c.id0, c.id1]
    // The same features touch after a small move: each point keeps its own impulses.
    b.body.x += 0.001
    b.body.updateCenter()
    updateContact(c, SPECULATIVE_DISTANCE)
    expect([c.id0, c.id1]).toEqual(ids)
    expect([c.normalImpulse0, c.tangentImpulse0, c.normalImpulse1, c.tangentImpulse1]).toEqual([3, -1, 5, 2])
    // Apart beyond the speculative distance: no points, no normal.
    b.body.y += 1
    b.body.updateCenter()
    expect(updateContact(c, SPECULATIVE_DISTANCE)).toBe(false)
    expect([c.pointCount, c.normalX, c.normalY]).toEqual([0, 0, 0])
  })
})
