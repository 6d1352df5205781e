/*
 * Goal: the two-team ball game (docs/games.md, "Goal"): discs steered by `run`, a ball kicked by
 * `kick`, goals as sensors, first to WIN_SCORE or the most goals when the clock runs out.
 */

export { type GoalView, goalClient } from './goal-client.ts'
export {
  BALL_DAMPING,
  BALL_DENSITY,
  BALL_RADIUS,
  FIELD_X,
  FIELD_Y,
  GOAL_DEPTH,
  GOAL_Y,
  type GoalPlayer,
  type GoalState,
  goal,
  KICK_COOLDOWN,
  KICK_IMPULSE,
  KICK_REACH,
  MATCH_TICKS,
  MAX_FORCE,
  MAX_SPEED,
  PLAYER_DENSITY,
  PLAYER_RADIUS,
  WIN_SCORE,
} from './goal-game.ts'
