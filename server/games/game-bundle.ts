/*
 * A game loaded from a directory (--games DIR) travels as one self-contained ES module: the
 * game's files, the game SDK (games/sdk.ts) and the engine, bundled by esbuild (game-loader.ts)
 * into text with no imports. The same text runs everywhere: the server's main thread and each room
 * worker import it from a data: URL (this file; no file is written, no eval), and the browser page
 * imports it from GET /games/NAME.js (same origin, so the page's `script-src 'self'` allows it).
 * The hash checkpoints then prove every replica runs the same rules. This file has no dependency
 * beyond Node, so a worker thread loads games without the TypeScript compiler or esbuild.
 */
import { type Game, isGame } from '../../games/index.ts'

/** A game bundle: the game's name, the file it came from, and the bundled module's text. */
export interface GameBundle {
  name: string
  /** The game's entry file (DIR/NAME/index.ts or .js), for messages. */
  file: string
  code: string
}

/** Why a game module was refused, naming its file (the server does not start). */
export class GameLoadError extends Error {
  override name = 'GameLoadError'
}

/** Run a bundle's module and return its game; a GameLoadError naming the file if it is not one. */
export async function importGameBundle(bundle: { file: string; code: string }): Promise<Game> {
  const url = `data:text/javascript;base64,${Buffer.from(bundle.code).toString('base64')}`
  let module: { default?: unknown }
  try {
    module = await import(/* @vite-ignore */ url)
  } catch (error) {
    const e = error as Error
    const what = e instanceof RangeError ? 'game definition refused' : 'module failed while loading'
    throw new GameLoadError(`${bundle.file}: ${what}: ${e.message}`)
  }
  if (!isGame(module.default))
    throw new GameLoadError(
      `${bundle.file}: the default export must be a game made with defineGame (export default defineGame({...})), got ${describe(module.default)}`,
    )
  return module.default
}

function describe(value: unknown): string {
  if (value === undefined) return 'no default export'
  if (value === null) return 'null'
  if (typeof value === 'object')
    return `an object with keys ${Object.keys(value).slice(0, 6).join(', ') || '(none)'}`
  return `a ${typeof value}`
}
