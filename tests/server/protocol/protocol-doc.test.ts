import { decode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { parseSnapshotData } from './doc-client.ts'
import { documentedFields } from './doc-tables.ts'

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ defaultScene: 'tower' })
})
afterAll(async () => {
  await server.close()
})

describe('PROTOCOL.md', () => {
  it('documents every field of every server message, checked with an independent MessagePack decoder', async () => {
    const doc = documentedFields()
    const bot = new BotClient({ url: server.url, room: 'doc', name: 'reader' })
    bot.keepFrames = true
    await bot.opened
    bot.join()
    await bot.waitFor(() => bot.mirror.clientId !== 0)
    const other = await BotClient.connect({ url: server.url, room: 'doc', name: 'other' })
    const spawnSeq = bot.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 3, y: 2 })
    await bot.waitFor(() => bot.mirror.bodies.size > 21)
    const box = [...bot.mirror.bodies.values()].find((b) => b.kind === 2 && b.x > 2)!
    // The tower's lowest block touches the ground and the block above: contacts with points.
    const lowest = [...bot.mirror.bodies.values()].filter((b) => b.kind === 2).sort((a, b) => a.y - b.y)[0]
    bot.command({ k: 'inspect', body: lowest.id })
    await bot.waitFor(() => bot.mirror.inspected !== null, 'contacts')
    bot.command({ k: 'pin', a: 0, b: box.id, x: 3, y: 2.5 })
    bot.command({ k: 'grab', body: box.id, lx: 0, ly: 0 })
    // The pinned and grabbed box: its contacts message lists a pin and a grab pulling on it.
    bot.command({ k: 'inspect', body: box.id })
    await bot.waitFor(
      () => bot.mirror.inspected?.body === box.id && bot.mirror.inspected.joints.length === 2,
      'pulls on the pinned, grabbed box',
    )
    bot.command({ k: 'pause', paused: true })
    const badSceneSeq = bot.command({ k: 'scene', name: 'does-not-exist' })
    bot.ping()
    const t0 = bot.mirror.tick
    await bot.waitFor(
      () => bot.mirror.lastHash !== null && bot.mirror.tick > t0 + 4 && bot.rtt >= 0,
      'hash and pong',
    )
    bot.command({ k: 'reset' })
    await bot.waitFor(() => bot.received.some((m) => m.t === 'state'))
    // A scene with every joint kind: its joints come in the state message (after the load limit).
    const reset = bot.mirror.tick
    await bot.waitFor(() => bot.mirror.tick > reset + 12, 'the scene-load limit')
    bot.command({ k: 'scene', name: 'joints' })
    await bot.waitFor(() => bot.mirror.scene === 'joints' && bot.mirror.joints.size === 3, 'the joints scene')

    const byType = new Map<string, Record<string, unknown>[]>()
    for (const frame of bot.frames) {
      const value = decode(frame) as Record<string, unknown>
      byType.set(value.t as string, [...(byType.get(value.t as string) ?? []), value])
    }
    const checkFields = (section: string, value: Record<string, unknown>): void => {
      const documented = doc.get(section)
      expect(documented, `PROTOCOL.md section ${section}`).toBeDefined()
      const keys = Object.keys(value).sort()
      for (const key of keys) expect(documented!.all, `${section}.${key} documented`).toContain(key)
      for (const key of documented!.all) {
        if (!documented!.optional.includes(key)) expect(keys, `${section}.${key} present`).toContain(key)
      }
    }
    for (const type of [
      'welcome',
      'state',
      'events',
      'room',
      'players',
      'snap',
      'pong',
      'hash',
      'error',
      'contacts',
    ]) {
      const messages = byType.get(type)
      expect(messages, `a ${type} message was received`).toBeDefined()
      for (const m of messages!) checkFields(type, m)
    }
    const welcome = byType.get('welcome')![0]
    checkFields('RoomRules', welcome.rules as Record<string, unknown>)
    const state = welcome.state as Record<string, unknown>
    checkFields('FullState', state)
    for (const b of state.bodies as Record<string, unknown>[]) checkFields('Body', b)
    for (const p of welcome.players as Record<string, unknown>[]) checkFields('Player', p)
    // events.add bodies are Bodies; the spawned box names its spawner and the spawn's seq.
    const adds = byType.get('events')!.flatMap((e) => e.add as Record<string, unknown>[])
    for (const b of adds) checkFields('Body', b)
    expect(adds.find((b) => b.id === box.id)).toMatchObject({ player: bot.mirror.clientId, seq: spawnSeq })
    // The refused scene load's error echoes its input's seq.
    expect(byType.get('error')!.some((e) => e.code === 'refused' && e.seq === badSceneSeq)).toBe(true)
    const joints = byType.get('events')!.flatMap((e) => e.jadd as Record<string, unknown>[])
    expect(joints.length).toBeGreaterThan(0)
    const sceneJoints = byType
      .get('state')!
      .flatMap((m) => (m.state as { joints: Record<string, unknown>[] }).joints)
    expect(sceneJoints.map((j) => j.kind).sort()).toEqual(['pin', 'pin', 'spring'])
    for (const j of [...joints, ...sceneJoints]) checkFields('Joint', j)
    const pulls = byType.get('contacts')!.flatMap((m) => m.joints as Record<string, unknown>[])
    expect(new Set(pulls.map((p) => p.kind))).toEqual(new Set(['pin', 'grab']))
    for (const p of pulls) checkFields('Pull', p)
    const contacts = byType.get('contacts')!.flatMap((m) => m.contacts as Record<string, unknown>[])
    expect(contacts.length).toBeGreaterThan(0)
    for (const c of contacts) {
      checkFields('Contact', c)
      for (const p of c.points as Record<string, unknown>[]) checkFields('ContactPoint', p)
    }
    // contacts follow this player's snapshot of the same tick.
    const order = bot.frames.map((f) => decode(f) as Record<string, unknown>)
    for (let i = 0; i < order.length; i++) {
      if (order[i].t !== 'contacts') continue
      expect(order[i - 1].t).toBe('snap')
      expect(order[i].tick).toBe(order[i - 1].tick)
    }
    // The snapshot payload parses with the documented layout, and absolute entries match the mirror.
    let entries = 0
    for (const snap of byType.get('snap')!) {
      const data = snap.data as Uint8Array
      expect(data).toBeInstanceOf(Uint8Array)
      for (const e of parseSnapshotData(data)) {
        entries++
        if (e.flags & 1) expect(e.a).toBeLessThan(65536)
      }
    }
    expect(entries).toBeGreaterThan(0)
    await Promise.all([bot.close(), other.close()])
  })
})
