// `npm run build:static`: the offline sandbox and the benchmark page as plain static files in
// dist/static (or OUTDIR), for any static host under any path: every URL in them is relative, and
// the sandbox's index.html carries <meta name="concord-mode" content="offline">, which makes the
// client run the engine in the page (client/main.ts) since a static host has no game server.
// Run: node scripts/build-static.mjs [OUTDIR]
import { readFile, rm, writeFile } from 'node:fs/promises'
import { fileURLToPath } from 'node:url'
import { buildBenchPage } from './build-bench-page.mjs'
import { buildClient } from './build-client.mjs'

/** The marker client/main.ts looks for. */
export const OFFLINE_META = '<meta name="concord-mode" content="offline">'

/** Build the static site into `outdir` (emptied first); returns the sizes of the two bundles. */
export async function buildStatic(outdir = 'dist/static') {
  await rm(outdir, { recursive: true, force: true })
  const client = await buildClient(outdir)
  const bench = await buildBenchPage(outdir)
  const index = `${outdir}/index.html`
  const html = await readFile(index, 'utf8')
  if (!html.includes('<meta charset="utf-8">'))
    throw new Error(`${index} has no <meta charset="utf-8"> to put the offline marker after`)
  await writeFile(index, html.replace('<meta charset="utf-8">', `<meta charset="utf-8">\n${OFFLINE_META}`))
  return { appBytes: client.bytes, benchBytes: bench.bytes }
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const outdir = process.argv[2] ?? 'dist/static'
  const { appBytes, benchBytes } = await buildStatic(outdir)
  console.log(
    `${outdir}: index.html + app.js (${appBytes} bytes), bench.html + bench.js (${benchBytes} bytes) + wasm/`,
  )
}
