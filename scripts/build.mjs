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

// The server and the bots: Node bundles, runtime packages left external.
for (const name of ['main', 'bots']) {
  await build({
    entryPoints: [`server/${name}.ts`],
    outfile: name === 'main' ? 'dist/server.js' : 'dist/bots.js',
    bundle: true,
    platform: 'node',
    target: 'node20',
    format: 'esm',
    sourcemap: true,
    external: ['ws', 'msgpackr', 'pino', 'prom-client'],
    logLevel: 'warning',
  })
}

if (await exists('client/main.ts')) await buildClient()
