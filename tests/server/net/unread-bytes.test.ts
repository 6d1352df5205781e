import { describe, expect, it } from 'vitest'
import { UnreadBytes } from '../../../server/net/unread-bytes.ts'

describe('unread bytes from acks', () => {
  it('counts everything sent after the last acknowledged snapshot, by hand', () => {
    const u = new UnreadBytes()
    // Before any ack only the unsent bytes count.
    u.snapshotSent(2, 1000)
    u.snapshotSent(4, 2500)
    expect(u.unread(4000, 300)).toBe(300)
    // Ack of tick 2: read through byte 1000; 4000 sent so far -> 3000 unread.
    u.acknowledged(2)
    expect(u.unread(4000, 300)).toBe(3000)
    // An ack for a tick never sent, or an older one, changes nothing.
    u.acknowledged(3)
    u.acknowledged(2)
    expect(u.unread(4000, 300)).toBe(3000)
    u.acknowledged(4)
    expect(u.unread(4000, 300)).toBe(1500)
    // Unsent bytes win when larger (the server's own queue).
    expect(u.unread(4000, 2000)).toBe(2000)
  })
})
