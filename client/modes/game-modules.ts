/*
 * Games the page runs that this build does not ship: a server started with --games DIR serves
 * each loaded game as one self-contained ES module at GET /games/NAME.js (server/games/
 * game-bundle.ts), the very text its rooms run. A lockstep or predicting page that joins a room
 * of such a game imports that module before it simulates anything (the page's CSP allows scripts
 * from its own origin, so the server that served the page must serve the game), and the hash
 * checkpoints prove the page runs the same rules as the room. Snapshot pages need no game code,
 * but import the module too for its client module: a named export `client` made with
 * defineGameClient (docs/games.md, "Client modules"), which every page of such a room then uses.
 */
import {
  findGame,
  findGameClient,
  GAME_NAME,
  type Game,
  type GameClient,
  gameModuleUrl,
  gameOfModule,
} from '../../games/index.ts'

const loaded = new Map<string, Game>()
const clients = new Map<string, GameClient>()

/** A game by name: one this build ships, or one imported by loadGameModule; else undefined. */
export function findClientGame(name: string): Game | undefined {
  return findGame(name) ?? loaded.get(name)
}

/** The client module of a game by name: one this build ships, or one a loaded game module exports. */
export function findClientGameClient(name: string): GameClient | undefined {
  return findGameClient(name) ?? clients.get(name)
}

/** Whether a module's `client` export looks like what defineGameClient returns for the game `name`. */
function isGameClient(value: unknown, name: string): value is GameClient {
  const c = value as Partial<GameClient> | null
  return typeof c === 'object' && c !== null && c.game === name && typeof c.keys === 'object'
}

/**
 * Import the game module `name` from the game server at `wsUrl` (its /games/NAME.js) unless the
 * page has it already. Rejects with an error naming the game when the module cannot be loaded or
 * is not a game.
 */
export async function loadGameModule(wsUrl: string, name: string): Promise<void> {
  if (findClientGame(name)) return
  if (!GAME_NAME.test(name)) throw new Error(`game name ${JSON.stringify(name)} is not a game name`)
  const url = gameModuleUrl(wsUrl, name)
  let module: { default?: unknown; client?: unknown }
  try {
    module = await import(/* @vite-ignore */ url)
  } catch (error) {
    throw new Error(`cannot load game ${name} from ${url}: ${(error as Error).message}`)
  }
  loaded.set(name, gameOfModule(module, name, url))
  if (isGameClient(module.client, name)) clients.set(name, module.client)
}
