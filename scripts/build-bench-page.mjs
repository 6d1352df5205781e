// Build the benchmark page: bench/page/bench-page.ts -> OUTDIR/bench.js (esbuild, browser, minified,
// every engine bundled in) plus bench/page/bench.html, and the WebAssembly binaries of box2d-wasm and
// box2d3-wasm under OUTDIR/wasm/, which the page finds relative to its own address (so the page
// works under any base path). Run alone with `node scripts/build-bench-page.mjs [OUTDIR]`.
import { copyFile, mkdir, stat } from 'node:fs/promises'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { build } from 'esbuild'

/** The folder of a package's resolved entry file. */
const entryDir = (name) => dirname(fileURLToPath(import.meta.resolve(name)))

/** The wasm files the page may fetch: [source, file name]. */
function wasmFiles() {
  const box2d = join(entryDir('box2d-wasm'), '../es') // entry: dist/umd/entry.js
  const box2d3 = join(entryDir('box2d3-wasm'), 'compat') // entry: build/dist/es/entry.mjs
  return [
    [join(box2d, 'Box2D.wasm'), 'Box2D.wasm'],
    [join(box2d, 'Box2D.simd.wasm'), 'Box2D.simd.wasm'],
    [join(box2d3, 'Box2D.compat.wasm'), 'Box2D.compat.wasm'],
  ]
}

/** Bundle the benchmark page into `outdir` (default dist/client); returns the size of bench.js. */
export async function buildBenchPage(outdir = 'dist/client', format = 'esm') {
  await mkdir(join(outdir, 'wasm'), { recursive: true })
  await build({
    entryPoints: ['bench/page/bench-page.ts'],
    outfile: `${outdir}/bench.js`,
    bundle: true,
    minify: true,
    platform: 'browser',
    target: 'es2022',
    format,
    // The wasm packages' Emscripten loaders import Node modules only on their Node branch.
    external: ['node:*', 'module', 'fs', 'path', 'url', 'crypto', 'worker_threads', 'os'],
    legalComments: 'none',
    logLevel: 'warning',
  })
  await copyFile('bench/page/bench.html', `${outdir}/bench.html`)
  for (const [source, name] of wasmFiles()) await copyFile(source, join(outdir, 'wasm', name))
  return { bytes: (await stat(`${outdir}/bench.js`)).size }
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const outdir = process.argv[2] ?? 'dist/client'
  const { bytes } = await buildBenchPage(outdir)
  console.log(`${outdir}/bench.js: ${bytes} bytes, with bench.html and wasm/`)
}
