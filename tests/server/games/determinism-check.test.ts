/*
 * The static determinism check of game modules (server/games/determinism-check.ts). Each fixture
 * below breaks one rule at a line counted by hand (the `// <-` marker), and must be reported with
 * that file, line and rule and nothing else; a clean fixture full of near misses (a local named
 * Date, a parameter shadowing a module-level name, `this` in a class, exact Math, module-level
 * tables built while the module loads) must pass. Then the check runs over every game in games/.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import {
  checkGameDirectory,
  checkGameSources,
  type DeterminismRule,
  formatViolation,
  gameModuleFiles,
} from '../../../server/games/determinism-check.ts'

/** A fixture: its source, and the rule broken on each line marked `// <-`. */
const FIXTURES: Array<[string, DeterminismRule, string]> = [
  ['random', 'no-random', 'export function roll() {\n  return Math.random() // <-\n}'],
  ['date-now', 'no-clock', 'export const f = () => Date.now() // <-'],
  ['new-date', 'no-clock', 'export function f() {\n  const d = new Date() // <-\n  return d\n}'],
  ['performance', 'no-clock', 'export const f = () => performance.now() // <-'],
  ['timeout', 'no-timers', 'export function f(ctx: any) {\n  setTimeout(() => ctx.emit(1), 10) // <-\n}'],
  ['microtask', 'no-timers', 'export function f(g: () => void) {\n  queueMicrotask(g) // <-\n}'],
  ['async', 'no-async', 'export async function f() { // <-\n  return 1\n}'],
  ['promise', 'no-async', 'export const f = () => Promise.resolve(1) // <-'],
  [
    'await',
    'no-async',
    'export function f(p: any) {\n  return async () => { // <-\n    await p // <-\n  }\n}',
  ],
  ['sin', 'inexact-math', 'export const f = (a: number) => Math.sin(a) // <-'],
  ['atan2', 'inexact-math', 'export const f = (y: number, x: number) =>\n  Math.atan2(y, x) // <-'],
  ['pow', 'inexact-math', 'export const f = (a: number) => a ** 2 // <-'],
  ['math-index', 'inexact-math', "export const f = (a: number) => Math['cos'](a) // <-"],
  ['let', 'module-state', 'let count = 0 // <-\nexport const f = () => count'],
  ['var', 'module-state', 'var count = 0 // <-\nexport const f = () => count'],
  [
    'mutate',
    'module-state',
    'const scores: Record<string, number> = {}\nexport function f(p: string) {\n  scores[p] = 1 // <-\n}',
  ],
  [
    'push',
    'module-state',
    'const log: string[] = []\nexport function f(s: string) {\n  log.push(s) // <-\n}',
  ],
  ['increment', 'module-state', 'const box = { n: 0 }\nexport function f() {\n  box.n++ // <-\n}'],
  [
    'delete',
    'module-state',
    'const seen: Record<string, 1> = {}\nexport function f(k: string) {\n  delete seen[k] // <-\n}',
  ],
  [
    'map-set',
    'module-state',
    'const cache = new Map<number, number>()\nexport function f(k: number) {\n  cache.set(k, k) // <-\n}',
  ],
  [
    'import-mutate',
    'module-state',
    "import { sandboxCommands } from '../index.ts'\nexport function f() {\n  Object.assign(sandboxCommands, {}) // <-\n}",
  ],
  ['fetch', 'no-io', "export const f = () => fetch('http://x') // <-"],
  ['package', 'no-io', "import { readFileSync } from 'node:fs' // <-\nexport const f = () => readFileSync"],
  ['dynamic-import', 'no-io', "export const f = () => import('./other.ts') // <-"],
  ['global-this', 'no-io', 'export const f = () => globalThis // <-'],
  ['eval', 'no-eval', "export const f = () => eval('1') // <-"],
  ['function', 'no-eval', "export const f = () => new Function('return 1') // <-"],
  ['locale', 'no-locale', 'export const f = (a: string, b: string) => a.localeCompare(b) // <-'],
  ['this', 'no-this', 'export function f() {\n  return this // <-\n}'],
  ['this-arrow', 'no-this', 'export const f = () => this // <-'],
]

/** The (line, rule) pairs a fixture's markers expect. */
function expected(source: string, rule: DeterminismRule): Array<[number, DeterminismRule]> {
  return source
    .split('\n')
    .flatMap((line, i) => (line.includes('// <-') ? [[i + 1, rule] as [number, DeterminismRule]] : []))
}

