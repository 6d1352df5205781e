/*
 * The goal game's client module (docs/games.md, "Client modules"): the HUD shows the score (red -
 * blue), the match clock and the phase or winner, from the game's per-player view; the arrow keys
 * and WASD steer this player's disc with `run` (the held keys' direction at full speed, sent again
 * whenever one of them goes down or up), Space kicks at full power (the room refuses a kick out of
 * reach), and R asks for a rematch once the match is over.
 */
import {
  clockText,
  defineGameClient,
  type GameClientCommand,
  type KeyBinding,
  type KeyInput,
} from '../game-client.ts'
import { MAX_SPEED } from './goal-game.ts'

/** The goal game's view of one player (goal-game.ts `view`). */
export interface GoalView {
  score: { red: number; blue: number }
  phase: 'waiting' | 'playing' | 'over'
  secondsLeft: number
  team: 'red' | 'blue' | null
  winner: string | null
}

function isGoalView(state: unknown): state is GoalView {
  const v = state as GoalView | null
  return (
    typeof v === 'object' && v !== null && typeof v.score === 'object' && typeof v.secondsLeft === 'number'
  )
}

const LEFT = ['arrowleft', 'a']
const RIGHT = ['arrowright', 'd']
const UP = ['arrowup', 'w']
const DOWN = ['arrowdown', 's']

/** The `run` command for the movement keys held now (diagonals at full speed too; the game scales them). */
function run(input: KeyInput): GameClientCommand {
  const on = (keys: string[]): number => (keys.some((k) => input.held.has(k)) ? 1 : 0)
  const x = on(RIGHT) - on(LEFT)
  const y = on(UP) - on(DOWN)
  const scale = x !== 0 && y !== 0 ? MAX_SPEED / Math.sqrt(2) : MAX_SPEED
  return { kind: 'run', args: { x: x * scale, y: y * scale } }
}

const move: KeyBinding = { down: run, up: run }

export const goalClient = defineGameClient({
  game: 'goal',
  hud(state) {
    if (!isGoalView(state)) return []
    const phase =
      state.phase === 'over'
        ? state.winner === 'draw'
          ? 'draw (R: rematch)'
          : `${state.winner} wins (R: rematch)`
        : state.phase === 'waiting'
          ? 'waiting for both teams'
          : 'playing'
    const items = [
      { label: 'score', value: `${state.score.red} - ${state.score.blue}` },
      { label: 'clock', value: clockText(state.secondsLeft) },
      { label: 'match', value: phase },
    ]
    if (state.team) items.push({ label: 'team', value: state.team })
    return items
  },
  keys: {
    arrowleft: move,
    arrowright: move,
    arrowup: move,
    arrowdown: move,
    a: move,
    d: move,
    w: move,
    s: move,
    ' ': () => ({ kind: 'kick', args: { power: 1 } }),
    r: ({ state }) => (isGoalView(state) && state.phase === 'over' ? { kind: 'rematch', args: {} } : null),
  },
  keysHelp: [
    { keys: ['arrowup', 'arrowleft', 'arrowdown', 'arrowright'], help: 'run your disc (held: keep running)' },
    { keys: ['w', 'a', 's', 'd'], help: 'run your disc, as the arrows do' },
    { keys: [' '], help: 'kick the ball away from your disc, when it is within reach' },
    { keys: ['r'], help: 'rematch, once the match is over' },
  ],
})
