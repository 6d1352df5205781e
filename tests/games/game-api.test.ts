/*
 * The game module API (games/game-api.ts) running inside RoomSimulation: commands with JSON Schema
 * arguments, hooks, the seeded PRNG, events, and the game's own state as part of the simulation's
 * save, sync and hash. The oracles are independent of the code under test: hand-counted scores,
 * a second simulation fed the same inputs, hashes of data written out by hand, and deliberate
 * tampering (one changed number, a PRNG restarted from its seed) that must change the hash.
 */
import { describe, expect, it } from 'vitest'
import { circle, SAVE_FORMAT_VERSION } from '../../engine/index.ts'
import {
  builtin,
  compileArgs,
  defineGame,
  findGame,
  type Game,
  sandbox,
  sandboxCommands,
} from '../../games/index.ts'
import {
  cloneSimulation,
  encodePreamble,
  encodeRecord,
  encodeSyncPayload,
  hashPlainData,
  type PlainData,
  PROTOCOL_VERSION,
  REPLAY_FORMAT_VERSION,
  type ReplayRecord,
  RoomSimulation,
  replayBytes,
  restoreSyncPayload,
  type SimCommand,
  type SimulationObserver,
  TICK_RATE,
} from '../../shared/index.ts'

interface TallyState {
  [key: string]: PlainData
  scores: Record<string, number>
  drops: number
  log: string[]
}

/** Applies that ran (a refused command must never get here). */
const applied: string[] = []

