// Build the client SDK (docs/sdk.md): sdk/index.ts and sdk/render.ts -> dist/sdk/index.js and
// dist/sdk/render.js, ES modules for browsers and Node (esbuild, browser platform, engine, protocol,
// games and msgpackr bundled in; code both entries use goes to a shared chunk), and their type
// declarations (tsc -p tsconfig.sdk.json) under dist/sdk/types, with dist/sdk/index.d.ts and
// render.d.ts pointing there. Usage: npm run build:sdk [-- OUTDIR] (default dist/sdk).
import { execFileSync } from 'node:child_process'
import { mkdir, readdir, readFile, rm, writeFile } from 'node:fs/promises'
import { createRequire } from 'node:module'
import { relative, resolve } from 'node:path'
import { fileURLToPath } from 'node:url'
import { build } from 'esbuild'

/** Build the SDK into `outdir`; returns the entry files written. */
export async function buildSdk(outdir = 'dist/sdk') {
  await rm(outdir, { recursive: true, force: true })
  await mkdir(outdir, { recursive: true })
  await build({
    entryPoints: { index: 'sdk/index.ts', render: 'sdk/render.ts' },
    outdir,
    bundle: true,
    splitting: true,
    format: 'esm',
    platform: 'browser',
    target: 'es2022',
    sourcemap: 'linked',
    legalComments: 'none',
    logLevel: 'warning',
  })
  const types = `${outdir}/types`
  const tsc = createRequire(import.meta.url).resolve('typescript/bin/tsc')
  try {
    execFileSync(process.execPath, [tsc, '-p', 'tsconfig.sdk.json', '--outDir', types], { stdio: 'pipe' })
  } catch (error) {
    throw new Error(`build:sdk: tsc failed:\n${error.stdout ?? ''}${error.stderr ?? ''}`)
  }
  // tsc keeps the sources' `.ts` import paths in declarations: point them at the `.js` names a
  // consumer's resolver maps to the .d.ts files beside them.
  for (const file of await readdir(types, { recursive: true })) {
    if (!file.endsWith('.d.ts')) continue
    const path = `${types}/${file}`
    const text = await readFile(path, 'utf8')
    await writeFile(path, text.replace(/(from\s+|import\()(['"])(\.{1,2}\/[^'"]*?)\.ts\2/g, '$1$2$3.js$2'))
  }
  for (const entry of ['index', 'render']) {
    const target = relative(outdir, `${types}/sdk/${entry}.js`).replaceAll('\\', '/')
    await writeFile(`${outdir}/${entry}.d.ts`, `export * from './${target}'\n`)
  }
  const pkg = {
    type: 'module',
    main: 'index.js',
    types: 'index.d.ts',
    exports: { '.': './index.js', './render': './render.js' },
  }
  await writeFile(`${outdir}/package.json`, `${JSON.stringify(pkg, null, 2)}\n`)
  return [`${outdir}/index.js`, `${outdir}/render.js`]
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const outdir = resolve(process.argv[2] ?? 'dist/sdk')
  const files = await buildSdk(outdir)
  console.log(`build:sdk: ${files.map((f) => relative(process.cwd(), f)).join(', ')} with type declarations`)
}
