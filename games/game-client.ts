/*
 * A game's client module (docs/games.md, "Client modules"): what a page shows and binds for rooms
 * of one game, beside the world it draws anyway. `defineGameClient({...})` names the game and
 * lists optional parts: HUD items (a few label/value strings shown in the page's game panel), key
 * bindings (a key turns into one of the game's commands, with a line of Help each), pointer
 * bindings (a press, drag and release of a mouse, pen or finger turn into commands), and extra
 * drawing after the world. Each part reads `state`, the game state the page has: the player's
 * `view` (snapshot pages receive it, lockstep and predicting pages compute it), which for a game
 * without `view` is its whole state; null for a game without state or before the first view.
 *
 * A client module runs in the page only, never in the simulation: it decides what to send, and the
 * room's rules decide what happens. It still lives in the game's folder and passes the same static
 * check as the game (no clock, no locale functions), so its text is the same in every browser.
 */
import type { PlainData } from '../shared/index.ts'
import { GAME_NAME } from './game-api.ts'

/** One HUD item: a short label and its value, both plain strings (e.g. 'score', '2 - 1'). */
export interface HudItem {
  label: string
  value: string
}

/** A game command a key sends: the game's command kind and its arguments. */
export interface GameClientCommand {
  kind: string
  args: { [key: string]: PlainData }
}

/** What a key binding reads: the state, this player's id, and the game's bound keys held now (lower case). */
export interface KeyInput {
  state: unknown
  me: number
  held: ReadonlySet<string>
}

/** A key binding: the command to send (or null for none) when the key goes down, and optionally up. */
export type KeyBinding =
  | ((input: KeyInput) => GameClientCommand | null)
  | {
      down(input: KeyInput): GameClientCommand | null
      up?(input: KeyInput): GameClientCommand | null
    }

/**
 * What a pointer binding reads: the state, this player's id, the pointer's world point (m, y up),
 * and `position(id)`, where the page draws a body now (null for a body it does not have).
 */
export interface PointerInput {
  state: unknown
  me: number
  x: number
  y: number
  position(id: number): { x: number; y: number } | null
}

/**
 * Pointer bindings (mouse, pen and touch alike): `down` is asked first when one pointer presses
 * the world; a command it returns is sent and the gesture is the game's (the page's tool does not
 * see it). While it is held, `move` is asked every POINTER_MOVE_INTERVAL ms with the pointer's
 * latest point (it may stay put while the world moves), and what it returns is sent when it differs
 * from the last command sent; `up` when it is lifted or cancelled (a second finger, the page losing
 * focus). A null from `down` leaves the press to the page's tool.
 */
export interface PointerBindings {
  down?(input: PointerInput): GameClientCommand | null
  move?(input: PointerInput): GameClientCommand | null
  up?(input: PointerInput): GameClientCommand | null
  /** What the gesture does, for the page's Help (e.g. 'press and hold: run toward the pointer'). */
  help?: string
}

/** How often a held pointer's `move` is asked (ms): at most one command per interval. */
export const POINTER_MOVE_INTERVAL = 50

/** One row of the page's Help for a game: the keys (as in `keys`) and what they do, e.g. 'kick the ball'. */
export interface KeyHelp {
  keys: readonly string[]
  help: string
}

/** The 2D context a client draws with, and the world-to-screen mapping (m to CSS px, y up to y down). */
export type ToScreen = (x: number, y: number) => { x: number; y: number }

/** A game's client module, as passed to defineGameClient. */
export interface GameClientDefinition {
  /** The game's name (games/index.ts GAMES); the page uses the module in rooms of this game. */
  game: string
  /** HUD items for the game panel, refreshed a few times a second; at most MAX_HUD_ITEMS are shown. */
  hud?(state: unknown, me: number): HudItem[]
  /** Bindings by KeyboardEvent.key in lower case (' ' for Space, 'arrowup' ...); they win over the page's shortcuts. */
  keys?: Readonly<Record<string, KeyBinding>>
  /**
   * What the keys do, for the page's Help (in this order): each entry names bound keys and says
   * in a few words what they do. Keys no entry names are listed last as sending a game command.
   */
  keysHelp?: readonly KeyHelp[]
  /** Pointer bindings: a press the game takes (its `down` returns a command) is not the page tool's. */
  pointer?: PointerBindings
  /** Extra drawing after the world, in screen coordinates (CSS px). */
  draw?(ctx: CanvasRenderingContext2D, toScreen: ToScreen, state: unknown, me: number): void
}

/** A checked client module (what defineGameClient returns). */
export interface GameClient {
  readonly game: string
  hud?(state: unknown, me: number): HudItem[]
  readonly keys: Readonly<Record<string, KeyBinding>>
  /** Every bound key in one row or another: the definition's keysHelp, then the keys it left out. */
  readonly keysHelp: readonly KeyHelp[]
  readonly pointer?: PointerBindings
  draw?(ctx: CanvasRenderingContext2D, toScreen: ToScreen, state: unknown, me: number): void
}

