/*
 * Ball drop, the tutorial game of docs/games.md: players drop balls from the top of the room
 * (one a second each); a ball that comes to rest on the target platform in the middle scores a
 * point for its dropper and is removed. It shows a game command with a JSON Schema, the state,
 * the PRNG, a tick rule and events, and doubles as the game the wire tests play.
 */
import { box, circle } from '../../engine/index.ts'
import type { PlainData } from '../../shared/index.ts'
import { defineGame } from '../game-api.ts'

/** Ball drop's state: points per player id, each ball's dropper, each player's last drop tick. */
export interface BallDropState {
  [key: string]: PlainData
  scores: Record<string, number>
  owners: Record<string, number>
  lastDrop: Record<string, number>
}

export const ballDrop = defineGame<BallDropState>({
  name: 'ball-drop',
  maxPlayers: 8,
  state: { scores: {}, owners: {}, lastDrop: {} },
  setup(ctx) {
    ctx.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5) })
    ctx.createBody({ type: 'static', position: { x: 0, y: 3 }, shape: box(1, 0.1) })
  },
  commands: {
    drop: {
      args: {
        type: 'object',
        properties: { x: { type: 'number', minimum: -8, maximum: 8 } },
        required: ['x'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { x: number }) {
        const last = ctx.state.lastDrop[player]
        if (last !== undefined && ctx.tick - last < 60) return 'one ball a second'
        const ball = ctx.createBody({
          type: 'dynamic',
          position: { x: args.x, y: 10 },
          shape: circle(ctx.random.range(0.25, 0.35)),
        })
        if (typeof ball === 'string') return ball
        ctx.state.owners[ball] = player
        ctx.state.lastDrop[player] = ctx.tick
      },
    },
  },
  onJoin(ctx, player) {
    ctx.state.scores[player] = 0
  },
  onLeave(ctx, player) {
    delete ctx.state.scores[player]
  },
  tick(ctx) {
    for (const key of Object.keys(ctx.state.owners).sort((a, b) => Number(a) - Number(b))) {
      const ball = Number(key)
      if (!ctx.world.hasBody(ball)) {
        delete ctx.state.owners[key]
        continue
      }
      const p = ctx.world.getPosition(ball)
      if (ctx.world.isAwake(ball) || Math.abs(p.x) > 1 || p.y < 3) continue
      const player = ctx.state.owners[key]
      if (ctx.state.scores[player] !== undefined) ctx.state.scores[player] += 1
      ctx.emit({ scored: player, ball })
      ctx.destroyBody(ball)
      delete ctx.state.owners[key]
    }
  },
})
