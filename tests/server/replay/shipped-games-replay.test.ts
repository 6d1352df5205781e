/*
 * The goal and tower games' recorded logs verify: a room of each game runs in process under the
 * server's Recordings (keyframes every 120 ticks), scripted players act (tests/games/
 * scripted-players.ts: a striker against a player out of the way until two goals; two builders),
 * one player leaves midway, and the live state hash (world, PRNG and game state) is kept at every
 * tick. Then `npm run replay -- FILE --verify --json` (the CLI, in its own process) must replay
 * the log with every recorded hash and keyframe matching, end at the live room's last tick with
 * its hash, and exit 0.
 */
import { spawnSync } from 'node:child_process'
import { mkdtemp } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { describe, expect, it } from 'vitest'
import type { GoalState, TowerState } from '../../../games/index.ts'
import { loadConfig } from '../../../server/config/config.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { Recordings } from '../../../server/replay/recordings.ts'
import { RoomManager } from '../../../server/rooms/room-manager.ts'
import type { GameCommand, RoomSimulation } from '../../../shared/index.ts'
import { benchCommands, builderCommands, strikerCommands } from '../../games/scripted-players.ts'

type Script = (sim: RoomSimulation, player: number) => GameCommand[]

const CASES: Array<{
  game: string
  scripts: [Script, Script]
  done: (sim: RoomSimulation) => boolean
}> = [
  {
    game: 'goal',
    scripts: [strikerCommands, benchCommands],
    done: (sim) => (sim.gameState as GoalState).score.red >= 2,
  },
  {
    game: 'tower',
    scripts: [(sim, p) => builderCommands(sim, p, 50, 1), (sim, p) => builderCommands(sim, p, 70, 1.5)],
    done: (sim) => Object.keys((sim.gameState as TowerState).blocks).length >= 20,
  },
]

describe('recorded game rooms verify with npm run replay', () => {
  for (const { game, scripts, done } of CASES) {
    it(`${game}: every hash and keyframe matches, and the replay ends on the live hash`, async () => {
      const dir = await mkdtemp(join(tmpdir(), `concord-${game}-replay-`))
      const config = loadConfig(
        [],
        {},
        { logLevel: 'silent', record: true, replayDir: dir, keyframeTicks: 120, keyframeBudget: 0 },
      )
      const log = pino({ level: 'silent' })
      const recordings = new Recordings(config, createMetrics(false), log)
      expect(await recordings.prepare()).toBe(true)
      const rooms = new RoomManager(config, createMetrics(false), log)
      recordings.hook(rooms)
      const room = rooms.getOrCreate(`${game}-log`, game)
      if (!room) throw new Error('no room')
      const sim = room.sim
      sim.join(1, 'a', '#f00')
      sim.join(2, 'b', '#00f')
      sim.join(3, 'c', '#0f0')
      const recorder = recordings.recorders.get(`${game}-log`)
      if (!recorder) throw new Error('no recorder')
      const live = new Map<number, number>()
      let i = 0
      for (; i < 6000 && !done(sim); i++) {
        if (i === 300) sim.leave(3)
        for (const [k, script] of scripts.entries()) for (const c of script(sim, k + 1)) sim.apply(k + 1, c)
        room.runTick()
        live.set(room.tick, sim.hash())
        if (i % 100 === 0) await recorder.flush()
      }
      expect(done(sim), `${game} reached its goal within 6000 ticks`).toBe(true)
      const lastTick = room.tick
      await recordings.closeAll('test')

      const run = spawnSync(
        'npx',
        ['tsx', 'server/replay/replay-cli.ts', join(dir, recorder.name), '--verify', '--json'],
        { encoding: 'utf8', timeout: 120_000 },
      )
      expect(run.status, run.stderr).toBe(0)
      const report = JSON.parse(run.stdout) as {
        lastTick: number
        finalHash: number
        hashesChecked: number
        keyframesChecked: number
        commands: number
        divergence: unknown
      }
      console.log(
        `${game}: ${i} ticks, ${report.commands} commands, ${report.hashesChecked} hashes and ${report.keyframesChecked} keyframes checked`,
      )
      expect(report.divergence).toBeNull()
      expect(report.hashesChecked).toBeGreaterThan(5)
      expect(report.keyframesChecked).toBeGreaterThan(2)
      expect(report.commands).toBeGreaterThan(20)
      expect(report.lastTick).toBe(lastTick)
      expect(report.finalHash).toBe(live.get(lastTick))
    }, 180_000)
  }
})
