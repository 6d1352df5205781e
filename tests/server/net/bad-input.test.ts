import { encode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { PROTOCOL_VERSION } from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reads rooms' worlds.
  server = await startTestServer({ ...inProcessRooms, maxBodies: 40, maxRejects: 20, heartbeatMs: 60_000 })
})
afterAll(async () => {
  await server.close()
})

/** Frames no valid client sends, each built by hand or by an independent encoder. */
const GARBAGE: Array<[string, Uint8Array]> = [
  ['a reserved MessagePack byte', new Uint8Array([0xc1])],
  ['a truncated array', new Uint8Array([0x92, 0x01])],
  ['an array header claiming 4 billion items', new Uint8Array([0xdd, 0xff, 0xff, 0xff, 0xff, 0x01])],
  ['a string where a number belongs', encode({ t: 'ack', tick: 'soon' })],
  ['NaN coordinates', encode({ t: 'input', seq: 1, cmd: { k: 'move', x: Number.NaN, y: 0 } })],
  [
    'infinite velocity',
    encode({
      t: 'input',
      seq: 2,
      cmd: { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0, vx: Number.POSITIVE_INFINITY },
    }),
  ],
  [
    'a huge polygon array',
    encode({
      t: 'input',
      seq: 3,
      cmd: { k: 'spawn', shape: { type: 'polygon', v: new Array(500).fill(1) }, x: 0, y: 0 },
    }),
  ],
  ['an unknown message type', encode({ t: 'teleport' })],
  ['a __proto__ key', encode(JSON.parse('{"t":"ack","tick":1,"__proto__":{"polluted":true}}'))],
]

/** Wait until `bot` has received `n` more snapshots (the room keeps ticking). */
function snapshotsLater(bot: BotClient, n: number): Promise<void> {
  const start = bot.mirror.tick
  return bot.waitFor(() => bot.mirror.tick >= start + n * 2, `${n} more snapshots`)
}

function worldIsFinite(room: string): boolean {
  const world = server.rooms.get(room)!.world
  return world.bodyIds().every((id) => {
    const p = world.getPosition(id)
    return Number.isFinite(p.x) && Number.isFinite(p.y) && Number.isFinite(world.getAngle(id))
  })
}

