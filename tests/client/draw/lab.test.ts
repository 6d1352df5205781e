/*
 * The lab's free-body diagram against the inclined-plane formula: a box of mass m resting on a
 * ramp of angle theta feels normal = m g cos(theta) and friction = m g sin(theta), and no net
 * force. Checked for both sources: the stepping world's contacts (offline) and the server's
 * `contacts` message, built by the server's own function and sent through the codec (online).
 */
import { describe, expect, it } from 'vitest'
import {
  arrowScale,
  computeFreeBody,
  describeFreeBody,
  labFromServer,
  labFromWorld,
} from '../../../client/draw/lab.ts'
import { buildScene, createWorld, rampScene, towerScene, type World } from '../../../engine/index.ts'
import { contactsMessage } from '../../../server/rooms/room-wire.ts'
import { type ContactsMessage, decodeServerMessage, encodeMessage } from '../../../shared/index.ts'

function restingRamp(degrees: number) {
  const theta = (degrees * Math.PI) / 180
  const world = createWorld()
  const [, ramp, box] = buildScene(world, rampScene(theta))
  for (let i = 0; i < 120; i++) world.step()
  return { world, ramp, box, theta }
}

/** What the server sends about `body` in `world`, after a trip through the codec. */
function serverLab(world: World, body: number) {
  const touching = world.contacts().filter((c) => c.bodyA === body || c.bodyB === body)
  const decoded = decodeServerMessage(encodeMessage(contactsMessage(world, world.tick, body, touching, [])))
  if (!decoded.ok) throw new Error(decoded.reason)
  return labFromServer(decoded.value as ContactsMessage, world.getGravity())
}

function expectInclinedPlane(fb: ReturnType<typeof computeFreeBody>, theta: number) {
  const mg = fb.mass * 10
  expect(fb.contacts).toHaveLength(1)
  expect(fb.contacts[0].normalN / (mg * Math.cos(theta))).toBeCloseTo(1, 1)
  expect(Math.abs(fb.contacts[0].normalN / (mg * Math.cos(theta)) - 1)).toBeLessThan(0.02)
  expect(Math.abs(fb.contacts[0].frictionN / (mg * Math.sin(theta)) - 1)).toBeLessThan(0.02)
  expect(Math.hypot(fb.net.x, fb.net.y)).toBeLessThan(0.02 * mg)
}

describe('free-body diagram', () => {
  for (const degrees of [10, 20, 30]) {
    it(`matches m g cos and m g sin on a ${degrees} degree ramp from the world's contacts`, () => {
      const { world, box, theta } = restingRamp(degrees)
      const fb = computeFreeBody(
        box,
        labFromWorld(world, box, world.contacts(), () => undefined),
      )
      expectInclinedPlane(fb, theta)
      // The normal force points away from the ramp, up its normal (-sin, cos).
      const n = fb.contacts[0].normal
      expect(n.x / Math.hypot(n.x, n.y)).toBeCloseTo(-Math.sin(theta), 2)
      // Friction points up the slope (cos, sin) to hold the box.
      const f = fb.contacts[0].friction
      expect(f.x / Math.hypot(f.x, f.y)).toBeCloseTo(Math.cos(theta), 2)
    })
  }

  it("matches the formula from the server's contacts message (the online lab)", () => {
    const { world, theta, box } = restingRamp(20)
    const fb = computeFreeBody(box, serverLab(world, box))
    expect(fb.source).toBe('server')
    expect(fb.mass).toBe(world.getMass(box))
    expectInclinedPlane(fb, theta)
    expect(describeFreeBody(box, fb)).toContain("source: the server's contact impulses")
  })

  it("carries the weight of the boxes above in a tower, from the world and from the server's message", () => {
    // A block with k blocks above it is pushed up by (k + 1) m g and down by k m g.
    const world = createWorld()
    const ids = buildScene(world, towerScene(8, false))
    for (let i = 0; i < 240; i++) world.step()
    const mg = 10
    for (const index of [1, 3, 6]) {
      const id = ids[index]
      const above = 8 - index
      const sources = [labFromWorld(world, id, world.contacts(), () => undefined), serverLab(world, id)]
      for (const data of sources) {
        const fb = computeFreeBody(id, data)
        const up = fb.contacts.filter((c) => c.normal.y > 0).reduce((sum, c) => sum + c.normalN, 0)
        const down = fb.contacts.filter((c) => c.normal.y < 0).reduce((sum, c) => sum + c.normalN, 0)
        expect(Math.abs(up / ((above + 1) * mg) - 1), `${data.source} under block ${index}`).toBeLessThan(
          0.05,
        )
        if (above > 0)
          expect(Math.abs(down / (above * mg) - 1), `${data.source} on block ${index}`).toBeLessThan(0.05)
      }
    }
  })
})

describe('free-body arrow sizes', () => {
  it('draws the weight 2 m long, or 100 px on screen when zoomed out, and the rest in proportion', () => {
    // The ramp scene's 1 kg box (10 N) at 25 px per metre, the zoom that frames the ramp at 1000 px:
    // 2 m would be 50 px; the weight is drawn 100 px = 4 m, the normal 9.4 N 3.76 m (94 px).
    const far = arrowScale(10, 25)
    expect(10 * far.unit * 25).toBeCloseTo(100, 9)
    expect(9.4 * far.unit * 25).toBeCloseTo(94, 9)
    expect(far.max).toBeCloseTo(12, 9)
    // Zoomed in (100 px per metre) the weight keeps its 2 m (200 px), whatever the body's mass.
    for (const weight of [0.5, 10, 400]) expect(weight * arrowScale(weight, 100).unit).toBeCloseTo(2, 9)
    expect(arrowScale(10, 100).max).toBe(6)
  })
})
