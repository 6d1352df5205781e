// Build with esbuild: the server (server/main.ts -> dist/server.js, Node, runtime packages left
// external), the bots, and, when the browser client exists, the minified client
// (scripts/build-client.mjs). Usage: node scripts/build.mjs
import { stat } from 'node:fs/promises'
import { build } from 'esbuild'
import { buildClient } from './build-client.mjs'

const exists = (path) =>
  stat(path).then(
    () => true,
    () => false,
  )

await build({
  entryPoints: ['server/main.ts'],
  outfile: 'dist/server.js',
  bundle: true,
  platform: 'node',
  target: 'node20',
  format: 'esm',
  sourcemap: true,
  external: ['ws', 'msgpackr', 'pino', 'prom-client'],
  logLevel: 'warning',
})
await build({
  entryPoints: ['server/bots.ts'],
  outfile: 'dist/bots.js',
  bundle: true,
  platform: 'node',
  target: 'node20',
  format: 'esm',
  sourcemap: true,
  external: ['ws', 'msgpackr', 'pino', 'prom-client'],
  logLevel: 'warning',
})

if (await exists('client/main.ts')) await buildClient()
