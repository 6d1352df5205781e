/*
 * The page side of the goal match test (game-match.test.ts): evaluated by the test driver in a
 * client page joined to a goal room in lockstep or predict mode, it plays the page's player with
 * a script of tests/games/scripted-players.ts, computing each command from the page's own
 * confirmed simulation and sending it over the page's own connection as a `cmd` message (the page
 * has no game input bindings yet: a game's client module is later work). `report()` reads the
 * page's game state and lockstep figures, `history()` the score at each tick the page was seen at.
 */
import type { GoalState } from '../../games/index.ts'
import type { GameCommand, RoomSimulation } from '../../shared/index.ts'
import { benchCommands, strikerCommands } from '../games/scripted-players.ts'

/** What the test reads from a page. */
export interface MatchReport {
  player: number
  tick: number
  score: { red: number; blue: number } | null
  phase: string | null
  team: string | null
  desyncs: number
  resyncs: number
  hashesChecked: number
  sent: number
}

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
/** [tick, [score, phase] as JSON] each time the page's confirmed simulation was seen at a new tick. */
const history: Array<[number, string]> = []

/** Note the page's score at its confirmed tick, every 5 ms (a frame may step several ticks). */
function watch(): void {
  setInterval(() => {
    const sim = sandbox().runner.sim
    if (!sim || history[history.length - 1]?.[0] === sim.tick) return
    const state = sim.gameState as GoalState
    history.push([sim.tick, JSON.stringify([state.score, state.phase])])
  }, 5)
}

function start(role: 'striker' | 'bench'): void {
  watch()
  const script = role === 'striker' ? strikerCommands : benchCommands
  setInterval(() => {
    const s = sandbox()
    const sim = s.runner.sim
    if (!sim || !(sim.gameState as GoalState).players[s.runner.playerId]) return
    for (const c of script(sim, s.runner.playerId, 1)) {
      s.connection.send({ t: 'cmd', seq: ++seq, k: c.kind, a: c.a })
      sent++
    }
  }, 50)
}

function report(): MatchReport {
  const s = sandbox()
  const state = s.runner.sim?.gameState as GoalState | undefined
  return {
    player: s.runner.playerId,
    tick: s.runner.sim?.tick ?? 0,
    score: state ? { ...state.score } : null,
    phase: state?.phase ?? null,
    team: state?.players[s.runner.playerId]?.team ?? null,
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
