// Build with esbuild: the server (server/main.ts -> dist/server.js, Node, runtime packages left
// external) and, when the browser client exists, client/main.ts -> dist/client/app.js plus
// client/index.html. Usage: node scripts/build.mjs [--watch is not supported; rerun it]
import { copyFile, mkdir, stat } from 'node:fs/promises'
import { build } from 'esbuild'

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

if (await exists('client/main.ts')) {
  await mkdir('dist/client', { recursive: true })
  await build({
    entryPoints: ['client/main.ts'],
    outfile: 'dist/client/app.js',
    bundle: true,
    platform: 'browser',
    target: 'es2022',
    format: 'esm',
    sourcemap: true,
    logLevel: 'warning',
  })
  if (await exists('client/index.html')) await copyFile('client/index.html', 'dist/client/index.html')
}
