/*
 * Reading TypeScript source as text for the static checks (the engine's determinism rules in
 * tests/engine/rules.test.ts, the layers and cycles in tests/architecture/layers.test.ts): comments
 * and string literals blanked out so prose may name what code may not do, and the module
 * specifiers of static imports and re-exports.
 */

/** Source with comments, string and template literals replaced by spaces (line breaks kept). */
export function stripCommentsAndStrings(src: string): string {
  let out = ''
  let i = 0
  const blank = (s: string) => s.replace(/[^\n]/g, ' ')
  while (i < src.length) {
    const c = src[i]
    const next = src[i + 1]
    let end = i + 1
    if (c === '/' && next === '/') {
      end = src.indexOf('\n', i)
      if (end < 0) end = src.length
    } else if (c === '/' && next === '*') {
      end = src.indexOf('*/', i + 2)
      end = end < 0 ? src.length : end + 2
    } else if (c === "'" || c === '"' || c === '`') {
      end = i + 1
      while (end < src.length && src[end] !== c) end += src[end] === '\\' ? 2 : 1
      end = Math.min(end + 1, src.length)
    } else {
      out += c
      i++
      continue
    }
    out += c === '/' ? blank(src.slice(i, end)) : `${c}${blank(src.slice(i + 1, end - 1))}${c}`
    i = end
  }
  return out
}

/** Module specifiers of static imports and re-exports (read from the raw source: specifiers are strings). */
export function importSpecifiers(src: string): string[] {
  const code = stripCommentsAndStrings(src)
  const specs: string[] = []
  // Find `from '...'` / `import '...'` in the stripped code, then read the specifier from the raw source.
  for (const m of code.matchAll(/\b(from|import)\s*(['"])/g)) {
    const start = (m.index ?? 0) + m[0].length
    const end = src.indexOf(m[2], start)
    specs.push(src.slice(start, end))
  }
  return specs
}

/** One static import or re-export: its specifier, its 1-based line, and whether it is `import type`/`export type`. */
export interface ImportStatement {
  specifier: string
  line: number
  typeOnly: boolean
}

/**
 * The static imports and re-exports of a source. A statement is type-only when it says so as a
 * whole (`import type`, `export type`); `import { type A }` still loads the module at run time
 * (verbatimModuleSyntax keeps it as `import {} from`), so it counts as a value import.
 */
export function importStatements(src: string): ImportStatement[] {
  const code = stripCommentsAndStrings(src)
  const found: ImportStatement[] = []
  for (const m of code.matchAll(/\b(from|import)\s*(['"])/g)) {
    const at = m.index ?? 0
    const start = at + m[0].length
    const specifier = src.slice(start, src.indexOf(m[2], start))
    const statementStart = Math.max(code.lastIndexOf('import', at), code.lastIndexOf('export', at))
    const head = code.slice(statementStart, at)
    const typeOnly = /^(import|export)\s+type\s/.test(head)
    found.push({ specifier, line: code.slice(0, at).split('\n').length, typeOnly })
  }
  return found
}
