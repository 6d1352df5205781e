/*
 * The server's side of game modules: the static determinism check (determinism-check.ts) that
 * reads a game's source with the TypeScript compiler and names every break of docs/games.md's
 * determinism rules by file, line and rule.
 */
export {
  checkGameDirectory,
  checkGameSources,
  type DeterminismRule,
  type DeterminismViolation,
  formatViolation,
  gameModuleFiles,
} from './determinism-check.ts'
