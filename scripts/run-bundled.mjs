// Runs a benchmark as production runs the server: bundled by esbuild (as scripts/build.mjs builds
// dist/server.js and dist/room-worker.js, and scripts/build-client.mjs the browser client), not as
// TypeScript modules compiled one by one by tsx. The form matters: Nov 24 on the 2-core AMD EPYC
// VM (Node 20.20.2, bench/engine-ab.ts with two copies of each, bench/results/engine-ab-bundles.json),
// the engine bundled stepped rooms-10, pyramid-50 and pile-1000 in 0.87-0.94 of the time it took
// as modules (modules / bundle 1.05-1.07, 1.08-1.17, 1.08-1.14): a call or constant imported from
// another module costs more in V8 than one in the same module, and a bundle is one module.
//
// Usage: node [node flags] scripts/run-bundled.mjs bench/ENTRY.ts [arguments]
// The bundle is written beside the entry as .ENTRY.bundle.mjs, so paths the entry takes from
// import.meta.url (./results/...) still hold; npm packages stay external. The room worker
// (server/workers/room-worker.ts) is bundled beside it as room-worker.js, where server/workers/worker-pool.ts
// looks for it when it runs from a bundle. Both files are ignored by git and rewritten every run.
import { basename, dirname, join, resolve } from 'node:path'
import { pathToFileURL } from 'node:url'
import { build } from 'esbuild'

const [entry, ...args] = process.argv.slice(2)
if (!entry?.endsWith('.ts')) {
  throw new Error(
    `usage: node scripts/run-bundled.mjs bench/ENTRY.ts [arguments], got ${JSON.stringify(entry)}`,
  )
}
const dir = dirname(resolve(entry))
const outfile = join(dir, `.${basename(entry, '.ts')}.bundle.mjs`)
const common = {
  bundle: true,
  platform: 'node',
  format: 'esm',
  target: 'node20',
  packages: 'external',
  sourcemap: 'inline',
  logLevel: 'warning',
}
await build({ ...common, entryPoints: [entry], outfile })
await build({
  ...common,
  entryPoints: ['server/workers/room-worker.ts'],
  outfile: join(dir, 'room-worker.js'),
})
process.argv = [process.argv[0], outfile, ...args]
await import(pathToFileURL(outfile).href)
