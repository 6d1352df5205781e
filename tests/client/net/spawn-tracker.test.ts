/*
 * SpawnTracker against hand-made server answers: a spawn is answered by the add event that names
 * this player and its seq (not another player's with the same seq), forgotten when refused or on
 * a new world, and handed back when dropped over the budget, up to MAX_SENDS sends in all.
 */
import { describe, expect, it } from 'vitest'
import { MAX_SENDS, SpawnTracker } from '../../../client/net/spawn-tracker.ts'
import type { SpawnCommand, WireBody } from '../../../shared/index.ts'

const circle = (x: number): SpawnCommand => ({ k: 'spawn', shape: { type: 'circle', radius: 0.3 }, x, y: 2 })
const body = (player: number | undefined, seq: number | undefined): WireBody => ({
  id: 7,
  kind: 2,
  shapes: [{ type: 'circle', radius: 0.3 }],
  x: 0,
  y: 2000,
  a: 0,
  awake: 1,
  ...(player === undefined ? {} : { player }),
  ...(seq === undefined ? {} : { seq }),
})

describe('SpawnTracker', () => {
  it("is answered by the add event with this player's id and the spawn's seq, and no other", () => {
    const t = new SpawnTracker()
    t.sent(4, circle(0))
    t.sent(5, circle(1))
    t.added(body(2, 4), 1) // another player's spawn with the same seq
    t.added(body(undefined, undefined), 1) // a body from a scene or reset
    expect(t.size).toBe(2)
    t.added(body(1, 4), 1)
    expect(t.size).toBe(1)
    expect(t.dropped(4)).toBeNull() // answered already
    expect(t.dropped(5)).toEqual(circle(1))
  })

  it('hands a dropped spawn back until it has been sent MAX_SENDS times', () => {
    const t = new SpawnTracker()
    const cmd = circle(0)
    let seq = 10
    t.sent(seq, cmd)
    let sends = 1
    for (;;) {
      const again = t.dropped(seq)
      if (!again) break
      expect(again).toBe(cmd)
      t.sent(++seq, again)
      sends++
    }
    expect(sends).toBe(MAX_SENDS)
    expect(t.size).toBe(0)
  })

  it('forgets a spawn the server refused for good, and everything on a new world', () => {
    const t = new SpawnTracker()
    t.sent(1, circle(0))
    t.sent(2, circle(1))
    t.refused(1)
    expect(t.dropped(1)).toBeNull()
    expect(t.size).toBe(1)
    t.refused(99)
    expect(t.size).toBe(1)
    t.clear()
    expect(t.size).toBe(0)
  })
})
