import { fileURLToPath } from 'node:url'
import { defineConfig } from 'vitest/config'

export default defineConfig({
  // Game modules import the SDK as `concord/game` (docs/games.md), as tsconfig.json's paths map it
  // for the type checker; vitest does not read those, so a test importing a game needs this too.
  resolve: { alias: { 'concord/game': fileURLToPath(new URL('./games/sdk.ts', import.meta.url)) } },
  test: {
    include: ['tests/**/*.test.ts'],
    testTimeout: 120_000,
    hookTimeout: 60_000,
    pool: 'forks',
    // Two test files at once. Vitest's default on two cores is one (cores - 1), which ran the
    // files one after another: most of the suite waits on servers, browsers and sockets, not on
    // the CPU, and the tests wait for conditions, so a second file at a time is safe and faster.
    maxWorkers: 2,
  },
})
