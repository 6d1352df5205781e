/*
 * The game module API (docs/games.md is the guide): a game is one module whose default export is
 * `defineGame({...})`. The definition names the game, its player limits, its initial state (plain
 * data), a setup that builds the room's first world, its commands (each an argument schema in JSON
 * Schema and an apply function), optional join, leave and tick hooks, and an optional per-player
 * view. defineGame checks the definition (names, limits, schemas, state) and returns the SimGame
 * that shared/sim's RoomSimulation runs, on the server, in lockstep and predicting clients and in
 * replays alike.
 *
 * Built-in commands (the input message's kinds: spawn, grab, move, ...) are listed with
 * `builtin(kind, apply)` instead of a schema: the protocol validates them (PROTOCOL.md), and their
 * arguments are the command map itself. The sandbox (games/sandbox/) lists all of them; a game may
 * reuse any of the sandbox's (sandboxCommands) or wrap one with its own rule.
 */
import {
  BUILTIN_KINDS,
  type BuiltinKind,
  type Command,
  copyPlainData,
  type GameContext,
  type PlainData,
  type SimCommandDef,
  type SimGame,
} from '../shared/index.ts'
import { type ArgsSchema, compileArgs } from './args-schema.ts'

/** What an apply function or hook returns: nothing, or a reason that refuses the command. */
// biome-ignore lint/suspicious/noConfusingVoidType: an apply written without a return accepts
export type CommandResult = string | null | undefined | void

/** A game command: its arguments' schema and what it does. */
export interface GameCommandDefinition<S, A = unknown> {
  /** Absent: a game command (built-in commands come from builtin()). */
  builtin?: undefined
  /** JSON Schema of the arguments (an object); checked before apply sees them. */
  args: ArgsSchema
  /** A room control (refused when the room's controls are off, like the sandbox's pause). */
  control?: boolean
  /** Apply the command for `player`; return a reason to refuse it, before changing anything. */
  apply(ctx: GameContext<S>, player: number, args: A): CommandResult
}

/** A built-in command as a game lists it (see builtin()). */
export interface BuiltinCommandDefinition<S, K extends BuiltinKind = BuiltinKind> {
  builtin: K
  control?: boolean
  apply(ctx: GameContext<S>, player: number, cmd: Extract<Command, { k: K }>): CommandResult
}

/** A built-in command definition of any kind. */
export type AnyBuiltinDefinition<S> = { [K in BuiltinKind]: BuiltinCommandDefinition<S, K> }[BuiltinKind]

/** A game's definition, as passed to defineGame. */
export interface GameDefinition<S extends PlainData | undefined = undefined> {
  /** Lowercase letters, digits and dashes, 1 to 32 characters; rooms choose a game by it. */
  name: string
  /** Players the game needs to be played (informational for the game: ctx reads it); default 1. */
  minPlayers?: number
  /** Players a room of this game admits (joins beyond it are refused); default 64. */
  maxPlayers?: number
  /** The initial state (plain data, copied for each room); omit for a game without state. */
  state?: S
  /** Build the room's first world (the simulation starts with an empty world). */
  setup?(ctx: GameContext<S>, options: { scene: string }): void
  /** The commands by kind (custom kinds: a letter, then letters, digits or _, up to 32). */
  commands: Record<string, GameCommandDefinition<S> | AnyBuiltinDefinition<S>>
  onJoin?(ctx: GameContext<S>, player: number): void
  onLeave?(ctx: GameContext<S>, player: number): void
  /** After every world step (not while the room is paused); ctx.events holds the step's events. */
  tick?(ctx: GameContext<S>): void
  /**
   * What `player` sees of the game: plain data sent to that player only (a snapshot player gets
   * it in a `view` message when it changed, at most MAX_VIEW_BYTES as MessagePack; a lockstep or
   * predicting player computes it). Read the state; change nothing. Without it, every player's
   * view is the whole state (sent while it fits MAX_VIEW_BYTES).
   */
  view?(ctx: GameContext<S>, player: number): PlainData
}

/** A defined game: what RoomSimulation runs, with its definition kept for tools. */
export interface Game extends SimGame {
  readonly definition: GameDefinition<PlainData | undefined>
}

/** List a built-in command (see the file comment): `spawn: builtin('spawn', (ctx, p, cmd) => ...)`. */
export function builtin<S, K extends BuiltinKind>(
  kind: K,
  apply: (ctx: GameContext<S>, player: number, cmd: Extract<Command, { k: K }>) => CommandResult,
  options: { control?: boolean } = {},
): BuiltinCommandDefinition<S, K> {
  return { builtin: kind, apply, control: options.control }
}

/** A game's name: 1 to 32 lowercase letters, digits or dashes, starting with a letter. */
export const GAME_NAME = /^[a-z][a-z0-9-]{0,31}$/
const COMMAND_KIND = /^[A-Za-z][A-Za-z0-9_]{0,31}$/
const noCheck = (): null => null

