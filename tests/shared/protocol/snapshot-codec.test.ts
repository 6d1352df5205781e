import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { ByteReader, ByteWriter } from '../../../shared/protocol/byte-io.ts'
import { QuantizedFrame } from '../../../shared/protocol/quantized-frame.ts'
import { readUpdates } from '../../../shared/protocol/snapshot-codec.ts'
import { SnapshotEncoder } from '../../../shared/protocol/snapshot-encoder.ts'
import { SnapshotHistory } from '../../../shared/protocol/snapshot-history.ts'

type Pose = { x: number; y: number; a: number; awake: boolean }

function frameOf(poses: Map<number, Pose>): QuantizedFrame {
  const f = new QuantizedFrame(4)
  for (const id of [...poses.keys()].sort((p, q) => p - q)) {
    const p = poses.get(id)!
    f.put(id, p.x, p.y, p.a, p.awake)
  }
  return f
}

function expectFrameEquals(frame: QuantizedFrame, poses: Map<number, Pose>): void {
  expect(frame.count).toBe(poses.size)
  for (const [id, p] of poses) {
    expect(frame.has(id)).toBe(true)
    expect([frame.x[id], frame.y[id], frame.a[id]]).toEqual([p.x, p.y, p.a])
  }
}

describe('varints', () => {
  it('zigzag varints round-trip every safe integer magnitude', () => {
    fc.assert(
      fc.property(fc.array(fc.integer({ min: -(2 ** 40), max: 2 ** 40 })), (values) => {
        const w = new ByteWriter(2)
        for (const v of values) w.writeZigzag(v)
        const r = new ByteReader(w.toBytes())
        for (const v of values) expect(r.readZigzag()).toBe(v)
        expect(r.done).toBe(true)
      }),
    )
  })

  it('truncated input throws instead of reading garbage', () => {
    const w = new ByteWriter()
    w.writeVarint(300)
    expect(() => new ByteReader(w.toBytes().subarray(0, 1)).readVarint()).toThrow(RangeError)
  })
})

describe('snapshot delta compression', () => {
  it('a client reconstructs the server state exactly across deltas, lost snapshots and late acks', () => {
    fc.assert(
      fc.property(
        fc.array(
          fc.record({
            moves: fc.array(fc.tuple(fc.integer({ min: 1, max: 40 }), fc.integer({ min: -5000, max: 5000 }))),
            spawn: fc.boolean(),
            remove: fc.integer({ min: 0, max: 60 }),
            lost: fc.boolean(),
            ackLate: fc.boolean(),
          }),
          { maxLength: 40 },
        ),
        (steps) => {
          const poses = new Map<number, Pose>()
          for (let id = 1; id <= 20; id++) poses.set(id, { x: id * 1000, y: 0, a: id * 3000, awake: true })
          let nextId = 21
          const encoder = new SnapshotEncoder()
          const history = new SnapshotHistory()
          encoder.reset(frameOf(poses), 0)
          history.reset(frameOf(poses), 0)
          const lateAcks: number[] = []
          const out = new ByteWriter()
          let tick = 0
          for (const step of steps) {
            tick += 2
            for (const [id, d] of step.moves) {
              const p = poses.get(id)
              if (p)
                poses.set(id, { x: p.x + d, y: p.y - d, a: (p.a + d + 65536) % 65536, awake: d % 3 !== 0 })
            }
            if (step.spawn) poses.set(nextId++, { x: -7, y: 9, a: 65535, awake: true })
            if (poses.has(step.remove)) {
              poses.delete(step.remove)
              encoder.removeBody(step.remove)
              history.removeBody(step.remove)
            }
            out.reset()
            encoder.encode(out, frameOf(poses), tick, 1e9)
            if (step.lost) continue
            const applied = history.apply(tick, encoder.referenceTick, out.toBytes())
            expect(applied).not.toBeNull()
            expectFrameEquals(applied!.frame, poses)
            if (step.ackLate) lateAcks.push(tick)
            else encoder.ack(tick)
            if (lateAcks.length > 2) encoder.ack(lateAcks.shift()!)
          }
        },
      ),
    )
  })

  it('unchanged and resting bodies cost nothing once acknowledged', () => {
    const poses = new Map<number, Pose>()
    for (let id = 1; id <= 500; id++) poses.set(id, { x: id, y: id, a: id, awake: false })
    const encoder = new SnapshotEncoder()
    encoder.reset(frameOf(poses), 0)
    const out = new ByteWriter()
    encoder.encode(out, frameOf(poses), 2, 1e9)
    expect(out.toBytes()).toEqual(new Uint8Array([0]))
  })

  it('a moving 2D body costs under 8 bytes per snapshot', () => {
    const poses = new Map<number, Pose>([[1, { x: 0, y: 10000, a: 0, awake: true }]])
    const encoder = new SnapshotEncoder()
    const history = new SnapshotHistory()
    encoder.reset(frameOf(poses), 0)
    history.reset(frameOf(poses), 0)
    const out = new ByteWriter()
    for (let tick = 2; tick < 60; tick += 2) {
      poses.set(1, { x: tick * 40, y: 10000 - tick * 90, a: tick * 50, awake: true })
      out.reset()
      encoder.encode(out, frameOf(poses), tick, 1e9)
      expect(out.length - 1).toBeLessThan(8)
      history.apply(tick, encoder.referenceTick, out.toBytes())
      encoder.ack(tick)
    }
  })

  it('a byte budget sends the highest-priority bodies first and still refreshes every body', () => {
    const poses = new Map<number, Pose>()
    for (let id = 1; id <= 200; id++) poses.set(id, { x: 0, y: 0, a: 0, awake: true })
    const encoder = new SnapshotEncoder()
    const history = new SnapshotHistory()
    encoder.reset(frameOf(poses), 0)
    history.reset(frameOf(poses), 0)
    const out = new ByteWriter()
    const lastSeen = new Map<number, number>()
    let worst = 0
    for (let tick = 2; tick <= 200; tick += 2) {
      for (const [id, p] of poses) poses.set(id, { ...p, x: p.x + 1000 + id, y: p.y - 500 })
      out.reset()
      const stats = encoder.encode(out, frameOf(poses), tick, 200, (id) => (id === 7 ? 100 : 0))
      expect(out.length).toBeLessThanOrEqual(200 + 2)
      const applied = history.apply(tick, encoder.referenceTick, out.toBytes())!
      expect(applied.updated).toContain(7)
      for (const id of applied.updated) {
        worst = Math.max(worst, tick - (lastSeen.get(id) ?? 0))
        lastSeen.set(id, tick)
      }
      expect(stats.sent).toBe(applied.updated.length)
      encoder.ack(tick)
    }
    expect(lastSeen.size).toBe(200)
    expect(worst).toBeLessThan(60)
  })

  it('corrupt payloads throw RangeError rather than producing bodies', () => {
    const base = new QuantizedFrame()
    const out = new QuantizedFrame()
    expect(() => readUpdates(new Uint8Array([5, 4]), base, out)).toThrow(RangeError)
    expect(() => readUpdates(new Uint8Array([1, 4, 0, 0, 0]), base, out)).toThrow(/baseline/)
    expect(() => readUpdates(new Uint8Array([1, 5, 0, 0, 0, 9]), base, out)).toThrow(/trailing/)
  })
})
