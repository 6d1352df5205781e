import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer

beforeAll(async () => {
  // Rooms on the main thread: this file reads rooms' worlds and players.
  server = await startTestServer(inProcessRooms)
})
afterAll(async () => {
  await server.close()
})

describe('two clients in one room', { timeout: 20_000 }, () => {
  it('both see a body spawned by one with the same id and shape, and a drag by one moves it for both', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'shared', name: 'ada' })
    const b = await BotClient.connect({ url: server.url, room: 'shared', name: 'bob' })
    expect(a.mirror.clientId).not.toBe(b.mirror.clientId)
    const before = new Set(a.mirror.bodies.keys())
    a.command({
      k: 'spawn',
      shape: { type: 'polygon', v: [-0.5, -0.4, 0.5, -0.4, 0.6, 0.3, 0, 0.7, -0.6, 0.3] },
      x: 0,
      y: 3,
    })
    const spawned = () => [...a.mirror.bodies.keys()].find((id) => !before.has(id))
    await a.waitFor(() => spawned() !== undefined, 'spawn on a')
    const id = spawned()!
    await b.waitFor(() => b.mirror.bodies.has(id), 'spawn on b')
    expect(b.mirror.bodies.get(id)!.shapes).toEqual(a.mirror.bodies.get(id)!.shapes)
    expect(a.mirror.bodies.get(id)!.shapes[0].type).toBe('polygon')
    // The server's own body is the independent reference for the shape.
    const world = server.rooms.get('shared')!.world
    expect(world.hasBody(id)).toBe(true)

    a.command({ k: 'grab', body: id, lx: 0, ly: 0 })
    a.command({ k: 'move', x: 6, y: 4 })
    await a.waitFor(() => a.mirror.bodies.get(id)!.x > 5, 'drag seen by a')
    await b.waitFor(() => b.mirror.bodies.get(id)!.x > 5, 'drag seen by b')
    await b.waitFor(() => b.mirror.cursors.get(a.mirror.clientId)?.body === id, 'cursor of a seen by b')
    // Several players can pull one body: each grab is that player's own mouse joint.
    b.command({ k: 'grab', body: id, lx: 0.2, ly: 0 })
    b.command({ k: 'move', x: 6, y: 8 })
    await a.waitFor(() => a.mirror.cursors.get(b.mirror.clientId)?.body === id, 'grab of b seen by a')
    expect(
      server.rooms
        .get('shared')!
        .world.joints()
        .filter((j) => j.type === 'mouse'),
    ).toHaveLength(2)
    a.command({ k: 'release' })
    await b.waitFor(() => b.mirror.cursors.get(a.mirror.clientId)?.body === 0, 'release seen by b')
    expect(
      server.rooms
        .get('shared')!
        .world.joints()
        .filter((j) => j.type === 'mouse'),
    ).toHaveLength(1)
    await Promise.all([a.close(), b.close()])
  })

  it('joints, deletes and room controls reach every client in the room', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'controls', name: 'ada' })
    const b = await BotClient.connect({ url: server.url, room: 'controls', name: 'bob' })
    a.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 5 })
    await b.waitFor(() => [...b.mirror.bodies.values()].some((x) => x.kind === 2))
    const id = [...b.mirror.bodies.values()].find((x) => x.kind === 2)!.id
    a.command({ k: 'pin', a: 0, b: id, x: 0, y: 5.5 })
    await b.waitFor(() => [...b.mirror.joints.values()].some((j) => j.kind === 'pin' && j.b === id), 'pin')
    a.command({ k: 'gravity', x: 0, y: -5 })
    a.command({ k: 'pause', paused: true })
    await b.waitFor(() => b.mirror.paused && b.mirror.gravity[1] === -5, 'room settings')
    a.command({ k: 'delete', body: id })
    await b.waitFor(() => !b.mirror.bodies.has(id) && b.mirror.joints.size === 0, 'delete with its joint')
    a.command({ k: 'scene', name: 'tower' })
    await b.waitFor(() => b.mirror.scene === 'tower' && b.mirror.bodies.size === 21, 'scene load')
    a.command({ k: 'scene', name: 'no-such-scene' })
    await a.waitFor(
      () => a.mirror.errors.some((e) => e.reason.includes('no-such-scene')),
      'unknown scene refused',
    )
    await Promise.all([a.close(), b.close()])
  })

  it('a client reconnecting with its token within the window keeps its id, and its grab was released', async () => {
    const a = await BotClient.connect({ url: server.url, room: 'again', name: 'ada' })
    const watcher = await BotClient.connect({ url: server.url, room: 'again', name: 'eve' })
    a.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 2 })
    await a.waitFor(() => [...a.mirror.bodies.values()].some((x) => x.kind === 2))
    const body = [...a.mirror.bodies.values()].find((x) => x.kind === 2)!.id
    a.command({ k: 'grab', body, lx: 0, ly: 0 })
    const room = server.rooms.get('again')!
    await watcher.waitFor(() => watcher.mirror.cursors.get(a.mirror.clientId)?.body === body)
    const { clientId, token } = a.mirror
    await a.close()
    await watcher.waitFor(() => !watcher.mirror.players.has(clientId), 'leave seen')
    expect(room.grabCounts.size).toBe(0)
    expect(room.world.joints().filter((j) => j.type === 'mouse')).toHaveLength(0)
    const back = await BotClient.connect({ url: server.url, room: 'again', name: 'ignored', token })
    expect(back.mirror.clientId).toBe(clientId)
    expect(back.mirror.players.get(clientId)?.name).toBe('ada')
    const stranger = await BotClient.connect({
      url: server.url,
      room: 'again',
      name: 'x',
      token: 'not-a-token',
    })
    expect(stranger.mirror.clientId).not.toBe(clientId)
    await Promise.all([back.close(), watcher.close(), stranger.close()])
  })
})
