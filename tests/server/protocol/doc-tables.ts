/*
 * PROTOCOL.md read as data for the protocol tests: the field table under each "### `name`"
 * heading, and the lockstep entry kind table. The tests compare what the server sends with these
 * tables, so a field added on the wire without its row (or a row without its field) fails.
 */
import { readFileSync } from 'node:fs'

/** A heading's documented fields; `optional` are those whose meaning starts with "optional". */
export interface DocumentedFields {
  all: string[]
  optional: string[]
}

/** Field names per heading of PROTOCOL.md: `### \`name\`` followed by a `| \`field\` | ...` table. */
export function documentedFields(): Map<string, DocumentedFields> {
  const doc = readFileSync('shared/protocol/PROTOCOL.md', 'utf8')
  const sections = new Map<string, DocumentedFields>()
  let current: DocumentedFields | null = null
  for (const line of doc.split('\n')) {
    const heading = /^### `(\w+)`/.exec(line)
    if (heading) {
      current = { all: [], optional: [] }
      sections.set(heading[1], current)
      continue
    }
    if (line.startsWith('#')) current = null
    const row = /^\|\s*`(\w+)`\s*\|[^|]*\|(.*)\|$/.exec(line)
    if (current && row) {
      current.all.push(row[1])
      if (row[2].trim().startsWith('optional')) current.optional.push(row[1])
    }
  }
  return sections
}

/**
 * The `ticks` entry kinds: kind number to its name, its argument names, and the arguments that
 * follow a "then" (sent only when the input gave any of them, so an entry has either `args` or
 * `args` + `optional` arguments), from the kind table.
 */
export function documentedEntryKinds(): Map<number, { name: string; args: string[]; optional: string[] }> {
  const lines = readFileSync('shared/protocol/PROTOCOL.md', 'utf8').split('\n')
  const start = lines.findIndex((l) => /^\|\s*kind\s*\|\s*entry\s*\|/.test(l))
  if (start < 0) throw new Error('PROTOCOL.md has no "| kind | entry |" table')
  const kinds = new Map<number, { name: string; args: string[]; optional: string[] }>()
  const names = (text: string): string[] => [...text.matchAll(/`(\w+)`/g)].map((m) => m[1])
  for (const line of lines.slice(start + 2)) {
    const row = /^\|\s*(\d+)\s*\|\s*`?(\w+)`?\s*\|(.*)\|$/.exec(line)
    if (!row) break
    const [required, later = ''] = row[3].split(/\bthen\b/)
    kinds.set(Number(row[1]), { name: row[2], args: names(required), optional: names(later) })
  }
  return kinds
}