describe('bad input', { timeout: 20_000 }, () => {
  it('malformed, mistyped, non-finite, oversized-array and unknown messages and text frames each get an error; the server and other rooms carry on', async () => {
    const bystander = await BotClient.connect({ url: server.url, room: 'calm', name: 'bystander' })
    const attacker = await BotClient.connect({ url: server.url, room: 'target', name: 'mallory' })
    attacker.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 2 })
    for (const [, bytes] of GARBAGE) attacker.ws.send(bytes)
    attacker.ws.send('{"t":"join"}')
    await attacker.waitFor(
      () => attacker.mirror.errors.length >= GARBAGE.length + 1,
      'an error per bad frame',
    )
    const codes = attacker.mirror.errors.map((e) => e.code)
    expect(codes).toContain('malformed')
    expect(codes).toContain('invalid')
    expect(codes).toContain('text-frame')
    expect(attacker.mirror.errors.some((e) => e.reason.includes('teleport'))).toBe(true)
    expect(({} as Record<string, unknown>).polluted).toBeUndefined()
    await snapshotsLater(bystander, 10)
    await snapshotsLater(attacker, 2)
    expect(worldIsFinite('target')).toBe(true)
    expect(server.rooms.get('target')!.world.bodyCount).toBe(2)
    const metrics = await server.metrics.registry.getSingleMetricAsString('concord_messages_rejected_total')
    expect(metrics).toContain('reason="text-frame"')
    await Promise.all([bystander.close(), attacker.close()])
  })

  it('a client that keeps sending garbage is disconnected with a reason', async () => {
    const attacker = await BotClient.connect({ url: server.url, room: 'target', name: 'mallory' })
    for (let i = 0; i < 30; i++) attacker.ws.send(new Uint8Array([0xc1]))
    await attacker.closed
    expect(attacker.closeCode).toBe(1008)
    expect(attacker.closeReason).toContain('too many invalid messages')
    const again = await BotClient.connect({ url: server.url, room: 'target', name: 'next' })
    await snapshotsLater(again, 2)
    await again.close()
  })

  it('an input flood is refused beyond the per-tick budget and the flooder is disconnected', async () => {
    const bystander = await BotClient.connect({ url: server.url, room: 'target', name: 'bystander' })
    const flooder = await BotClient.connect({ url: server.url, room: 'target', name: 'flood' })
    // A sustained flood: 50 inputs for every snapshot received, far over 8 per tick.
    flooder.onServerMessage = (m) => {
      if (m.t === 'snap') for (let i = 0; i < 50; i++) flooder.command({ k: 'release' })
    }
    flooder.command({ k: 'release' })
    await flooder.closed
    expect(flooder.closeCode).toBe(1008)
    expect(flooder.mirror.errors.some((e) => e.code === 'input-budget')).toBe(true)
    await snapshotsLater(bystander, 3)
    expect(worldIsFinite('target')).toBe(true)
    await bystander.close()
  })

  it('moves coalesce to the latest per tick, so a fast mouse never exceeds the budget', async () => {
    const mouse = await BotClient.connect({ url: server.url, room: 'target', name: 'mouse' })
    for (let i = 0; i <= 200; i++) mouse.command({ k: 'move', x: i / 10, y: 1 })
    const watcher = await BotClient.connect({ url: server.url, room: 'target', name: 'watch' })
    await watcher.waitFor(
      () => watcher.mirror.cursors.get(mouse.mirror.clientId)?.x === 20,
      'the last cursor position',
    )
    expect(mouse.mirror.errors).toEqual([])
    await Promise.all([mouse.close(), watcher.close()])
  })

  it('a short burst beyond the budget and its waiting room drops the excess but keeps the client', async () => {
    const bursty = await BotClient.connect({ url: server.url, room: 'target', name: 'bursty' })
    // 8 for this tick and 32 waiting for the next ticks are kept; the other 20 are refused.
    for (let i = 0; i < 60; i++) bursty.command({ k: 'release' })
    await snapshotsLater(bursty, 3)
    expect(bursty.mirror.errors.some((e) => e.code === 'input-budget')).toBe(true)
    expect(bursty.ws.readyState).toBe(bursty.ws.OPEN)
    await bursty.close()
  })

  it('a frame over the size limit closes the socket with 1009', async () => {
    const big = await BotClient.connect({ url: server.url, room: 'target', name: 'big' })
    big.ws.send(new Uint8Array(server.config.maxMessageBytes + 1))
    await big.closed
    expect(big.closeCode).toBe(1009)
  })

  it('a join with another protocol version gets an error naming both versions, then a close', async () => {
    const old = new BotClient({ url: server.url, room: 'target', name: 'old' })
    await old.opened
    old.join(PROTOCOL_VERSION + 41)
    await old.closed
    expect(old.closeCode).toBe(4004)
    const error = old.mirror.errors.find((e) => e.code === 'version')!
    expect(error.reason).toContain(String(PROTOCOL_VERSION + 41))
    expect(error.reason).toContain(`server ${PROTOCOL_VERSION}`)
  })

  it('spawns are clamped to the world bounds and refused beyond the room body limit', async () => {
    const bot = await BotClient.connect({ url: server.url, room: 'limits', name: 'builder' })
    bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 1e5, y: 3 })
    await bot.waitFor(() => [...bot.mirror.bodies.values()].some((b) => b.kind === 2))
    const far = [...bot.mirror.bodies.values()].find((b) => b.kind === 2)!
    expect(far.x).toBe(500)
    const room = server.rooms.get('limits')!
    for (let round = 0; round < 10; round++) {
      for (let i = 0; i < 5; i++)
        bot.command({ k: 'spawn', shape: { type: 'box', hw: 0.3, hh: 0.3 }, x: i, y: 5 + round })
      await snapshotsLater(bot, 1)
    }
    await bot.waitFor(
      () => bot.mirror.errors.some((e) => e.reason.includes('body limit')),
      'body limit refusal',
    )
    expect(room.world.bodyCount).toBe(server.config.maxBodies)
    await bot.close()
  })
})
