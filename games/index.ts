/*
 * Game modules: the API a game is written with (defineGame, builtin; game-api.ts), the argument
 * schemas' checker (@cfworker/json-schema; args-schema.ts), and the games this build ships, in one catalogue that
 * the server, the client, the bots and the replay tools look games up in by name. A game runs
 * inside shared/sim's RoomSimulation; games/ imports engine/ and shared/ only.
 */
import { ballDrop } from './ball-drop/index.ts'
import type { Game } from './game-api.ts'
import { goal } from './goal/index.ts'
import { sandbox } from './sandbox/index.ts'
import { tower } from './tower/index.ts'

export { type ArgsChecker, type ArgsSchema, compileArgs } from './args-schema.ts'
export { type BallDropState, ballDrop } from './ball-drop/index.ts'
export {
  type BuiltinCommandDefinition,
  builtin,
  type CommandResult,
  defineGame,
  type Game,
  type GameCommandDefinition,
  type GameDefinition,
} from './game-api.ts'
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
} from './goal/index.ts'
export {
  editCommands,
  filterLayer,
  jointCommands,
  layerFilter,
  MAX_DELETE_MANY,
  MAX_JOINT_MOTOR_SPEED,
  MAX_LAYER,
  MIN_TICKS_BETWEEN_LOADS,
  sandbox,
  sandboxCommands,
} from './sandbox/index.ts'
export {
  type BuiltScene,
  buildScene,
  checkScene,
  type ParsedScene,
  parseScene,
  SCENE_FORMAT_VERSION,
  SCENE_LIMITS,
  SCENE_SCHEMA,
  type SceneFile,
  saveScene,
  sceneText,
} from './scenes/index.ts'
export {
  BLOCKS,
  DROP_CLEARANCE,
  DROP_COOLDOWN,
  FALL_LINE,
  FALL_PENALTY,
  LANE_SPACING,
  LANES,
  laneX,
  PLATFORM_HALF_WIDTH,
  ROUND_TICKS,
  SETTLED_SPEED,
  type TowerBlock,
  type TowerState,
  tower,
  towerScore,
} from './tower/index.ts'

/** The games this build ships, by name. */
export const GAMES: Readonly<Record<string, Game>> = Object.freeze({
  sandbox,
  'ball-drop': ballDrop,
  goal,
  tower,
})

/** The game of that name, or undefined (a GameCatalog for shared/'s simulations and replays). */
export function findGame(name: string): Game | undefined {
  return Object.hasOwn(GAMES, name) ? GAMES[name] : undefined
}
