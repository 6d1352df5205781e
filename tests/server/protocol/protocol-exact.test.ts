/*
 * Three places where the server and PROTOCOL.md disagreed (issue 30, point 12; found by a client
 * written from the document alone): whole numbers of 2^32 and above left the server as float 64s,
 * a shape extent given as a string was refused with a range the document does not have, and a
 * server without tokens let `key=no-such-key` through where the Access table says 403. The
 * expected bytes are the MessagePack spec's int 64 layout written out by hand; the client is
 * doc-client.ts (`ws` and @msgpack/msgpack, no shared/ code).
 */
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import type { RunningServer } from '../../../server/server.ts'
import { rawRequest, upgradeRequest } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'
import { DocClient } from './doc-client.ts'

let server: RunningServer

beforeAll(async () => {
  const replayDir = await mkdtemp(join(tmpdir(), 'concord-exact-'))
  server = await startTestServer({ defaultScene: 'empty', replayDir })
})
afterAll(async () => {
  await server.close()
})

/** A str key (fixstr header 0xa0 + length) followed by the bytes of its value. */
const field = (key: string, value: number[]): Buffer =>
  Buffer.from([0xa0 + key.length, ...Buffer.from(key), ...value])

/** The frame received whose decoded message passes `check`. */
function frameOf(c: DocClient, check: (m: Record<string, unknown>) => boolean): Buffer {
  const i = c.messages.findIndex(check)
  expect(i, 'the message').toBeGreaterThanOrEqual(0)
  return Buffer.from(c.frames[i])
}

describe('PROTOCOL.md: integers are MessagePack integers whatever their size', { timeout: 30_000 }, () => {
  it('echoes a ping id of 2^53 - 1 and a time of -2^40 as int 64s, and an error.seq of 2^53 - 1 too', async () => {
    const c = await DocClient.joined(server.url, 'wide-ints', 'wide')
    c.send({ t: 'ping', id: 2 ** 53 - 1, time: -(2 ** 40) })
    c.send({ t: 'input', seq: 2 ** 53 - 1, cmd: { k: 'fly' } }) // invalid: answered with its seq
    c.send({ t: 'input', seq: 2 ** 32, cmd: { k: 'fly' } })
    await c.waitFor((m) => m.t === 'pong', 'the pong')
    await c.waitFor(() => c.all('error').length === 2, 'two errors')
    // int 64 is 0xd3 and eight big-endian bytes: 2^53 - 1 = 0x001fffffffffffff,
    // -2^40 = 0xffffff0000000000 (two's complement), 2^32 = 0x0000000100000000.
    const max = [0xd3, 0x00, 0x1f, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff]
    const pong = frameOf(c, (m) => m.t === 'pong')
    expect(pong.includes(field('id', max)), pong.toString('hex')).toBe(true)
    expect(pong.includes(field('time', [0xd3, 0xff, 0xff, 0xff, 0, 0, 0, 0, 0])), pong.toString('hex')).toBe(
      true,
    )
    const first = frameOf(c, (m) => m.t === 'error' && m.seq === 2 ** 53 - 1)
    expect(first.includes(field('seq', max)), first.toString('hex')).toBe(true)
    const second = frameOf(c, (m) => m.t === 'error' && m.seq === 2 ** 32)
    expect(second.includes(field('seq', [0xd3, 0, 0, 0, 0x01, 0, 0, 0, 0])), second.toString('hex')).toBe(
      true,
    )
    // No float 64 (0xcb) anywhere in the errors: every number in them is whole (the pong's tick
    // is fractional, a float by right).
    for (const frame of [first, second]) expect(frame.includes(0xcb), frame.toString('hex')).toBe(false)
    c.end()
  })
})

describe('PROTOCOL.md: shape extents', { timeout: 30_000 }, () => {
  it('refuses a radius, hw or hh that is a string or out of [0.05, 10] with the documented range', async () => {
    const c = await DocClient.joined(server.url, 'extents', 'extent')
    const shapes = [
      { type: 'circle', radius: '1' },
      { type: 'circle', radius: -1 },
      { type: 'circle', radius: 10.5 },
      { type: 'box', hw: '0.5', hh: 0.5 },
      { type: 'box', hw: 0.5, hh: 0.01 },
    ]
    shapes.forEach((shape, seq) => {
      c.send({ t: 'input', seq, cmd: { k: 'spawn', shape, x: 0, y: 5 } })
    })
    await c.waitFor(() => c.all('error').length === shapes.length, 'an error per shape')
    for (const e of c.all('error')) {
      expect(e.code).toBe('invalid')
      expect(e.reason).toMatch(/(circle radius|box hw|box hh) must be a finite number in \[0\.05, 10\]/)
    }
    c.end()
  })
})

describe('PROTOCOL.md Access: a key that matches no token', { timeout: 30_000 }, () => {
  it('is refused with 403 by a server with no token at all, at the upgrade and for the replays', async () => {
    const status = async (target: string): Promise<number> =>
      (await rawRequest(server.port, upgradeRequest(target))).status
    expect(await status('/ws?room=lobby&key=no-such-key')).toBe(403)
    expect(await status('/ws?key=no-such-key')).toBe(403)
    // An empty key is no key; without one every room is public.
    expect(await status('/ws?room=lobby&key=')).toBe(101)
    expect(await status('/ws?room=lobby')).toBe(101)
    const replays = await fetch(`${server.url}/replays?key=no-such-key`)
    expect(replays.status).toBe(403)
    expect(await replays.text()).toContain('matches no token')
    expect((await fetch(`${server.url}/replays`)).status).toBe(200)
  })
})
