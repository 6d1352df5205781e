/*
 * Crash recovery of a game room, in process: a ball-drop room (games/ball-drop) recorded by the
 * server's Recordings, two players dropping balls and scoring, the live state hash (world, PRNG and
 * game state) kept at every tick. The process "dies" (the log is never closed); a fresh
 * RoomManager and Recordings rebuild the room from the log: it must run ball drop again, at the
 * last checkpoint, with the live hash and the live game state of that tick.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { describe, expect, it } from 'vitest'
import type { BallDropState } from '../../../games/index.ts'
import { loadConfig } from '../../../server/config/config.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { Recordings } from '../../../server/replay/recordings.ts'
import { RoomManager } from '../../../server/rooms/room-manager.ts'
import { copyPlainData, type PlainData } from '../../../shared/index.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'

describe('crash recovery of a game room', () => {
  it('reopens the room running its game, at the last checkpoint, with the live hash and score', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-game-recovery-'))
    const config = loadConfig(
      [],
      {},
      { defaultScene: 'empty', logLevel: 'silent', record: true, replayDir: dir },
    )
    const log = pino({ level: 'silent' })
    const recordings = new Recordings(config, createMetrics(false), log)
    expect(await recordings.prepare()).toBe(true)
    const rooms = new RoomManager(config, createMetrics(false), log)
    recordings.hook(rooms)
    const room = rooms.getOrCreate('gr', 'ball-drop')
    if (!room) throw new Error('no room')
    expect(room.game.name).toBe('ball-drop')
    const live = new Map<number, { hash: number; world: number; random: number; state: PlainData }>()
    room.sim.join(1, 'a', '#f00')
    room.sim.join(2, 'b', '#0f0')
    const recorder = recordings.recorders.get('gr')
    if (!recorder) throw new Error('no recorder')
    for (let i = 0; i < 1100; i++) {
      if (i % 70 === 5)
        expect(room.sim.apply(1 + (((i / 70) % 2) | 0), { k: 'cmd', kind: 'drop', a: { x: 0.2 } })).toBeNull()
      room.runTick()
      live.set(room.tick, {
        hash: room.sim.hash(),
        world: room.world.hash(),
        random: room.sim.random.position(),
        state: copyPlainData(room.sim.gameState),
      })
      if (i % 50 === 0) await recorder.flush()
    }
    await recorder.flush()
    const state = room.sim.gameState as BallDropState
    // Both players scored: a ball dropped at x = 0.2 lands on the 2 m target (about 70 ticks) and
    // sleeps there before the next drop, 150 ticks later.
    expect(state.scores[1]).toBeGreaterThan(0)
    expect(state.scores[2]).toBeGreaterThan(0)

    // The last checkpoint the log holds, read with the reader.
    let checkpoint = -1
    new ReplayLogReader().push(new Uint8Array(await readFile(join(dir, recorder.name))), (r) => {
      if (r.type === 'hash' || r.type === 'keyframe' || r.type === 'header') checkpoint = r.tick
    })
    expect(checkpoint).toBeGreaterThan(1000)

    // A new process: the room is rebuilt from its unclosed log, at the checkpoint, with the hash
    // (world, PRNG and game state) the live room had there.
    const after = new Recordings(config, createMetrics(false), log)
    const rooms2 = new RoomManager(config, createMetrics(false), log)
    after.hook(rooms2)
    const recovered = await after.reopen(rooms2, recorder.name)
    const there = live.get(checkpoint)
    expect([recovered.tick, recovered.hash]).toEqual([checkpoint, there?.hash])
    const back = rooms2.get('gr')
    if (!back) throw new Error('the room did not reopen')
    expect(back.game.name).toBe('ball-drop')
    expect([back.tick, back.world.hash(), back.sim.random.position()]).toEqual([
      checkpoint,
      there?.world,
      there?.random,
    ])
    // The crashed process's players are gone: they left (ball drop's onLeave drops their scores),
    // and the balls in play and the drop times are as they were.
    const expected = there?.state as BallDropState
    expect(back.sim.gameState).toEqual({ ...expected, scores: {} })
    await recordings.closeAll('test')
    await after.closeAll('test')
  }, 60_000)
})
