/*
 * docs/games.md's tutorial is the shipped ball-drop game (games/ball-drop/): every statement of
 * the tutorial's setup, command and tick blocks appears in the game's source, comments and layout
 * aside, so the guide cannot drift from code that runs (the game's own behaviour is tested in
 * tests/server/rooms/game-room.test.ts and tests/server/replay/game-recovery.test.ts). And the
 * guide's list of determinism rules names exactly the rules the check reports.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import { checkGameSources } from '../../server/games/determinism-check.ts'

const doc = readFileSync('docs/games.md', 'utf8')
const game = readFileSync('games/ball-drop/ball-drop-game.ts', 'utf8')

/** Code without comments, whitespace, semicolons and trailing commas. */
const squash = (code: string): string =>
  code
    .replace(/\/\/.*$/gm, '')
    .replace(/\/\*[\s\S]*?\*\//g, '')
    .replace(/[\s;]+/g, '')
    .replace(/,([}\])])/g, '$1')

/** The ```ts blocks under a "### N. ..." heading of the tutorial. */
function blocks(heading: string): string[] {
  const at = doc.indexOf(heading)
  expect(at, heading).toBeGreaterThanOrEqual(0)
  const section = doc.slice(at, doc.indexOf('\n### ', at + 1))
  return [...section.matchAll(/```ts\n([\s\S]*?)```/g)].map((m) => m[1])
}

describe('docs/games.md', () => {
  it.each([['### 2. Build the world'], ['### 3. Add a command'], ['### 4. Write the rule']])(
    '%s: the block is in games/ball-drop',
    (heading) => {
      const [code] = blocks(heading)
      // The block is a member of the definition: drop its trailing comma and match it inside.
      const body = squash(code).replace(/,$/, '')
      expect(squash(game)).toContain(body)
    },
  )

  it('"Games in their own directory": the command block is in examples/games/hoops', () => {
    const at = doc.indexOf('## Games in their own directory')
    const section = doc.slice(at, doc.indexOf('\n## ', at + 1))
    const [block] = [...section.matchAll(/```ts\n([\s\S]*?)```/g)].map((m) => m[1])
    expect(block).toBeDefined()
    const example = readFileSync('examples/games/hoops/index.ts', 'utf8')
    expect(squash(example)).toContain(squash(block).replace(/,$/, ''))
  })

  it('lists exactly the rules the determinism check reports', () => {
    const listed = [...doc.matchAll(/`(no-[a-z]+|inexact-math|module-state)`/g)].map((m) => m[1])
    const rules = new Set(listed)
    expect(rules).toEqual(
      new Set([
        'no-random',
        'no-clock',
        'no-timers',
        'no-async',
        'inexact-math',
        'module-state',
        'no-io',
        'no-eval',
        'no-locale',
        'no-this',
      ]),
    )
    // Each named rule is one the check can report (a module breaking all of them at once).
    const all = [
      'let a = 0',
      'export async function f(x: any) {',
      '  Math.random(); Date.now(); setTimeout(() => 0); Math.sin(1); fetch(x); eval(x);',
      '  x.localeCompare(x)',
      '  return this',
      '}',
    ].join('\n')
    expect(new Set(checkGameSources(new Map([['m.ts', all]])).map((v) => v.rule))).toEqual(rules)
  })
})