/** A small game: players add points, a ball drops at a random x every 30 ticks, goals are logged. */
const tally = defineGame<TallyState>({
  name: 'tally',
  minPlayers: 1,
  maxPlayers: 3,
  state: { scores: {}, drops: 0, log: [] },
  setup(ctx) {
    ctx.createBody({ type: 'static', position: { x: 0, y: -1 }, shape: circle(1) })
  },
  commands: {
    add: {
      args: {
        type: 'object',
        properties: {
          n: { type: 'integer', minimum: 1, maximum: 10 },
          why: { type: 'string', maxLength: 8 },
        },
        required: ['n'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { n: number; why?: string }) {
        applied.push(`add ${args.n}`)
        if (args.why === 'no') return 'the game says no'
        ctx.state.scores[player] = (ctx.state.scores[player] ?? 0) + args.n
      },
    },
    boom: {
      args: { type: 'object', additionalProperties: false },
      apply(ctx) {
        ctx.state.drops += 100
        throw new Error('boom')
      },
    },
    move: builtin('move', (ctx, player, cmd) => ctx.moveCursor(player, cmd.x, cmd.y)),
  },
  onJoin(ctx, player) {
    ctx.state.scores[player] = 0
    ctx.state.log.push(`join ${player} at ${ctx.tick}`)
  },
  onLeave(ctx, player) {
    delete ctx.state.scores[player]
    ctx.state.log.push(`leave ${player}`)
  },
  tick(ctx) {
    if (ctx.tick % 30 !== 0) return
    const x = ctx.random.range(-5, 5)
    ctx.createBody({ type: 'dynamic', position: { x, y: 5 }, shape: circle(0.25) })
    ctx.state.drops++
    ctx.emit({ drop: ctx.state.drops, x })
  },
})

const catalog = (name: string): Game | undefined => (name === 'tally' ? tally : findGame(name))
const options = { game: tally, name: 'g', scene: 'empty', maxBodies: 200, controls: true }

const add = (n: number, why?: string): SimCommand => ({ k: 'cmd', kind: 'add', a: why ? { n, why } : { n } })

/** A session: joins, adds and a leave at fixed ticks; `until` ticks long. */
function play(sim: RoomSimulation, from: number, until: number, each?: (sim: RoomSimulation) => void): void {
  for (let t = from; t < until; t++) {
    if (t === 0) sim.join(1, 'a', '#f00')
    if (t === 5) sim.join(2, 'b', '#0f0')
    if (t % 7 === 3) expect(sim.apply(1, add((t % 10) + 1))).toBeNull()
    if (t % 11 === 4 && sim.players.has(2)) expect(sim.apply(2, add(2))).toBeNull()
    if (t === 150) sim.leave(2)
    sim.runTick()
    each?.(sim)
  }
}

describe('a game on the game module API', () => {
  it('applies its commands and hooks to its own state, as counted by hand', () => {
    applied.length = 0
    const sim = new RoomSimulation(options)
    sim.join(1, 'a', '#f00')
    sim.join(2, 'b', '#0f0')
    expect(sim.apply(1, add(3))).toBeNull()
    expect(sim.apply(1, add(4))).toBeNull()
    expect(sim.apply(2, add(10))).toBeNull()
    expect(sim.gameState).toEqual({ scores: { 1: 7, 2: 10 }, drops: 0, log: ['join 1 at 0', 'join 2 at 0'] })
    sim.leave(2)
    expect(sim.gameState).toMatchObject({ scores: { 1: 7 }, log: ['join 1 at 0', 'join 2 at 0', 'leave 2'] })
    expect(sim.world.bodyCount).toBe(1)
    for (let i = 0; i < 90; i++) sim.runTick()
    // Ticks 30, 60 and 90 each drop one ball.
    expect((sim.gameState as TallyState).drops).toBe(3)
    expect(sim.world.bodyCount).toBe(4)
  })

  it('refuses arguments that do not fit the schema, naming the field, before apply runs', () => {
    applied.length = 0
    const sim = new RoomSimulation(options)
    sim.join(1, 'a', '#f00')
    const refusals: Array<[PlainData, string]> = [
      [{ n: 11 }, 'add refused: n must be <= 10'],
      [{ n: 0 }, 'add refused: n must be >= 1'],
      [{ n: 1.5 }, 'add refused: n must be integer'],
      [{ n: '3' }, 'add refused: n must be integer'],
      [{}, 'add refused: n is required'],
      [{ n: 1, extra: true }, 'add refused: extra is not allowed'],
      [{ n: 1, why: 'x'.repeat(9) }, 'add refused: why must NOT have more than 8 characters'],
      [null, 'add refused: arguments must be object'],
      [[1], 'add refused: arguments must be object'],
    ]
    for (const [a, reason] of refusals) expect(sim.apply(1, { k: 'cmd', kind: 'add', a })).toBe(reason)
    // NaN and the infinities never pass as numbers (msgpack can carry them).
    for (const n of [Number.NaN, Number.POSITIVE_INFINITY])
      expect(sim.apply(1, { k: 'cmd', kind: 'add', a: { n } })).toBe('add refused: n must be a finite number')
    expect(sim.apply(1, { k: 'cmd', kind: 'kick', a: {} })).toBe('game tally has no kick command')
    expect(sim.apply(1, { k: 'spawn', shape: { type: 'circle', radius: 1 }, x: 0, y: 0 })).toBe(
      'game tally has no spawn command',
    )
    expect(sim.apply(1, { k: 'cmd', kind: 'move', a: { x: 1, y: 1 } })).toBe('game tally has no move command')
    expect(applied).toEqual([])
    // The game's own refusal: apply ran, nothing was recorded.
    const seen: SimCommand[] = []
    sim.observers.push({ ...silent, command: (_t, _p, cmd) => seen.push(cmd) })
    expect(sim.apply(1, add(2, 'no'))).toBe('the game says no')
    expect(applied).toEqual(['add 2'])
    expect(seen).toEqual([])
  })

  it('checks arguments without eval, as a browser page under a CSP without unsafe-eval must', () => {
    // The page's Content Security Policy refuses new Function (Ajv's way of compiling a schema made
    // every page fail to start); forbid it here and compile and check a schema.
    const saved = globalThis.Function
    const refuse = () => {
      throw new EvalError('eval is forbidden here')
    }
    globalThis.Function = refuse as unknown as FunctionConstructor
    try {
      const check = compileArgs('kick', {
        type: 'object',
        properties: {
          power: { type: 'integer', minimum: 1, maximum: 10 },
          foot: { enum: ['left', 'right'] },
        },
        required: ['power'],
        additionalProperties: false,
      })
      expect(check({ power: 3, foot: 'left' })).toBeNull()
      expect(check({ power: 11 })).toBe('power must be <= 10')
      expect(check({ power: 2, foot: 'head' })).toBe('foot must be equal to one of the allowed values')
      expect(check({ power: 2, to: 1 })).toBe('to is not allowed')
    } finally {
      globalThis.Function = saved
    }
  })

  it('a game command that throws is refused to its sender but recorded, since it changed the state', () => {
    const sim = new RoomSimulation(options)
    sim.join(1, 'a', '#f00')
    const seen: SimCommand[] = []
    sim.observers.push({ ...silent, command: (_t, _p, cmd) => seen.push(cmd) })
    const boom: SimCommand = { k: 'cmd', kind: 'boom', a: {} }
    expect(sim.apply(1, boom)).toBe('boom failed: boom')
    expect(seen).toEqual([boom])
    expect((sim.gameState as TallyState).drops).toBe(100)
    // A replica applying the recorded command throws alike and reports no divergence.
    const replica = new RoomSimulation(options)
    replica.join(1, 'a', '#f00')
    expect(replica.applyAccepted(1, boom)).toBeNull()
    expect(replica.hash()).toBe(sim.hash())
  })

  it('a tick that throws pauses the room and reports it', () => {
    const failing = defineGame({
      name: 'failing',
      commands: {},
      tick(ctx) {
        if (ctx.tick === 3) throw new Error('bad rule')
      },
    })
    const failures: string[] = []
    const sim = new RoomSimulation({
      ...options,
      game: failing,
      listener: { ...quietListener, gameFailed: (tick, message) => failures.push(`${tick}: ${message}`) },
    })
    for (let i = 0; i < 10; i++) sim.runTick()
    expect(failures).toEqual(['3: failing tick failed: bad rule'])
    expect(sim.paused).toBe(true)
    expect(sim.world.tick).toBe(3)
  })

  it('admits at most maxPlayers; a rejoin of a present player is not a new one', () => {
    const sim = new RoomSimulation(options)
    for (const id of [1, 2, 3]) expect(sim.join(id, `p${id}`, '#fff')).toBeNull()
    expect(sim.join(4, 'p4', '#fff')).toBe('game tally is full (3 players)')
    expect(sim.join(2, 'p2', '#fff')).toBeNull()
    expect(sim.players.size).toBe(3)
    expect((sim.gameState as TallyState).log.length).toBe(3)
  })

  it('emits events to the listener with their tick, as plain data copies', () => {
    const events: Array<[number, PlainData]> = []
    const sim = new RoomSimulation({
      ...options,
      listener: { ...quietListener, gameEvent: (tick, e) => events.push([tick, e]) },
    })
    for (let i = 0; i < 60; i++) sim.runTick()
    expect(events.map(([t, e]) => [t, (e as { drop: number }).drop])).toEqual([
      [30, 1],
      [60, 2],
    ])
  })

  it('ctx.events is empty outside tick and holds the step events inside it', () => {
    const seen: Array<string> = []
    const probe = defineGame({
      name: 'probe',
      setup(ctx) {
        seen.push(`setup ${ctx.events.contacts === null}`)
      },
      commands: {
        look: {
          args: { type: 'object' },
          apply(ctx) {
            seen.push(`command ${ctx.events.contacts === null}`)
          },
        },
      },
      tick(ctx) {
        // The engine's event calls are another branch's: until they merge, null everywhere.
        const has = typeof (ctx.world as unknown as { contactEvents?: unknown }).contactEvents === 'function'
        seen.push(`tick ${(ctx.events.contacts !== null) === has}`)
      },
    })
    const sim = new RoomSimulation({ ...options, game: probe })
    sim.join(1, 'a', '#fff')
    sim.apply(1, { k: 'cmd', kind: 'look', a: {} })
    sim.runTick()
    expect(seen).toEqual(['setup true', 'command true', 'tick true'])
  })
})

const silent: SimulationObserver = {
  command: () => {},
  join: () => {},
  leave: () => {},
  worldLoaded: () => {},
}

const quietListener = {
  bodyAdded: () => {},
  bodyRemoved: () => {},
  jointAdded: () => {},
  jointRemoved: () => {},
  roomChanged: () => {},
  cursorChanged: () => {},
  worldReplaced: () => {},
}

describe("a game's state is part of the simulation's save and hash", () => {
  it('save, load into a fresh simulation, continue: the hashes agree at every tick', () => {
    const a = new RoomSimulation(options)
    play(a, 0, 100)
    const b = new RoomSimulation(options)
    b.restoreState(a.saveState(), cloneWorld(a))
    expect(b.hash()).toBe(a.hash())
    const hashesA: number[] = []
    const hashesB: number[] = []
    play(a, 100, 400, (s) => hashesA.push(s.hash()))
    play(b, 100, 400, (s) => hashesB.push(s.hash()))
    expect(hashesB).toEqual(hashesA)
    expect((a.gameState as TallyState).drops).toBe(13)
    expect(b.gameState).toEqual(a.gameState)
  })

  it('one changed number in the state, or a PRNG back at its seed, changes the hash (and the future)', () => {
    const a = new RoomSimulation(options)
    play(a, 0, 100)
    const tampered = a.saveState()
    ;(tampered.gameState as TallyState).scores[1] += 1
    const b = new RoomSimulation(options)
    b.restoreState(tampered, cloneWorld(a))
    expect(b.hash()).not.toBe(a.hash())
    expect(b.world.hash()).toBe(a.world.hash())
    const reseeded = a.saveState()
    reseeded.random = new RoomSimulation(options).random.position()
    const c = new RoomSimulation(options)
    c.restoreState(reseeded, cloneWorld(a))
    expect(c.hash()).not.toBe(a.hash())
    play(a, 100, 130)
    play(c, 100, 130)
    // The tick-120 ball fell at another x.
    expect(c.world.hash()).not.toBe(a.world.hash())
  })

  it('a sandbox room keeps no game state: its hash is its world hash', () => {
    const sim = new RoomSimulation({ ...options, game: sandbox, scene: 'pyramid' })
    for (let i = 0; i < 10; i++) sim.runTick()
    expect(sim.gameState).toBeUndefined()
    expect(sim.hash()).toBe(sim.world.hash())
    expect(sim.saveState()).toMatchObject({ game: 'sandbox', gameState: null })
  })

  it('hashPlainData hashes equal data alike whatever its key order, and anything else apart', () => {
    expect(hashPlainData({ a: 1, b: [true, 'x'] })).toBe(hashPlainData({ b: [true, 'x'], a: 1 }))
    expect(hashPlainData(0)).toBe(hashPlainData(-0))
    const distinct: PlainData[] = [
      null,
      false,
      true,
      0,
      1,
      0.1,
      '',
      '0',
      'a',
      [],
      [null],
      {},
      { a: null },
      [[]],
      { '': 0 },
    ]
    const hashes = new Set(distinct.map((v) => hashPlainData(v)))
    expect(hashes.size).toBe(distinct.length)
    // FNV-1a of the bytes written out by hand: tag 0 (null) from the offset basis.
    expect(hashPlainData(null)).toBe(Math.imul(0x811c9dc5 ^ 0, 0x01000193) >>> 0)
  })

  it('a lockstep sync carries the state and the PRNG: the restored simulation continues bit for bit', () => {
    const a = new RoomSimulation(options)
    play(a, 0, 100)
    const restored = restoreSyncPayload(encodeSyncPayload(a), {
      maxBodies: 200,
      controls: true,
      name: 'g',
      games: catalog,
    })
    if (!restored.ok) throw new Error(restored.reason)
    const b = restored.sim
    expect(b.game).toBe(tally)
    expect(b.hash()).toBe(a.hash())
    const copy = cloneSimulation(a, { maxBodies: 200, controls: true, name: 'g' })
    const hashes: number[][] = [[], [], []]
    play(a, 100, 300, (s) => hashes[0].push(s.hash()))
    play(b, 100, 300, (s) => hashes[1].push(s.hash()))
    play(copy, 100, 300, (s) => hashes[2].push(s.hash()))
    expect(hashes[1]).toEqual(hashes[0])
    expect(hashes[2]).toEqual(hashes[0])
  })

  it('a sync of a game this build does not have is refused by name', () => {
    const a = new RoomSimulation(options)
    const restored = restoreSyncPayload(encodeSyncPayload(a), {
      maxBodies: 200,
      controls: true,
      name: 'g',
      games: findGame,
    })
    expect(restored).toEqual({ ok: false, reason: 'sync payload: game tally is not in this build' })
  })

  it('a recorded log of a game room replays with every hash matching (and a wrong hash is caught)', async () => {
    const records: ReplayRecord[] = []
    const sim = new RoomSimulation(options)
    const header = (): ReplayRecord => ({
      type: 'header',
      tick: sim.tick,
      room: 'g',
      scene: 'empty',
      start: 0,
      maxBodies: 200,
      controls: true,
      state: sim.saveState(),
      host: 'test',
      pid: 1,
      z: 0,
      world: sim.world.save(),
    })
    records.push(header())
    sim.observers.push({
      command: (tick, player, cmd) => records.push({ type: 'command', tick, player, cmd }),
      join: (tick, player, name, color) => records.push({ type: 'join', tick, player, name, color }),
      leave: (tick, player) => records.push({ type: 'leave', tick, player }),
      worldLoaded: () => {},
      ticked: (tick) => {
        if (tick % TICK_RATE === 0)
          records.push({ type: 'hash', tick, hash: sim.hash(), step: sim.world.tick })
      },
    })
    play(sim, 0, 300)
    expect(sim.apply(1, { k: 'cmd', kind: 'boom', a: {} })).toBe('boom failed: boom')
    sim.runTick()
    for (let i = 0; i < TICK_RATE; i++) sim.runTick()
    records.push({ type: 'close', tick: sim.tick, reason: 'test', end: 0 })
    const log = (list: ReplayRecord[], protocol = PROTOCOL_VERSION): Uint8Array => {
      const parts = [
        encodePreamble({
          format: REPLAY_FORMAT_VERSION,
          engine: SAVE_FORMAT_VERSION,
          protocol,
          tickRate: TICK_RATE,
        }),
        ...list.map(encodeRecord),
      ]
      const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0))
      let at = 0
      for (const p of parts) {
        out.set(p, at)
        at += p.length
      }
      return out
    }
    const noInflate = (): Uint8Array => {
      throw new Error('nothing is deflated')
    }
    const report = await replayBytes(log(records), noInflate, catalog, { verify: true })
    expect(report.divergence).toBeNull()
    expect(report.hashesChecked).toBe(6)
    expect(report.finalHash).toBe(sim.hash())
    // A game state that differs only in the game's part is caught by the hash records.
    const hashes = records.filter((r) => r.type === 'hash')
    const last = hashes[hashes.length - 1] as Extract<ReplayRecord, { type: 'hash' }>
    const wrong = records.map((r) => (r === last ? { ...last, hash: (last.hash + 1) >>> 0 } : r))
    const bad = await replayBytes(log(wrong), noInflate, catalog, { verify: true })
    expect(bad.divergence?.tick).toBe(last.tick)
    // A log of the protocol before games (version 2) is refused in one line naming both versions.
    await expect(replayBytes(log(records, 2), noInflate, catalog)).rejects.toThrow(
      'cannot start from the header: log written with protocol version 2; this build speaks version 3',
    )
    await expect(replayBytes(log(records), noInflate, findGame)).rejects.toThrow(
      "cannot start from the header: the log's game tally is not in this build",
    )
  })
})

