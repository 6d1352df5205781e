/*
 * The tower game's client module (docs/games.md, "Client modules"): the HUD shows the round's time
 * left, this player's tower height with their blocks and fallen blocks, the best height in the room
 * and the winners once the round is over (R then restarts), from the game's per-player view.
 */
import { clockText, defineGameClient } from '../game-client.ts'

/** The tower game's view of one player (tower-game.ts `view`). */
export interface TowerView {
  phase: 'waiting' | 'building' | 'over'
  secondsLeft: number
  /** Tower heights (m, to the centimetre) by player id. */
  heights: Record<string, number>
  blocks: number
  fallen: number
  winners: number[]
}

function isTowerView(state: unknown): state is TowerView {
  const v = state as TowerView | null
  return (
    typeof v === 'object' && v !== null && typeof v.heights === 'object' && typeof v.secondsLeft === 'number'
  )
}

/** Metres to two decimals without locale functions (the view rounds heights to the centimetre). */
export function metres(m: number): string {
  const cm = Math.round(Math.abs(m) * 100)
  const rest = cm % 100
  return `${m < 0 && cm > 0 ? '-' : ''}${Math.floor(cm / 100)}.${rest < 10 ? '0' : ''}${rest} m`
}

export const towerClient = defineGameClient({
  game: 'tower',
  hud(state, me) {
    if (!isTowerView(state)) return []
    let best = 0
    for (const h of Object.values(state.heights)) best = Math.max(best, h)
    const items = [
      { label: 'time', value: state.phase === 'waiting' ? 'waiting' : clockText(state.secondsLeft) },
      { label: 'height', value: metres(state.heights[me] ?? 0) },
      { label: 'best', value: metres(best) },
      { label: 'blocks', value: `${state.blocks} placed, ${state.fallen} fallen` },
    ]
    if (state.phase === 'over')
      items.push({
        label: 'round',
        value: `${state.winners.includes(me) ? 'you win' : `won by ${state.winners.join(', ')}`} (R: again)`,
      })
    return items
  },
  keys: {
    r: ({ state }) => (isTowerView(state) && state.phase === 'over' ? { kind: 'restart', args: {} } : null),
  },
  keysHelp: [{ keys: ['r'], help: 'start a new round, once the round is over' }],
})
