/*
 * Goal: a two-team ball game seen from above (docs/games.md, "Goal"). Gravity is off; the field
 * is a walled rectangle with a goal mouth in each end wall and a goal box behind it. Each player
 * is a disc of their own that they steer with `run` (a target velocity the game reaches with a
 * capped force every tick) and that may `kick` the ball when touching it (an impulse along the
 * line from the disc's centre to the ball's, at most one kick every half second). A goal is a
 * sensor shape at the back of each goal box, placed so that it only overlaps a ball that is wholly
 * over the goal line; the game reads the step's sensor events, scores once per entry and puts the
 * ball back on the centre spot. The match starts when both teams have a player, and ends at
 * WIN_SCORE goals or after MATCH_TICKS; then `rematch` starts another.
 *
 * Every rule reads the world and the state in a defined order (players in join order, events in
 * the engine's shape-id order) with exact arithmetic only, so every replica scores alike.
 */
import { box, circle, type SensorEvents } from '../../engine/index.ts'
import type { GameContext, PlainData } from '../../shared/index.ts'
import { defineGame } from '../game-api.ts'

/** Goals that win the match. */
export const WIN_SCORE = 5
/** Length of a match (ticks): two minutes at 60 Hz. */
export const MATCH_TICKS = 7200
/** Field half-length along x and half-width along y (m); the goal lines are at x = +-FIELD_X. */
export const FIELD_X = 12
export const FIELD_Y = 7
/** Half-width of a goal mouth (m). */
export const GOAL_Y = 2
/** Depth of a goal box behind its line (m). */
export const GOAL_DEPTH = 1.5
/** Ball radius (m), density (kg/m^2), restitution and linear damping (1/s). */
export const BALL_RADIUS = 0.3
export const BALL_DENSITY = 1
export const BALL_DAMPING = 0.5
/** Player disc radius (m) and density (kg/m^2). */
export const PLAYER_RADIUS = 0.5
export const PLAYER_DENSITY = 1
/** Fastest target speed of a player (m/s) and the largest force that drives a disc to it (N). */
export const MAX_SPEED = 6
export const MAX_FORCE = 20
/** Kick impulse at full power (N s), the reach beyond touching (m), ticks between a player's kicks. */
export const KICK_IMPULSE = 2
export const KICK_REACH = 0.1
export const KICK_COOLDOWN = 30

/** Collision categories: walls, player discs, the ball, and the goal-line gates that keep discs out of the goals. */
const WALLS = 1
const DISCS = 2
const BALL = 4
const GATES = 8
const STEP = 1 / 60
/** Ticks per second (the room's fixed rate). */
const TICK_HZ = 60
/** The sensor's inner edge: a ball overlaps it only once wholly past the goal line. */
const SENSOR_INNER = FIELD_X + 2 * BALL_RADIUS
const WALL = 0.25

/** Kickoff spots of the left team's players (the right team's are mirrored), by slot. */
const SPOTS: ReadonlyArray<readonly [number, number]> = Object.freeze([
  Object.freeze([-4, 0] as const),
  Object.freeze([-7, 3] as const),
  Object.freeze([-7, -3] as const),
  Object.freeze([-10, 0] as const),
])

/** A player's disc, team, target velocity and last kick tick. */
export interface GoalPlayer {
  [key: string]: PlainData
  team: 'red' | 'blue'
  disc: number
  vx: number
  vy: number
  lastKick: number
}

/** The goal game's state. */
export interface GoalState {
  [key: string]: PlainData
  /** 'waiting' until both teams have a player, 'playing', then 'over'. */
  phase: 'waiting' | 'playing' | 'over'
  /** The ball's body id and its shape id (what the goal sensors see). */
  ball: number
  ballShape: number
  /** The sensor shape ids of the left goal (red defends it) and the right goal (blue defends it). */
  leftGoal: number
  rightGoal: number
  score: { red: number; blue: number }
  /** Room tick the match started at, or -1. */
  startTick: number
  /** 'red', 'blue' or 'draw' once the match is over, else null. */
  winner: string | null
  /** Players by id. */
  players: Record<string, GoalPlayer>
}

type Ctx = GameContext<GoalState>

function teamSize(ctx: Ctx, team: string): number {
  let n = 0
  for (const id of ctx.players) if (ctx.state.players[id]?.team === team) n++
  return n
}

/** A kickoff spot for the `slot`-th player of a team (a fifth player and more share the last spots). */
function spot(team: string, slot: number): { x: number; y: number } {
  const [x, y] = SPOTS[slot % SPOTS.length]
  const depth = slot < SPOTS.length ? 0 : -1
  return team === 'red' ? { x: x + depth, y } : { x: -x - depth, y }
}

function resetBall(ctx: Ctx): void {
  ctx.world.setTransform(ctx.state.ball, { x: 0, y: 0 }, 0)
  ctx.world.setLinearVelocity(ctx.state.ball, { x: 0, y: 0 })
  ctx.world.setAngularVelocity(ctx.state.ball, 0)
}

