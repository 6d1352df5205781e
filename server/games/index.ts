/*
 * The server's side of game modules: the catalogue of games this server runs (game-catalog.ts:
 * the built-in games plus those loaded with --games DIR) and the bundles that carry a loaded game
 * to the room workers and to browsers (game-bundle.ts). The loader (game-loader.ts) and the static
 * determinism check (determinism-check.ts) use esbuild and the TypeScript compiler, development
 * packages: they are not exported here, so the server's bundle never contains them; game-catalog.ts's
 * loadGameDirectory imports game-loader.ts by its URL only when --games is set (the build ships dist/game-loader.js),
 * and tests import the two files directly.
 */

export { type GameBundle, GameLoadError, importGameBundle } from './game-bundle.ts'
export {
  addLoadedGames,
  findServerGame,
  importGameBundles,
  loadedGameBundle,
  loadedGameBundles,
  loadGameDirectory,
  serverGameNames,
} from './game-catalog.ts'
