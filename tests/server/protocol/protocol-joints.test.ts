/*
 * PROTOCOL.md's sandbox joint commands against a real server and WebSocket clients: each command
 * makes the `Joint` the document describes (every field of the Joint table, values computed by
 * hand from the bodies' poses: the room is paused so the bodies stay where they were spawned),
 * every bad argument is refused naming the field, and `jointMotor` drives a motor for its maker
 * only, at the speed asked (measured from the snapshots' angles).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { WireJoint } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'
import { documentedFields } from './doc-tables.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'empty', roomControls: true })
})
afterAll(async () => {
  await server.close()
})

/** A Joint with every documented field at its "does not apply" value (0 or false). */
function blank(): Record<string, number | boolean | string> {
  const flags = new Set(['limit', 'motor', 'collide', 'spring'])
  const out: Record<string, number | boolean | string> = {}
  for (const f of documentedFields().get('Joint')!.all) out[f] = flags.has(f) ? false : 0
  return out
}

/** Spawn a body while paused and return its id (it stays exactly where it was spawned). */
async function spawn(bot: BotClient, shape: Record<string, unknown>, x: number, y: number): Promise<number> {
  const seq = bot.command({ k: 'spawn', shape: shape as never, x, y })
  await bot.waitFor(() => [...bot.mirror.bodies.values()].some((b) => b.seq === seq), `body of spawn ${seq}`)
  return [...bot.mirror.bodies.values()].find((b) => b.seq === seq)!.id
}

/** Send a joint command and wait for the joint it adds (or fail with the error it got). */
async function joint(bot: BotClient, kind: string, args: Record<string, unknown>): Promise<WireJoint> {
  const before = new Set(bot.mirror.joints.keys())
  const seq = bot.gameCommand(kind, args)
  await bot.waitFor(
    () =>
      [...bot.mirror.joints.keys()].some((id) => !before.has(id)) ||
      bot.mirror.errors.some((e) => e.seq === seq),
    `${kind} joint`,
  )
  const error = bot.mirror.errors.find((e) => e.seq === seq)
  if (error) throw new Error(`${kind} refused: ${error.code} ${error.reason}`)
  return [...bot.mirror.joints.values()].find((j) => !before.has(j.id))!
}

/** Send a command expected to be refused; resolve with its error. */
async function refusal(bot: BotClient, kind: string, args: Record<string, unknown>) {
  const seq = bot.gameCommand(kind, args)
  await bot.waitFor(() => bot.mirror.errors.some((e) => e.seq === seq), `the refusal of ${kind}`)
  return bot.mirror.errors.find((e) => e.seq === seq)!
}

