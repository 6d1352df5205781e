/*
 * Tug, a third tiny game written from docs/games.md only (issue 29's check that the guide is
 * enough): a ball on a floor; each player joins the left or the right team (by join order) and
 * sends `pull` to push the ball toward their side; a team scores when the ball passes x = +-6,
 * and the ball goes back to the middle. First to 3 wins; the winner is announced with ctx.emit.
 */
import { box, circle } from '../../../../engine/index.ts'
import { defineGame } from '../../../../games/index.ts'
import type { PlainData } from '../../../../shared/index.ts'

interface TugState {
  [key: string]: PlainData
  ball: number
  teams: Record<string, string>
  score: { left: number; right: number }
  winner: string | null
}

/** Points to win. */
export const TARGET = 3

export const tug = defineGame<TugState>({
  name: 'tug',
  minPlayers: 2,
  maxPlayers: 4,
  state: { ball: 0, teams: {}, score: { left: 0, right: 0 }, winner: null },
  setup(ctx) {
    ctx.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(20, 0.5) })
    const ball = ctx.createBody({ type: 'dynamic', position: { x: 0, y: 0.5 }, shape: circle(0.5) })
    if (typeof ball === 'number') ctx.state.ball = ball
  },
  commands: {
    pull: {
      args: {
        type: 'object',
        properties: { strength: { type: 'integer', minimum: 1, maximum: 5 } },
        required: ['strength'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { strength: number }) {
        if (ctx.state.winner !== null) return 'the match is over'
        const team = ctx.state.teams[player]
        if (team === undefined) return 'you are not on a team'
        const sign = team === 'left' ? -1 : 1
        const p = ctx.world.getPosition(ctx.state.ball)
        ctx.world.applyLinearImpulse(ctx.state.ball, { x: sign * args.strength, y: 0 }, p)
      },
    },
  },
  onJoin(ctx, player) {
    ctx.state.teams[player] = ctx.players.length % 2 === 1 ? 'left' : 'right'
  },
  onLeave(ctx, player) {
    delete ctx.state.teams[player]
  },
  tick(ctx) {
    if (ctx.state.winner !== null) return
    const p = ctx.world.getPosition(ctx.state.ball)
    if (Math.abs(p.x) < 6) return
    const side = p.x < 0 ? 'left' : 'right'
    ctx.state.score[side] += 1
    ctx.emit({ point: side, score: ctx.state.score })
    ctx.destroyBody(ctx.state.ball)
    const ball = ctx.createBody({ type: 'dynamic', position: { x: 0, y: 0.5 }, shape: circle(0.5) })
    if (typeof ball === 'number') ctx.state.ball = ball
    if (ctx.state.score[side] >= TARGET) {
      ctx.state.winner = side
      ctx.emit({ winner: side })
    }
  },
})