/** A world copy through save/load. */
function cloneWorld(sim: RoomSimulation) {
  return cloneSimulation(sim, { maxBodies: 200, controls: true, name: 'x' }).world
}

describe('defineGame refuses a bad definition with a message naming what is wrong', () => {
  const ok = { name: 'ok', commands: {} }
  it.each([
    [{ ...ok, name: 'Bad Name' }, 'game name "Bad Name" must be 1 to 32 lowercase letters'],
    [{ ...ok, maxPlayers: 0 }, 'game ok: maxPlayers must be an integer from 1 to 1024, got 0'],
    [{ ...ok, minPlayers: 5, maxPlayers: 2 }, 'game ok: minPlayers 5 is more than maxPlayers 2'],
    [{ ...ok, state: { when: new Date(0) } }, 'game ok state.when is a class instance'],
    [{ ...ok, state: { f: () => 1 } }, 'game ok state.f is function'],
    [
      { ...ok, commands: { spawn: { args: { type: 'object' }, apply: () => {} } } },
      "game ok: command spawn is a built-in kind; list it with builtin('spawn', ...)",
    ],
    [
      { ...ok, commands: { 'no-dash': { args: { type: 'object' }, apply: () => {} } } },
      'game ok: command kind "no-dash" must be a letter',
    ],
    [
      { ...ok, commands: { kick: { args: { type: 'number' }, apply: () => {} } } },
      "command kick: its args schema must be a JSON Schema of type 'object'",
    ],
    [
      {
        ...ok,
        commands: {
          kick: { args: { type: 'object', properties: { p: { type: 'nmber' } } }, apply: () => {} },
        },
      },
      'command kick: bad args schema',
    ],
    [
      { ...ok, commands: { grab: { ...sandboxCommands.spawn } } },
      'game ok: command grab is listed as built-in spawn',
    ],
  ])('%#: %s', (definition, message) => {
    expect(() => defineGame(definition as never)).toThrow(message)
  })
})
