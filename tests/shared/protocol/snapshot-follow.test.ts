/*
 * SnapshotEncoder.follow: a client whose baseline equals another's takes over that client's
 * encode. The oracle is a twin encoder that sees exactly what the follower sees (frames, budgets,
 * removals, acks) but always encodes for itself: on every tick the follower's bytes (the leader's
 * when it follows) and stats must equal the twin's, whatever the acks, budgets and removals.
 */
import fc from 'fast-check'
import { describe, expect, it } from 'vitest'
import { ByteWriter } from '../../../shared/protocol/byte-io.ts'
import { QuantizedFrame } from '../../../shared/protocol/quantized-frame.ts'
import { type EncodeStats, SnapshotEncoder } from '../../../shared/protocol/snapshot-encoder.ts'

interface Step {
  moves: Array<[number, number]>
  remove: number
  /** Snapshot byte budget of this tick (every client of a room has the same). */
  budget: number
  leaderAcks: boolean
  /** The follower acks as the leader did (their baselines stay equal) or on its own. */
  sameAck: boolean
  followerAcks: boolean
}

const step = fc.record({
  moves: fc.array(fc.tuple(fc.integer({ min: 1, max: 30 }), fc.integer({ min: -3000, max: 3000 })), {
    maxLength: 20,
  }),
  remove: fc.integer({ min: 0, max: 80 }),
  budget: fc.constantFrom(8, 40, 100000),
  leaderAcks: fc.boolean(),
  sameAck: fc.boolean(),
  followerAcks: fc.boolean(),
})

function encodeBytes(e: SnapshotEncoder, frame: QuantizedFrame, tick: number, budget: number) {
  const w = new ByteWriter()
  const stats = e.encode(w, frame, tick, budget, (id) => (id % 7 === 0 ? 8 : 0))
  return { bytes: [...w.toBytes()], stats }
}

describe('SnapshotEncoder.follow', () => {
  it('gives the bytes and stats the follower would have encoded itself', () => {
    let followed = 0
    let refused = 0
    fc.assert(
      fc.property(fc.array(step, { minLength: 1, maxLength: 40 }), (steps: Step[]) => {
        const poses = new Map<number, [number, number, number, boolean]>()
        for (let id = 1; id <= 30; id++) poses.set(id, [id * 100, -id * 50, id * 7, id % 3 !== 0])
        const frame = new QuantizedFrame(4)
        const fill = (): void => {
          frame.clear()
          for (const id of [...poses.keys()].sort((a, b) => a - b)) {
            const [x, y, a, awake] = poses.get(id)!
            frame.put(id, x, y, a, awake)
          }
        }
        fill()
        const leader = new SnapshotEncoder()
        const follower = new SnapshotEncoder()
        const twin = new SnapshotEncoder()
        for (const e of [leader, follower, twin]) e.reset(frame, 0)
        for (let i = 0; i < steps.length; i++) {
          const s = steps[i]
          const tick = (i + 1) * 2
          for (const [id, dx] of s.moves) {
            const p = poses.get(id)
            if (p) poses.set(id, [p[0] + dx, p[1] - dx, p[2] + (dx % 5), dx % 2 === 0])
          }
          if (poses.has(s.remove)) {
            poses.delete(s.remove)
            for (const e of [leader, follower, twin]) e.removeBody(s.remove)
          }
          fill()
          const lead = encodeBytes(leader, frame, tick, s.budget)
          let mine: { bytes: number[]; stats: EncodeStats }
          const stats = follower.follow(leader, frame, tick, s.budget)
          if (stats) {
            followed++
            mine = { bytes: lead.bytes, stats }
          } else {
            refused++
            mine = encodeBytes(follower, frame, tick, s.budget)
          }
          const expected = encodeBytes(twin, frame, tick, s.budget)
          expect(mine.bytes).toEqual(expected.bytes)
          expect(mine.stats).toEqual(expected.stats)
          if (s.leaderAcks) leader.ack(tick)
          const followerAcks = s.sameAck ? s.leaderAcks : s.followerAcks
          if (followerAcks) {
            expect(follower.ack(tick)).toBe(twin.ack(tick))
          }
          expect(follower.referenceTick).toBe(twin.referenceTick)
          expect(follower.reference.equals(twin.reference)).toBe(true)
          expect(follower.pendingCount).toBe(twin.pendingCount)
        }
      }),
      { numRuns: 200 },
    )
    // Both paths ran: taken over, and refused (baselines apart, or over the budget).
    expect(followed).toBeGreaterThan(100)
    expect(refused).toBeGreaterThan(100)
  })

  it('refuses a leader whose encode was cut by the budget or was for another tick', () => {
    const frame = new QuantizedFrame(4)
    for (let id = 1; id <= 10; id++) frame.put(id, id * 1000, 0, 0, true)
    const empty = new QuantizedFrame(4)
    const leader = new SnapshotEncoder()
    const follower = new SnapshotEncoder()
    leader.reset(empty, 0)
    follower.reset(empty, 0)
    leader.encode(new ByteWriter(), frame, 2, 10)
    expect(follower.follow(leader, frame, 2, 10)).toBeNull()
    leader.encode(new ByteWriter(), frame, 4, 100000)
    expect(follower.follow(leader, frame, 6, 100000)).toBeNull()
    // A budget smaller than what the leader wrote: refused even though the leader's fitted.
    expect(follower.follow(leader, frame, 4, 10)).toBeNull()
    expect(follower.follow(leader, frame, 4, 100000)).not.toBeNull()
  })
})