const CLEAN = `
import { atan2, cos, sin } from '../../engine/index.ts'
import { defineGame } from '../index.ts'

/** A table built while the module loads: the same in every replica. */
const ANGLES: number[] = []
for (let i = 0; i < 8; i++) ANGLES.push((i * 3.141592653589793) / 4)
const LIMITS = { speed: 10 }

class Vector {
  constructor(public x: number, public y: number) {}
  length(): number {
    const f = () => this.x * this.x + this.y * this.y
    return Math.sqrt(f())
  }
}

export const clean = defineGame({
  name: 'clean',
  state: { n: 0, names: [] as string[] },
  commands: {
    go: {
      args: { type: 'object' },
      apply(ctx, player, args: { a: number }) {
        const Date = { now: () => ctx.tick }
        const LIMITS = { speed: 1 }
        LIMITS.speed = 2
        const list: number[] = []
        list.push(Date.now())
        ctx.state.names.push('p' + player)
        ctx.state.n += Math.floor(Math.abs(args.a)) + Math.max(1, 2) + Math.imul(3, 4) + Math.PI
        const v = new Vector(cos(1), sin(1))
        return v.length() > atan2(1, 2) ? undefined : 'no'
      },
    },
  },
  tick(ctx) {
    for (const key of Object.keys(ctx.state).sort((a, b) => (a < b ? -1 : a > b ? 1 : 0))) ctx.emit(key)
    let local = 0
    local += ANGLES[ctx.tick % 8] * LIMITS.speed
    ctx.state.n = local
  },
})
`

describe('the determinism check of game modules', () => {
  it.each(FIXTURES)('%s: reports %s on the marked lines and nothing else', (name, rule, source) => {
    const file = `games/fixture/${name}.ts`
    const found = checkGameSources(new Map([[file, source]]))
    expect(found.map((v) => [v.line, v.rule])).toEqual(expected(source, rule))
    for (const v of found) {
      expect(v.file).toBe(file)
      expect(formatViolation(v)).toMatch(new RegExp(`^games/fixture/${name}\\.ts:\\d+:\\d+ ${rule}: .+`))
    }
  })

  it('passes a module full of near misses', () => {
    expect(checkGameSources(new Map([['games/clean/clean.ts', CLEAN]])).map(formatViolation)).toEqual([])
  })

  it('names the engine trig for inexact Math and ctx.random for Math.random', () => {
    const [sin] = checkGameSources(new Map([['a.ts', 'export const f = (x: number) => Math.sin(x)']]))
    expect(sin.message).toContain("engine's sin, cos and atan2")
    const [random] = checkGameSources(new Map([['a.ts', 'export const f = () => Math.random()']]))
    expect(random.message).toContain('ctx.random')
  })

  it('finds several breaks in one file, in line order, with columns', () => {
    const source = 'let a = 0\nexport const f = () => Math.random() + Date.now()\n'
    expect(checkGameSources(new Map([['m.ts', source]])).map(formatViolation)).toEqual([
      'm.ts:1:1 module-state: let at module level: rooms share the module; keep room data in ctx.state',
      'm.ts:2:24 no-random: Math.random differs everywhere: use ctx.random',
      'm.ts:2:40 no-clock: Date: Date reads the clock: use ctx.tick (60 per second)',
    ])
  })

  it('every game in games/ passes', () => {
    const files = gameModuleFiles('games')
    expect(files).toContain('games/sandbox/sandbox-game.ts')
    expect(checkGameDirectory('games').map(formatViolation)).toEqual([])
    // The check reads what it is given: the sandbox with one rule broken is caught.
    const broken = readFileSync('games/sandbox/sandbox-game.ts', 'utf8').replace(
      'ctx.setGravity(cmd.x, cmd.y)',
      'ctx.setGravity(Math.cos(cmd.x), cmd.y)',
    )
    const found = checkGameSources(new Map([['games/sandbox/sandbox-game.ts', broken]]))
    expect(found.map((v) => v.rule)).toEqual(['inexact-math'])
  })

  it('every example game in examples/games/ and the loaded test game pass (and may import concord/game)', () => {
    expect(gameModuleFiles('examples/games')).toContain('examples/games/hoops/index.ts')
    expect(checkGameDirectory('examples/games').map(formatViolation)).toEqual([])
    expect(checkGameDirectory('tests/server/games/loaded').map(formatViolation)).toEqual([])
    const other = checkGameSources(new Map([['g.ts', "import { box } from 'concord/games'\n"]]))
    expect(other.map(formatViolation)).toEqual([
      "g.ts:1:1 no-io: imports 'concord/games': game code imports only its own files, 'concord/game', and engine/, shared/ and games/ modules",
    ])
  })
})