describe("PROTOCOL.md: the sandbox's joint commands", { timeout: 30_000 }, () => {
  it('each command makes the Joint the table describes, every field from the paused bodies by hand', async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'jfields', name: 'maker' })
    expect(bot.mirror.rules!.commands).toEqual([
      'deleteMany',
      'duplicate',
      'edit',
      'editJoint',
      'explode',
      'hinge',
      'jointMotor',
      'lock',
      'redo',
      'slider',
      'slow',
      'spring',
      'transform',
      'undo',
      'weld',
      'wheel',
    ])
    bot.command({ k: 'pause', paused: true })
    await bot.waitFor(() => bot.mirror.paused, 'paused')
    const me = bot.mirror.clientId
    const box1 = await spawn(bot, { type: 'box', hw: 0.5, hh: 0.5 }, 0, 3)
    const box2 = await spawn(bot, { type: 'box', hw: 0.5, hh: 0.5 }, 2, 3)
    const wheel = await spawn(bot, { type: 'circle', radius: 0.4 }, 0.8, 2.3)

    const weld = await joint(bot, 'weld', {
      a: 0,
      b: box1,
      x: 0.5,
      y: 3,
      hz: 2,
      damping: 0.3,
      breakForce: 1000,
    })
    expect(weld).toEqual({
      ...blank(),
      ...{ id: weld.id, kind: 'weld', a: 0, b: box1, ax: 0.5, ay: 3, bx: 0.5, by: 0 },
      ...{ hz: 2, damping: 0.3, ahz: 2, adamping: 0.3, breakForce: 1000, owner: me },
    })
    const hinge = await joint(bot, 'hinge', {
      ...{ a: box1, b: box2, x: 1, y: 3, lower: -0.5, upper: 0.5, speed: 2, torque: 50, breakTorque: 70 },
    })
    expect(hinge).toEqual({
      ...blank(),
      ...{ id: hinge.id, kind: 'pin', a: box1, b: box2, ax: 1, ay: 0, bx: -1, by: 0 },
      ...{
        limit: true,
        lower: -0.5,
        upper: 0.5,
        motor: true,
        speed: 2,
        torque: 50,
        breakTorque: 70,
        owner: me,
      },
    })
    const spring = await joint(bot, 'spring', { a: box1, b: box2, ax: 0, ay: 3.5, bx: 2, by: 3.5, hz: 3 })
    expect(spring).toEqual({
      ...blank(),
      ...{ id: spring.id, kind: 'spring', a: box1, b: box2, ax: 0, ay: 0.5, bx: 0, by: 0.5 },
      ...{ length: 2, min: 2, max: 2, hz: 3, damping: 0.5, collide: true, owner: me },
    })
    const slider = await joint(bot, 'slider', {
      ...{ a: 0, b: box2, x: 2, y: 3, dx: 3, dy: 4, lower: -1, upper: 2, speed: 1, force: 100 },
    })
    // The axis (3, 4) / 5, normalized twice (by the command, then in body a's frame): to 1e-15.
    expect(slider.ux).toBeCloseTo(0.6, 15)
    expect(slider.uy).toBeCloseTo(0.8, 15)
    expect(slider).toEqual({
      ...blank(),
      ...{
        id: slider.id,
        kind: 'slider',
        a: 0,
        b: box2,
        ax: 2,
        ay: 3,
        bx: 0,
        by: 0,
        ux: slider.ux,
        uy: slider.uy,
      },
      ...{ limit: true, lower: -1, upper: 2, motor: true, speed: 1, force: 100, damping: 0.7, owner: me },
    })
    // The wheel: anchor at the wheel's centre, axis up, 4 Hz suspension by default.
    const axle = await joint(bot, 'wheel', { a: box1, b: wheel, speed: -3, torque: 20 })
    expect(axle.ax).toBeCloseTo(0.8, 12)
    expect(axle.ay).toBeCloseTo(-0.7, 12)
    expect(axle).toEqual({
      ...blank(),
      ...{
        id: axle.id,
        kind: 'wheel',
        a: box1,
        b: wheel,
        ax: axle.ax,
        ay: axle.ay,
        bx: 0,
        by: 0,
        ux: 0,
        uy: 1,
      },
      ...{ spring: true, hz: 4, damping: 0.7, motor: true, speed: -3, torque: 20, owner: me },
    })
    // A new wheel made by the command: a circle at (x, y) joined to the chassis at its centre.
    const made = await joint(bot, 'wheel', { a: box2, radius: 0.3, x: 2.5, y: 2.5, torque: 5 })
    const tyre = bot.mirror.bodies.get(made.b)!
    expect([tyre.kind, tyre.shapes, tyre.x, tyre.y]).toEqual([
      2,
      [{ type: 'circle', radius: 0.3, friction: 0.9 }],
      2.5,
      2.5,
    ])
    expect(made).toMatchObject({
      kind: 'wheel',
      a: box2,
      ax: 0.5,
      ay: -0.5,
      bx: 0,
      by: 0,
      motor: true,
      torque: 5,
    })
    // A late joiner's welcome lists them all, as made.
    const late = await BotClient.connect({ url: server.url, room: 'jfields', name: 'late' })
    expect([...late.mirror.joints.values()].map((j) => j.kind).sort()).toEqual([
      'pin',
      'slider',
      'spring',
      'weld',
      'wheel',
      'wheel',
    ])
    expect(late.mirror.joints.get(axle.id)).toEqual(axle)
    await Promise.all([bot.close(), late.close()])
  })

  it('refuses every bad argument naming the field, and bodies, anchors and axes that cannot hold a joint', async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'jrefuse', name: 'maker' })
    const other = await BotClient.connect({ url: server.url, room: 'jrefuse', name: 'other' })
    bot.command({ k: 'pause', paused: true })
    const box = await spawn(bot, { type: 'box', hw: 0.5, hh: 0.5 }, 0, 3)
    const ground = [...bot.mirror.bodies.values()].find((b) => b.kind === 0)!.id
    const point = { a: 0, b: box, x: 0, y: 3 }
    const cases: Array<[string, Record<string, unknown>, string, RegExp]> = [
      ['weld', { ...point, hz: 61 }, 'invalid', /^weld refused: hz must be <= 60/],
      ['weld', { ...point, damping: -1 }, 'invalid', /^weld refused: damping must be >= 0/],
      ['weld', { ...point, breakForce: 0 }, 'invalid', /^weld refused: breakForce must be > 0/],
      ['weld', { ...point, breakTorque: 2e9 }, 'invalid', /^weld refused: breakTorque must be <= 1000000000/],
      ['weld', { a: 0, b: box, x: 0 }, 'invalid', /^weld refused: y is required/],
      ['weld', { ...point, glue: 1 }, 'invalid', /^weld refused: glue is not allowed/],
      ['weld', { ...point, b: 0 }, 'invalid', /^weld refused: b must be >= 1/],
      ['weld', { ...point, a: box }, 'refused', /^a joint needs two different bodies$/],
      [
        'weld',
        { ...point, b: ground },
        'refused',
        new RegExp(`^body ${ground} does not exist or is static$`),
      ],
      [
        'weld',
        { ...point, x: 5 },
        'refused',
        /^weld anchor \(5\.00, 3\.00\) is 5\.00 m from body \d+; it must be within 1\.21 m$/,
      ],
      ['hinge', { ...point, upper: 4 }, 'invalid', /^hinge refused: upper must be <= 3\.14159/],
      [
        'hinge',
        { ...point, lower: 0.5, upper: -0.5 },
        'refused',
        /^hinge refused: lower \(0\.5\) must not be above upper \(-0\.5\)$/,
      ],
      ['hinge', { ...point, speed: 51 }, 'invalid', /^hinge refused: speed must be <= 50/],
      ['hinge', { ...point, torque: 0 }, 'invalid', /^hinge refused: torque must be > 0/],
      ['spring', { a: 0, b: box, ax: 0, ay: 5, bx: 0, by: 3 }, 'invalid', /^spring refused: hz is required/],
      [
        'spring',
        { a: 0, b: box, ax: 0, ay: 5, bx: 0, by: 3, hz: 0 },
        'invalid',
        /^spring refused: hz must be > 0/,
      ],
      [
        'spring',
        { a: 0, b: box, ax: 0, ay: 200, bx: 0, by: 3, hz: 1 },
        'refused',
        /^spring longer than 100 m$/,
      ],
      [
        'slider',
        { ...point, dx: 0, dy: 0 },
        'refused',
        /^slider refused: axis \(dx, dy\) = \(0, 0\) must not be zero$/,
      ],
      ['slider', { ...point, dx: 1, dy: 0, force: -1 }, 'invalid', /^slider refused: force must be > 0/],
      [
        'slider',
        { ...point, dx: 1, dy: 0, lower: -101 },
        'invalid',
        /^slider refused: lower must be >= -100/,
      ],
      ['wheel', { a: 0, b: ground }, 'refused', new RegExp(`^body ${ground} does not exist or is static$`)],
      ['wheel', { a: 0, b: box, hz: 100 }, 'invalid', /^wheel refused: hz must be <= 60/],
      ['wheel', { a: 0, b: 999 }, 'refused', /^body 999 does not exist or is static$/],
      ['wheel', { a: box }, 'refused', /^wheel refused: give b \(the wheel body\) or radius/],
      ['wheel', { a: 0, b: box, radius: 1, x: 0, y: 0 }, 'refused', /^wheel refused: give b .* not both$/],
      [
        'wheel',
        { a: box, radius: 0.4, x: 0 },
        'refused',
        /^wheel refused: a new wheel \(radius\) needs x and y$/,
      ],
      [
        'wheel',
        { a: box, radius: 0.4, x: 5, y: 3 },
        'refused',
        /^wheel anchor \(5\.00, 3\.00\) is 5\.00 m from body/,
      ],
      ['wheel', { a: box, radius: 11, x: 0, y: 3 }, 'invalid', /^wheel refused: radius must be <= 10/],
      ['jointMotor', { joint: 1, speed: 60 }, 'invalid', /^jointMotor refused: speed must be <= 50/],
      ['jointMotor', { joint: 999, speed: 1 }, 'refused', /^joint 999 is not a joint in this room$/],
    ]
    const bodies = bot.mirror.bodies.size
    for (const [kind, args, code, reason] of cases) {
      const e = await refusal(bot, kind, args)
      expect([kind, e.code, e.reason], JSON.stringify(args)).toEqual([
        kind,
        code,
        expect.stringMatching(reason),
      ])
    }
    expect(bot.mirror.joints.size).toBe(0)
    // A refused new wheel made no body either.
    expect(bot.mirror.bodies.size).toBe(bodies)
    // Motors: only the maker drives them, and only joints that have one.
    const hinge = await joint(bot, 'hinge', { ...point, torque: 10 })
    const weld = await joint(bot, 'weld', point)
    const theirs = await refusal(other, 'jointMotor', { joint: hinge.id, speed: 1 })
    expect(theirs).toMatchObject({
      code: 'refused',
      reason: `joint ${hinge.id} belongs to player ${bot.mirror.clientId}: only its maker may drive its motor`,
    })
    expect((await refusal(bot, 'jointMotor', { joint: weld.id, speed: 1 })).reason).toBe(
      `joint ${weld.id} has no motor`,
    )
    await Promise.all([bot.close(), other.close()])
  })

  it("jointMotor from the maker turns a hinge's motor at the speed asked (from the snapshots' angles)", async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'jmotor', name: 'driver' })
    const disc = await spawn(bot, { type: 'circle', radius: 0.5 }, 0, 5)
    // A hinge at the disc's centre: gravity exerts no torque, the motor alone turns it.
    const at = bot.mirror.bodies.get(disc)!
    const hinge = await joint(bot, 'hinge', { a: 0, b: disc, x: at.x, y: at.y, speed: 0, torque: 1000 })
    const seq = bot.gameCommand('jointMotor', { joint: hinge.id, speed: 4 })
    const angleAt = new Map<number, number>()
    const unwrapped = { last: Number.NaN, turns: 0 }
    const read = () => {
      const b = bot.mirror.bodies.get(disc)!
      if (angleAt.has(b.tick)) return
      if (!Number.isNaN(unwrapped.last) && b.angle < unwrapped.last - Math.PI) unwrapped.turns++
      unwrapped.last = b.angle
      angleAt.set(b.tick, b.angle + 2 * Math.PI * unwrapped.turns)
    }
    const start = bot.mirror.tick
    await bot.waitFor(() => {
      read()
      return bot.mirror.tick > start + 150
    }, '150 ticks of motor')
    expect(bot.mirror.errors.find((e) => e.seq === seq)).toBeUndefined()
    // The joint came again in events.jadd with the speed the motor now has.
    expect(bot.mirror.joints.get(hinge.id)!.speed).toBe(4)
    // After the first half second (the motor reaches its speed in a step: 1000 N m on 0.1 kg m^2),
    // the angle grows at 4 rad/s: the slope of the snapshot angles over a second.
    const ticks = [...angleAt.keys()].filter((t) => t > start + 30).sort((a, b) => a - b)
    const t0 = ticks[0]
    const t1 = ticks[ticks.length - 1]
    expect(t1 - t0).toBeGreaterThanOrEqual(60)
    const rate = (angleAt.get(t1)! - angleAt.get(t0)!) / ((t1 - t0) / 60)
    expect(rate).toBeGreaterThan(4 * 0.99)
    expect(rate).toBeLessThan(4 * 1.01)
    await bot.close()
  })

  it('editJoint changes a joint in place: it comes back in events.jadd with its id and the new settings; another player is refused', async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'jedit', name: 'maker' })
    const other = await BotClient.connect({ url: server.url, room: 'jedit', name: 'other' })
    bot.command({ k: 'pause', paused: true })
    await bot.waitFor(() => bot.mirror.paused, 'paused')
    const arm = await spawn(bot, { type: 'box', hw: 1, hh: 0.1 }, 1, 5)
    const hinge = await joint(bot, 'hinge', { a: 0, b: arm, x: 0, y: 5, speed: 1, torque: 2 })
    const seq = bot.gameCommand('editJoint', {
      joint: hinge.id,
      torque: 40,
      limit: true,
      lower: -0.2,
      upper: 0.6,
    })
    const changed = (m: BotClient) => m.mirror.joints.get(hinge.id)?.torque === 40
    await bot.waitFor(() => changed(bot) || bot.mirror.errors.some((e) => e.seq === seq), 'the edited joint')
    expect(bot.mirror.errors.find((e) => e.seq === seq)).toBeUndefined()
    await other.waitFor(() => changed(other), 'the edited joint at the other player')
    expect(other.mirror.joints.get(hinge.id)).toEqual({
      ...hinge,
      torque: 40,
      limit: true,
      lower: -0.2,
      upper: 0.6,
    })
    expect(await refusal(other, 'editJoint', { joint: hinge.id, torque: 1 })).toMatchObject({
      code: 'refused',
      reason: expect.stringContaining(
        `joint ${hinge.id} belongs to player ${bot.mirror.clientId}: only its maker may edit it`,
      ),
    })
    expect(await refusal(bot, 'editJoint', { joint: hinge.id, force: 1 })).toMatchObject({
      reason: expect.stringContaining('a pin joint has no force'),
    })
    expect(await refusal(bot, 'editJoint', { joint: hinge.id, torque: -1 })).toMatchObject({
      code: 'invalid',
    })
    expect(bot.mirror.joints.get(hinge.id)!.torque).toBe(40)
    await other.close()
    await bot.close()
  })
})
