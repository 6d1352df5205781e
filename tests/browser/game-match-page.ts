/*
 * The page side of the game match tests (game-match.test.ts, tower-match.test.ts): evaluated by
 * the test driver in a client page joined to a goal or tower room in lockstep or predict mode, it
 * plays the page's player with a script of tests/games/scripted-players.ts, computing each command
 * from the page's own confirmed simulation and sending it over the page's own connection as a
 * `cmd` message (the page has no game input bindings yet: a game's client module is later work).
 * `report()` reads the page's game summary and lockstep figures; `history()` the summary at each
 * tick the page was seen at (matchSummary, the same function the test applies to the server's room).
 */
import { DROP_COOLDOWN, type GoalState, type TowerState } from '../../games/index.ts'
import type { GameCommand, RoomSimulation } from '../../shared/index.ts'
import { benchCommands, builderCommands, strikerCommands } from '../games/scripted-players.ts'

/** What the tests compare between a page and the server: the game's result-bearing state, as JSON. */
export function matchSummary(sim: RoomSimulation): string {
  if (sim.game.name === 'goal') {
    const s = sim.gameState as GoalState
    return JSON.stringify([s.score, s.phase])
  }
  const s = sim.gameState as TowerState
  return JSON.stringify([s.height, s.fallen, s.phase, s.winners])
}

/** What the test reads from a page. */
export interface MatchReport {
  player: number
  tick: number
  summary: string | null
  joined: boolean
  desyncs: number
  resyncs: number
  hashesChecked: number
  sent: number
}

/** A page's script role: goal's striker or bench, or tower's builder. */
export type MatchRole = 'striker' | 'bench' | 'builder'

/** The parts of the page's lockstep sandbox this script uses (client/modes/lockstep-sandbox.ts). */
interface PageSandbox {
  runner: {
    sim: RoomSimulation | null
    playerId: number
    stats: { desyncs: number; resyncs: number; hashesChecked: number }
  }
  connection: { send(message: { t: 'cmd'; seq: number; k: string; a: GameCommand['a'] }): void }
}

const sandbox = (): PageSandbox =>
  (window as unknown as { concord: { sandbox: PageSandbox } }).concord.sandbox

let sent = 0
let seq = 1000
/** [tick, summary] each time the page's confirmed simulation was seen at a new tick. */
const history: Array<[number, string]> = []

/** Note the page's summary at its confirmed tick, every 5 ms (a frame may step several ticks). */
function watch(): void {
  setInterval(() => {
    const sim = sandbox().runner.sim
    if (!sim || history[history.length - 1]?.[0] === sim.tick) return
    history.push([sim.tick, matchSummary(sim)])
  }, 5)
}

function joined(sim: RoomSimulation, player: number): boolean {
  const state = sim.gameState as GoalState | TowerState
  return sim.game.name === 'goal'
    ? (state as GoalState).players[player] !== undefined
    : (state as TowerState).lanes[player] !== undefined
}

/**
 * The builder's commands: a scripted block once the cooldown is over (asked again only after the
 * last one landed or a second passed, so the game refuses few: each refusal is a strike).
 */
function builder(): (sim: RoomSimulation, player: number) => GameCommand[] {
  let askedAt = Number.NEGATIVE_INFINITY
  return (sim, player) => {
    const state = sim.gameState as TowerState
    const last = state.lastDrop[player] ?? Number.NEGATIVE_INFINITY
    if (state.phase !== 'building' || sim.tick - last < DROP_COOLDOWN + 5) return []
    if (askedAt > last && sim.tick - askedAt < 60) return []
    askedAt = sim.tick
    // builderCommands draws its block from (player, tick); with `every` 1 it always sends one.
    return builderCommands(sim, player, 1, 0.3)
  }
}

function start(role: MatchRole): void {
  watch()
  const script =
    role === 'builder'
      ? builder()
      : (sim: RoomSimulation, p: number) =>
          role === 'striker' ? strikerCommands(sim, p, 1) : benchCommands(sim, p, 1)
  setInterval(() => {
    const s = sandbox()
    const sim = s.runner.sim
    if (!sim || !joined(sim, s.runner.playerId)) return
    for (const c of script(sim, s.runner.playerId)) {
      s.connection.send({ t: 'cmd', seq: ++seq, k: c.kind, a: c.a })
      sent++
    }
  }, 50)
}

function report(): MatchReport {
  const s = sandbox()
  const sim = s.runner.sim
  return {
    player: s.runner.playerId,
    tick: sim?.tick ?? 0,
    summary: sim ? matchSummary(sim) : null,
    joined: sim !== null && joined(sim, s.runner.playerId),
    desyncs: s.runner.stats.desyncs,
    resyncs: s.runner.stats.resyncs,
    hashesChecked: s.runner.stats.hashesChecked,
    sent,
  }
}

;(globalThis as unknown as { concordGameMatch: unknown }).concordGameMatch = {
  start,
  report,
  history: () => history,
}
