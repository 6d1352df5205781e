/*
 * The server's game catalogue: the games this build ships (games/index.ts's GAMES) and the games
 * loaded at start from --games DIR (game-loader.ts on the main thread, the same bundles imported
 * again in each room worker). One catalogue per thread: join checks, room creation and crash
 * recovery look games up here, and GET /games/NAME.js serves a loaded game's bundle to browsers.
 */
import { findGame, GAMES, type Game } from '../../games/index.ts'
import { type GameBundle, GameLoadError, importGameBundle } from './game-bundle.ts'

const loaded = new Map<string, { game: Game; bundle: GameBundle }>()

/** A game by name: built in or loaded from --games DIR; undefined for an unknown name. */
export function findServerGame(name: string): Game | undefined {
  return findGame(name) ?? loaded.get(name)?.game
}

/** Every game name this server runs, built-in ones first, then the loaded ones in name order. */
export function serverGameNames(): string[] {
  return [...Object.keys(GAMES), ...[...loaded.keys()].sort()]
}

/** The browser bundle of a game loaded from --games DIR (undefined for built-in and unknown games). */
export function loadedGameBundle(name: string): GameBundle | undefined {
  return loaded.get(name)?.bundle
}

/** The bundles of every loaded game, for the room workers. */
export function loadedGameBundles(): GameBundle[] {
  return [...loaded.values()].map((g) => g.bundle)
}

/**
 * Add loaded games. A name that a built-in game has is refused (GameLoadError naming the file);
 * a name loaded before is replaced (a second server started in the same process, as tests do).
 */
export function addLoadedGames(games: readonly { game: Game; bundle: GameBundle }[]): void {
  for (const { game, bundle } of games)
    if (findGame(game.name))
      throw new GameLoadError(
        `${bundle.file}: game name "${game.name}" is a built-in game's; choose another name`,
      )
  for (const entry of games) loaded.set(entry.game.name, entry)
}

/** Import bundles made on the main thread (a room worker at boot) and add their games. */
export async function importGameBundles(bundles: readonly GameBundle[]): Promise<void> {
  const games = []
  for (const bundle of bundles) games.push({ game: await importGameBundle(bundle), bundle })
  addLoadedGames(games)
}

/**
 * Load the game modules of --games DIR (the server at start, the replay tool) with
 * game-loader.ts, imported by its URL so that the server's bundle holds neither esbuild nor the
 * TypeScript compiler (development packages); the build ships the loader as dist/game-loader.js.
 * Throws a GameLoadError naming the file of a bad module, or saying which package is missing.
 * The games are not added to the catalogue: addLoadedGames does that.
 */
export async function loadGameDirectory(dir: string): Promise<{ game: Game; bundle: GameBundle }[]> {
  const here = import.meta.url
  const url = new URL(here.endsWith('.ts') ? './game-loader.ts' : './game-loader.js', here)
  let loader: { loadGameDirectory(dir: string): Promise<{ game: Game; bundle: GameBundle }[]> }
  try {
    loader = await import(url.href)
  } catch (error) {
    throw new GameLoadError(
      `--games needs the game loader and its packages (esbuild, typescript: npm install without --omit=dev): ${(error as Error).message}`,
    )
  }
  return loader.loadGameDirectory(dir)
}
