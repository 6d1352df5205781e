/*
 * The browser side of the rollback-cost benchmark: bundled with esbuild and injected into a page
 * by lockstep-browser-bench.ts, so Chromium times the same code (rollback-cost.ts) as Node.
 */
import { measureRollbackScenes } from './rollback-cost.ts'

;(globalThis as unknown as { concordRollbackBench: typeof measureRollbackScenes }).concordRollbackBench =
  measureRollbackScenes
