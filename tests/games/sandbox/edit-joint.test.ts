/*
 * The sandbox's editJoint command (games/sandbox/joint-commands.ts; docs/games.md "Editing a
 * joint") in a RoomSimulation: the engine joint and the room's wire joint both carry the new
 * settings; a hinge's motor raised above the arm's gravity torque m g r lifts it (a hand
 * computation, not the solver's); every refusal in the document's order names the field and
 * changes nothing (same hash); undo restores the old settings (a rebuilt joint, new id) and redo
 * the new ones; a recorded session replays with the same hash every tick, also from a saved state.
 */
import { describe, expect, it } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { type Command, RoomSimulation, type SimCommand, type WireJoint } from '../../../shared/index.ts'
import { commandKinds, expectReplays, recordSession } from './recorded-session.ts'

const options = { game: sandbox, name: 'joints', scene: 'empty', maxBodies: 100, controls: true }

function room(): RoomSimulation {
  const sim = new RoomSimulation(options)
  sim.join(1, 'ada', '#e6194b')
  sim.join(2, 'bob', '#3cb44b')
  return sim
}

const cmd = (kind: string, a: Record<string, unknown>): SimCommand => ({ k: 'cmd', kind, a }) as SimCommand

function spawn(sim: RoomSimulation, c: Omit<Extract<Command, { k: 'spawn' }>, 'k'>, player = 1): number {
  const before = new Set(sim.world.bodyIds())
  expect(sim.apply(player, { k: 'spawn', ...c })).toBeNull()
  return sim.world.bodyIds().find((id) => !before.has(id)) as number
}

/** A 2 m x 0.2 m arm (density 1: 0.4 kg) hinged to the world at its left end, (0, 6), with a motor. */
function arm(sim: RoomSimulation, player = 1, torque = 1) {
  const b = spawn(sim, { shape: { type: 'box', hw: 1, hh: 0.1 }, x: 1, y: 6 }, player)
  expect(sim.apply(player, cmd('hinge', { a: 0, b, x: 0, y: 6, speed: 1, torque }))).toBeNull()
  const j = sim.world.jointIds()[sim.world.jointIds().length - 1]
  return { b, j }
}

const wire = (sim: RoomSimulation, j: number): WireJoint => sim.userJoints.get(j) as WireJoint

