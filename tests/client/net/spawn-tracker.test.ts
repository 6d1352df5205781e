/*
 * SpawnTracker against hand-made server answers: a spawn is answered by the add event that names
 * this player and its seq (not another player's with the same seq), forgotten when refused or on
 * a new world, and handed back when dropped over the budget, up to MAX_SENDS sends in all.
 */
import { describe, expect, it } from 'vitest'
import { InputOutbox } from '../../../client/net/input-outbox.ts'
import { MAX_SENDS, SpawnTracker } from '../../../client/net/spawn-tracker.ts'
import type { SimCommand, SpawnCommand, WireBody } from '../../../shared/index.ts'

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

describe('InputOutbox', () => {
  it('queues a dropped spawn first again, and counts the spawns given up after MAX_SENDS sends', () => {
    let seq = 0
    const sent: Array<[number, SimCommand]> = []
    const outbox: InputOutbox = new InputOutbox(
      (cmd) => {
        sent.push([++seq, cmd])
        if (cmd.k === 'spawn') outbox.spawns.sent(seq, cmd)
      },
      () => {},
    )
    outbox.push(circle(0))
    outbox.push({ k: 'move', x: 1, y: 1 })
    outbox.startFrame()
    outbox.drain(8) // a share of 2 per frame
    expect(sent.map(([, c]) => c.k)).toEqual(['spawn', 'move'])
    outbox.dropped(2) // a dropped move is not sent again
    expect(outbox.length).toBe(0)
    for (let i = 1; i < MAX_SENDS; i++) {
      outbox.dropped(sent[sent.length - (i === 1 ? 2 : 1)][0])
      expect(outbox.length).toBe(1)
      outbox.startFrame()
      outbox.drain(8)
    }
    expect(outbox.takeResent()).toBe(MAX_SENDS - 1)
    expect(outbox.takeGivenUp()).toBe(0)
    outbox.dropped(sent[sent.length - 1][0])
    expect(outbox.length).toBe(0)
    expect(outbox.takeGivenUp()).toBe(1)
    expect(outbox.takeGivenUp()).toBe(0)
  })
})
