// Build the browser client: client/main.ts -> dist/client/app.js (esbuild, browser platform,
// minified, engine and protocol bundled in) plus client/index.html. scripts/build.mjs may call
// buildClient(); run alone with `node scripts/build-client.mjs`. Prints the gzipped size.
import { copyFile, mkdir, readFile } from 'node:fs/promises'
import { fileURLToPath } from 'node:url'
import { gzipSync } from 'node:zlib'
import { build } from 'esbuild'

/**
 * Bundle the client into `outdir`; returns { bytes, gzipBytes } of app.js. `format` 'iife' makes a
 * classic script (the static build: a page opened from disk, a file: URL, may not load a module
 * script, which Chromium fetches with CORS from the null origin).
 */
export async function buildClient(outdir = 'dist/client', format = 'esm') {
  await mkdir(outdir, { recursive: true })
  await build({
    entryPoints: ['client/main.ts'],
    outfile: `${outdir}/app.js`,
    bundle: true,
    minify: true,
    platform: 'browser',
    target: 'es2022',
    format,
    sourcemap: 'linked',
    legalComments: 'none',
    logLevel: 'warning',
  })
  await copyFile('client/index.html', `${outdir}/index.html`)
  const js = await readFile(`${outdir}/app.js`)
  const html = await readFile(`${outdir}/index.html`)
  return {
    bytes: js.length,
    gzipBytes: gzipSync(js, { level: 9 }).length,
    htmlGzipBytes: gzipSync(html, { level: 9 }).length,
  }
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const size = await buildClient()
  console.log(
    `dist/client/app.js: ${size.bytes} bytes, ${size.gzipBytes} gzipped (+ index.html ${size.htmlGzipBytes} gzipped)`,
  )
}