function endMatch(ctx: Ctx): void {
  const { red, blue } = ctx.state.score
  ctx.state.phase = 'over'
  ctx.state.winner = red > blue ? 'red' : blue > red ? 'blue' : 'draw'
  for (const id of ctx.players) {
    const p = ctx.state.players[id]
    if (p) {
      p.vx = 0
      p.vy = 0
    }
  }
  ctx.emit({ over: ctx.state.winner, score: { red, blue } })
}

/** The static walls: sides, end walls beside the goal mouths, and each goal box. */
function buildField(ctx: Ctx): void {
  const wall = (x: number, y: number, hw: number, hh: number): void => {
    ctx.createBody({ type: 'static', position: { x, y }, shape: box(hw, hh), restitution: 0.5 })
  }
  const endHalf = (FIELD_Y - GOAL_Y) / 2
  wall(0, FIELD_Y + WALL, FIELD_X + 2 * WALL, WALL)
  wall(0, -FIELD_Y - WALL, FIELD_X + 2 * WALL, WALL)
  for (const side of [-1, 1]) {
    wall(side * (FIELD_X + WALL), GOAL_Y + endHalf, WALL, endHalf)
    wall(side * (FIELD_X + WALL), -GOAL_Y - endHalf, WALL, endHalf)
    wall(side * (FIELD_X + GOAL_DEPTH + WALL), 0, WALL, GOAL_Y + 2 * WALL)
    wall(side * (FIELD_X + GOAL_DEPTH / 2), GOAL_Y + WALL, GOAL_DEPTH / 2, WALL)
    wall(side * (FIELD_X + GOAL_DEPTH / 2), -GOAL_Y - WALL, GOAL_DEPTH / 2, WALL)
    // The goal line: a gate only discs collide with, so the ball goes in and the players stay out.
    ctx.createBody({
      type: 'static',
      position: { x: side * (FIELD_X + WALL), y: 0 },
      shapes: [{ shape: box(WALL, GOAL_Y), filter: { categoryBits: GATES, maskBits: DISCS, groupIndex: 0 } }],
    })
  }
}

/** A goal sensor from SENSOR_INNER to the back of the goal box on one side; its shape id. */
function goalSensor(ctx: Ctx, side: number): number {
  const hw = (FIELD_X + GOAL_DEPTH - SENSOR_INNER) / 2
  const body = ctx.createBody({
    type: 'static',
    position: { x: side * (SENSOR_INNER + hw), y: 0 },
    shapes: [{ shape: box(hw, GOAL_Y), sensor: true }],
  })
  if (typeof body === 'string') throw new Error(`goal sensor refused: ${body}`)
  return ctx.world.bodyShapes(body)[0]
}

/** Score the first goal of this step's sensor events (a goal puts the ball back at once). */
function checkGoals(ctx: Ctx): void {
  const sensors = ctx.events.sensors as SensorEvents | null
  if (sensors === null) return
  for (const e of sensors.begin) {
    if (e.visitor !== ctx.state.ballShape) continue
    if (e.sensor !== ctx.state.leftGoal && e.sensor !== ctx.state.rightGoal) continue
    resetBall(ctx)
    if (ctx.state.phase !== 'playing') return
    const team = e.sensor === ctx.state.leftGoal ? 'blue' : 'red'
    ctx.state.score[team] += 1
    ctx.emit({ goal: team, score: { red: ctx.state.score.red, blue: ctx.state.score.blue } })
    if (ctx.state.score[team] >= WIN_SCORE) endMatch(ctx)
    return
  }
}

/** Push each disc toward its target velocity with at most MAX_FORCE (as an impulse over one step). */
function drive(ctx: Ctx): void {
  const v = { x: 0, y: 0 }
  const c = { x: 0, y: 0 }
  const limit = MAX_FORCE * STEP
  for (const id of ctx.players) {
    const p = ctx.state.players[id]
    if (!p || !ctx.world.hasBody(p.disc)) continue
    ctx.world.getLinearVelocity(p.disc, v)
    const m = ctx.world.getMass(p.disc)
    let jx = m * (p.vx - v.x)
    let jy = m * (p.vy - v.y)
    const size = Math.sqrt(jx * jx + jy * jy)
    if (size < 1e-9) continue
    if (size > limit) {
      jx *= limit / size
      jy *= limit / size
    }
    ctx.world.applyLinearImpulse(p.disc, { x: jx, y: jy }, ctx.world.getWorldCenter(p.disc, c))
  }
}

