/*
 * The `inspect` command and the `contacts` message against a real server on 127.0.0.1 with real
 * WebSocket clients: the server's own contact impulses for a box resting on the ramp scene match
 * the inclined-plane formula (normal = m g cos(theta), friction = m g sin(theta)); the stream goes
 * only to the inspecting player and stops when it clears the choice, when the body is deleted
 * and when a new world is loaded. The oracle is the formula with the ramp scene's own geometry,
 * not the server's code. The cap on contacts per message is checked on a settled pile.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { buildScene, createWorld, pileScene, rampScene } from '../../../engine/index.ts'
import { contactsMessage } from '../../../server/rooms/room-wire.ts'
import type { RunningServer } from '../../../server/server.ts'
import {
  type ContactsMessage,
  encodeMessage,
  MAX_INSPECT_CONTACTS,
  type ServerMessage,
} from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reads a room's server-side players.
  server = await startTestServer({ ...inProcessRooms, defaultScene: 'ramp' })
})
afterAll(async () => {
  await server.close()
})

const isContacts = (m: ServerMessage): m is ContactsMessage => m.t === 'contacts'

/** The server's session for a bot (to read its inspection directly). */
function sessionOf(room: string, bot: BotClient) {
  return server.rooms.get(room)!.players.get(bot.mirror.clientId)!
}

/** Resolve once the server has received everything sent so far: a ping's pong comes back after it. */
async function flush(bot: BotClient): Promise<number> {
  const pongs = bot.received.filter((m) => m.t === 'pong').length
  bot.ping()
  await bot.waitFor(() => bot.received.filter((m) => m.t === 'pong').length > pongs, 'pong')
  const pong = bot.received.filter((m) => m.t === 'pong').at(-1)!
  return pong.t === 'pong' ? Math.ceil(pong.tick) : 0
}

