// Build with esbuild: the server (server/main.ts -> dist/server.js, and server/workers/room-worker.ts ->
// dist/room-worker.js for --workers, server/games/game-loader.ts -> dist/game-loader.js for --games;
// Node, runtime packages left external), the bots, the container health check, and, when the browser client exists, the minified client
// (scripts/build-client.mjs) and the benchmark page (scripts/build-bench-page.mjs, served as /bench.html). Usage: node scripts/build.mjs
import { stat } from 'node:fs/promises'
import { build } from 'esbuild'
import { buildBenchPage } from './build-bench-page.mjs'
import { buildClient } from './build-client.mjs'

const exists = (path) =>
  stat(path).then(
    () => true,
    () => false,
  )

// The server, its room worker thread (loaded from beside dist/server.js), the bots and the container health check: Node bundles, runtime packages left external.
const OUTPUTS = {
  'server/main.ts': 'dist/server.js',
  'server/workers/room-worker.ts': 'dist/room-worker.js',
  'bots/bots.ts': 'dist/bots.js',
  'server/hosting/healthcheck.ts': 'dist/healthcheck.js',
}
for (const [entry, outfile] of Object.entries(OUTPUTS)) {
  await build({
    entryPoints: [entry],
    outfile,
    bundle: true,
    platform: 'node',
    target: 'node20',
    format: 'esm',
    sourcemap: true,
    external: ['ws', 'msgpackr', 'pino', 'prom-client', '@google-cloud/agones-sdk', 'ioredis'],
    logLevel: 'warning',
  })
}

// The game loader (--games DIR), loaded by dist/server.js only when that flag is set: it uses
// esbuild and the TypeScript compiler, development packages that the server bundle never holds.
await build({
  entryPoints: ['server/games/game-loader.ts'],
  outfile: 'dist/game-loader.js',
  bundle: true,
  platform: 'node',
  target: 'node20',
  format: 'esm',
  sourcemap: true,
  external: ['esbuild', 'typescript'],
  logLevel: 'warning',
})

if (await exists('client/main.ts')) await buildClient()
if (await exists('bench/page/bench-page.ts')) await buildBenchPage()
