/*
 * Tug (tests/games/examples/tug/), a third game written from docs/games.md only, played in a
 * RoomSimulation: the left team pulls harder and must win 3-0 (the hand-worked outcome: a pull of 5
 * gives the 0.785 kg ball 6.4 m/s, the right team's pull of 1 only 1.3 m/s back), the match ends
 * and refuses more pulls, a copy made mid-match through save and load plays on with the same
 * hashes, and the module passes the determinism check.
 */
import { describe, expect, it } from 'vitest'
import { checkGameDirectory, formatViolation } from '../../server/games/determinism-check.ts'
import { cloneSimulation, type PlainData, RoomSimulation } from '../../shared/index.ts'
import { TARGET, tug } from './examples/tug/tug-game.ts'

const options = { game: tug, name: 'tug', scene: 'empty', maxBodies: 50, controls: false }

/** One tick of the match: left (player 1) pulls 5 every 20 ticks, right (player 2) pulls 1 every 10. */
function play(sim: RoomSimulation): void {
  if (sim.tick % 20 === 0) sim.apply(1, { k: 'cmd', kind: 'pull', a: { strength: 5 } })
  if (sim.tick % 10 === 5) sim.apply(2, { k: 'cmd', kind: 'pull', a: { strength: 1 } })
  sim.runTick()
}

describe('tug, a game written from the guide', () => {
  it('the stronger team wins 3-0, the match ends, and a save/load copy plays on bit for bit', () => {
    const events: PlainData[] = []
    const sim = new RoomSimulation({
      ...options,
      listener: {
        bodyAdded: () => {},
        bodyRemoved: () => {},
        jointAdded: () => {},
        jointRemoved: () => {},
        roomChanged: () => {},
        cursorChanged: () => {},
        worldReplaced: () => {},
        gameEvent: (_t, e) => events.push(e),
      },
    })
    sim.join(1, 'l', '#00f')
    sim.join(2, 'r', '#f00')
    expect(sim.gameState).toMatchObject({ teams: { 1: 'left', 2: 'right' } })
    for (let i = 0; i < 60; i++) play(sim)
    const copy = cloneSimulation(sim, { maxBodies: 50, controls: false, name: 'tug' })
    const hashes: number[][] = [[], []]
    for (let i = 0; i < 1800 && (sim.gameState as { winner: string | null }).winner === null; i++) {
      play(sim)
      play(copy)
      hashes[0].push(sim.hash())
      hashes[1].push(copy.hash())
    }
    expect(hashes[1]).toEqual(hashes[0])
    expect(sim.gameState).toMatchObject({ score: { left: TARGET, right: 0 }, winner: 'left' })
    expect(events.filter((e) => (e as { point?: string }).point === 'left').length).toBe(TARGET)
    expect(events[events.length - 1]).toEqual({ winner: 'left' })
    expect(sim.apply(1, { k: 'cmd', kind: 'pull', a: { strength: 5 } })).toBe('the match is over')
    expect(sim.apply(1, { k: 'cmd', kind: 'pull', a: { strength: 6 } })).toBe(
      'pull refused: strength must be <= 5',
    )
  })

  it('passes the determinism check', () => {
    expect(checkGameDirectory('tests/games/examples').map(formatViolation)).toEqual([])
  })
})
