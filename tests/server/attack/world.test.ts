/*
 * Legal commands that used to break a world (issue 11, item 4): pins and ropes anchored hundreds
 * of metres from their bodies acted through huge lever arms, flung bodies to kilometres and NaN,
 * and NaN reached clients in welcome.state, contacts and events. Against a real server: the far
 * anchors are refused with a reason naming the distance, and every number in every frame a client
 * receives, decoded by an independent MessagePack decoder, is finite.
 */
import { decode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { encodeMessage } from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reads a room's joints (sim.userJoints).
  server = await startTestServer({
    ...inProcessRooms,
    defaultScene: 'pyramid',
    inputsPerTick: 100,
    heartbeatMs: 60_000,
  })
})
afterAll(async () => {
  await server.close()
})

/** Every number inside a decoded value (bin payloads hold varints, not floats, and are skipped). */
function numbersIn(value: unknown, out: number[] = []): number[] {
  if (typeof value === 'number') out.push(value)
  else if (Array.isArray(value)) for (const v of value) numbersIn(v, out)
  else if (value !== null && typeof value === 'object' && !ArrayBuffer.isView(value))
    for (const v of Object.values(value)) numbersIn(v, out)
  return out
}

describe('pins and ropes anchored far from their bodies', { timeout: 30_000 }, () => {
  it('are refused with the distance named, and every number any client receives stays finite', async () => {
    const attacker = await BotClient.connect({ url: server.url, room: 'lever', name: 'archimedes' })
    const watcher = new BotClient({ url: server.url, room: 'lever', name: 'watcher' })
    watcher.keepFrames = true
    await watcher.opened
    watcher.join()
    await watcher.waitFor(() => watcher.mirror.clientId !== 0, 'the welcome')
    const movable = [...attacker.mirror.bodies.values()].filter((b) => b.kind === 2).map((b) => b.id)
    expect(movable.length).toBeGreaterThan(10)
    // The attack: lawful-looking pins and ropes whose anchors lie hundreds of metres away,
    // plus an inspect so contacts flow, repeated over many bodies.
    const seqs: number[] = []
    // Three pairs, nine commands: within the 10 error replies a client gets per heartbeat.
    for (let i = 0; i + 1 < movable.length && i < 6; i += 2) {
      const [a, b] = [movable[i], movable[i + 1]]
      seqs.push(attacker.command({ k: 'pin', a, b, x: 400, y: 400 }))
      seqs.push(attacker.command({ k: 'pin', a: 0, b, x: -450, y: 300 }))
      seqs.push(attacker.command({ k: 'rope', a, b, ax: 300, ay: 300, bx: 300, by: 380 }))
    }
    attacker.command({ k: 'inspect', body: movable[0] })
    await attacker.waitFor(
      () => seqs.every((s) => attacker.received.some((m) => m.t === 'error' && m.seq === s)),
      'a refusal for every far anchor',
    )
    for (const m of attacker.received) {
      if (m.t === 'error' && seqs.includes(m.seq ?? -1))
        expect(m.reason).toMatch(/m from body \d+; it must be within/)
    }
    const start = watcher.mirror.tick
    await watcher.waitFor(() => watcher.mirror.tick >= start + 120, '2 s of snapshots')
    // A late joiner's welcome.state after the attack.
    const late = new BotClient({ url: server.url, room: 'lever', name: 'late' })
    late.keepFrames = true
    await late.opened
    late.join()
    await late.waitFor(() => late.mirror.clientId !== 0, 'the late welcome')
    let numbers = 0
    for (const frame of [...watcher.frames, ...late.frames]) {
      for (const n of numbersIn(decode(frame))) {
        expect(Number.isFinite(n)).toBe(true)
        numbers++
      }
    }
    expect(numbers).toBeGreaterThan(1000)
    expect(server.rooms.get('lever')!.sim.userJoints.size).toBe(0)
    await Promise.all([attacker.close(), watcher.close(), late.close()])
  })
})

describe('the wire encoding', () => {
  it('writes a non-finite number as 0, whatever message carries it', () => {
    const ctl = { slow: 1, creator: 0, locked: false }
    const bytes = encodeMessage({
      t: 'room',
      tick: 5,
      paused: false,
      gravity: [Number.NaN, Number.NEGATIVE_INFINITY],
      scene: 'pile',
      ...ctl,
    })
    expect(decode(bytes)).toEqual({
      t: 'room',
      tick: 5,
      paused: false,
      gravity: [0, 0],
      scene: 'pile',
      ...ctl,
    })
    const plain = encodeMessage({
      t: 'room',
      tick: 5,
      paused: false,
      gravity: [0.5, -10],
      scene: 'pile',
      ...ctl,
    })
    expect(decode(plain)).toEqual({
      t: 'room',
      tick: 5,
      paused: false,
      gravity: [0.5, -10],
      scene: 'pile',
      ...ctl,
    })
  })
})
