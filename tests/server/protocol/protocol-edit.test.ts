/*
 * PROTOCOL.md's sandbox edit commands against a real server and WebSocket clients: a second
 * snapshot player sees every change through `events` (`change` replaces a body in place, a
 * duplicate comes in `add`, deleteMany in `remove` with its joints in `jremove`), matching the
 * server's world to the millimetre; a Node lockstep client and a predicting one, which apply the
 * same commands themselves, match every hash checkpoint (no desync).
 */
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { LockstepBot } from '../../../bots/lockstep-bot.ts'
import type { RunningServer } from '../../../server/server.ts'
import { type MirrorBody, quantizePosition } from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ ...inProcessRooms, defaultScene: 'empty', roomControls: true })
})
afterAll(async () => {
  await server.close()
})

/** Spawn a body and return its id (from the spawner's own events). */
async function spawn(bot: BotClient, c: Record<string, unknown>): Promise<number> {
  const seq = bot.command({ k: 'spawn', ...c } as never)
  await bot.waitFor(() => [...bot.mirror.bodies.values()].some((b) => b.seq === seq), `body of spawn ${seq}`)
  return [...bot.mirror.bodies.values()].find((b) => b.seq === seq)!.id
}

/** Send a game command and wait until `done` holds for the watcher (or fail with the error it got). */
async function edit(bot: BotClient, watcher: BotClient, kind: string, a: object, done: () => boolean) {
  const seq = bot.gameCommand(kind, a as Record<string, unknown>)
  await watcher.waitFor(() => done() || bot.mirror.errors.some((e) => e.seq === seq), `${kind} seen`)
  const error = bot.mirror.errors.find((e) => e.seq === seq)
  if (error) throw new Error(`${kind} refused: ${error.reason}`)
}

describe("PROTOCOL.md: the sandbox's edit commands", { timeout: 30_000 }, () => {
  it('a second player sees edit, transform, duplicate and deleteMany; lockstep and predict clients agree', async () => {
    const name = 'edits'
    const a = await BotClient.connect({ url: server.url, room: name, name: 'editor' })
    const b = await BotClient.connect({ url: server.url, room: name, name: 'watcher' })
    const lockstep = await LockstepBot.connect({ url: server.url, room: name, name: 'ls' })
    const predict = await LockstepBot.connect({ url: server.url, room: name, name: 'pr' }, 'predict')
    const world = () => server.rooms.get(name)!.world
    const seen = (id: number): MirrorBody | undefined => b.mirror.bodies.get(id)

    const box = await spawn(a, { shape: { type: 'box', hw: 0.5, hh: 0.25 }, x: 0, y: 0.25 })
    const ball = await spawn(a, { shape: { type: 'circle', radius: 0.3 }, x: 2, y: 0.3 })
    const ground = await spawn(a, { shape: { type: 'box', hw: 2, hh: 0.1 }, x: -5, y: 3, static: true })
    await b.waitFor(() => seen(ground) !== undefined, 'the spawns')

    // edit: colour, friction and static travel whole in events.change.
    await edit(a, b, 'edit', { body: box, friction: 0.2, color: 0x336699, static: true, layer: 2 }, () => {
      const m = seen(box)
      return m?.kind === 0 && m.color === 0x336699
    })
    expect(seen(box)!.shapes).toEqual([{ type: 'box', hw: 0.5, hh: 0.25, friction: 0.2, filter: [4, 5, 0] }])
    // transform of a static body (never in snapshots): its new pose comes in events.change.
    await edit(
      a,
      b,
      'transform',
      { body: ground, x: -6, y: 4, angle: 0.5, scale: 1.5 },
      () => seen(ground)?.x === -6,
    )
    expect(seen(ground)!.y).toBe(4)
    expect(seen(ground)!.angle).toBeCloseTo(0.5, 4)
    expect(seen(ground)!.shapes).toEqual([{ type: 'box', hw: 3, hh: 0.15000000000000002 }])
    expect(world().getShapeGeometry(world().bodyShapes(ground)[0]).box).toEqual({
      halfWidth: 3,
      halfHeight: 0.1 * 1.5,
    })
    // duplicate: a new body in events.add with the original's shapes and colour.
    const before = new Set(b.mirror.bodies.keys())
    await edit(a, b, 'duplicate', { body: ball, dx: 0, dy: 2 }, () => b.mirror.bodies.size > before.size)
    const copy = [...b.mirror.bodies.keys()].find((id) => !before.has(id))!
    expect(seen(copy)!.shapes).toEqual(seen(ball)!.shapes)
    expect(seen(copy)!.color).toBe(seen(ball)!.color)
    // A joint on the ball goes with it.
    a.command({ k: 'pin', a: 0, b: ball, x: 2, y: 0.3 })
    await b.waitFor(() => [...b.mirror.joints.values()].some((j) => j.b === ball), 'the pin')
    await edit(a, b, 'deleteMany', { bodies: [copy, ball] }, () => !seen(ball) && !seen(copy))
    expect([...b.mirror.joints.values()].some((j) => j.b === ball)).toBe(false)
    expect(world().hasBody(ball) || world().hasBody(copy)).toBe(false)
    // The box made dynamic again falls back into snapshots (it was static at y 0.25, on the ground).
    await edit(a, b, 'transform', { body: box, x: 0, y: 3, angle: 0 }, () => seen(box)?.y === 3)
    await edit(a, b, 'edit', { body: box, static: false }, () => seen(box)?.kind === 2)
    await b.waitFor(() => seen(box)!.y < 0.3, 'the box falls in snapshots')
    await b.waitFor(() => !world().isAwake(box) && seen(box)!.awake === false, 'the box at rest')
    // Every body the watcher has is where the server has it, to the millimetre.
    for (const m of b.mirror.bodies.values()) {
      const p = world().getPosition(m.id)
      expect(quantizePosition(m.x)).toBe(quantizePosition(p.x))
      expect(quantizePosition(m.y)).toBe(quantizePosition(p.y))
    }
    // The lockstep and predicting clients applied the same commands: every checkpoint matches.
    const checked = lockstep.runner.stats.hashesChecked
    await lockstep.waitFor(() => lockstep.runner.stats.hashesChecked >= checked + 2, 'two more checkpoints')
    await predict.waitFor(() => predict.runner.stats.hashesChecked >= 3, 'predict checkpoints')
    for (const c of [lockstep, predict]) {
      expect(c.runner.stats.desyncs, c.runner.lastProblem).toBe(0)
      expect(c.runner.stats.refused).toBe(0)
      expect(c.runner.sim!.world.getBodyType(box)).toBe('dynamic')
      expect(c.runner.sim!.world.hasBody(ball)).toBe(false)
    }
    expect(a.failure ?? b.failure).toBeNull()
    await Promise.all([a.close(), b.close(), lockstep.close(), predict.close()])
  })
})
