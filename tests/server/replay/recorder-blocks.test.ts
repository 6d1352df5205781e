/*
 * The writer keeps the reader's limits on blocks (shared/replay/replay-log.ts): a flush a second makes
 * blocks of about 60 ticks, but a room stepped synchronously (a test, a benchmark, a tool) or a
 * flood of commands in one flush must still make a log its own reader accepts whole. The
 * recorder starts a new block at MAX_BLOCK_ENTRIES entries or past MAX_BLOCK_TICKS ticks, and the
 * log replays with every hash matching.
 */

import pino from 'pino'
import { Counter } from 'prom-client'
import { describe, expect, it } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import type { LogFile } from '../../../server/replay/replay-files.ts'
import { replayLog } from '../../../server/replay/replay-tool.ts'
import { MAX_BLOCK_ENTRIES, MAX_BLOCK_TICKS, MAX_RECORD_GAP } from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'

/** A recorder writing into memory, with no keyframes after the header (they would split blocks). */
function recorded(sim: RoomSimulation, name: string): { recorder: RoomRecorder; bytes: () => Uint8Array } {
  const chunks: Buffer[] = []
  const recorder = new RoomRecorder(name, sim, {
    dir: '/nonexistent',
    fsync: 'none',
    keyframeTicks: 1_000_000,
    maxBytes: 1 << 30,
    compress: true,
    log: pino({ level: 'silent' }),
    failures: new Counter({ name: `test_${name}_failures`, help: 'test', registers: [] }),
    openNames: new Set(),
    openLog: async (): Promise<LogFile> => ({
      write: async (b) => void chunks.push(Buffer.from(b)),
      sync: async () => {},
      close: async () => {},
    }),
  })
  return { recorder, bytes: () => new Uint8Array(Buffer.concat(chunks)) }
}

/** The log's frames of small records: records that share a frame end came from one block. */
function frames(bytes: Uint8Array): Array<{ count: number; span: number }> {
  const reader = new ReplayLogReader()
  const byEnd = new Map<number, number[]>()
  reader.push(bytes, (r, end) => {
    if (r.type === 'header') return
    const ticks = byEnd.get(end)
    if (ticks) ticks.push(r.tick)
    else byEnd.set(end, [r.tick])
  })
  expect(reader.finish()).toMatchObject({ state: 'end', closed: true })
  return [...byEnd.values()].map((ticks) => ({ count: ticks.length, span: ticks.at(-1)! - ticks[0] }))
}

describe('the recorder keeps every block within the reader limits', () => {
  it('1,300 ticks stepped in one run and flushed once: blocks of at most 600 ticks, every hash matching', async () => {
    const sim = new RoomSimulation({
      game: sandbox,
      name: 'span',
      scene: 'pyramid',
      maxBodies: 500,
      controls: true,
    })
    const { recorder, bytes } = recorded(sim, 'span')
    recorder.start(0)
    sim.join(1, 'ada', '#e6194b')
    while (sim.tick < 1300) {
      sim.apply(1, { k: 'move', x: Math.sin(sim.tick / 30), y: 5 })
      sim.runTick()
    }
    await recorder.close('test over')
    const log = bytes()
    const blocks = frames(log)
    expect(blocks.length).toBeGreaterThanOrEqual(3)
    for (const b of blocks) expect(b.span).toBeLessThanOrEqual(MAX_BLOCK_TICKS)
    const report = await replayLog(log)
    expect(report.divergence).toBe(null)
    expect(report.lastTick).toBe(1300)
    expect(report.hashesChecked).toBeGreaterThanOrEqual(Math.floor(1300 / MAX_RECORD_GAP))
  })

  it('70,000 commands in one tick: blocks of at most 65,536 entries, all replayed', async () => {
    const sim = new RoomSimulation({
      game: sandbox,
      name: 'flood',
      scene: 'pyramid',
      maxBodies: 500,
      controls: true,
    })
    const { recorder, bytes } = recorded(sim, 'flood')
    recorder.start(0)
    sim.join(1, 'ada', '#e6194b')
    for (let i = 0; i < 70_000; i++) sim.apply(1, { k: 'move', x: (i % 100) / 10, y: 5 })
    sim.runTick()
    await recorder.close('test over')
    const log = bytes()
    const counts = frames(log).map((b) => b.count)
    expect(Math.max(...counts)).toBe(MAX_BLOCK_ENTRIES)
    expect(counts.reduce((a, b) => a + b, 0)).toBeGreaterThan(70_000)
    const report = await replayLog(log)
    expect(report.divergence).toBe(null)
    expect(report.commands).toBe(70_000)
  })
})
