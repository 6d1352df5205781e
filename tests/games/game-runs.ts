/*
 * Long scripted runs of the shipped games in a RoomSimulation, for the cross-engine test
 * (tests/browser/game-determinism.test.ts): the same code runs in Node and, bundled, in Chromium
 * and Firefox pages, and must give the same state hashes (world, PRNG and game state) there. The
 * scripts (scripted-players.ts) depend only on the simulation, so each run is one fixed sequence
 * of commands; players leave and join midway, and a finished match or round is started again, so
 * every rule runs within the 10,000 ticks.
 */
import { Prng } from '../../engine/index.ts'
import { findGame, type GoalState, type TowerState } from '../../games/index.ts'
import { type GameCommand, type PlainData, RoomSimulation } from '../../shared/index.ts'
import { benchCommands, builderCommands, strikerCommands } from './scripted-players.ts'

/** The games the cross-engine run plays. */
export const RUN_GAMES = ['goal', 'tower', 'ball-drop'] as const

/** What a run reports: hashes every `every` ticks, the final state, the game events counted. */
export interface GameRun {
  game: string
  hashes: number[]
  finalHash: number
  state: PlainData | undefined
  events: number
}

type Script = (sim: RoomSimulation, player: number) => GameCommand[]

const cmd = (kind: string, a: GameCommand['a']): GameCommand => ({ k: 'cmd', kind, a })

/** Ball drop: each player drops a ball every 400 ticks at a scripted x (about a hundred in all). */
function dropper(sim: RoomSimulation, player: number): GameCommand[] {
  if ((sim.tick + player * 97) % 400 !== 0) return []
  const rng = new Prng((Math.imul(player, 0x85ebca6b) ^ sim.tick) >>> 0)
  return [cmd('drop', { x: rng.range(-1.5, 1.5) })]
}

/**
 * Goal: one striker at a time (red's player 1 for the first half of the run, then blue's player
 * 5, who joins at half), the others keep out of the way; a finished match is started again.
 */
function goalScript(sim: RoomSimulation, player: number): GameCommand[] {
  const state = sim.gameState as GoalState
  if (state.phase === 'over') return sim.tick % 90 === player ? [cmd('rematch', {})] : []
  const striker = player === 5 || (player === 1 && !state.players[5])
  return striker ? strikerCommands(sim, player) : benchCommands(sim, player)
}

/** Tower: builders at different paces and spreads; a finished round is restarted. */
function towerScript(sim: RoomSimulation, player: number): GameCommand[] {
  const state = sim.gameState as TowerState
  if (state.phase === 'over') return sim.tick % 90 === player ? [cmd('restart', {})] : []
  return builderCommands(sim, player, 90 + 10 * player, 0.4 * player)
}

const SCRIPTS: Record<(typeof RUN_GAMES)[number], Script> = {
  goal: goalScript,
  tower: towerScript,
  'ball-drop': dropper,
}

/**
 * Play `game` for `ticks` ticks with four scripted players (player 4 leaves at a third of the
 * run and player 5 joins at half), recording the hash every `every` ticks.
 */
export function runGame(game: (typeof RUN_GAMES)[number], ticks: number, every: number): GameRun {
  const found = findGame(game)
  if (!found) throw new Error(`no game ${game}`)
  let events = 0
  const sim = new RoomSimulation({
    game: found,
    name: `run-${game}`,
    scene: 'empty',
    maxBodies: 200,
    controls: false,
    listener: {
      bodyAdded: () => {},
      bodyRemoved: () => {},
      jointAdded: () => {},
      jointRemoved: () => {},
      roomChanged: () => {},
      cursorChanged: () => {},
      worldReplaced: () => {},
      gameEvent: () => {
        events++
      },
    },
  })
  const script = SCRIPTS[game]
  const players = [1, 2, 3, 4]
  for (const p of players) sim.join(p, `p${p}`, '#888')
  const hashes: number[] = []
  for (let t = 1; t <= ticks; t++) {
    if (t === Math.floor(ticks / 3)) {
      sim.leave(4)
      players.splice(players.indexOf(4), 1)
    }
    if (t === Math.floor(ticks / 2)) {
      sim.join(5, 'p5', '#888')
      players.push(5)
    }
    for (const p of players) for (const c of script(sim, p)) sim.apply(p, c)
    sim.runTick()
    if (t % every === 0) hashes.push(sim.hash())
  }
  return { game, hashes, finalHash: sim.hash(), state: sim.gameState, events }
}
