/*
 * The goal game's client module (docs/games.md, "Client modules"): the HUD shows the score (red -
 * blue), the match clock and the phase or winner, from the game's per-player view; the arrow keys
 * and WASD steer this player's disc with `run` (the held keys' direction at full speed, sent again
 * whenever one of them goes down or up), Space kicks at full power (the room refuses a kick out of
 * reach), and R asks for a rematch once the match is over. A press on the field (mouse, pen or
 * finger) runs the disc toward the pointer at full speed while held, re-aimed as it moves; letting
 * go stops it.
 */
import {
  clockText,
  defineGameClient,
  type GameClientCommand,
  type KeyBinding,
  type KeyInput,
  type PointerInput,
} from '../game-client.ts'
import { MAX_SPEED, PLAYER_RADIUS } from './goal-game.ts'

/** The goal game's view of one player (goal-game.ts `view`). */
export interface GoalView {
  score: { red: number; blue: number }
  phase: 'waiting' | 'playing' | 'over'
  secondsLeft: number
  team: 'red' | 'blue' | null
  winner: string | null
  /** This player's disc (a body id), null for a player without one. */
  disc: number | null
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

const clampSpeed = (v: number): number => Math.max(-MAX_SPEED, Math.min(MAX_SPEED, v))

/**
 * `run` toward the pointer at full speed from where the page draws this player's disc (a pointer
 * on the disc: stand still); null (the press is the page tool's) without a disc or once the match
 * is over.
 */
export function runToward(input: PointerInput): GameClientCommand | null {
  const state = input.state
  if (!isGoalView(state) || state.disc === null || state.disc === undefined || state.phase === 'over')
    return null
  const at = input.position(state.disc)
  if (!at) return null
  const dx = input.x - at.x
  const dy = input.y - at.y
  const distance = Math.sqrt(dx * dx + dy * dy)
  if (distance <= PLAYER_RADIUS) return { kind: 'run', args: { x: 0, y: 0 } }
  const k = MAX_SPEED / distance
  return { kind: 'run', args: { x: clampSpeed(dx * k), y: clampSpeed(dy * k) } }
}

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
  pointer: {
    down: runToward,
    move: runToward,
    up: ({ state }) =>
      isGoalView(state) && state.disc !== null ? { kind: 'run', args: { x: 0, y: 0 } } : null,
    help: 'press and hold on the field: your disc runs toward the pointer; let go: it stops',
  },
  keysHelp: [
    { keys: ['arrowup', 'arrowleft', 'arrowdown', 'arrowright'], help: 'run your disc (held: keep running)' },
    { keys: ['w', 'a', 's', 'd'], help: 'run your disc, as the arrows do' },
    { keys: [' '], help: 'kick the ball away from your disc, when it is within reach' },
    { keys: ['r'], help: 'rematch, once the match is over' },
  ],
})