describe('inspect and contacts', { timeout: 20_000 }, () => {
  it("streams the server's contact impulses of the box on the ramp: m g cos(theta) and m g sin(theta)", async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'ramp-lab', name: 'lab' })
    const blueprint = rampScene()
    const theta = blueprint.bodies[1].angle!
    expect(theta).toBeCloseTo((20 * Math.PI) / 180, 12)
    const box = [...bot.mirror.bodies.values()].find((b) => b.kind === 2)!
    const ramp = [...bot.mirror.bodies.values()].find((b) => b.kind === 0 && b.id !== 1)!
    bot.command({ k: 'inspect', body: box.id })
    // Let the box settle for a second of server ticks, then read the next message.
    const start = bot.mirror.tick
    await bot.waitFor(
      () => bot.mirror.inspected !== null && bot.mirror.inspected.tick > start + 60,
      'settled',
    )
    const message = bot.mirror.inspected!
    expect(message.body).toBe(box.id)
    // A 1 m x 1 m box at density 1 (the scene's default): m = 1 kg; g = 10 m/s^2.
    expect(message.mass).toBeCloseTo(1, 9)
    const mg = 1 * 10
    expect(message.total).toBe(1)
    expect(message.contacts).toHaveLength(1)
    const c = message.contacts[0]
    expect([c.a, c.b].sort()).toEqual([box.id, ramp.id].sort())
    const sign = c.b === box.id ? 1 : -1
    // The normal on the box points up the ramp's normal (-sin, cos).
    expect(sign * c.nx).toBeCloseTo(-Math.sin(theta), 6)
    expect(sign * c.ny).toBeCloseTo(Math.cos(theta), 6)
    const normal = sign * c.points.reduce((s, p) => s + p.n, 0) * 60
    const friction = sign * c.points.reduce((s, p) => s + p.t, 0) * 60
    console.log(
      `ramp (server): normal ${normal.toFixed(4)} N (m g cos = ${(mg * Math.cos(theta)).toFixed(4)}),` +
        ` friction ${Math.abs(friction).toFixed(4)} N (m g sin = ${(mg * Math.sin(theta)).toFixed(4)})`,
    )
    expect(Math.abs(normal / (mg * Math.cos(theta)) - 1)).toBeLessThan(0.02)
    expect(Math.abs(Math.abs(friction) / (mg * Math.sin(theta)) - 1)).toBeLessThan(0.02)
    // Friction holds the box: its force points up the slope (cos, sin), along -tangent or +tangent.
    const fx = friction * sign * c.ny
    expect(fx / Math.abs(friction)).toBeCloseTo(Math.cos(theta), 6)
    // Points lie on the ramp's top face (0.5 m from its centre line along the normal).
    for (const p of c.points) {
      const d = -(p.x - ramp.x) * Math.sin(theta) + (p.y - ramp.y) * Math.cos(theta)
      expect(Math.abs(d - 0.5)).toBeLessThan(0.01)
    }
    await bot.close()
  })

  it('goes to the inspecting player only, and stops on inspect 0, a delete and a scene load', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'ramp-life', name: 'ada' })
    const b = await BotClient.connect({ url: server.url, room: 'ramp-life', name: 'bob' })
    const box = [...a.mirror.bodies.values()].find((x) => x.kind === 2)!.id
    a.command({ k: 'inspect', body: box })
    await a.nextMessage(isContacts)
    // A static body (the ground) and a missing body are refused.
    a.command({ k: 'inspect', body: 1 })
    a.command({ k: 'inspect', body: 999 })
    await a.waitFor(
      () => a.mirror.errors.filter((e) => /does not exist or is static/.test(e.reason)).length === 2,
    )
    expect(sessionOf('ramp-life', a).inspect).toBe(box)

    // inspect 0 stops the stream from the next tick on.
    a.command({ k: 'inspect', body: 0 })
    const stopped = (await flush(a)) + 1
    await a.waitFor(() => a.mirror.tick > stopped + 10, 'snapshots after the stop')
    expect(a.received.filter((m) => isContacts(m) && m.tick > stopped)).toEqual([])
    expect(sessionOf('ramp-life', a).inspect).toBe(0)

    // Deleting the inspected body clears the inspection on the server and in the mirror.
    a.command({ k: 'inspect', body: box })
    await a.nextMessage(isContacts)
    b.command({ k: 'delete', body: box })
    await a.waitFor(() => !a.mirror.bodies.has(box), 'delete')
    expect(sessionOf('ramp-life', a).inspect).toBe(0)
    expect(a.mirror.inspected).toBeNull()
    const deleted = a.mirror.tick
    await a.waitFor(() => a.mirror.tick > deleted + 10, 'snapshots after the delete')
    expect(a.received.filter((m) => isContacts(m) && m.tick > deleted)).toEqual([])

    // A scene load starts a new world with none inspected, even when the same id exists again.
    a.command({ k: 'reset' })
    await a.waitFor(() => a.received.some((m) => m.t === 'state'), 'reset')
    const again = [...a.mirror.bodies.values()].find((x) => x.kind === 2)!.id
    a.command({ k: 'inspect', body: again })
    await a.nextMessage(isContacts)
    // Scene loads are limited to one per 10 ticks per room.
    const resetTick = a.received.filter((m) => m.t === 'state').at(-1)!
    await a.waitFor(() => resetTick.t === 'state' && a.mirror.tick > resetTick.state.tick + 12, 'load limit')
    a.command({ k: 'scene', name: 'ramp' })
    const states = a.received.filter((m) => m.t === 'state').length
    await a.waitFor(() => a.received.filter((m) => m.t === 'state').length > states, 'scene load')
    expect(sessionOf('ramp-life', a).inspect).toBe(0)
    expect(a.mirror.inspected).toBeNull()

    expect(b.received.some(isContacts)).toBe(false)
    await Promise.all([a.close(), b.close()])
  })

  it(`caps a message at ${MAX_INSPECT_CONTACTS} contacts, keeping the largest normal impulses`, () => {
    const world = createWorld()
    const ids = buildScene(world, pileScene(300))
    for (let i = 0; i < 240; i++) world.step()
    const all = world.contacts()
    const impulse = (c: (typeof all)[number]) => c.points.reduce((s, p) => s + p.normalImpulse, 0)
    // The body with the most contacts (the container's floor or a wall).
    const counts = new Map<number, number>()
    for (const c of all) for (const id of [c.bodyA, c.bodyB]) counts.set(id, (counts.get(id) ?? 0) + 1)
    const [busiest, count] = [...counts].sort((x, y) => y[1] - x[1])[0]
    expect(ids).toContain(busiest)
    expect(count).toBeGreaterThan(MAX_INSPECT_CONTACTS)
    const touching = all.filter((c) => c.bodyA === busiest || c.bodyB === busiest)
    const message = contactsMessage(world, world.tick, busiest, touching, [])
    expect(message.total).toBe(count)
    expect(message.contacts).toHaveLength(MAX_INSPECT_CONTACTS)
    const sent = message.contacts.map((c) => c.points.reduce((s, p) => s + p.n, 0))
    const kept = new Set(message.contacts.map((c) => `${c.a}-${c.b}`))
    const dropped = touching.filter((c) => !kept.has(`${c.bodyA}-${c.bodyB}`)).map(impulse)
    expect(Math.min(...sent)).toBeGreaterThanOrEqual(Math.max(...dropped))
    expect(encodeMessage(message).length).toBeLessThan(2500)
  })
})
