/*
 * Hoops: an example game in a directory of its own, loaded with `npm start -- --games
 * examples/games` (docs/games.md, "Games in their own directory"). Each player shoots balls from
 * the launcher on the left at an angle and a speed of their choosing; a ball that falls down
 * through the hoop on the right scores a point for its shooter. It imports only the SDK
 * (`concord/game`) and its own files, as a game outside this repository does, and shows a game
 * command with a JSON Schema, the engine's exact trig, a sensor and its events, state and events.
 */
import { box, circle, cos, defineGame, type PlainData, type SensorEvents, sin } from 'concord/game'
import { BALL_LIFE_TICKS, HOOP, LAUNCHER, SHOT_INTERVAL_TICKS } from './layout.ts'

interface Hoops {
  [key: string]: PlainData
  scores: Record<string, number> // player id -> points
  shooters: Record<string, number> // ball body id -> player id
  shotAt: Record<string, number> // ball body id -> room tick it was shot
  lastShot: Record<string, number> // player id -> room tick of the player's last shot
  hoopSensor: number // the sensor shape inside the hoop
}

export default defineGame<Hoops>({
  name: 'hoops',
  maxPlayers: 8,
  state: { scores: {}, shooters: {}, shotAt: {}, lastShot: {}, hoopSensor: 0 },
  setup(ctx) {
    ctx.createBody({ type: 'static', position: { x: 0, y: -0.5 }, shape: box(14, 0.5) })
    // The rim's two ends, the backboard, and a sensor across the hoop just below the rim.
    for (const dx of [-HOOP.halfWidth, HOOP.halfWidth])
      ctx.createBody({ type: 'static', position: { x: HOOP.x + dx, y: HOOP.y }, shape: box(0.05, 0.05) })
    ctx.createBody({
      type: 'static',
      position: { x: HOOP.x + HOOP.halfWidth + 0.3, y: HOOP.y + 1 },
      shape: box(0.1, 1.2),
    })
    const net = ctx.createBody({
      type: 'static',
      position: { x: HOOP.x, y: HOOP.y - 0.3 },
      shapes: [{ shape: box(HOOP.halfWidth - 0.1, 0.1), sensor: true }],
    })
    if (typeof net === 'number') ctx.state.hoopSensor = ctx.world.bodyShapes(net)[0]
  },
  commands: {
    shoot: {
      args: {
        type: 'object',
        properties: {
          angle: { type: 'number', minimum: 0, maximum: 1.5 },
          speed: { type: 'number', minimum: 1, maximum: 20 },
        },
        required: ['angle', 'speed'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { angle: number; speed: number }) {
        const last = ctx.state.lastShot[player]
        if (last !== undefined && ctx.tick - last < SHOT_INTERVAL_TICKS) return 'one shot every half second'
        const ball = ctx.createBody({
          type: 'dynamic',
          position: { x: LAUNCHER.x, y: LAUNCHER.y },
          linearVelocity: { x: args.speed * cos(args.angle), y: args.speed * sin(args.angle) },
          shape: circle(0.2),
          restitution: 0.5,
        })
        if (typeof ball === 'string') return ball
        ctx.state.shooters[ball] = player
        ctx.state.shotAt[ball] = ctx.tick
        ctx.state.lastShot[player] = ctx.tick
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
    // A ball entering the sensor while falling scores once for its shooter.
    const sensors = ctx.events.sensors as SensorEvents | null
    for (const e of sensors?.begin ?? []) {
      if (e.sensor !== ctx.state.hoopSensor) continue
      const ball = ctx.world.getShapeBody(e.visitor)
      const shooter = ctx.state.shooters[ball]
      if (shooter === undefined || ctx.world.getLinearVelocity(ball).y >= 0) continue
      if (ctx.state.scores[shooter] !== undefined) ctx.state.scores[shooter] += 1
      ctx.emit({ scored: shooter, ball })
      delete ctx.state.shooters[ball]
    }
    // Balls live five seconds; one that never scored is a miss.
    for (const key of Object.keys(ctx.state.shotAt).sort((a, b) => Number(a) - Number(b))) {
      if (ctx.tick - ctx.state.shotAt[key] < BALL_LIFE_TICKS) continue
      const ball = Number(key)
      const shooter = ctx.state.shooters[key]
      if (shooter !== undefined) ctx.emit({ missed: shooter, ball })
      if (ctx.world.hasBody(ball)) ctx.destroyBody(ball)
      delete ctx.state.shotAt[key]
      delete ctx.state.shooters[key]
    }
  },
})
