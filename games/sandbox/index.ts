/*
 * The sandbox game: Concord's building game (spawn, grab, pin, rope, delete, scenes, pause, step,
 * reset, gravity) written on the game module API; its commands are reusable by other games.
 */
export { MIN_TICKS_BETWEEN_LOADS, sandbox, sandboxCommands } from './sandbox-game.ts'
