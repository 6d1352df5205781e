/*
 * The room worker's outbox (server/workers/worker-outbox.ts): the sends of a tick packed into one buffer
 * (a broadcast copied once), the operations in the order the room produced them, and the buffer
 * handed over holding exactly the batch's bytes. Checked against the bytes handed in, byte for byte.
 */
import { MessageChannel } from 'node:worker_threads'
import { describe, expect, it } from 'vitest'
import { Outbox, WorkerConnection } from '../../../server/workers/worker-outbox.ts'
import type { FromWorker, FromWorkerOp } from '../../../server/workers/worker-protocol.ts'
import { decodeValue } from '../../../shared/index.ts'

const bytes = (n: number, seed: number): Uint8Array =>
  Uint8Array.from({ length: n }, (_, i) => (i * 31 + seed) & 255)

function batch(outbox: Outbox, ticks = 1): Extract<FromWorker, { t: 'batch' }> {
  const taken = outbox.take(ticks, true)
  if (taken?.message.t !== 'batch') throw new Error('no batch')
  return taken.message
}

describe('worker outbox', () => {
  it('packs a broadcast once, keeps the order of sends, closes and errors, and slices back the exact bytes', () => {
    const outbox = new Outbox()
    const a = new WorkerConnection(1, outbox)
    const b = new WorkerConnection(2, outbox)
    const shared = bytes(300, 1)
    const own = bytes(77, 2)
    a.sendBytes(shared)
    b.sendBytes(shared)
    b.sendBytes(own, 42)
    a.sendError('refused', 'no such body', 7)
    a.send({ t: 'pong', id: 3, time: 1.5, tick: 10.25 })
    b.close(4008, 'room lost')
    const message = batch(outbox, 9)
    expect(message.ticks).toBe(9)
    expect(message.ops.map((op) => [op.k, 'conn' in op ? op.conn : 0])).toEqual([
      ['send', 1],
      ['send', 2],
      ['send', 2],
      ['error', 1],
      ['send', 1],
      ['close', 2],
    ])
    const sends = message.ops.filter((op): op is Extract<FromWorkerOp, { k: 'send' }> => op.k === 'send')
    const view = new Uint8Array(message.buf)
    const slice = (op: (typeof sends)[number]): Uint8Array => view.subarray(op.at, op.at + op.len)
    // The broadcast is in the buffer once: both players' sends point at the same bytes.
    expect(sends[0].at).toBe(sends[1].at)
    expect(slice(sends[0])).toEqual(shared)
    expect(slice(sends[2])).toEqual(own)
    expect(sends.map((s) => s.snap)).toEqual([-1, -1, 42, -1])
    const pong = decodeValue(slice(sends[3]))
    expect(pong.ok && pong.value).toEqual({ t: 'pong', id: 3, time: 1.5, tick: 10.25 })
    expect(message.ops[3]).toEqual({ k: 'error', conn: 1, code: 'refused', reason: 'no such body', seq: 7 })
    expect(message.ops[5]).toEqual({ k: 'close', conn: 2, code: 4008, reason: 'room lost' })
  })

  it('posts nothing when empty unless asked; hands over exactly the filled bytes and keeps its own buffer', () => {
    const outbox = new Outbox()
    expect(outbox.take(1, false)).toBeNull()
    expect(batch(outbox).buf.byteLength).toBe(0)
    const conn = new WorkerConnection(5, outbox)
    const channel = new MessageChannel()
    try {
      for (let tick = 0; tick < 3; tick++) {
        const sent = [bytes(1000 + tick, tick), bytes(30, 10 + tick)]
        for (const b of sent) conn.sendBytes(b)
        const taken = outbox.take(tick, true)
        if (taken?.message.t !== 'batch') throw new Error('no batch')
        expect(taken.message.buf.byteLength).toBe(1030 + tick)
        expect(taken.transfer).toEqual([taken.message.buf])
        const view = new Uint8Array(taken.message.buf)
        expect(view.subarray(0, 1000 + tick)).toEqual(sent[0])
        expect(view.subarray(1000 + tick)).toEqual(sent[1])
        // Transferring detaches the handed-over buffer, never the outbox's own.
        channel.port1.postMessage(taken.message, taken.transfer)
        expect(taken.message.buf.byteLength).toBe(0)
      }
    } finally {
      channel.port1.close()
    }
  })

  it('copies a batch bigger than its buffer whole, and shrinks back to the size the next batches need', () => {
    const outbox = new Outbox()
    const conn = new WorkerConnection(5, outbox)
    const big = bytes(300_000, 3)
    conn.sendBytes(bytes(10, 2))
    conn.sendBytes(big)
    const first = batch(outbox)
    expect(first.buf.byteLength).toBe(300_010)
    expect(Buffer.compare(new Uint8Array(first.buf).subarray(10), big)).toBe(0)
    expect(outboxBufferBytes(outbox)).toBe(512 * 1024)
    conn.sendBytes(bytes(100_000, 4))
    expect(batch(outbox).buf.byteLength).toBe(100_000)
    expect(outboxBufferBytes(outbox)).toBe(128 * 1024)
    conn.sendBytes(bytes(10, 5))
    expect(batch(outbox).buf.byteLength).toBe(10)
    expect(outboxBufferBytes(outbox)).toBe(64 * 1024)
  })
})

/** The size of the outbox's own buffer (a private field, read for this test only). */
function outboxBufferBytes(outbox: Outbox): number {
  return (outbox as unknown as { buf: Uint8Array }).buf.length
}
