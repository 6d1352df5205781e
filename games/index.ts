/*
 * Game modules: the API a game is written with (defineGame, builtin; game-api.ts), the argument
 * schemas' checker (@cfworker/json-schema; args-schema.ts), and the games this build ships, in one catalogue that
 * the server, the client, the bots and the replay tools look games up in by name; and the games'
 * client modules (defineGameClient; game-client.ts), which pages look up by the room's game. A game runs
 * inside shared/sim's RoomSimulation; games/ imports engine/ and shared/ only.
 */
import { ballDrop } from './ball-drop/index.ts'
import type { Game } from './game-api.ts'
import type { GameClient } from './game-client.ts'
import { goal, goalClient } from './goal/index.ts'
import { sandbox } from './sandbox/index.ts'
import { tower, towerClient } from './tower/index.ts'

export { type ArgsChecker, type ArgsSchema, compileArgs } from './args-schema.ts'
export { type BallDropState, ballDrop } from './ball-drop/index.ts'
export {
  type BuiltinCommandDefinition,
  builtin,
  type CommandResult,
  defineGame,
  GAME_NAME,
  type Game,
  type GameCommandDefinition,
  type GameDefinition,
  gameModuleUrl,
  gameOfModule,
  isGame,
} from './game-api.ts'
export {
  clockText,
  defineGameClient,
  type GameClient,
  type GameClientCommand,
  type GameClientDefinition,
  type HudItem,
  type KeyBinding,
  type KeyHelp,
  type KeyInput,
  keyCommand,
  MAX_HUD_ITEMS,
  POINTER_MOVE_INTERVAL,
  type PointerBindings,
  type PointerInput,
  type ToScreen,
} from './game-client.ts'
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
  type GoalView,
  goal,
  goalClient,
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
  EDITABLE_JOINT_SETTINGS,
  type EditJointArgs,
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
  saveRoomScene,
  saveScene,
  sceneForRoom,
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
  metres,
  PLATFORM_HALF_WIDTH,
  ROUND_TICKS,
  SETTLED_SPEED,
  type TowerBlock,
  type TowerState,
  type TowerView,
  tower,
  towerClient,
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

/** The client modules of the games this build ships, by game name (docs/games.md, "Client modules"). */
export const GAME_CLIENTS: Readonly<Record<string, GameClient>> = Object.freeze({
  goal: goalClient,
  tower: towerClient,
})

/** The client module of the game of that name, or undefined: the page then shows no game panel. */
export function findGameClient(name: string): GameClient | undefined {
  return Object.hasOwn(GAME_CLIENTS, name) ? GAME_CLIENTS[name] : undefined
}