describe('editJoint', () => {
  it('changes the engine joint and the wire joint together; a motor raised above m g r lifts the arm', () => {
    const sim = room()
    const { b, j } = arm(sim)
    // m g r = 0.4 kg x 10 m/s^2 x 1 m = 4 N m: 1 N m cannot hold the arm up, it falls.
    for (let i = 0; i < 30; i++) sim.runTick()
    expect(sim.world.getJointAngle(j)).toBeLessThan(-0.05)
    expect(
      sim.apply(1, cmd('editJoint', { joint: j, torque: 6, limit: true, lower: -1, upper: 0.5 })),
    ).toBeNull()
    const def = sim.world.getJointDef(j)
    expect(
      def.type === 'revolute' && [def.maxMotorTorque, def.enableLimit, def.lowerAngle, def.upperAngle],
    ).toEqual([6, true, -1, 0.5])
    expect(wire(sim, j)).toMatchObject({
      kind: 'pin',
      torque: 6,
      limit: true,
      lower: -1,
      upper: 0.5,
      motor: true,
      speed: 1,
    })
    let top = Number.NEGATIVE_INFINITY
    for (let i = 0; i < 240; i++) {
      sim.runTick()
      top = Math.max(top, sim.world.getJointAngle(j))
    }
    // Lifted at 1 rad/s up to the upper limit, and held there.
    expect(sim.world.getJointAngle(j)).toBeGreaterThan(0.45)
    expect(top).toBeLessThan(0.52)
    expect(sim.world.hasBody(b)).toBe(true)
  })

  it('a spring: hz and length in place, the wire kind follows (hz 0 with min = max: a rod)', () => {
    const sim = room()
    const a = spawn(sim, { shape: { type: 'circle', radius: 0.3 }, x: 0, y: 5 })
    const b = spawn(sim, { shape: { type: 'circle', radius: 0.3 }, x: 2, y: 5 })
    expect(sim.apply(1, cmd('spring', { a, b, ax: 0, ay: 5, bx: 2, by: 5, hz: 2 }))).toBeNull()
    const j = sim.world.jointIds()[sim.world.jointIds().length - 1]
    expect(wire(sim, j).kind).toBe('spring')
    expect(sim.apply(1, cmd('editJoint', { joint: j, hz: 0, length: 1.5 }))).toBeNull()
    expect(wire(sim, j)).toMatchObject({ kind: 'rod', hz: 0, length: 1.5, min: 1.5, max: 1.5 })
    const def = sim.world.getJointDef(j)
    expect(def.type === 'distance' && [def.hertz, def.length, def.minLength, def.maxLength]).toEqual([
      0, 1.5, 1.5, 1.5,
    ])
    expect(sim.apply(1, cmd('editJoint', { joint: j, breakForce: 5 }))).toBeNull()
    expect(wire(sim, j).breakForce).toBe(5)
    expect(sim.apply(1, cmd('editJoint', { joint: j, breakForce: 0 }))).toBeNull()
    expect(wire(sim, j).breakForce).toBe(0)
    expect(sim.world.getJointDef(j).breakForce).toBeUndefined() // Infinity: never
  })

  it('refusals name what is wrong and change nothing', () => {
    const sim = room()
    const { j } = arm(sim)
    const other = arm(sim, 2)
    for (let i = 0; i < 5; i++) sim.runTick()
    const hash = sim.hash()
    const refusals: Array<[number, Record<string, unknown>, RegExp]> = [
      [1, { joint: 999, torque: 1 }, /joint 999 is not a joint in this room/],
      [
        1,
        { joint: other.j, torque: 1 },
        new RegExp(`joint ${other.j} belongs to player 2: only its maker may edit it`),
      ],
      [1, { joint: j }, /give at least one setting/],
      [
        1,
        { joint: j, force: 3 },
        /a pin joint has no force \(its settings: limit, lower, upper, motor, speed, torque/,
      ],
      [1, { joint: j, ahz: 3 }, /a pin joint has no ahz/],
      [1, { joint: j, lower: 4 }, /a pin's lower must be within \+-pi rad, got 4/],
      [1, { joint: j, lower: 0.5, upper: 0.2 }, /lower \(0.5\) must not be above upper \(0.2\)/],
      [1, { joint: j, upper: -0.5 }, /lower \(0\) must not be above upper \(-0.5\)/],
    ]
    for (const [player, a, reason] of refusals) {
      const got = sim.apply(player, cmd('editJoint', a))
      expect(got, JSON.stringify(a)).toMatch(reason)
      expect(sim.hash(), JSON.stringify(a)).toBe(hash)
    }
    // Bounds the schema checks (invalid, naming the field).
    for (const a of [
      { joint: j, torque: -1 },
      { joint: j, speed: 51 },
      { joint: j, hz: 61 },
      { joint: j, colour: 1 },
    ]) {
      const got = sim.apply(1, cmd('editJoint', a))
      expect(got, JSON.stringify(a)).toMatch(/torque|speed|hz|colour/)
    }
    expect(sim.hash()).toBe(hash)
  })

  it('undo restores the old settings (a rebuilt joint), redo the new ones', () => {
    const sim = room()
    const { j } = arm(sim)
    expect(
      sim.apply(1, cmd('editJoint', { joint: j, torque: 9, limit: true, lower: -0.3, upper: 0.3 })),
    ).toBeNull()
    expect(sim.apply(1, cmd('undo', {}))).toBeNull()
    expect(sim.world.hasJoint(j)).toBe(false)
    const undone = [...sim.userJoints.values()].find((w) => w.kind === 'pin') as WireJoint
    expect(undone).toMatchObject({ torque: 1, limit: false, motor: true, speed: 1, owner: 1 })
    const def = sim.world.getJointDef(undone.id)
    expect(def.type === 'revolute' && [def.maxMotorTorque, def.enableLimit]).toEqual([1, false])
    expect(sim.apply(1, cmd('redo', {}))).toBeNull()
    const redone = [...sim.userJoints.values()].find((w) => w.kind === 'pin') as WireJoint
    expect(redone).toMatchObject({ torque: 9, limit: true, lower: -0.3, upper: 0.3 })
    expect(sim.world.getJointDef(redone.id)).toMatchObject({ maxMotorTorque: 9, enableLimit: true })
  })

  it('a recorded session replays with the same hash every tick, also resumed from a saved state midway', () => {
    let j = 0
    const session = recordSession(options, 200, 50, (live, t) => {
      if (t === 0) j = arm(live).j
      if (t === 20)
        live.apply(1, cmd('editJoint', { joint: j, torque: 6, limit: true, lower: -0.6, upper: 0.4 }))
      if (t === 80) live.apply(1, cmd('editJoint', { joint: j, speed: -2, breakTorque: 1e4 }))
      if (t === 120) live.apply(1, cmd('undo', {}))
    })
    expect(commandKinds(session)).toEqual(['hinge', 'editJoint', 'editJoint', 'undo'])
    expectReplays(session)
  })
})
