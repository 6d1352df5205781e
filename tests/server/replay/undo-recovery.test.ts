/*
 * Undo histories through recording, crash recovery and replay, in process: a sandbox room recorded
 * by the server's Recordings, two players spawning, deleting, pinning, undoing and redoing, the
 * live state hash (which covers the histories) kept at every tick. The process "dies" (the log is
 * never closed); a fresh RoomManager and Recordings rebuild the room from the log, from a keyframe
 * saved while the players had history: it must reach the last checkpoint with the live hash, and
 * the recovered simulation must then undo exactly as the live one does (same refusals, same hash).
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { describe, expect, it } from 'vitest'
import { loadWorld } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { loadConfig } from '../../../server/config/config.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { Recordings } from '../../../server/replay/recordings.ts'
import { RoomManager } from '../../../server/rooms/room-manager.ts'
import { RoomSimulation, type SimCommand, type SimulationState } from '../../../shared/index.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'

const box = (x: number, y: number): SimCommand => ({
  k: 'spawn',
  shape: { type: 'box', hw: 0.4, hh: 0.4 },
  x,
  y,
})
const undo: SimCommand = { k: 'cmd', kind: 'undo', a: {} }
const redo: SimCommand = { k: 'cmd', kind: 'redo', a: {} }

describe('undo histories survive recording and crash recovery', () => {
  it('a recovered room has the live hash at the checkpoint and undoes as the live room does', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-undo-recovery-'))
    const config = loadConfig(
      [],
      {},
      { defaultScene: 'empty', logLevel: 'silent', record: true, replayDir: dir, roomControls: true },
    )
    const log = pino({ level: 'silent' })
    const recordings = new Recordings(config, createMetrics(false), log)
    expect(await recordings.prepare()).toBe(true)
    const rooms = new RoomManager(config, createMetrics(false), log)
    recordings.hook(rooms)
    const room = rooms.getOrCreate('ur', 'sandbox')
    if (!room) throw new Error('no room')
    room.sim.join(1, 'a', '#f00')
    room.sim.join(2, 'b', '#0f0')
    const recorder = recordings.recorders.get('ur')
    if (!recorder) throw new Error('no recorder')
    const live = new Map<number, { hash: number; state: SimulationState; world: Uint8Array }>()
    // Every 25 ticks a player acts: spawns, undoes, redoes, deletes the other's newest body.
    for (let i = 0; i < 1100; i++) {
      if (i % 25 === 3) {
        const player = 1 + (((i / 25) % 2) | 0)
        const step = (i / 50) | 0
        const cmd =
          step % 5 === 4
            ? undo
            : step % 5 === 3
              ? redo
              : step % 7 === 6
                ? { k: 'delete' as const, body: room.world.bodyIds().at(-1) as number }
                : box(-8 + (i % 16), 3 + (i % 3))
        room.sim.apply(player, cmd)
      }
      room.runTick()
      live.set(room.tick, { hash: room.sim.hash(), state: room.sim.saveState(), world: room.world.save() })
      if (i % 50 === 0) await recorder.flush()
    }
    await recorder.flush()
    expect(room.sim.history.empty).toBe(false)

    // The last checkpoint, and a keyframe after the players had history.
    let checkpoint = -1
    let keyframeWithHistory = false
    new ReplayLogReader().push(new Uint8Array(await readFile(join(dir, recorder.name))), (r) => {
      if (r.type === 'hash' || r.type === 'keyframe' || r.type === 'header') checkpoint = r.tick
      if (r.type === 'keyframe' && (r.state.history?.length ?? 0) > 0) keyframeWithHistory = true
    })
    expect(checkpoint).toBeGreaterThan(1000)
    expect(keyframeWithHistory).toBe(true)

    const after = new Recordings(config, createMetrics(false), log)
    const rooms2 = new RoomManager(config, createMetrics(false), log)
    after.hook(rooms2)
    const recovered = await after.reopen(rooms2, recorder.name)
    const there = live.get(checkpoint)
    if (!there) throw new Error('no live state at the checkpoint')
    expect(there.state.history?.length).toBeGreaterThan(0)
    expect([recovered.tick, recovered.hash]).toEqual([checkpoint, there.hash])
    expect(recovered.runner.sim.saveState().history).toEqual(there.state.history)

    // From the checkpoint on, the recovered simulation and a copy of the live one undo alike.
    const copy = new RoomSimulation({
      game: sandbox,
      name: 'ur',
      scene: 'empty',
      maxBodies: 1000,
      controls: true,
    })
    copy.restoreState(structuredClone(there.state), loadWorld(there.world))
    const sim = recovered.runner.sim
    let accepted = 0
    for (const player of [1, 2, 1, 2, 1, 1, 2, 2]) {
      for (const s of [sim, copy]) s.runTick()
      const a = sim.apply(player, undo)
      expect(copy.apply(player, undo)).toBe(a)
      expect(sim.hash()).toBe(copy.hash())
      if (a === null) accepted++
    }
    expect(accepted).toBeGreaterThan(3)
    await recordings.closeAll('test')
    await after.closeAll('test')
  }, 60_000)
})
