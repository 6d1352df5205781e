/*
 * Scripted players for the games' tests: pure functions of a room simulation's world and state that
 * return the commands a player sends this tick, so the same script plays a match in a Node unit
 * test, a browser page (the cross-engine run bundles this file) and against a real server (where
 * the script reads a lockstep mirror of the room). They use only exact arithmetic, so a script
 * plays alike everywhere.
 */
import { Prng } from '../../engine/index.ts'
import { BALL_RADIUS, FIELD_X, type GoalState, PLAYER_RADIUS, type TowerState } from '../../games/index.ts'
import type { GameCommand, RoomSimulation } from '../../shared/index.ts'

const cmd = (kind: string, a: GameCommand['a']): GameCommand => ({ k: 'cmd', kind, a })

/**
 * A goal striker: runs to the spot behind the ball on the line from the goal it attacks, then
 * through the ball, kicking at full power when in reach. Sends `run` every `runEvery`th tick (4:
 * a real client's input rate; 1 for a script called at its own pace) and `kick` when it would land.
 */
export function strikerCommands(sim: RoomSimulation, player: number, runEvery = 4): GameCommand[] {
  const state = sim.gameState as GoalState
  const me = state.players[player]
  if (!me || state.phase === 'over' || !sim.world.hasBody(me.disc)) return []
  const out: GameCommand[] = []
  const b = sim.world.getPosition(state.ball)
  const d = sim.world.getPosition(me.disc)
  const goalX = me.team === 'red' ? FIELD_X + 0.75 : -FIELD_X - 0.75
  let ux = goalX - b.x
  let uy = -b.y
  const ul = Math.sqrt(ux * ux + uy * uy)
  ux /= ul
  uy /= ul
  const behind = BALL_RADIUS + PLAYER_RADIUS + 0.05
  let tx = b.x - ux * behind
  let ty = b.y - uy * behind
  // Not behind the ball yet: go round it, on the side the disc is on, not through it.
  const ahead = (d.x - b.x) * ux + (d.y - b.y) * uy
  if (ahead > -0.4) {
    const side = (d.x - b.x) * -uy + (d.y - b.y) * ux >= 0 ? 1 : -1
    tx += -uy * side * 1.5
    ty += ux * side * 1.5
  }
  const ex = tx - d.x
  const ey = ty - d.y
  const miss = Math.sqrt(ex * ex + ey * ey)
  const bx = b.x - d.x
  const by = b.y - d.y
  const gap = Math.sqrt(bx * bx + by * by) - BALL_RADIUS - PLAYER_RADIUS
  if (gap < 0.08 && (bx * ux + by * uy) / (gap + BALL_RADIUS + PLAYER_RADIUS) > 0.9) {
    if (me.lastKick < 0 || sim.tick - me.lastKick >= 30) out.push(cmd('kick', { power: 1 }))
  }
  if (sim.tick % runEvery === 0) {
    // Far from the spot behind the ball: go there (slowing down near it); on it: go through the ball.
    const speed = miss > 0.3 ? Math.min(6, 1 + 4 * miss) : 6
    const vx = miss > 0.3 ? ex / miss : ux
    const vy = miss > 0.3 ? ey / miss : uy
    out.push(cmd('run', { x: vx * speed, y: vy * speed }))
  }
  return out
}

/** A goal player who keeps to a corner of its own half (out of the ball's way); `run` every `every`th tick. */
export function benchCommands(sim: RoomSimulation, player: number, every = 30): GameCommand[] {
  const state = sim.gameState as GoalState
  const me = state.players[player]
  if (!me || state.phase === 'over' || sim.tick % every !== 0) return []
  const d = sim.world.getPosition(me.disc)
  const cx = me.team === 'red' ? -8 : 8
  const dx = cx - d.x
  const dy = 6 - d.y
  const l = Math.sqrt(dx * dx + dy * dy)
  return [cmd('run', l < 0.2 ? { x: 0, y: 0 } : { x: (dx / l) * 3, y: (dy / l) * 3 })]
}

/**
 * A tower builder: a block every `every` ticks, its kind and offset (`spread` m either side of the
 * lane centre) drawn from a script PRNG seeded by the player and the tick, so the script keeps no
 * state and any copy of a room gets the same commands.
 */
export function builderCommands(
  sim: RoomSimulation,
  player: number,
  every: number,
  spread: number,
): GameCommand[] {
  const state = sim.gameState as TowerState
  if (state.phase === 'over' || sim.tick % every !== 0) return []
  const rng = new Prng((Math.imul(player, 0x9e3779b1) ^ sim.tick) >>> 0)
  const kind = BLOCK_KINDS[rng.int(BLOCK_KINDS.length)]
  return [cmd('block', { kind, x: rng.range(-spread, spread) })]
}

const BLOCK_KINDS = ['square', 'slab', 'post'] as const
