/*
 * The game checker: `npm run check-games -- DIR` loads DIR exactly as `npm start -- --games DIR`
 * does before it listens (docs/games.md, "What the server does with DIR at start": the
 * determinism check over every game folder's files, the bundle, the import, the definition
 * checks), without starting a server. It prints one line per game and exits 0 when every game
 * loads; otherwise it prints what the server would (`check-games: ` and the reason, a determinism
 * break on a line of its own as `FILE:LINE:COLUMN RULE: why`) and exits 1. Bad usage exits 2.
 */
import { GameLoadError, loadGameDirectory } from './index.ts'

const USAGE = 'usage: npm run check-games -- DIR'

async function main(): Promise<void> {
  const args = process.argv.slice(2)
  if (args.length !== 1 || args[0].startsWith('-')) {
    process.stderr.write(
      `check-games: ${args.length === 0 ? 'no directory given' : `bad arguments ${JSON.stringify(args)}`}\n${USAGE}\n`,
    )
    process.exit(2)
  }
  const dir = args[0]
  try {
    const loaded = await loadGameDirectory(dir)
    for (const { game, bundle } of loaded)
      process.stdout.write(
        `check-games: ${game.name} ok (${bundle.file}, ${bundle.code.length} bytes bundled)\n`,
      )
    process.stdout.write(`check-games: ${dir}: ${loaded.length} game${loaded.length === 1 ? '' : 's'} pass\n`)
  } catch (error) {
    if (!(error instanceof GameLoadError) && (error as Error)?.name !== 'GameLoadError') throw error
    process.stderr.write(`check-games: ${(error as Error).message}\n`)
    process.exit(1)
  }
}

await main()
