/*
 * The game SDK: everything a game module written outside this repository imports, as the one
 * module `concord/game` (docs/games.md, "Games in their own directory"). A server started with
 * `--games DIR` bundles each game with esbuild, resolving `concord/game` to this file, so a game
 * gets the very engine and game API the server runs; tsconfig.json maps the same name for the
 * type checker. It is games/index.ts's API plus the engine pieces game rules use (shapes, the
 * exact trig, the constants and types), without the catalogue.
 */

export {
  atan2,
  type BodyDef,
  type BodyId,
  type BodyType,
  box,
  capsule,
  circle,
  cos,
  type JointDef,
  type JointId,
  PI,
  Prng,
  polygon,
  regularPolygon,
  type SensorEvent,
  type SensorEvents,
  type ShapeDef,
  STEP_SECONDS,
  segment,
  sin,
  TWO_PI,
  type Vec2,
  type World,
  wrapAngle,
} from '../engine/index.ts'
export type { Command, GameContext, PlainData } from '../shared/index.ts'
export { MAX_VIEW_BYTES } from '../shared/index.ts'
export type { ArgsSchema } from './args-schema.ts'
export {
  type AnyBuiltinDefinition,
  type BuiltinCommandDefinition,
  builtin,
  type CommandResult,
  defineGame,
  type Game,
  type GameCommandDefinition,
  type GameDefinition,
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
  type PointerBindings,
  type PointerInput,
} from './game-client.ts'
export { MIN_TICKS_BETWEEN_LOADS, sandboxCommands } from './sandbox/index.ts'
