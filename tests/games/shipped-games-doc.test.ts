/*
 * docs/games.md's Goal and Tower sections state each game's constants in a table; those tables
 * are a contract a lockstep client is written from, so every constant named there must be the
 * value games/index.ts exports (and every exported number of the games must be in its table).
 * The rules themselves are checked by playing the games (goal.test.ts, tower.test.ts).
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import * as games from '../../games/index.ts'

const doc = readFileSync('docs/games.md', 'utf8')

/** The constants table of the `## NAME` section: constant name -> the value written. */
function table(name: string): Map<string, string> {
  const at = doc.indexOf(`\n## ${name}\n`)
  expect(at, `section ${name}`).toBeGreaterThanOrEqual(0)
  const end = doc.indexOf('\n## ', at + 1)
  const section = doc.slice(at, end < 0 ? undefined : end)
  const out = new Map<string, string>()
  for (const row of section.matchAll(/^\| (`[^|]+) \| ([^|]+) \|/gm)) {
    const names = [...row[1].matchAll(/`([A-Z_]+)`/g)].map((m) => m[1])
    const values = names.length > 1 ? row[2].split(',').map((v) => v.trim()) : [row[2].trim()]
    for (const [i, n] of names.entries()) out.set(n, values[i])
  }
  return out
}

const exported = (names: string[]): Record<string, unknown> =>
  Object.fromEntries(names.map((n) => [n, (games as Record<string, unknown>)[n]]))

describe('docs/games.md states the shipped games constants as exported', () => {
  it('Goal', () => {
    const t = table('Goal')
    const names = [...t.keys()]
    expect(names.sort()).toEqual(
      [
        'WIN_SCORE',
        'MATCH_TICKS',
        'FIELD_X',
        'FIELD_Y',
        'GOAL_Y',
        'GOAL_DEPTH',
        'BALL_RADIUS',
        'BALL_DENSITY',
        'BALL_DAMPING',
        'PLAYER_RADIUS',
        'PLAYER_DENSITY',
        'MAX_SPEED',
        'MAX_FORCE',
        'KICK_IMPULSE',
        'KICK_REACH',
        'KICK_COOLDOWN',
      ].sort(),
    )
    expect(Object.fromEntries(names.map((n) => [n, Number(t.get(n))]))).toEqual(exported(names))
  })

  it('Tower', () => {
    const t = table('Tower')
    const blocks = t.get('BLOCKS') as string
    t.delete('BLOCKS')
    const names = [...t.keys()]
    expect(names.sort()).toEqual(
      [
        'LANES',
        'LANE_SPACING',
        'PLATFORM_HALF_WIDTH',
        'DROP_COOLDOWN',
        'DROP_CLEARANCE',
        'SETTLED_SPEED',
        'FALL_LINE',
        'FALL_PENALTY',
        'ROUND_TICKS',
      ].sort(),
    )
    expect(Object.fromEntries(names.map((n) => [n, Number(t.get(n))]))).toEqual(exported(names))
    const kinds = Object.fromEntries(
      [...blocks.matchAll(/(\w+) ([\d.]+) x ([\d.]+)/g)].map((m) => [m[1], [Number(m[2]), Number(m[3])]]),
    )
    expect(kinds).toEqual(games.BLOCKS)
  })
})