/** HUD items the game panel shows at most. */
export const MAX_HUD_ITEMS = 8

/** The longest keysHelp text (characters). */
export const MAX_KEY_HELP = 120

/** Check a client module's definition; throws a RangeError naming what is wrong. */
export function defineGameClient(definition: GameClientDefinition): GameClient {
  const name = definition.game
  if (typeof name !== 'string' || !GAME_NAME.test(name))
    throw new RangeError(`game client: game ${JSON.stringify(name)} is not a game name`)
  for (const part of ['hud', 'draw'] as const) {
    if (definition[part] !== undefined && typeof definition[part] !== 'function')
      throw new RangeError(`game client ${name}: ${part} must be a function`)
  }
  const keys: Record<string, KeyBinding> = {}
  for (const [key, binding] of Object.entries(definition.keys ?? {})) {
    if (key.length === 0 || key !== key.toLowerCase())
      throw new RangeError(
        `game client ${name}: key ${JSON.stringify(key)} must be a KeyboardEvent.key in lower case`,
      )
    const ok =
      typeof binding === 'function' ||
      (typeof binding === 'object' &&
        binding !== null &&
        typeof binding.down === 'function' &&
        (binding.up === undefined || typeof binding.up === 'function'))
    if (!ok)
      throw new RangeError(
        `game client ${name}: key ${JSON.stringify(key)} must be a function or { down, up? }`,
      )
    keys[key] = binding
  }
  return Object.freeze({
    game: name,
    hud: definition.hud,
    keys: Object.freeze(keys),
    keysHelp: checkKeysHelp(name, keys, definition.keysHelp),
    pointer: checkPointer(name, definition.pointer),
    draw: definition.draw,
  })
}

/** Check pointer bindings: functions where given, a short help text; returns them frozen. */
function checkPointer(name: string, pointer: PointerBindings | undefined): PointerBindings | undefined {
  if (pointer === undefined) return undefined
  if (typeof pointer !== 'object' || pointer === null)
    throw new RangeError(`game client ${name}: pointer must be { down?, move?, up?, help? }`)
  for (const part of ['down', 'move', 'up'] as const) {
    if (pointer[part] !== undefined && typeof pointer[part] !== 'function')
      throw new RangeError(`game client ${name}: pointer.${part} must be a function`)
  }
  if (!pointer.down) throw new RangeError(`game client ${name}: pointer needs down (a gesture starts there)`)
  const help = pointer.help
  if (help !== undefined && (typeof help !== 'string' || help.length === 0 || help.length > MAX_KEY_HELP))
    throw new RangeError(
      `game client ${name}: pointer.help must be a string of 1 to ${MAX_KEY_HELP} characters`,
    )
  return Object.freeze({ down: pointer.down, move: pointer.move, up: pointer.up, help })
}

/** Check keysHelp against the bound keys; returns it with a last row for the keys it left out. */
function checkKeysHelp(
  name: string,
  keys: Readonly<Record<string, KeyBinding>>,
  keysHelp: readonly KeyHelp[] | undefined,
): readonly KeyHelp[] {
  if (keysHelp !== undefined && !Array.isArray(keysHelp))
    throw new RangeError(`game client ${name}: keysHelp must be an array of { keys, help }`)
  const rows: KeyHelp[] = []
  const named = new Set<string>()
  for (const [i, row] of (keysHelp ?? []).entries()) {
    const where = `game client ${name}: keysHelp[${i}]`
    if (typeof row !== 'object' || row === null || !Array.isArray(row.keys) || row.keys.length === 0)
      throw new RangeError(`${where} must be { keys: [at least one bound key], help }`)
    for (const key of row.keys) {
      if (typeof key !== 'string' || !(key in keys))
        throw new RangeError(`${where}: key ${JSON.stringify(key)} is not one of the bound keys`)
      named.add(key)
    }
    if (typeof row.help !== 'string' || row.help.length === 0 || row.help.length > MAX_KEY_HELP)
      throw new RangeError(`${where}: help must be a string of 1 to ${MAX_KEY_HELP} characters`)
    rows.push(Object.freeze({ keys: Object.freeze([...row.keys]), help: row.help }))
  }
  const rest = Object.keys(keys).filter((key) => !named.has(key))
  if (rest.length > 0) rows.push(Object.freeze({ keys: Object.freeze(rest), help: `a ${name} command` }))
  return Object.freeze(rows)
}

/** The command a binding sends for a key going down (`down`) or up; null for none. */
export function keyCommand(binding: KeyBinding, down: boolean, input: KeyInput): GameClientCommand | null {
  if (typeof binding === 'function') return down ? binding(input) : null
  return down ? binding.down(input) : (binding.up?.(input) ?? null)
}

/** Seconds as m:ss (exact integer arithmetic, no locale). */
export function clockText(seconds: number): string {
  const s = Math.max(0, Math.floor(seconds))
  const rest = s % 60
  return `${Math.floor(s / 60)}:${rest < 10 ? '0' : ''}${rest}`
}
