/*
 * Loading game modules from a directory at server start (--games DIR, docs/games.md "Games in
 * their own directory"). DIR holds one folder per game; the folder's index.ts (or index.js) has
 * the game as its default export (`export default defineGame({...})`) and imports the SDK as
 * `concord/game`. For each folder, in name order:
 *
 *   1. bundle: esbuild bundles the entry, its own files, the SDK (games/sdk.ts) and the engine
 *      into one ES module with no imports (a syntax error or an unresolvable import stops here);
 *   2. check: the determinism check (determinism-check.ts) reads every .ts and .js file of DIR's
 *      game folders before any of their code runs, and names each break by file, line and rule;
 *   3. import: the bundle runs (game-bundle.ts) and its default export must be a defined game
 *      (defineGame's RangeError is reported with the file), with a name no other game has.
 *
 * Any failure is a GameLoadError whose message names the file, and the server does not start:
 * nothing is half-loaded. This file imports esbuild and the TypeScript compiler (development
 * packages), so the server loads it only when --games is set; the build ships it as
 * dist/game-loader.js beside dist/server.js.
 */
import { type Dirent, readdirSync, statSync } from 'node:fs'
import { join, relative, resolve } from 'node:path'
import { fileURLToPath } from 'node:url'
import { build, type Message, type Plugin } from 'esbuild'
import { findGame, type Game } from '../../games/index.ts'
import { checkGameDirectory, formatViolation } from './determinism-check.ts'
import { type GameBundle, GameLoadError, importGameBundle } from './game-bundle.ts'

/** games/sdk.ts, which `concord/game` names: beside the source tree, or one folder up from dist/. */
function sdkPath(): string {
  const here = import.meta.url
  return fileURLToPath(new URL(here.endsWith('.ts') ? '../../games/sdk.ts' : '../games/sdk.ts', here))
}

/** The entry of each game folder under `dir` (index.ts or index.js), in folder-name order. */
export function gameEntries(dir: string): string[] {
  let entries: Dirent[]
  try {
    if (!statSync(dir).isDirectory()) throw new Error('not a directory')
    entries = readdirSync(dir, { withFileTypes: true })
  } catch {
    throw new GameLoadError(`--games ${dir}: no such directory`)
  }
  const found: string[] = []
  for (const entry of entries.sort((a, b) => (a.name < b.name ? -1 : a.name > b.name ? 1 : 0))) {
    if (entry.name.startsWith('.') || entry.name === 'node_modules') continue
    const path = join(dir, entry.name)
    if (entry.isFile() && /\.(ts|js|mjs)$/.test(entry.name) && !entry.name.endsWith('.d.ts'))
      throw new GameLoadError(
        `${path}: a game lives in its own folder (${join(dir, 'NAME', 'index.ts')}); move this file into one`,
      )
    if (!entry.isDirectory()) continue
    const entryFile = ['index.ts', 'index.js'].map((f) => join(path, f)).find(isFile)
    if (!entryFile)
      throw new GameLoadError(
        `${path}: a game folder needs an index.ts or index.js whose default export is the game`,
      )
    found.push(entryFile)
  }
  if (found.length === 0)
    throw new GameLoadError(`--games ${dir}: no game folders (each game is DIR/NAME/index.ts)`)
  return found
}

function isFile(path: string): boolean {
  try {
    return statSync(path).isFile()
  } catch {
    return false
  }
}

/** `concord/game` -> games/sdk.ts. */
function sdkPlugin(sdk: string): Plugin {
  return {
    name: 'concord-game-sdk',
    setup(b) {
      b.onResolve({ filter: /^concord\/game$/ }, () => ({ path: sdk }))
    },
  }
}

/** "file:line:column: text" for esbuild's first error. */
function formatBuildError(entry: string, errors: readonly Message[]): string {
  const e = errors[0]
  if (!e) return `${entry}: bundling failed`
  const at = e.location ? `${e.location.file}:${e.location.line}:${e.location.column + 1}` : entry
  const more = errors.length > 1 ? ` (and ${errors.length - 1} more)` : ''
  return `${at}: ${e.text}${more}`
}

/** Bundle one game folder's entry into a self-contained ES module (step 1). */
export async function bundleGame(entry: string): Promise<string> {
  try {
    const result = await build({
      entryPoints: [entry],
      bundle: true,
      write: false,
      format: 'esm',
      platform: 'neutral',
      mainFields: ['module', 'main'],
      target: 'es2022',
      logLevel: 'silent',
      absWorkingDir: process.cwd(),
      plugins: [sdkPlugin(sdkPath())],
    })
    return result.outputFiles[0].text
  } catch (error) {
    const errors = (error as { errors?: Message[] }).errors
    if (errors) throw new GameLoadError(formatBuildError(entry, errors))
    throw new GameLoadError(`${entry}: bundling failed: ${(error as Error).message}`)
  }
}

/** Load every game under `dir` (see the file comment); throws a GameLoadError naming the file. */
export async function loadGameDirectory(dir: string): Promise<{ game: Game; bundle: GameBundle }[]> {
  const root = resolve(dir)
  const shown = (path: string): string => {
    const r = relative(process.cwd(), path)
    return r.startsWith('..') ? path : r
  }
  const entries = gameEntries(root)
  const codes: string[] = []
  for (const entry of entries) codes.push(await bundleGame(entry))
  const violations = checkGameDirectory(root)
  if (violations.length > 0)
    throw new GameLoadError(
      `game modules in ${shown(root)} break the determinism rules (docs/games.md):\n${violations
        .map((v) => formatViolation({ ...v, file: shown(v.file) }))
        .join('\n')}`,
    )
  const loaded: { game: Game; bundle: GameBundle }[] = []
  const byName = new Map<string, string>()
  for (let i = 0; i < entries.length; i++) {
    const file = shown(entries[i])
    const bundle = { name: '', file, code: codes[i] }
    const game = await importGameBundle(bundle)
    if (findGame(game.name))
      throw new GameLoadError(`${file}: game name "${game.name}" is a built-in game's; choose another name`)
    const earlier = byName.get(game.name)
    if (earlier) throw new GameLoadError(`${file}: game name "${game.name}" is also the game of ${earlier}`)
    byName.set(game.name, file)
    bundle.name = game.name
    loaded.push({ game, bundle })
  }
  return loaded
}
