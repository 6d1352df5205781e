import { describe, expect, it } from 'vitest'
import { ByteWriter } from '../../../shared/protocol/byte-io.ts'
import type { FullState, ServerMessage } from '../../../shared/protocol/messages.ts'
import { QuantizedFrame } from '../../../shared/protocol/quantized-frame.ts'
import { SnapshotEncoder } from '../../../shared/protocol/snapshot-encoder.ts'
import { ClientMirror } from '../../../shared/sim/client-mirror.ts'

const state: FullState = {
  tick: 10,
  scene: 'test',
  paused: false,
  gravity: [0, -10],
  slow: 1,
  creator: 0,
  locked: false,
  bodies: [
    { id: 1, kind: 0, shapes: [{ type: 'box', hw: 50, hh: 1 }], x: 0, y: -1000, a: 0, awake: 0 },
    { id: 2, kind: 2, shapes: [{ type: 'circle', radius: 0.5 }], x: 1000, y: 2000, a: 0, awake: 1 },
  ],
  joints: [],
}

function snapshot(encoder: SnapshotEncoder, tick: number, x: number, awake: boolean): ServerMessage {
  const frame = new QuantizedFrame()
  frame.put(2, x, 2000, 0, awake)
  const out = new ByteWriter()
  const base = encoder.referenceTick
  encoder.encode(out, frame, tick, 1e6)
  return { t: 'snap', tick, base, data: out.toBytes(), cursors: [] }
}

describe('client mirror', () => {
  it('shows a body that returned to its baseline pose after an unacknowledged move', () => {
    const mirror = new ClientMirror()
    mirror.handle({
      t: 'welcome',
      v: 2,
      id: 7,
      token: 't',
      room: 'r',
      rules: {
        tickRate: 60,
        snapshotRate: 30,
        maxBodies: 10,
        maxClients: 2,
        inputsPerTick: 8,
        controls: true,
        scenes: [],
        worldHalfExtent: 500,
        game: 'sandbox',
        commands: [],
        builtins: [],
        maxSpectators: 64,
      },
      players: [],
      state,
    })
    const encoder = new SnapshotEncoder()
    const frame = new QuantizedFrame()
    frame.put(2, 1000, 2000, 0, true)
    encoder.reset(frame, 10)
    expect(mirror.handle(snapshot(encoder, 12, 1500, true))).toEqual({ t: 'ack', tick: 12 })
    expect(mirror.bodies.get(2)!.x).toBe(1.5)
    // The ack is lost: the next snapshot is still against tick 10, where the body is back.
    mirror.handle(snapshot(encoder, 14, 1000, true))
    expect(mirror.bodies.get(2)!.x).toBe(1)
    mirror.handle(snapshot(encoder, 16, 1000, false))
    expect(mirror.bodies.get(2)!.awake).toBe(false)
  })

  it('drops removed bodies and their joints, and a state message starts a new world', () => {
    const mirror = new ClientMirror()
    mirror.handle({ t: 'state', state })
    mirror.handle({
      t: 'events',
      tick: 11,
      add: [],
      remove: [],
      jadd: [
        {
          ...{ id: 1, kind: 'pin', a: 0, b: 2, ax: 1, ay: 2, bx: 0, by: 0, length: 0, min: 0, max: 0 },
          ...{ hz: 0, damping: 0, ref: 0, limit: false, lower: 0, upper: 0 },
          ...{ motor: false, speed: 0, torque: 0, collide: false },
          ...{ force: 0, ux: 0, uy: 0, spring: false, target: 0, ahz: 0, adamping: 0, correction: 0 },
          ...{ breakForce: 0, breakTorque: 0, owner: 0 },
        },
      ],
      jremove: [],
    })
    expect(mirror.joints.size).toBe(1)
    mirror.handle({ t: 'events', tick: 12, add: [], remove: [2], jadd: [], jremove: [] })
    expect(mirror.bodies.has(2)).toBe(false)
    expect(mirror.joints.size).toBe(0)
    mirror.handle({ t: 'state', state: { ...state, tick: 20 } })
    expect(mirror.bodies.size).toBe(2)
    expect(mirror.history.get(10)).toBeUndefined()
    expect(mirror.history.get(20)!.has(2)).toBe(true)
  })

  it('keeps the latest contacts of the inspected body until it is removed or a new world starts', () => {
    const mirror = new ClientMirror()
    mirror.handle({ t: 'state', state })
    const contacts = (tick: number): ServerMessage => ({
      t: 'contacts',
      tick,
      body: 2,
      mass: 0.785,
      total: 1,
      contacts: [{ a: 1, b: 2, nx: 0, ny: 1, points: [{ x: 1, y: 1.5, n: 0.13, t: 0 }] }],
      inertia: 0.1,
      vx: 0,
      vy: 0,
      w: 0,
      joints: [],
    })
    mirror.handle(contacts(11))
    mirror.handle(contacts(12))
    expect(mirror.inspected?.tick).toBe(12)
    mirror.handle({ t: 'events', tick: 13, add: [], remove: [2], jadd: [], jremove: [] })
    expect(mirror.inspected).toBeNull()
    mirror.handle(contacts(14))
    mirror.handle({ t: 'state', state: { ...state, tick: 20 } })
    expect(mirror.inspected).toBeNull()
  })
})
