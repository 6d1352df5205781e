// `npm run build:static`: the offline sandbox and the benchmark page as plain static files in
// dist/static (or OUTDIR), for any static host under any path: every URL in them is relative, and
// the sandbox's index.html carries <meta name="concord-mode" content="offline">, which makes the
// client run the engine in the page (client/main.ts) since a static host has no game server. The
// sandbox's script is classic (an IIFE bundle), so it also runs opened from disk (file:); the
// benchmark page cannot (module script, WebAssembly) and says so when opened from disk.
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
  // Classic scripts, not modules: a page opened from disk (file:) cannot load a module script.
  const client = await buildClient(outdir, 'iife')
  const bench = await buildBenchPage(outdir)
  const index = `${outdir}/index.html`
  const html = classicScript(await readFile(index, 'utf8'), 'app.js', index)
  if (!html.includes('<meta charset="utf-8">'))
    throw new Error(`${index} has no <meta charset="utf-8"> to put the offline marker after`)
  await writeFile(index, html.replace('<meta charset="utf-8">', `<meta charset="utf-8">\n${OFFLINE_META}`))
  const benchPage = `${outdir}/bench.html`
  const benchHtml = await readFile(benchPage, 'utf8')
  const benchTag = '<script type="module" src="./bench.js"></script>'
  if (!benchHtml.includes(benchTag)) throw new Error(`${benchPage} has no ${benchTag}`)
  await writeFile(benchPage, benchHtml.replace(benchTag, `${FROM_DISK_NOTE}\n${benchTag}`))
  return { appBytes: client.bytes, benchBytes: bench.bytes }
}

/**
 * The benchmark cannot run from disk: its engines are a module script with top-level await and
 * WebAssembly files, which a file: page may not load. Opened from disk, the static bench.html says
 * so and how to serve it, instead of a Run button that does nothing.
 */
const FROM_DISK_NOTE = `<script>
if (location.protocol === 'file:') {
  document.getElementById('status').textContent = 'Opened from disk (file:): browsers do not let such a page load the benchmark, a module script with WebAssembly engines. Serve this folder over http (for example python3 -m http.server in it) and open bench.html from there. The sandbox, index.html, does work from disk.'
  document.getElementById('run').disabled = true
}
</script>`

/** `html` with its module script tag for `src` made a classic deferred script. */
function classicScript(html, src, file) {
  const tag = `<script type="module" src="./${src}"></script>`
  if (!html.includes(tag)) throw new Error(`${file} has no ${tag} to make a classic script`)
  return html.replace(tag, `<script defer src="./${src}"></script>`)
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const outdir = process.argv[2] ?? 'dist/static'
  const { appBytes, benchBytes } = await buildStatic(outdir)
  console.log(
    `${outdir}: index.html + app.js (${appBytes} bytes), bench.html + bench.js (${benchBytes} bytes) + wasm/`,
  )
}
