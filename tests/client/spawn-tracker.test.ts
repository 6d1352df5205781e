/*
 * SpawnTracker against hand-made add events: a spawn is confirmed by the body added at its
 * (world-clamped) point with its shape, forgotten when refused by seq or by a new world, and due
 * again only after RESEND_TICKS plus the round trip, at most MAX_SENDS times in all.
 */
import { describe, expect, it } from 'vitest'
import { MAX_SENDS, RESEND_TICKS, SpawnTracker } from '../../client/spawn-tracker.ts'
import { type SpawnCommand, type WireBody, WORLD_HALF_EXTENT } from '../../shared/index.ts'

const circle = (x: number, y: number): SpawnCommand => ({
  k: 'spawn',
  shape: { type: 'circle', radius: 0.3 },
  x,
  y,
})
const added = (cmd: SpawnCommand, dx = 0, kind: 0 | 1 | 2 = 2): WireBody => ({
  id: 7,
  kind,
  shape: cmd.shape,
  x: Math.round((cmd.x + dx) * 1000),
  y: Math.round(cmd.y * 1000),
  a: 0,
  awake: 1,
})

describe('SpawnTracker', () => {
  it('confirms a spawn by the dynamic body added at its point with its shape, and no other', () => {
    const t = new SpawnTracker()
    const a = circle(1, 2)
    const b = circle(3, 2)
    t.sent(1, a, 100)
    t.sent(2, b, 100)
    t.added({ ...added(a), shape: { type: 'circle', radius: 0.4 } }) // another shape
    t.added(added(a, 0.5)) // 0.5 m away
    t.added(added(a, 0, 0)) // static
    expect(t.size).toBe(2)
    t.added(added(a, 0.001)) // the mm quantization
    expect(t.size).toBe(1)
    expect(t.overdue(100 + RESEND_TICKS + 11, 10)).toEqual([b])
  })

  it("confirms by the player and seq an add event names: not another player's body at the same point, any seq the spawn went out with", () => {
    const t = new SpawnTracker()
    const a = circle(1, 2)
    const b = circle(3, 2)
    t.sent(1, a, 100)
    t.sent(2, b, 100)
    t.added({ ...added(a), player: 9, seq: 1 }, 4) // another player's seq 1, at a's very point
    t.added({ ...added(a), player: 4, seq: 3 }, 4) // ours, a seq never sent
    expect(t.size).toBe(2)
    t.sent(5, a, 140) // a sent again with seq 5; the first send (seq 1) arrives late
    t.added({ ...added(a, 0.7), player: 4, seq: 1 }, 4) // named: the pose need not match
    expect(t.size).toBe(1)
    t.added({ ...added(a), player: 4, seq: 5 }, 4) // the resend's body confirms nothing more
    expect(t.size).toBe(1)
    t.refused(2)
    expect(t.size).toBe(0)
  })

  it('matches a spawn clamped to the world bounds where the server put it', () => {
    const t = new SpawnTracker()
    t.sent(1, circle(5000, 2), 0)
    t.added(added(circle(WORLD_HALF_EXTENT, 2)))
    expect(t.size).toBe(0)
  })

  it('is due again only after RESEND_TICKS plus the round trip, once per resend, up to MAX_SENDS sends', () => {
    const t = new SpawnTracker()
    const a = circle(0, 0)
    t.sent(1, a, 0)
    expect(t.overdue(RESEND_TICKS + 6, 6)).toEqual([])
    expect(t.overdue(RESEND_TICKS + 7, 6)).toEqual([a])
    // Handed out once: not due again while waiting to be sent.
    expect(t.overdue(RESEND_TICKS + 8, 6)).toEqual([])
    let sends = 1
    let tick = RESEND_TICKS + 7
    for (;;) {
      t.sent(10 + sends, a, tick)
      sends++
      tick += RESEND_TICKS + 7
      const due = t.overdue(tick, 6)
      if (due.length === 0) break
    }
    expect(sends).toBe(MAX_SENDS)
    expect(t.size).toBe(0)
  })

  it('forgets a spawn the server refused (by seq) and everything on a new world', () => {
    const t = new SpawnTracker()
    t.sent(1, circle(0, 0), 0)
    t.sent(2, circle(1, 0), 0)
    t.refused(1)
    expect(t.size).toBe(1)
    t.refused(99)
    expect(t.size).toBe(1)
    t.clear()
    expect(t.size).toBe(0)
  })
})
