/*
 * PROTOCOL.md's "The sandbox's undo and redo" against a real server and two real WebSocket
 * clients in one paused room (bodies stay where they were spawned): each player's undo removes
 * only its own last action, redo brings it back as a new body with the same pose, shapes and
 * colour, refusals come back as `refused` with the documented reasons, and a delete's undo brings
 * the body back in `events.add`.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'empty', roomControls: true })
})
afterAll(async () => {
  await server.close()
})

/** Spawn a box at (x, y) and return its id once the mirror has it. */
async function spawn(bot: BotClient, x: number, y: number): Promise<number> {
  const seq = bot.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.3 }, x, y })
  await bot.waitFor(() => [...bot.mirror.bodies.values()].some((b) => b.seq === seq), `body of spawn ${seq}`)
  return [...bot.mirror.bodies.values()].find((b) => b.seq === seq)!.id
}

/** The mirror's body ids besides the ground, ascending. */
const ids = (bot: BotClient): number[] =>
  [...bot.mirror.bodies.values()]
    .filter((b) => b.kind !== 0)
    .map((b) => b.id)
    .sort((a, b) => a - b)

/** Send undo or redo; resolve with its refusal, or null once `done` holds. */
async function send(
  bot: BotClient,
  kind: 'undo' | 'redo',
  done: () => boolean,
): Promise<{ code: string; reason: string } | null> {
  const seq = bot.gameCommand(kind, {})
  await bot.waitFor(() => done() || bot.mirror.errors.some((e) => e.seq === seq), `${kind} ${seq}`)
  return bot.mirror.errors.find((e) => e.seq === seq) ?? null
}

describe("PROTOCOL.md: the sandbox's undo and redo", { timeout: 60_000 }, () => {
  it('each player undoes only its own actions; redo brings a body back as it was; refusals name the reason', async () => {
    const ada = await BotClient.connect({ url: server.url, room: 'undo2', name: 'ada' })
    const bob = await BotClient.connect({ url: server.url, room: 'undo2', name: 'bob' })
    ada.command({ k: 'pause', paused: true })
    await ada.waitFor(() => ada.mirror.paused, 'paused')
    const a1 = await spawn(ada, -3, 2)
    const b1 = await spawn(bob, 0, 2)
    const a2 = await spawn(ada, 3, 2)
    await bob.waitFor(() => ids(bob).length === 3, 'three bodies')

    // Ada's undo removes her last body (a2), not bob's later-or-earlier one.
    expect(await send(ada, 'undo', () => !bob.mirror.bodies.has(a2))).toBeNull()
    await ada.waitFor(() => !ada.mirror.bodies.has(a2), 'a2 gone for ada')
    expect(ids(bob)).toEqual([a1, b1])
    // Bob's undo removes his.
    expect(await send(bob, 'undo', () => !ada.mirror.bodies.has(b1))).toBeNull()
    await bob.waitFor(() => ids(bob).length === 1, 'b1 gone')
    expect(ids(ada)).toEqual([a1])
    expect(await send(bob, 'undo', () => false)).toEqual(
      expect.objectContaining({ code: 'refused', reason: 'nothing to undo' }),
    )

    // Ada redoes a2: a new id, the pose and colour it was spawned with, seen by bob.
    const before = new Set(ids(bob))
    expect(await send(ada, 'redo', () => ids(bob).length === 2)).toBeNull()
    const back = ids(bob).find((id) => !before.has(id))!
    expect(back).toBeGreaterThan(a2)
    const body = bob.mirror.bodies.get(back)!
    expect([body.x, body.y, body.angle]).toEqual([3, 2, 0])
    expect(body.shapes).toEqual([expect.objectContaining({ type: 'box', hw: 0.5, hh: 0.3 })])
    expect(body.color).toBe(ada.mirror.bodies.get(a1)!.color)

    // Bob deletes ada's redone body: her undo is refused naming him; his undo brings it back
    // (a new id), and then her undo removes that one.
    bob.command({ k: 'delete', body: back })
    await ada.waitFor(() => !ada.mirror.bodies.has(back), 'deleted by bob')
    expect(await send(ada, 'undo', () => false)).toEqual(
      expect.objectContaining({
        code: 'refused',
        reason: `cannot undo spawn: body ${back} was deleted by player ${bob.mirror.clientId}`,
      }),
    )
    expect(await send(bob, 'undo', () => ids(ada).length === 2)).toBeNull()
    const again = ids(ada).find((id) => id !== a1)!
    expect(again).toBeGreaterThan(back)
    expect([ada.mirror.bodies.get(again)!.x, ada.mirror.bodies.get(again)!.y]).toEqual([3, 2])
    expect(await send(ada, 'undo', () => !bob.mirror.bodies.has(again))).toBeNull()
    await ada.waitFor(() => ids(ada).length === 1, 'again gone')
    expect(ids(bob)).toEqual([a1])
    // Bob's redo (of his delete) finds the body gone: ada's undo removed it.
    expect(await send(bob, 'redo', () => false)).toEqual(
      expect.objectContaining({
        code: 'refused',
        reason: `cannot redo delete: body ${again} was removed by player ${ada.mirror.clientId}'s undo`,
      }),
    )
    // A new action of bob's empties his redo list.
    await spawn(bob, 5, 2)
    expect(await send(bob, 'redo', () => false)).toEqual(
      expect.objectContaining({ code: 'refused', reason: 'nothing to redo' }),
    )
    ada.close()
    bob.close()
  })
})
