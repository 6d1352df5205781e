import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { MAX_ANGLE_ERROR, MAX_POSITION_ERROR } from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // A large budget so every moving body is in every snapshot and each can be checked.
  // Rooms on the main thread: this file builds scenes in rooms' worlds directly.
  server = await startTestServer({ ...inProcessRooms, defaultScene: 'pile', clientBandwidth: 10_000_000 })
})
afterAll(async () => {
  await server.close()
})

type Pose = { x: number; y: number; angle: number }

/** Record the server's true poses after every tick (instrumenting the real room, not a mock). */
function recordServerPoses(roomName: string): Map<number, Map<number, Pose>> {
  const room = server.rooms.getOrCreate(roomName)!
  const history = new Map<number, Map<number, Pose>>()
  const runTick = room.runTick.bind(room)
  room.runTick = () => {
    runTick()
    const poses = new Map<number, Pose>()
    for (const id of room.world.bodyIds()) {
      const p = room.world.getPosition(id)
      poses.set(id, { x: p.x, y: p.y, angle: room.world.getAngle(id) })
    }
    history.set(room.tick, poses)
  }
  return history
}

function angleError(a: number, b: number): number {
  return Math.abs(Math.atan2(Math.sin(a - b), Math.cos(a - b)))
}

describe('snapshot reconstruction', { timeout: 20_000 }, () => {
  it('every snapshot reproduces the server poses within the quantization error, across deltas and lost snapshots', async () => {
    const truth = recordServerPoses('falling')
    const acking = await BotClient.connect({ url: server.url, room: 'falling', name: 'acks' })
    const lossy = await BotClient.connect({ url: server.url, room: 'falling', name: 'loses' })
    const silent = await BotClient.connect({
      url: server.url,
      room: 'falling',
      name: 'never acks',
      ack: false,
    })
    let checked = 0
    let worst = 0
    let worstAngle = 0
    const check = (bot: BotClient) => () => {
      const snap = bot.mirror.lastSnapshot
      if (!snap || snap.tick !== bot.mirror.tick) return
      const poses = truth.get(snap.tick)
      if (!poses) return
      for (const body of bot.mirror.bodies.values()) {
        if (body.kind === 0) continue
        const t = poses.get(body.id)!
        const e = Math.max(Math.abs(body.x - t.x), Math.abs(body.y - t.y))
        worst = Math.max(worst, e)
        worstAngle = Math.max(worstAngle, angleError(body.angle, t.angle))
        checked++
      }
    }
    for (const bot of [acking, lossy, silent]) bot.onServerMessage = check(bot)
    const startTick = acking.mirror.tick
    let snapshots = 0
    lossy.onServerMessage = (m) => {
      if (m.t === 'snap' && ++snapshots % 4 === 0) lossy.dropSnapshots = 1
      check(lossy)()
    }
    await acking.waitFor(() => acking.mirror.tick > startTick + 40, 'a second of snapshots')
    await lossy.waitFor(() => lossy.mirror.tick > startTick + 40, 'lossy client catching up')
    await silent.waitFor(() => silent.mirror.tick > startTick + 40, 'silent client')
    // Deltas were really used: the acking client's baseline moved past its welcome.
    const room = server.rooms.get('falling')!
    const session = [...room.players.values()].find((s) => s.id === acking.mirror.clientId)!
    expect(session.encoder.referenceTick).toBeGreaterThan(startTick)
    expect(checked).toBeGreaterThan(300 * 3 * 10)
    expect(worst).toBeGreaterThan(0)
    expect(worst).toBeLessThanOrEqual(MAX_POSITION_ERROR + 1e-9)
    expect(worstAngle).toBeLessThanOrEqual(MAX_ANGLE_ERROR + 1e-9)
    await Promise.all([acking.close(), lossy.close(), silent.close()])
  })
})
