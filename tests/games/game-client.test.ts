/*
 * Game client modules (games/game-client.ts): defineGameClient refuses a bad definition with a
 * message naming the part; the goal game's keys turn the held keys into `run` velocities (hand
 * computed: a diagonal is MAX_SPEED / sqrt 2 on each axis), and its HUD and the tower's read their
 * views. The clock and metre texts are checked against hand-written strings.
 */
import { readFileSync } from 'node:fs'
import { describe, expect, it } from 'vitest'
import {
  clockText,
  defineGameClient,
  findGameClient,
  type GameClientCommand,
  goalClient,
  keyCommand,
  MAX_SPEED,
  metres,
  towerClient,
} from '../../games/index.ts'

const press = (keys: string[], key: string, down: boolean): GameClientCommand | null => {
  const binding = goalClient.keys[key]
  return keyCommand(binding, down, { state: null, me: 1, held: new Set(keys) })
}

describe('game client modules', () => {
  it('defineGameClient names what is wrong', () => {
    expect(() => defineGameClient({ game: 'Goal!' })).toThrow(/game "Goal!" is not a game name/)
    expect(() => defineGameClient({ game: 'g', hud: 3 as never })).toThrow(/g: hud must be a function/)
    expect(() => defineGameClient({ game: 'g', keys: { W: () => null } })).toThrow(
      /key "W" must be .* lower case/,
    )
    expect(() => defineGameClient({ game: 'g', keys: { w: {} as never } })).toThrow(
      /key "w" must be a function/,
    )
  })

  it('keysHelp names only bound keys, with short text; keys it leaves out get a last row', () => {
    const keys = { a: () => null, b: () => null, c: () => null }
    expect(() => defineGameClient({ game: 'g', keys, keysHelp: [{ keys: ['z'], help: 'zoom' }] })).toThrow(
      /g: keysHelp\[0\]: key "z" is not one of the bound keys/,
    )
    expect(() => defineGameClient({ game: 'g', keys, keysHelp: [{ keys: [], help: 'x' }] })).toThrow(
      /g: keysHelp\[0\] must be \{ keys: \[at least one bound key\], help \}/,
    )
    expect(() =>
      defineGameClient({ game: 'g', keys, keysHelp: [{ keys: ['a'], help: 'x'.repeat(121) }] }),
    ).toThrow(/g: keysHelp\[0\]: help must be a string of 1 to 120 characters/)
    const client = defineGameClient({ game: 'g', keys, keysHelp: [{ keys: ['b'], help: 'boost' }] })
    expect(client.keysHelp).toEqual([
      { keys: ['b'], help: 'boost' },
      { keys: ['a', 'c'], help: 'a g command' },
    ])
    expect(defineGameClient({ game: 'g' }).keysHelp).toEqual([])
    // The shipped modules describe every key they bind (no catch-all row).
    for (const c of [goalClient, towerClient]) {
      expect(c.keysHelp.flatMap((r) => r.keys).sort()).toEqual(Object.keys(c.keys).sort())
      expect(c.keysHelp.some((r) => r.help.endsWith(' command'))).toBe(false)
    }
  })

  it('pointer bindings: functions, a down to start, short help; refused with the part named', () => {
    expect(() => defineGameClient({ game: 'g', pointer: 3 as never })).toThrow(/g: pointer must be/)
    expect(() => defineGameClient({ game: 'g', pointer: { down: 'x' as never } })).toThrow(
      /g: pointer.down must be a function/,
    )
    expect(() => defineGameClient({ game: 'g', pointer: { up: () => null } })).toThrow(
      /g: pointer needs down/,
    )
    expect(() => defineGameClient({ game: 'g', pointer: { down: () => null, help: '' } })).toThrow(
      /g: pointer.help must be a string of 1 to 120 characters/,
    )
    expect(defineGameClient({ game: 'g' }).pointer).toBeUndefined()
  })

  it('the goal pointer runs at full speed toward the point from the drawn disc, stands on it, leaves the press when over', () => {
    const view = {
      score: { red: 0, blue: 0 },
      phase: 'playing',
      secondsLeft: 90,
      team: 'red',
      winner: null,
      disc: 7,
    }
    const at = (x: number, y: number, state: unknown = view) => ({
      state,
      me: 1,
      x,
      y,
      position: (id: number) => (id === 7 ? { x: 1, y: -2 } : null),
    })
    const pointer = goalClient.pointer
    if (!pointer?.down || !pointer.move || !pointer.up)
      throw new Error('the goal client has no pointer bindings')
    // From (1, -2) to (4, 2): (3, 4), 5 m: MAX_SPEED * (0.6, 0.8).
    const diagonal = pointer.down(at(4, 2))
    expect(diagonal?.kind).toBe('run')
    expect(diagonal?.args.x).toBeCloseTo(MAX_SPEED * 0.6, 12)
    expect(diagonal?.args.y).toBeCloseTo(MAX_SPEED * 0.8, 12)
    expect(pointer.move(at(-9, -2))).toEqual({ kind: 'run', args: { x: -MAX_SPEED, y: 0 } })
    // On the disc (within its 0.5 m radius): stand still. Released: stop.
    expect(pointer.down(at(1.3, -1.7))).toEqual({ kind: 'run', args: { x: 0, y: 0 } })
    expect(pointer.up(at(5, 5))).toEqual({ kind: 'run', args: { x: 0, y: 0 } })
    // No view, no disc, a disc the page does not draw, or the match over: the page's tool has it.
    expect(pointer.down(at(4, 2, null))).toBeNull()
    expect(pointer.down(at(4, 2, { ...view, disc: null }))).toBeNull()
    expect(pointer.down(at(4, 2, { ...view, disc: 8 }))).toBeNull()
    expect(pointer.down(at(4, 2, { ...view, phase: 'over' }))).toBeNull()
  })

  it('the goal keys send run with the held direction, kick on Space, rematch only when over', () => {
    expect(press(['d'], 'd', true)).toEqual({ kind: 'run', args: { x: MAX_SPEED, y: 0 } })
    expect(press(['arrowup', 'arrowleft'], 'arrowup', true)).toEqual({
      kind: 'run',
      args: { x: -MAX_SPEED / Math.SQRT2, y: MAX_SPEED / Math.SQRT2 },
    })
    // Released: the keys still held decide; none held stops.
    expect(press(['w'], 'd', false)).toEqual({ kind: 'run', args: { x: 0, y: MAX_SPEED } })
    expect(press([], 'w', false)).toEqual({ kind: 'run', args: { x: 0, y: 0 } })
    expect(press([' '], ' ', true)).toEqual({ kind: 'kick', args: { power: 1 } })
    expect(press([' '], ' ', false)).toBeNull()
    const over = { score: { red: 5, blue: 3 }, phase: 'over', secondsLeft: 0, team: 'red', winner: 'red' }
    expect(keyCommand(goalClient.keys.r, true, { state: over, me: 1, held: new Set() })).toEqual({
      kind: 'rematch',
      args: {},
    })
    expect(
      keyCommand(goalClient.keys.r, true, { state: { ...over, phase: 'playing' }, me: 1, held: new Set() }),
    ).toBeNull()
  })

  it('the goal HUD shows the score, the clock and the phase; the tower HUD the time and heights', () => {
    const view = { score: { red: 2, blue: 1 }, phase: 'playing', secondsLeft: 65, team: 'blue', winner: null }
    expect(goalClient.hud?.(view, 1)).toEqual([
      { label: 'score', value: '2 - 1' },
      { label: 'clock', value: '1:05' },
      { label: 'match', value: 'playing' },
      { label: 'team', value: 'blue' },
    ])
    expect(goalClient.hud?.(null, 1)).toEqual([])
    const tower = {
      phase: 'building',
      secondsLeft: 9,
      heights: { 1: 1.5, 2: 2.07 },
      blocks: 4,
      fallen: 1,
      winners: [],
    }
    expect(towerClient.hud?.(tower, 1)).toEqual([
      { label: 'time', value: '0:09' },
      { label: 'height', value: '1.50 m' },
      { label: 'best', value: '2.07 m' },
      { label: 'blocks', value: '4 placed, 1 fallen' },
    ])
  })

  it('clock and metre texts', () => {
    expect([clockText(0), clockText(59), clockText(60), clockText(120), clockText(-3)]).toEqual([
      '0:00',
      '0:59',
      '1:00',
      '2:00',
      '0:00',
    ])
    expect([metres(0), metres(0.05), metres(12.3), metres(-0.5)]).toEqual([
      '0.00 m',
      '0.05 m',
      '12.30 m',
      '-0.50 m',
    ])
  })

  it('the catalogue finds the shipped client modules by game name only', () => {
    expect(findGameClient('goal')).toBe(goalClient)
    expect(findGameClient('tower')).toBe(towerClient)
    expect(findGameClient('sandbox')).toBeUndefined()
    expect(findGameClient('constructor')).toBeUndefined()
  })

  it("docs/games.md shows the goal client's run function as the source has it", () => {
    const doc = readFileSync('docs/games.md', 'utf8')
    const at = doc.indexOf('## Client modules')
    const section = doc.slice(at, doc.indexOf('\n## ', at + 1))
    const block = [...section.matchAll(/```ts\n([\s\S]*?)```/g)]
      .map((m) => m[1])
      .find((b) => b.startsWith('function run'))
    expect(block).toBeDefined()
    const squash = (code: string): string => code.replace(/[\s;]+/g, '')
    expect(squash(readFileSync('games/goal/goal-client.ts', 'utf8'))).toContain(squash(block ?? 'missing'))
  })
})
