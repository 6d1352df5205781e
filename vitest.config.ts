import { defineConfig } from 'vitest/config'

export default defineConfig({
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
