/*
 * PROTOCOL.md's Lockstep and predict section against a real server, read by a client written from
 * the document alone (doc-client.ts: `ws` and @msgpack/msgpack, zlib from node:zlib, no shared/
 * code). A snapshot-mode actor issues every command kind, a third player joins and leaves, and the
 * lockstep client checks what the document promises: the messages it may and may not receive;
 * every field of `sync`, its SyncPayload (inflated when `z`) and `ticks` against the tables; the
 * stream's ticks contiguous from the sync's tick + 1 (also after a `resync`); every entry's tick
 * offset, kind and argument count against the kind table; a hash exactly on the checkpoints (every
 * 60 ticks) and runs of at most 2 ticks; and the hash definition itself: in a paused room the next
 * checkpoint's hash is FNV-1a (offset basis 0x811c9dc5, prime 0x01000193) over the sync's saved
 * world after its 16-byte header, the value the header's last u32 also holds.
 */
import { inflateSync } from 'node:zlib'
import { decode } from '@msgpack/msgpack'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'
import { type Decoded, DocClient } from './doc-client.ts'
import { documentedEntryKinds, documentedFields } from './doc-tables.ts'

/** FNV-1a, 32-bit, written here from its definition (not the engine's). */
function fnv1a32(bytes: Uint8Array): number {
  let h = 0x811c9dc5
  for (const b of bytes) h = Math.imul(h ^ b, 0x01000193) >>> 0
  return h
}

let server: RunningServer

beforeAll(async () => {
  server = await startTestServer({ roomControls: true })
})
afterAll(async () => {
  await server.close()
})

/** Every entry the lockstep client received, with its absolute tick. */
function entries(ls: DocClient): Array<{ tick: number; e: unknown[] }> {
  return ls
    .all('ticks')
    .flatMap((m) => (m.c as unknown[][]).map((e) => ({ tick: (m.tick as number) + (e[0] as number), e })))
}

const kindsSeen = (ls: DocClient): Set<number> => new Set(entries(ls).map((x) => x.e[2] as number))