function playerLimit(value: number | undefined, fallback: number, what: string): number {
  if (value === undefined) return fallback
  if (!Number.isSafeInteger(value) || value < 1 || value > 1024)
    throw new RangeError(`${what} must be an integer from 1 to 1024, got ${value}`)
  return value
}

/** Check a game definition and build the SimGame it describes; throws a RangeError naming what is wrong. */
export function defineGame<S extends PlainData | undefined = undefined>(definition: GameDefinition<S>): Game {
  const name = definition.name
  if (typeof name !== 'string' || !GAME_NAME.test(name))
    throw new RangeError(
      `game name ${JSON.stringify(name)} must be 1 to 32 lowercase letters, digits or dashes, starting with a letter`,
    )
  const minPlayers = playerLimit(definition.minPlayers, 1, `game ${name}: minPlayers`)
  const maxPlayers = playerLimit(definition.maxPlayers, 64, `game ${name}: maxPlayers`)
  if (minPlayers > maxPlayers)
    throw new RangeError(`game ${name}: minPlayers ${minPlayers} is more than maxPlayers ${maxPlayers}`)
  const initial =
    definition.state === undefined ? undefined : copyPlainData(definition.state, `game ${name} state`)
  const commands: Record<string, SimCommandDef> = {}
  for (const [kind, def] of Object.entries(definition.commands)) {
    if (typeof def?.apply !== 'function')
      throw new RangeError(`game ${name}: command ${kind} has no apply function`)
    const control = def.control === true
    const apply = def.apply as SimCommandDef['apply']
    if (def.builtin !== undefined) {
      if (def.builtin !== kind)
        throw new RangeError(`game ${name}: command ${kind} is listed as built-in ${String(def.builtin)}`)
      if (!(BUILTIN_KINDS as readonly string[]).includes(kind))
        throw new RangeError(`game ${name}: ${kind} is not a built-in command`)
      commands[kind] = { builtin: true, control, check: noCheck, apply }
      continue
    }
    if (!COMMAND_KIND.test(kind))
      throw new RangeError(
        `game ${name}: command kind ${JSON.stringify(kind)} must be a letter then up to 31 letters, digits or _`,
      )
    if ((BUILTIN_KINDS as readonly string[]).includes(kind) || kind === 'inspect')
      throw new RangeError(
        `game ${name}: command ${kind} is a built-in kind; list it with builtin('${kind}', ...)`,
      )
    commands[kind] = { builtin: false, control, check: compileArgs(kind, def.args), apply }
  }
  const hook = <F>(f: F | undefined, what: string): F | undefined => {
    if (f !== undefined && typeof f !== 'function')
      throw new RangeError(`game ${name}: ${what} must be a function`)
    return f
  }
  const setup = hook(definition.setup, 'setup')
  return Object.freeze({
    name,
    minPlayers,
    maxPlayers,
    commands: Object.freeze(commands),
    initialState: () => (initial === undefined ? undefined : copyPlainData(initial)),
    setup: (ctx: GameContext, options: { scene: string }) => setup?.(ctx as GameContext<S>, options),
    onJoin: hook(definition.onJoin, 'onJoin') as SimGame['onJoin'],
    onLeave: hook(definition.onLeave, 'onLeave') as SimGame['onLeave'],
    tick: hook(definition.tick, 'tick') as SimGame['tick'],
    view: hook(definition.view, 'view') as SimGame['view'],
    definition: definition as GameDefinition<PlainData | undefined>,
  })
}

/** Whether a module's default export looks like what defineGame returns. */
export function isGame(value: unknown): value is Game {
  if (typeof value !== 'object' || value === null) return false
  const g = value as Record<string, unknown>
  return (
    typeof g.name === 'string' &&
    typeof g.initialState === 'function' &&
    typeof g.setup === 'function' &&
    typeof g.commands === 'object' &&
    g.commands !== null &&
    typeof g.definition === 'object'
  )
}

/**
 * Where a game server started with --games serves game `name`'s module (GET /games/NAME.js), from
 * the server's ws, wss, http or https address.
 */
export function gameModuleUrl(serverUrl: string, name: string): string {
  const origin = new URL(serverUrl)
  if (origin.protocol === 'wss:') origin.protocol = 'https:'
  else if (origin.protocol === 'ws:') origin.protocol = 'http:'
  return `${origin.origin}/games/${encodeURIComponent(name)}.js`
}

/** The game `name` a module imported from `url` exports as its default; throws naming both otherwise. */
export function gameOfModule(module: { default?: unknown }, name: string, url: string): Game {
  const game = module.default
  if (!isGame(game) || game.name !== name) throw new Error(`${url} is not the game ${name}`)
  return game
}
