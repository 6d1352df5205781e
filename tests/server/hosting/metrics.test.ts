/*
 * /metrics: bytes received equal the sum of the frames a raw client sent (counted here from the
 * encoded frames, not by the server), rejections are counted by reason, the loop tick histogram
 * counts one observation per clock tick, and a forced one-second stall of the clock drops
 * 60 - MAX_CATCH_UP ticks in every open room, counted per room.
 */
import { performance } from 'node:perf_hooks'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import WebSocket from 'ws'
import { MAX_CATCH_UP } from '../../../server/rooms/tick-clock.ts'
import type { RunningServer } from '../../../server/server.ts'
import { decodeServerMessage, encodeMessage, PROTOCOL_VERSION } from '../../../shared/index.ts'
import { inProcessRooms, startTestServer } from '../../support/test-server.ts'

let server: RunningServer
beforeAll(async () => {
  // Rooms on the main thread: this file drives the main tick clock by hand to drop ticks in its rooms.
  server = await startTestServer(inProcessRooms)
})
afterAll(async () => {
  await server.close()
})

async function scrape(): Promise<string> {
  return (await fetch(`${server.url}/metrics`)).text()
}

/** The value of one sample line, e.g. `concord_bytes_received_total` or `x{room="a"}`. */
function sample(text: string, name: string): number {
  const line = text.split('\n').find((l) => l.startsWith(`${name} `))
  if (!line) throw new Error(`no sample ${name} in /metrics`)
  return Number(line.slice(name.length + 1))
}

/** Dropped ticks counted for a room so far (0 before the first drop). */
function sampleOr0(text: string, room: string): number {
  const name = `concord_room_dropped_ticks_total{room="${room}"}`
  return text.includes(name) ? sample(text, name) : 0
}

describe('/metrics', { timeout: 60_000 }, () => {
  it('counts bytes received, rejections by reason, loop ticks and dropped ticks per room', async () => {
    const ws = new WebSocket(`${server.url.replace('http', 'ws')}/ws?room=m1`)
    const messages: Buffer[] = []
    ws.on('message', (data: Buffer) => messages.push(data))
    await new Promise((resolve, reject) => {
      ws.once('open', resolve)
      ws.once('error', reject)
    })
    let sent = 0
    const sendRaw = (bytes: Uint8Array | string): void => {
      sent += typeof bytes === 'string' ? Buffer.byteLength(bytes) : bytes.length
      ws.send(bytes)
    }
    sendRaw(encodeMessage({ t: 'join', v: PROTOCOL_VERSION, room: 'm1', name: 'meter', mode: 'snapshot' }))
    for (let i = 1; i <= 3; i++) sendRaw(encodeMessage({ t: 'ping', id: i, time: i * 1.5 }))
    sendRaw('a text frame is refused')
    const answered = (): number =>
      messages.filter((m) => {
        const d = decodeServerMessage(m)
        return d.ok && (d.value.t === 'pong' || (d.value.t === 'error' && d.value.code === 'text-frame'))
      }).length
    const deadline = Date.now() + 20_000
    while (answered() < 4) {
      if (Date.now() > deadline) throw new Error('no answers to the pings and the text frame')
      await new Promise((resolve) => setTimeout(resolve, 20))
    }
    let text = await scrape()
    expect(sample(text, 'concord_bytes_received_total')).toBe(sent)
    expect(sample(text, 'concord_messages_rejected_total{reason="text-frame"}')).toBe(1)
    expect(sample(text, 'concord_loop_tick_seconds_count{loop="main"}')).toBeGreaterThan(0)

    // A one-second stall, driven by hand: 60 ticks due, MAX_CATCH_UP run, the rest dropped in every room.
    const clock = server.rooms.clock
    clock.stop()
    const dropped0 = await scrape()
    const before = { lobby: sampleOr0(dropped0, 'lobby'), m1: sampleOr0(dropped0, 'm1') }
    const t0 = performance.now()
    clock.reset(t0)
    // 1,001 ms: (t0 + 1000) - t0 can round to 999.9999999 ms, 59 ticks (seen once in a CI run).
    expect(clock.pump(t0 + 1001)).toBe(MAX_CATCH_UP)
    text = await scrape()
    clock.start()
    const dropped = 60 - MAX_CATCH_UP
    expect(sampleOr0(text, 'm1') - before.m1).toBe(dropped)
    expect(sampleOr0(text, 'lobby') - before.lobby).toBe(dropped)
    ws.close()
  })
})
