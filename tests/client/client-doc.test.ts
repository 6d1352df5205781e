/*
 * docs/client.md and the README keep their promises about the page (issue 31: "docs/client.md
 * explains every tool with a screenshot"): every picture they show exists and is a PNG of at most
 * 800 x 500 px and 80 KB; every tool of the shortcut table (client/input/shortcuts.ts: each
 * `tool:*` action, and Static, Slow motion and Lock) has its own section in docs/client.md that
 * names its keys and shows a picture, so a tool added without docs fails here; and the toolbar's
 * tooltips name the keys the shortcut table binds.
 */
import { readFileSync, statSync } from 'node:fs'
import { dirname, join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { SHORTCUTS } from '../../client/input/shortcuts.ts'

const DOCS = {
  'docs/client.md': readFileSync('docs/client.md', 'utf8'),
  'README.md': readFileSync('README.md', 'utf8'),
}

/** The tools: the shortcut table's `tool:*` actions and the toggles that act like tools. */
const TOOLS = SHORTCUTS.filter(
  (s) => s.action.startsWith('tool:') || ['static', 'slow', 'lock'].includes(s.action),
)

/** A tool's name as Help shows it: the help text before its colon, or its first word. */
const nameOf = (help: string): string =>
  help.includes(':') ? help.slice(0, help.indexOf(':')) : help.split(' ')[0]

/** How a key is written in the docs: `G`, `/`, `Space`. */
const keyLabel = (k: string): string => (k === ' ' ? 'Space' : k.toUpperCase())

/** The `### ` sections of docs/client.md, by heading. */
function sections(md: string): Map<string, string> {
  const out = new Map<string, string>()
  const parts = md.split(/^### /m).slice(1)
  for (const part of parts) {
    const heading = part.slice(0, part.indexOf('\n')).trim()
    const body = part.slice(part.indexOf('\n')).split(/^## /m)[0]
    out.set(heading, body)
  }
  return out
}

/** Width and height of a PNG, from its IHDR chunk; throws when the file is not a PNG. */
function pngSize(path: string): { width: number; height: number } {
  const bytes = readFileSync(path)
  const signature = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]
  if (!signature.every((b, i) => bytes[i] === b)) throw new Error(`${path} is not a PNG`)
  return { width: bytes.readUInt32BE(16), height: bytes.readUInt32BE(20) }
}

describe('docs/client.md and the README', () => {
  it('show only pictures that exist, PNGs of at most 800 x 500 px and 80 KB', () => {
    let count = 0
    for (const [doc, md] of Object.entries(DOCS)) {
      for (const m of md.matchAll(/!\[([^\]]*)\]\(([^)]+)\)/g)) {
        const [, caption, target] = m
        const path = join(dirname(doc), target)
        expect(caption.length, `${doc}: ${target} has no caption`).toBeGreaterThan(20)
        expect(() => statSync(path), `${doc} shows ${target}: ${path} is missing`).not.toThrow()
        const size = pngSize(path)
        expect(size.width, path).toBeLessThanOrEqual(800)
        expect(size.height, path).toBeLessThanOrEqual(500)
        expect(statSync(path).size, path).toBeLessThan(80 * 1024)
        count++
      }
    }
    // The README's first picture, and at least one per tool in docs/client.md.
    expect(DOCS['README.md']).toMatch(/!\[[^\]]*\]\(docs\/images\/[^)]+\.png\)/)
    expect(count).toBeGreaterThan(TOOLS.length)
  })

  it('give every tool of the shortcut table a section with its keys and a picture', () => {
    const bySection = sections(DOCS['docs/client.md'])
    expect(TOOLS.length).toBeGreaterThanOrEqual(20)
    for (const tool of TOOLS) {
      const name = nameOf(tool.help)
      const body = bySection.get(name)
      expect(body, `docs/client.md has no "### ${name}" section for ${tool.action}`).toBeDefined()
      for (const k of tool.keys)
        expect(body, `### ${name} does not name its key ${k}`).toContain(`\`${keyLabel(k)}\``)
      expect(body, `### ${name} shows no picture`).toMatch(/!\[[^\]]+\]\(images\/[^)]+\.png\)/)
    }
  })

  it('keep a place for the Edit and Undo/Redo tools that are being added', () => {
    const bySection = sections(DOCS['docs/client.md'])
    expect(bySection.has('Edit')).toBe(true)
    expect(bySection.has('Undo/Redo')).toBe(true)
  })
})

describe('the toolbar', () => {
  /** Buttons by id whose action is in the shortcut table. */
  const BY_ID: Record<string, string> = {
    static: 'static',
    pause: 'pause',
    step: 'step',
    reset: 'reset',
    gravity: 'gravity',
    slow: 'slow',
    lock: 'lock',
    fit: 'fit',
    rooms: 'lobby',
    'help-button': 'help',
  }

  it("names in each tooltip a key the shortcut table binds to that button's action", () => {
    const html = readFileSync('client/index.html', 'utf8')
    let checked = 0
    for (const m of html.matchAll(/<button[^>]*?(data-tool|id)="([a-z-]+)"[^>]*? title="([^"]*)"/g)) {
      const [, attr, name, title] = m
      const action = attr === 'data-tool' ? `tool:${name}` : BY_ID[name]
      if (!action) continue
      const key = /\((;|[^()\s;]{1,5})[;)]/.exec(title)?.[1]
      expect(key, `the ${name} button's title "${title}" names no key`).toBeDefined()
      const bound = SHORTCUTS.find((s) => s.action === action)!
      const wanted = key === 'Space' ? ' ' : key!.toLowerCase()
      expect(bound.keys, `the ${name} button's title says (${key})`).toContain(wanted)
      checked++
    }
    expect(checked).toBeGreaterThanOrEqual(25)
  })
})
