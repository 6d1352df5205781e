/*
 * A game loaded from a directory by the --games tests (tests/server/games/game-loader.test.ts,
 * tests/browser/loaded-game.test.ts): players drop marbles (a random radius from ctx.random) at a
 * chosen x; the rule counts, once a second, the marbles resting left of x = 0 in the state, and
 * the world spins a kinematic paddle with the engine's trig. It imports only the SDK and its own
 * file, as a game outside this repository would. Its named export `client` is its client module
 * (docs/games.md, "Client modules"): the page shows the drops, binds M to a drop at x = 0 and
 * marks the world point (0, 1) with a magenta square.
 */
import { box, circle, defineGame, defineGameClient, type PlainData, sin } from 'concord/game'
import { PADDLE_SPEED } from './rules.ts'

interface Marbles {
  [key: string]: PlainData
  dropped: number
  left: number
  paddle: number
}

export default defineGame<Marbles>({
  name: 'marbles',
  maxPlayers: 4,
  state: { dropped: 0, left: 0, paddle: 0 },
  setup(ctx) {
    ctx.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(12, 0.5) })
    const paddle = ctx.createBody({ type: 'kinematic', position: { x: 0, y: 2 }, shape: box(2, 0.1) })
    if (typeof paddle === 'number') ctx.state.paddle = paddle
  },
  commands: {
    drop: {
      args: {
        type: 'object',
        properties: { x: { type: 'number', minimum: -10, maximum: 10 } },
        required: ['x'],
        additionalProperties: false,
      },
      apply(ctx, _player, args: { x: number }) {
        const id = ctx.createBody({
          type: 'dynamic',
          position: { x: args.x, y: 8 },
          shape: circle(ctx.random.range(0.2, 0.4)),
          restitution: 0.3,
        })
        if (typeof id === 'string') return id
        ctx.state.dropped += 1
      },
    },
  },
  tick(ctx) {
    const paddle = ctx.state.paddle
    if (ctx.world.hasBody(paddle)) ctx.world.setAngularVelocity(paddle, PADDLE_SPEED * sin(ctx.tick / 60))
    if (ctx.tick % 60 !== 0) return
    let left = 0
    for (const id of ctx.world.bodyIds())
      if (ctx.world.getBodyType(id) === 'dynamic' && ctx.world.getPosition(id).x < 0) left++
    ctx.state.left = left
  },
})

/** The page's part: the drops so far (in lockstep pages, which have the state; '-' in snapshot pages), and M drops at 0. */
export const client = defineGameClient({
  game: 'marbles',
  hud(state) {
    const s = state as Marbles | null
    return [{ label: 'marbles', value: s ? `${s.dropped} dropped, ${s.left} left` : '-' }]
  },
  keys: { m: () => ({ kind: 'drop', args: { x: 0 } }) },
  // A magenta 8 px square centred on the world point (0, 1), drawn over the world.
  draw(ctx2d, toScreen) {
    const p = toScreen(0, 1)
    ctx2d.fillStyle = '#ff00ff'
    ctx2d.fillRect(p.x - 4, p.y - 4, 8, 8)
  },
})
