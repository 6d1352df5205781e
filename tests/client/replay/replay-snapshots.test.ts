/*
 * The replay player's snapshot store alone, with made-up snapshots: where it wants one (against a
 * brute force of the rule), and what it drops when over its budget (against a hand count).
 */
import { describe, expect, it } from 'vitest'
import {
  type PlayerSnapshot,
  SNAPSHOT_TICKS,
  SnapshotStore,
} from '../../../client/replay/replay-snapshots.ts'

/** A snapshot at `tick` with a world of `worldBytes` bytes and the given delta base. */
function snapshot(tick: number, worldBytes: number, base: Uint8Array | null): PlayerSnapshot {
  const state = {
    tick,
    scene: 'empty',
    paused: false,
    stepRequested: false,
    lastLoadTick: null,
    players: [],
    userJoints: [],
    game: 'sandbox',
    gameState: null,
    random: 0,
  }
  return { tick, next: 0, state, world: new Uint8Array(worldBytes), base }
}

describe('replay snapshot store', () => {
  it('wants the state at a tick only on the grid and with no keyframe or snapshot in the SNAPSHOT_TICKS ticks up to it', () => {
    const keyframes = [37, 2_000, 7_250]
    const store = new SnapshotStore(keyframes, 10_000, 1 << 30)
    for (const t of [1_200, 3_000, 4_200]) store.add(snapshot(t, 100, null))
    const starts = [...keyframes, 1_200, 3_000, 4_200]
    for (let t = 0; t <= 10_000; t++) {
      const near = starts.some((s) => s > t - SNAPSHOT_TICKS && s <= t)
      expect(store.wants(t), `tick ${t}`).toBe(t % SNAPSHOT_TICKS === 0 && !near)
    }
    expect(new SnapshotStore(keyframes, 10_000, 0).wants(1_200)).toBe(false)
  })

  it('over its budget drops the snapshot whose neighbours (keyframes too) are closest, counting a shared base once', () => {
    const base = new Uint8Array(5_000)
    // Each snapshot counts its 1,000-byte world and 512 bytes of state; the base counts once.
    const own = 1_000 + 512
    const store = new SnapshotStore([0, 3_000], 6_000, 3 * own + base.byteLength)
    for (const t of [1_200, 2_400, 3_600]) store.add(snapshot(t, 1_000, base))
    expect(store.bytes).toBe(3 * own + base.byteLength)
    // A fourth: without 1,200 the stretch 0..2,400 would be 2,400; without 2,400, 1,200..3,000
    // (the keyframe) 1,800; without 3,600, 3,000..4,800 1,800; without 4,800, 3,600..6,000 (the
    // end) 2,400. The first of the closest goes.
    store.add(snapshot(4_800, 1_000, base))
    expect(store.ticks).toEqual([1_200, 3_600, 4_800])
    expect(store.bytes).toBe(3 * own + base.byteLength)
    // The newest at or before a tick.
    expect(store.before(1_199)).toBeNull()
    expect(store.before(3_599)?.tick).toBe(1_200)
    expect(store.before(9_999)?.tick).toBe(4_800)
    // A big one at 5,400 has the closest neighbours (4,800 and the end) and goes at once; its own
    // base no longer counts.
    store.add(snapshot(5_400, 20_000, new Uint8Array(7)))
    expect(store.ticks).toEqual([1_200, 3_600, 4_800])
    expect(store.bytes).toBe(3 * own + base.byteLength)
  })
})