describe('PROTOCOL.md, Lockstep and predict', { timeout: 90_000 }, () => {
  it('sync, ticks, the kind table, checkpoints and the hash definition hold on the wire', async () => {
    const doc = documentedFields()
    const kinds = documentedEntryKinds()
    // Kinds 0-14 are the sandbox's (all seen below); 15, a game command, is game-room.test.ts's.
    expect([...kinds.keys()]).toEqual([...Array(16).keys()])
    const checkFields = (section: string, value: Record<string, unknown>): void => {
      const documented = doc.get(section)
      expect(documented, `PROTOCOL.md section ${section}`).toBeDefined()
      const keys = Object.keys(value)
      for (const key of keys) expect(documented?.all, `${section}.${key} documented`).toContain(key)
      for (const key of documented?.all ?? [])
        if (!documented?.optional.includes(key)) expect(keys, `${section}.${key} present`).toContain(key)
    }

    const room = 'doc-lockstep'
    const actor = await BotClient.connect({ url: server.url, room, name: 'actor' })
    const ls = await DocClient.open(server.url, room)
    ls.send({ t: 'join', v: 3, room: '', name: 'ls', mode: 'lockstep' })
    await ls.waitFor((m) => m.t === 'sync', 'the first sync')

    // Every command kind, and a player joining and leaving.
    actor.command({ k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 2 })
    actor.command({
      k: 'spawn',
      shape: { type: 'circle', radius: 0.4 },
      x: 2,
      y: 2,
      angle: 0.3,
      vx: 1,
      vy: 0,
      w: 0.5,
    })
    await actor.waitFor(
      () => [...actor.mirror.bodies.values()].filter((b) => b.kind === 2).length === 2,
      'spawns',
    )
    const [a, b] = [...actor.mirror.bodies.values()].filter((x) => x.kind === 2).map((x) => x.id)
    actor.command({ k: 'grab', body: a, lx: 0, ly: 0 })
    actor.command({ k: 'move', x: 0.5, y: 3 })
    actor.command({ k: 'release' })
    const pa = actor.mirror.bodies.get(a)
    actor.command({ k: 'pin', a: 0, b: a, x: pa?.x ?? 0, y: pa?.y ?? 2 })
    const pb = actor.mirror.bodies.get(b)
    actor.command({ k: 'rope', a, b, ax: pa?.x ?? 0, ay: pa?.y ?? 2, bx: pb?.x ?? 2, by: pb?.y ?? 2 })
    await actor.waitFor(() => actor.mirror.joints.size === 2, 'the pin and the rope')
    actor.command({ k: 'unjoint', joint: Math.min(...actor.mirror.joints.keys()) })
    actor.command({ k: 'delete', body: b })
    actor.command({ k: 'gravity', x: 0, y: -9 })
    actor.command({ k: 'pause', paused: true })
    actor.command({ k: 'step' })
    actor.command({ k: 'pause', paused: false })
    actor.command({ k: 'reset' })
    const third = await BotClient.connect({ url: server.url, room, name: 'third' })
    await third.close()
    await until(() => kindsSeen(ls).has(13) && kindsSeen(ls).has(1), 'the reset and the leave in the stream')
    // The room's tick from the stream itself: the reset's entry, and the last tick covered so far.
    const resetAt = Math.max(
      ...entries(ls)
        .filter((x) => x.e[2] === 13)
        .map((x) => x.tick),
    )
    const covered = (): number =>
      Math.max(0, ...ls.all('ticks').map((m) => (m.tick as number) + (m.n as number) - 1))
    await until(() => covered() > resetAt + 12, 'the scene-load limit')
    actor.command({ k: 'scene', name: 'tower' })
    await until(() => kindsSeen(ls).size === 15, 'all 15 entry kinds of the sandbox', 30_000)

    // A paused room: the world does not change, so the next checkpoint's hash is the sync's world's.
    actor.command({ k: 'pause', paused: true })
    await until(() => entries(ls).some((x) => x.e[2] === 11 && x.e[3] === true && x.tick > resetAt), 'pause')
    const syncs = ls.all('sync').length
    ls.send({ t: 'resync' })
    const resynced = await ls.waitFor((m) => m.t === 'sync' && ls.all('sync').length > syncs, 'the resync')
    const sync2 = ls.all('sync')[syncs]
    expect(resynced.t).toBe('sync')
    const payloadOf = (m: Decoded): Record<string, unknown> =>
      decode(m.z ? inflateSync(m.data as Uint8Array) : (m.data as Uint8Array)) as Record<string, unknown>
    const checkpoint = Math.ceil(((sync2.tick as number) + 1) / 60) * 60
    const hashed = await ls.waitFor(
      (m) =>
        m.t === 'ticks' && m.hash !== undefined && (m.tick as number) + (m.n as number) - 1 === checkpoint,
      `the checkpoint at tick ${checkpoint}`,
    )
    const world = payloadOf(sync2).world as Uint8Array
    expect(new TextDecoder().decode(world.subarray(0, 4))).toBe('CNCW')
    const view = new DataView(world.buffer, world.byteOffset, world.byteLength)
    expect(view.getUint32(8, true)).toBe(world.length - 16)
    const expected = fnv1a32(world.subarray(16))
    expect(view.getUint32(12, true)).toBe(expected)
    expect(entries(ls).filter((x) => x.tick > (sync2.tick as number) && x.tick <= checkpoint)).toEqual([])
    expect(hashed.hash).toBe(expected)

    // What a lockstep player receives, and every field.
    const types = new Set(ls.messages.map((m) => m.t))
    for (const t of types) expect(['welcome', 'sync', 'ticks', 'players', 'pong', 'error']).toContain(t)
    expect(ls.messages[0].t).toBe('welcome')
    let next = -1
    let checkpoints = 0
    for (const m of ls.messages) {
      if (m.t === 'sync') {
        checkFields('sync', m)
        expect(typeof m.z).toBe('boolean')
        const payload = payloadOf(m)
        checkFields('SyncPayload', payload)
        expect(payload.tick).toBe(m.tick)
        expect(payload.world).toBeInstanceOf(Uint8Array)
        next = (m.tick as number) + 1
        continue
      }
      if (m.t !== 'ticks') continue
      checkFields('ticks', m)
      expect(next, 'ticks before any sync').toBeGreaterThan(0)
      expect(m.tick, 'the tick after the previous ticks or sync').toBe(next)
      const n = m.n as number
      expect(Number.isInteger(n) && n >= 1 && n <= 2, `n = ${n}`).toBe(true)
      const last = (m.tick as number) + n - 1
      next = last + 1
      expect(m.hash !== undefined, `hash present at ${last}`).toBe(last % 60 === 0)
      if (m.hash !== undefined) {
        checkpoints++
        expect(Number.isInteger(m.hash) && (m.hash as number) >= 0 && (m.hash as number) < 2 ** 32).toBe(true)
      }
      let previous = 0
      for (const e of m.c as unknown[][]) {
        const [offset, player, kind] = e as number[]
        expect(Number.isInteger(offset) && offset >= previous && offset < n, `entry offset ${offset}`).toBe(
          true,
        )
        previous = offset
        expect(Number.isInteger(player) && player > 0).toBe(true)
        const row = kinds.get(kind)
        expect(row, `kind ${kind} documented`).toBeDefined()
        const args = row?.args.length ?? 0
        expect(
          [3 + args, 3 + args + (row?.optional.length ?? 0)],
          `${row?.name} entry ${JSON.stringify(e)}`,
        ).toContain(e.length)
      }
    }
    expect(checkpoints).toBeGreaterThan(0)
    const spawns = entries(ls).filter((x) => x.e[2] === 2)
    expect(spawns[0].e.slice(3)).toEqual([{ type: 'box', hw: 0.5, hh: 0.5 }, 0, 2, null, null, null, null])
    expect(spawns[1].e.slice(4)).toEqual([2, 2, 0.3, 1, 0, 0.5])
    ls.end()
    await actor.close()
  })
})
