/*
 * A recorded two-player room session and the check that it replays: the sandbox command tests
 * (edit-commands, edit-joint) script commands into a live RoomSimulation, record every accepted
 * command with its tick and the room's hash after every tick, and save the room once; then a fresh
 * room fed the recorded commands, and a room restored from the save, must reach the same hash at
 * every tick.
 */
import { expect } from 'vitest'
import { loadWorld } from '../../../engine/index.ts'
import {
  RoomSimulation,
  type SimCommand,
  type SimulationObserver,
  type SimulationOptions,
  type SimulationState,
} from '../../../shared/index.ts'

interface Entry {
  tick: number
  player: number
  cmd: SimCommand
}

export interface Recording {
  options: SimulationOptions
  /** The accepted commands with the tick they were applied at. */
  log: Entry[]
  /** The room's hash after each tick, by tick. */
  hashes: number[]
  ticks: number
  /** The tick the room was saved at (before that tick's commands), its state and world. */
  savedAt: number
  state: SimulationState
  world: Uint8Array
}

/** Players 1 (ada) and 2 (bob) join, as in every recording. */
function joinBoth(sim: RoomSimulation): void {
  sim.join(1, 'ada', '#e6194b')
  sim.join(2, 'bob', '#3cb44b')
}

/**
 * Runs `ticks` ticks of a room with players 1 and 2, calling `script(live, t)` before each tick to
 * apply commands, and saves the room at the start of tick `savedAt`.
 */
export function recordSession(
  options: SimulationOptions,
  ticks: number,
  savedAt: number,
  script: (live: RoomSimulation, t: number) => void,
): Recording {
  const log: Entry[] = []
  const recorder: SimulationObserver = {
    command: (tick, player, c) => log.push({ tick, player, cmd: structuredClone(c) }),
    join: () => {},
    leave: () => {},
    worldLoaded: () => {},
  }
  const live = new RoomSimulation(options)
  live.observers.push(recorder)
  joinBoth(live)
  const hashes: number[] = []
  let state: SimulationState | undefined
  let world: Uint8Array | undefined
  for (let t = 0; t < ticks; t++) {
    if (t === savedAt) {
      state = structuredClone(live.saveState())
      world = live.world.save()
    }
    script(live, t)
    live.runTick()
    hashes[live.tick] = live.hash()
  }
  if (!state || !world)
    throw new Error(`the session ran ${ticks} ticks, so it was never saved at tick ${savedAt}`)
  return { options, log, hashes, ticks, savedAt, state, world }
}

/** The kinds of the recorded game commands, in order. */
export function commandKinds(r: Recording): string[] {
  return r.log.filter((e) => e.cmd.k === 'cmd').map((e) => (e.cmd as { kind: string }).kind)
}

/** A fresh room fed the log, and a room restored from the save, reach the recorded hash every tick. */
export function expectReplays(r: Recording): void {
  const replay = (from: RoomSimulation, start: number): void => {
    for (let t = start; t < r.ticks; t++) {
      for (const e of r.log) if (e.tick === from.tick) expect(from.applyAccepted(e.player, e.cmd)).toBeNull()
      from.runTick()
      expect(from.hash(), `tick ${from.tick}`).toBe(r.hashes[from.tick])
    }
  }
  const fresh = new RoomSimulation(r.options)
  joinBoth(fresh)
  replay(fresh, 0)
  const resumed = new RoomSimulation(r.options)
  resumed.restoreState(r.state, loadWorld(r.world))
  replay(resumed, r.savedAt)
}
