/*
 * Slow motion and the creator's control lock in a sandbox room over real sockets (rooms on
 * worker threads, as `npm start` runs them). The rules (docs/games.md, the sandbox's `slow` and
 * `lock`): in slow motion N the world steps on room ticks that are multiples of N, so a lockstep
 * client, which simulates the room itself, must step on exactly those ticks: it agrees with every
 * server hash and its world's step count grows 1/N as fast as the room tick. The room's first
 * player is its creator; only it may lock the controls; while locked, anyone else's room control
 * is refused; snapshot players and late joiners see slow, creator and locked.
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import type { RunningServer } from '../../../server/server.ts'
import type { ErrorMessage, ServerMessage } from '../../../shared/index.ts'
import { startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'tower' })
})
afterAll(async () => {
  await server?.close()
})

async function errorFor(bot: BotClient, seq: number): Promise<ErrorMessage> {
  let found: ErrorMessage | undefined
  await bot.waitFor(() => {
    found = bot.received.find((m): m is ErrorMessage => m.t === 'error' && m.seq === seq)
    return found !== undefined
  }, `the error for seq ${seq}`)
  return found as ErrorMessage
}

describe('sandbox slow motion and control lock over real sockets', { timeout: 90_000 }, () => {
  it('a lockstep client steps on the same slowed ticks as the server and agrees with every hash', async () => {
    const creator = await BotClient.connect({ url: server.url, room: 'slow', name: 'c' })
    const follower = await LockstepBot.connect({ url: server.url, room: 'slow', name: 'f' })
    await follower.waitFor(() => follower.runner.sim !== null, 'the sync')
    const seq = creator.gameCommand('slow', { every: 4 })
    await creator.waitFor(() => creator.mirror.slow === 4, 'slow 4 in the room message')
    expect(creator.received.some((m) => m.t === 'error' && m.seq === seq)).toBe(false)
    await follower.waitFor(() => follower.runner.sim?.slowMotion === 4, 'slow 4 in the lockstep simulation')
    const sim = () => follower.runner.sim as NonNullable<typeof follower.runner.sim>
    const start = { tick: sim().tick, steps: sim().world.tick }
    const checked = follower.runner.stats.hashesChecked
    await follower.waitFor(() => follower.runner.stats.hashesChecked >= checked + 3, 'three checkpoints')
    const ticks = sim().tick - start.tick
    const steps = sim().world.tick - start.steps
    // Steps happen on room ticks that are multiples of 4: floor or ceil of a quarter of the ticks.
    expect(Math.abs(steps - ticks / 4)).toBeLessThanOrEqual(1)
    expect(ticks).toBeGreaterThanOrEqual(120)
    expect(follower.runner.stats.desyncs, follower.runner.lastProblem).toBe(0)
    // A late snapshot joiner's welcome carries the slow motion.
    const late = await BotClient.connect({ url: server.url, room: 'slow', name: 'l' })
    const welcome = late.received.find(
      (m): m is Extract<ServerMessage, { t: 'welcome' }> => m.t === 'welcome',
    )
    expect(welcome?.state.slow).toBe(4)
    expect(welcome?.state.creator).toBe(creator.mirror.clientId)
    await Promise.all([creator.close(), follower.close(), late.close()])
  })

  it("only the room's creator locks the controls; others' controls are refused while locked; its leave frees them", async () => {
    const creator = await BotClient.connect({ url: server.url, room: 'lock', name: 'c' })
    const other = await BotClient.connect({ url: server.url, room: 'lock', name: 'o' })
    const id = creator.mirror.clientId
    const notCreator = await errorFor(other, other.gameCommand('lock', { locked: true }))
    expect([notCreator.code, notCreator.reason]).toEqual([
      'refused',
      `only the room's creator (player ${id}) can lock the controls`,
    ])
    creator.gameCommand('lock', { locked: true })
    await other.waitFor(
      () => other.mirror.locked && other.mirror.creator === id,
      'the lock in the room message',
    )
    for (const seq of [
      other.command({ k: 'pause', paused: true }),
      other.gameCommand('slow', { every: 2 }),
      other.command({ k: 'reset' }),
    ]) {
      const e = await errorFor(other, seq)
      expect([e.code, e.reason]).toEqual([
        'refused',
        `room controls are locked by the room's creator (player ${id})`,
      ])
    }
    const bad = await errorFor(other, other.gameCommand('lock', { locked: 'yes' }))
    expect(bad.reason).toMatch(/^lock refused: .*locked/)
    const pause = creator.command({ k: 'pause', paused: true })
    await other.waitFor(() => other.mirror.paused, 'the creator pausing')
    expect(creator.received.some((m) => m.t === 'error' && m.seq === pause)).toBe(false)
    await creator.close()
    await other.waitFor(() => !other.mirror.locked, 'the lock freed by the creator leaving')
    const resume = other.command({ k: 'pause', paused: false })
    await other.waitFor(() => !other.mirror.paused, 'the other player resuming')
    expect(other.received.some((m) => m.t === 'error' && m.seq === resume)).toBe(false)
    await other.close()
  })
})
