/*
 * The page side of the games' cross-engine test (game-determinism.test.ts): tests/games/game-runs.ts
 * bundled for the browser and evaluated in a blank Chromium or Firefox page, where the test calls
 * `globalThis.concordGameRuns.run(game, ticks, every)`. Node runs the same function.
 */
import { type GameRun, RUN_GAMES, runGame } from '../games/game-runs.ts'

/** The handle the test calls through page.evaluate. */
export interface GameRunsHandle {
  games: readonly string[]
  run(game: (typeof RUN_GAMES)[number], ticks: number, every: number): GameRun
}

;(globalThis as unknown as { concordGameRuns: GameRunsHandle }).concordGameRuns = {
  games: RUN_GAMES,
  run: runGame,
}
