/*
 * The engine's determinism rules, checked on the source text (grep-style, after stripping comments
 * and string literals so that prose and error messages may name what the code may not use):
 *
 * - Math: only the functions ECMAScript specifies exactly (sqrt, abs, min, max, floor, ceil, round,
 *   sign, trunc, fround, imul, clz32) and constants. Math.sin/cos/tan/atan/atan2/exp/log/pow/hypot/
 *   cbrt/asin/acos/sinh/cosh/tanh/random... differ between JavaScript engines.
 * - No `**` (it is Math.pow), no Date, performance, timers, process, require, dynamic import,
 *   globalThis/window/document.
 * - Imports only relative paths inside engine/ (no packages, no Node built-ins, no other layer).
 *
 * The checker itself is tested on small fixtures first, so a broken regex cannot pass silently.
 */
import { readdirSync, readFileSync, statSync } from 'node:fs'
import { dirname, join, relative, resolve } from 'node:path'
import { fileURLToPath } from 'node:url'
import { describe, expect, it } from 'vitest'
import { importSpecifiers, stripCommentsAndStrings } from '../support/source-scan.ts'

const ENGINE = resolve(dirname(fileURLToPath(import.meta.url)), '../../engine')

const ALLOWED_MATH = new Set([
  'sqrt',
  'abs',
  'min',
  'max',
  'floor',
  'ceil',
  'round',
  'sign',
  'trunc',
  'fround',
  'imul',
  'clz32',
  'PI',
  'E',
  'LN2',
  'LN10',
  'LOG2E',
  'LOG10E',
  'SQRT2',
  'SQRT1_2',
])

/** Forbidden identifiers and constructs (besides Math.*), with why. */
const FORBIDDEN: Array<[RegExp, string]> = [
  [/\*\*/, '`**` is Math.pow'],
  [/\bDate\b/, 'Date reads the clock'],
  [/\bperformance\b/, 'performance reads the clock'],
  [/\b(setTimeout|setInterval|setImmediate|queueMicrotask|requestAnimationFrame)\b/, 'timers'],
  [/\bprocess\b/, 'process is a Node API'],
  [/\brequire\s*\(/, 'require'],
  [/\bimport\s*\(/, 'dynamic import'],
  [/\b(globalThis|window|document|navigator|crypto)\b/, 'host objects'],
  [/\bMath\s*\[/, 'computed Math access'],
]

/** Every rule violation in one file's source, as "line: reason". */
function violations(src: string): string[] {
  const found: string[] = []
  const code = stripCommentsAndStrings(src)
  const lines = code.split('\n')
  lines.forEach((line, index) => {
    for (const m of line.matchAll(/\bMath\s*\.\s*([A-Za-z_$][\w$]*)/g)) {
      if (!ALLOWED_MATH.has(m[1])) found.push(`${index + 1}: Math.${m[1]} is not exactly specified`)
    }
    for (const [pattern, why] of FORBIDDEN) if (pattern.test(line)) found.push(`${index + 1}: ${why}`)
  })
  return found
}

function engineFiles(dir = ENGINE): string[] {
  const files: string[] = []
  for (const name of readdirSync(dir)) {
    const path = join(dir, name)
    if (statSync(path).isDirectory()) files.push(...engineFiles(path))
    else if (/\.(ts|js|mjs|cjs|mts|cts)$/.test(name)) files.push(path)
  }
  return files.sort()
}

describe('the rule checker itself', () => {
  it('finds forbidden Math functions, ** and clock reads in code, not in comments or strings', () => {
    const src = [
      '// Math.sin is fine in a comment, and so is 2 ** 3',
      "const s = 'Math.random() in a string'",
      'const a = Math.sin(x) + Math . atan2(y, x)',
      'const b = x ** 2',
      '/* Date.now() */ const t = Date.now()',
      'const ok = Math.sqrt(Math.abs(x)) * Math.PI',
      'const p = performance.now(); const r = require("fs")',
      // biome-ignore lint/suspicious/noTemplateCurlyInString: a template literal inside the fixture source
      'const s2 = `template ${Math.cos(1)}`',
    ].join('\n')
    const found = violations(src)
    expect(found).toEqual([
      '3: Math.sin is not exactly specified',
      '3: Math.atan2 is not exactly specified',
      '4: `**` is Math.pow',
      '5: Date reads the clock',
      '7: performance reads the clock',
      '7: require',
    ])
  })

  it('reads import specifiers, including type-only imports and re-exports', () => {
    const src = [
      "import { a } from './a.ts'",
      "import type { B } from '../b.ts'",
      "export { c } from 'node:fs'",
      "import './side-effect.ts'",
      "// import { x } from 'ignored'",
      'const s = "from \'not-an-import\'"',
    ].join('\n')
    expect(importSpecifiers(src)).toEqual(['./a.ts', '../b.ts', 'node:fs', './side-effect.ts'])
  })
})

describe('engine/ follows the determinism rules', () => {
  const files = engineFiles()

  it('has engine files to check', () => {
    expect(files.length).toBeGreaterThan(10)
    expect(files.some((f) => f.endsWith('world.ts'))).toBe(true)
  })

  it('uses only exactly specified Math functions, no clock, timers, host objects or Node APIs', () => {
    const found: string[] = []
    for (const file of files) {
      const src = readFileSync(file, 'utf8')
      for (const v of violations(src)) {
        if (v.includes('`**`')) continue // checked separately below
        found.push(`${relative(ENGINE, file)}:${v}`)
      }
    }
    expect(found).toEqual([])
  })

  it('never uses ** (it is Math.pow, which engines may round differently)', () => {
    const found: string[] = []
    for (const file of files) {
      for (const v of violations(readFileSync(file, 'utf8'))) {
        if (v.includes('`**`')) found.push(`${relative(ENGINE, file)}:${v}`)
      }
    }
    expect(found).toEqual([])
  })

  it('imports only relative paths that stay inside engine/ and exist', () => {
    const bad: string[] = []
    for (const file of files) {
      for (const spec of importSpecifiers(readFileSync(file, 'utf8'))) {
        const target = resolve(dirname(file), spec)
        const inside = !relative(ENGINE, target).startsWith('..')
        let exists = false
        try {
          exists = statSync(target).isFile()
        } catch {}
        if (!spec.startsWith('.') || !inside || !exists)
          bad.push(`${relative(ENGINE, file)} imports '${spec}'`)
      }
    }
    expect(bad).toEqual([])
  })
})
