/*
 * Game modules: the API a game is written with (defineGame, builtin; game-api.ts), the argument
 * schemas' checker (@cfworker/json-schema; args-schema.ts), and the games this build ships, in one catalogue that
 * the server, the client, the bots and the replay tools look games up in by name. A game runs
 * inside shared/sim's RoomSimulation; games/ imports engine/ and shared/ only.
 */
import { ballDrop } from './ball-drop/index.ts'
import type { Game } from './game-api.ts'
import { sandbox } from './sandbox/index.ts'

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
  jointCommands,
  MAX_JOINT_MOTOR_SPEED,
  MIN_TICKS_BETWEEN_LOADS,
  sandbox,
  sandboxCommands,
} from './sandbox/index.ts'

/** The games this build ships, by name. */
export const GAMES: Readonly<Record<string, Game>> = Object.freeze({ sandbox, 'ball-drop': ballDrop })

/** The game of that name, or undefined (a GameCatalog for shared/'s simulations and replays). */
export function findGame(name: string): Game | undefined {
  return Object.hasOwn(GAMES, name) ? GAMES[name] : undefined
}
