/*
 * The tower game (games/tower/) played headless in a RoomSimulation with scripted commands,
 * against hand computations from its rules (docs/games.md, "Tower"): N square blocks (1 m tall)
 * dropped on the lane centre stack to a measured height of N m (within the contacts' linear slop, 5 mm a
 * block); a block appears DROP_CLEARANCE above the player's highest block; a block pushed off the
 * platform falls below the line, is removed and costs FALL_PENALTY; the best score wins when the
 * round's ROUND_TICKS are over; restart clears the blocks; a save/load copy plays on bit for bit.
 */
import { describe, expect, it } from 'vitest'
import {
  BLOCKS,
  DROP_CLEARANCE,
  DROP_COOLDOWN,
  FALL_PENALTY,
  findGame,
  LANE_SPACING,
  PLATFORM_HALF_WIDTH,
  ROUND_TICKS,
  type TowerState,
  tower,
} from '../../games/index.ts'
import {
  cloneSimulation,
  encodeSyncPayload,
  type PlainData,
  RoomSimulation,
  restoreSyncPayload,
} from '../../shared/index.ts'
import { builderCommands } from './scripted-players.ts'

const ROOM = { maxBodies: 300, controls: false, name: 'tower' }

function room(players: number): { sim: RoomSimulation; events: PlainData[]; state: () => TowerState } {
  const events: PlainData[] = []
  const sim = new RoomSimulation({
    ...ROOM,
    game: tower,
    scene: 'empty',
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
  for (let p = 1; p <= players; p++) sim.join(p, `p${p}`, '#888')
  return { sim, events, state: () => sim.gameState as TowerState }
}

const block = (kind: string, x: number) => ({ k: 'cmd' as const, kind: 'block', a: { kind, x } })

/** Run ticks until the tower's blocks rest (at most `limit` ticks). */
function runFor(sim: RoomSimulation, ticks: number): void {
  for (let i = 0; i < ticks; i++) sim.runTick()
}

describe('tower', () => {
  it('gives players lanes LANE_SPACING apart in join order and starts the round at the first join', () => {
    const { sim, state, events } = room(3)
    expect(state().lanes).toEqual({ 1: 0, 2: 1, 3: 2 })
    expect(state()).toMatchObject({ phase: 'building', startTick: 0 })
    expect(events).toEqual([{ round: 0 }])
    expect(sim.apply(1, block('square', 0))).toBeNull()
    expect(sim.apply(2, block('square', 0))).toBeNull()
    const ids = Object.keys(state().blocks).map(Number)
    const x = ids.map((id) => sim.world.getPosition(id).x)
    expect(x[1] - x[0]).toBe(LANE_SPACING)
  })

  for (const n of [1, 5, 12]) {
    it(`${n} square blocks (1 m tall) dropped on the lane centre measure ${n} m`, () => {
      const { sim, state } = room(1)
      const h = 2 * BLOCKS.square[1]
      for (let i = 0; i < n; i++) {
        // Each block appears DROP_CLEARANCE above the top of the one before, at rest.
        const top = i * h
        expect(sim.apply(1, block('square', 0))).toBeNull()
        const id = Math.max(...Object.keys(state().blocks).map(Number))
        expect(sim.world.getPosition(id).y).toBeCloseTo(top + DROP_CLEARANCE + h / 2, 1)
        expect(sim.apply(1, block('square', 0))).toBe(`one block every ${DROP_COOLDOWN} ticks`)
        runFor(sim, DROP_COOLDOWN)
      }
      runFor(sim, 120)
      const height = state().height[1]
      console.log(`${n} squares: measured ${height} m`)
      expect(Math.abs(height - n * h)).toBeLessThan(0.005 * n)
      expect(state().fallen[1]).toBe(0)
    })
  }

  it('a slab lying on the platform measures its thickness; a post standing measures its height', () => {
    const { sim, state } = room(2)
    sim.apply(1, block('slab', 0))
    sim.apply(2, block('post', 0))
    runFor(sim, 120)
    expect(state().height[1]).toBeCloseTo(2 * BLOCKS.slab[1], 2)
    expect(state().height[2]).toBeCloseTo(2 * BLOCKS.post[1], 2)
  })

  it('a block off the platform falls below the line, is removed, and costs FALL_PENALTY', () => {
    const { sim, state, events } = room(1)
    sim.apply(1, block('square', 0))
    runFor(sim, DROP_COOLDOWN)
    // A post standing at the platform's edge, half over it, topples off.
    sim.apply(1, block('post', PLATFORM_HALF_WIDTH))
    const post = Math.max(...Object.keys(state().blocks).map(Number))
    runFor(sim, 240)
    expect(sim.world.hasBody(post)).toBe(false)
    expect(state().fallen[1]).toBe(1)
    expect(events).toContainEqual({ fell: 1, block: post })
    expect(state().height[1]).toBeCloseTo(1, 2)
  })

  it('when the round is over the best score wins and blocks are refused; restart clears the lanes', () => {
    const { sim, state, events } = room(2)
    // Player 1 stacks three squares; player 2 one square and a post off the edge (its penalty).
    for (let i = 0; i < 3; i++) {
      sim.apply(1, block('square', 0))
      if (i === 0) sim.apply(2, block('square', 0))
      if (i === 1) sim.apply(2, block('post', PLATFORM_HALF_WIDTH))
      runFor(sim, DROP_COOLDOWN)
    }
    while (sim.tick < ROUND_TICKS) sim.runTick()
    expect(state().phase).toBe('over')
    expect(state().winners).toEqual([1])
    const over = events[events.length - 1] as { over: number[]; scores: Record<string, number> }
    expect(over.over).toEqual([1])
    expect(over.scores[1]).toBeCloseTo(3, 1)
    expect(over.scores[2]).toBeCloseTo(1 - FALL_PENALTY, 1)
    expect(sim.apply(1, block('square', 0))).toBe('the round is over')
    expect(sim.apply(2, { k: 'cmd', kind: 'restart', a: {} })).toBeNull()
    expect(state()).toMatchObject({ phase: 'building', startTick: ROUND_TICKS, blocks: {}, winners: [] })
    expect(state().fallen).toEqual({ 1: 0, 2: 0 })
    expect(sim.world.bodyCount).toBe(4) // the platforms
    expect(sim.apply(1, { k: 'cmd', kind: 'restart', a: {} })).toBe('the round is not over')
  })

  it('refuses bad block arguments by field', () => {
    const { sim } = room(1)
    expect(sim.apply(1, block('cube', 0))).toBe(
      'block refused: kind must be equal to one of the allowed values',
    )
    expect(sim.apply(1, block('square', 3))).toBe('block refused: x must be <= 2')
  })

  it('copies made mid-round (clone, sync payload) play on with the same hashes', () => {
    const { sim } = room(3)
    const play = (s: RoomSimulation) => {
      for (let p = 1; p <= 3; p++) for (const c of builderCommands(s, p, 45, 1.2)) s.apply(p, c)
      s.runTick()
    }
    for (let i = 0; i < 400; i++) play(sim)
    const copy = cloneSimulation(sim, ROOM)
    const restored = restoreSyncPayload(encodeSyncPayload(sim), { ...ROOM, games: findGame })
    if (!restored.ok) throw new Error(restored.reason)
    const sims = [sim, copy, restored.sim]
    const hashes: number[][] = sims.map(() => [])
    for (let i = 0; i < 600; i++) {
      for (const [k, s] of sims.entries()) {
        play(s)
        hashes[k].push(s.hash())
      }
    }
    expect(Object.keys((sim.gameState as TowerState).blocks).length).toBeGreaterThan(10)
    expect(hashes[1]).toEqual(hashes[0])
    expect(hashes[2]).toEqual(hashes[0])
  })
})