export const goal = defineGame<GoalState>({
  name: 'goal',
  minPlayers: 2,
  maxPlayers: 8,
  state: {
    phase: 'waiting',
    ball: 0,
    ballShape: 0,
    leftGoal: 0,
    rightGoal: 0,
    score: { red: 0, blue: 0 },
    startTick: -1,
    winner: null,
    players: {},
  },
  setup(ctx) {
    ctx.setGravity(0, 0)
    buildField(ctx)
    ctx.state.leftGoal = goalSensor(ctx, -1)
    ctx.state.rightGoal = goalSensor(ctx, 1)
    const ball = ctx.createBody({
      type: 'dynamic',
      position: { x: 0, y: 0 },
      shapes: [
        {
          shape: circle(BALL_RADIUS),
          density: BALL_DENSITY,
          restitution: 0.6,
          friction: 0.2,
          filter: { categoryBits: BALL, maskBits: WALLS | DISCS | BALL, groupIndex: 0 },
        },
      ],
      linearDamping: BALL_DAMPING,
      angularDamping: 1,
      bullet: true,
    })
    if (typeof ball === 'string') throw new Error(`ball refused: ${ball}`)
    ctx.state.ball = ball
    ctx.state.ballShape = ctx.world.bodyShapes(ball)[0]
  },
  commands: {
    run: {
      args: {
        type: 'object',
        properties: {
          x: { type: 'number', minimum: -MAX_SPEED, maximum: MAX_SPEED },
          y: { type: 'number', minimum: -MAX_SPEED, maximum: MAX_SPEED },
        },
        required: ['x', 'y'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { x: number; y: number }) {
        if (ctx.state.phase === 'over') return 'the match is over'
        const p = ctx.state.players[player]
        if (!p) return 'you have no disc'
        const speed = Math.sqrt(args.x * args.x + args.y * args.y)
        const scale = speed > MAX_SPEED ? MAX_SPEED / speed : 1
        p.vx = args.x * scale
        p.vy = args.y * scale
      },
    },
    kick: {
      args: {
        type: 'object',
        properties: { power: { type: 'number', minimum: 0.1, maximum: 1 } },
        required: ['power'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { power: number }) {
        if (ctx.state.phase === 'over') return 'the match is over'
        const p = ctx.state.players[player]
        if (!p) return 'you have no disc'
        if (p.lastKick >= 0 && ctx.tick - p.lastKick < KICK_COOLDOWN) return 'one kick every half second'
        const ball = ctx.world.getPosition(ctx.state.ball)
        const disc = ctx.world.getPosition(p.disc)
        const dx = ball.x - disc.x
        const dy = ball.y - disc.y
        const d = Math.sqrt(dx * dx + dy * dy)
        if (d - PLAYER_RADIUS - BALL_RADIUS > KICK_REACH || d === 0) return 'the ball is out of reach'
        const j = (args.power * KICK_IMPULSE) / d
        ctx.world.applyLinearImpulse(ctx.state.ball, { x: dx * j, y: dy * j }, ball)
        p.lastKick = ctx.tick
      },
    },
    rematch: {
      args: { type: 'object', properties: {}, additionalProperties: false },
      apply(ctx) {
        if (ctx.state.phase !== 'over') return 'the match is not over'
        ctx.state.score.red = 0
        ctx.state.score.blue = 0
        ctx.state.winner = null
        ctx.state.phase = 'waiting'
        ctx.state.startTick = -1
        resetBall(ctx)
        const slots = { red: 0, blue: 0 }
        for (const id of ctx.players) {
          const p = ctx.state.players[id]
          if (!p) continue
          ctx.world.setTransform(p.disc, spot(p.team, slots[p.team]++), 0)
          ctx.world.setLinearVelocity(p.disc, { x: 0, y: 0 })
        }
      },
    },
  },
  onJoin(ctx, player) {
    const red = teamSize(ctx, 'red')
    const blue = teamSize(ctx, 'blue')
    const team = red <= blue ? 'red' : 'blue'
    const disc = ctx.createBody({
      type: 'dynamic',
      position: spot(team, team === 'red' ? red : blue),
      shapes: [
        {
          shape: circle(PLAYER_RADIUS),
          density: PLAYER_DENSITY,
          restitution: 0.2,
          friction: 0.2,
          filter: { categoryBits: DISCS, maskBits: WALLS | DISCS | BALL | GATES, groupIndex: 0 },
        },
      ],
      fixedRotation: true,
    })
    // At the body limit the player joins without a disc (and every command says so).
    if (typeof disc === 'string') return
    ctx.state.players[player] = { team, disc, vx: 0, vy: 0, lastKick: -1 }
  },
  onLeave(ctx, player) {
    const p = ctx.state.players[player]
    if (!p) return
    ctx.destroyBody(p.disc)
    delete ctx.state.players[player]
  },
  view(ctx, player) {
    const s = ctx.state
    const elapsed = s.phase === 'playing' ? ctx.tick - s.startTick : s.phase === 'over' ? MATCH_TICKS : 0
    return {
      score: { red: s.score.red, blue: s.score.blue },
      phase: s.phase,
      secondsLeft: Math.ceil(Math.max(0, MATCH_TICKS - elapsed) / TICK_HZ),
      team: s.players[player]?.team ?? null,
      winner: s.winner,
      disc: s.players[player]?.disc ?? null,
    }
  },
  tick(ctx) {
    if (ctx.state.phase === 'waiting' && teamSize(ctx, 'red') > 0 && teamSize(ctx, 'blue') > 0) {
      ctx.state.phase = 'playing'
      ctx.state.startTick = ctx.tick
      resetBall(ctx)
      ctx.emit({ kickoff: ctx.tick })
    }
    checkGoals(ctx)
    if (ctx.state.phase === 'playing' && ctx.tick - ctx.state.startTick >= MATCH_TICKS) endMatch(ctx)
    drive(ctx)
  },
})
