/*
 * Undo and redo in the sandbox (games/sandbox/undo-commands.ts, docs/games.md "Undo and redo"), on
 * a real RoomSimulation. The expectations are written by hand from what the guide promises (which
 * bodies and joints exist after which commands, with which poses, shapes and materials) and read
 * through the engine's own read-back (world.getBodyDef, getJointDef), not through the undo code.
 */
import { describe, expect, it } from 'vitest'
import { loadWorld } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { MAX_HISTORY, type PlainData, type SimCommand, type SpawnCommand } from '../../../shared/index.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { cloneSimulation, encodeSyncPayload, restoreSyncPayload } from '../../../shared/sim/sync-payload.ts'

const options = { game: sandbox, name: 'unit', scene: 'empty', maxBodies: 200, controls: true }
const cmd = (kind: string, a: { [key: string]: PlainData } = {}): SimCommand => ({ k: 'cmd', kind, a })
const undo = cmd('undo')
const redo = cmd('redo')
const spawnAt = (x: number, y: number, extra: Partial<SpawnCommand> = {}): SpawnCommand => ({
  k: 'spawn',
  shape: { type: 'box', hw: 0.5, hh: 0.25 },
  x,
  y,
  ...extra,
})

/** A sandbox room on the empty scene (its one body: the ground) with players 1 and 2. */
function room(): RoomSimulation {
  const sim = new RoomSimulation(options)
  sim.join(1, 'ada', '#ff0000')
  sim.join(2, 'bob', '#00ff00')
  return sim
}

/** The ids of the bodies besides the scene's ground (body 1), ascending. */
const built = (sim: RoomSimulation): number[] => sim.world.bodyIds().filter((id) => id !== 1)
/** The newest body (ids ascending, never reused). */
const newest = (sim: RoomSimulation): number => sim.world.bodyIds().at(-1) as number

/** Apply and expect acceptance. */
function ok(sim: RoomSimulation, player: number, c: SimCommand): void {
  expect(sim.apply(player, c), `${player}: ${c.k === 'cmd' ? c.kind : c.k}`).toBeNull()
}

describe('sandbox undo of spawns', () => {
  it('spawn three, undo twice: one body is left, the first, at the pose it was spawned with', () => {
    const sim = room()
    ok(sim, 1, spawnAt(-3, 4, { angle: 0.25 }))
    const first = newest(sim)
    ok(sim, 1, spawnAt(0, 4))
    ok(sim, 1, spawnAt(3, 4))
    ok(sim, 1, undo)
    ok(sim, 1, undo)
    expect(built(sim)).toEqual([first])
    expect(sim.world.getPosition(first)).toEqual({ x: -3, y: 4 })
    expect(sim.world.getAngle(first)).toBeCloseTo(0.25, 12)
  })

  it('redo brings an undone spawn back (a new id) as it was spawned, and a new action clears redo', () => {
    const sim = room()
    ok(sim, 1, spawnAt(2, 5, { density: 3, friction: 0.2, restitution: 0.5, color: 0x123456 }))
    const id = newest(sim)
    const def = sim.world.getBodyDef(id)
    ok(sim, 1, undo)
    expect(built(sim)).toEqual([])
    ok(sim, 1, redo)
    const back = newest(sim)
    expect(back).toBeGreaterThan(id) // ids are never reused
    expect(sim.world.getBodyDef(back)).toEqual(def)
    expect(sim.bodyColors.get(back)).toBe(0x123456)
    // The redone spawn undoes again (its entry names the new id).
    ok(sim, 1, undo)
    expect(built(sim)).toEqual([])
    ok(sim, 1, spawnAt(0, 3))
    expect(sim.apply(1, redo)).toBe('nothing to redo')
  })

  it('refuses with "nothing to undo" / "nothing to redo" and changes nothing', () => {
    const sim = room()
    const hash = sim.hash()
    expect(sim.apply(1, undo)).toBe('nothing to undo')
    expect(sim.apply(1, redo)).toBe('nothing to redo')
    expect(sim.hash()).toBe(hash)
  })

  it('keeps each player its own history: undo removes only the undoer’s last action', () => {
    const sim = room()
    ok(sim, 1, spawnAt(-2, 3))
    const a = newest(sim)
    ok(sim, 2, spawnAt(2, 3))
    const b = newest(sim)
    ok(sim, 1, spawnAt(0, 6))
    ok(sim, 2, undo)
    expect(built(sim)).toEqual([a, b + 1])
    ok(sim, 1, undo)
    ok(sim, 1, undo)
    expect(built(sim)).toEqual([])
    expect(sim.apply(1, undo)).toBe('nothing to undo')
    ok(sim, 2, redo)
    expect(built(sim)).toHaveLength(1)
    expect(sim.world.getPosition(newest(sim))).toEqual({ x: 2, y: 3 })
  })

  it(`keeps the last ${MAX_HISTORY} actions: 40 spawns undo down to the first 8`, () => {
    const sim = room()
    const ids: number[] = []
    for (let i = 0; i < 40; i++) {
      ok(sim, 1, spawnAt(i - 20, 5))
      ids.push(newest(sim))
    }
    for (let i = 0; i < MAX_HISTORY; i++) ok(sim, 1, undo)
    expect(sim.apply(1, undo)).toBe('nothing to undo')
    expect(built(sim)).toEqual(ids.slice(0, 8))
  })

  it('undoes a static shape a player drew (a static spawn of segments) like any spawn', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 1, { shape: { type: 'segment', v: [-2, 0, 2, 0] }, static: true }))
    const line = newest(sim)
    expect(sim.world.getBodyType(line)).toBe('static')
    ok(sim, 1, undo)
    expect(sim.world.hasBody(line)).toBe(false)
    ok(sim, 1, redo)
    expect(sim.world.getBodyType(newest(sim))).toBe('static')
  })

  it("forgets a player's history when it leaves", () => {
    const sim = room()
    ok(sim, 2, spawnAt(0, 3))
    sim.leave(2)
    sim.join(2, 'bob', '#00ff00')
    expect(sim.apply(2, undo)).toBe('nothing to undo')
    expect(sim.history.empty).toBe(true)
  })

  it('is cleared by a reset: nothing to undo afterwards', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 5))
    sim.tick += 20 // past the scene-load rate limit
    ok(sim, 1, { k: 'reset' })
    expect(sim.apply(1, undo)).toBe('nothing to undo')
  })
})

describe('sandbox undo of deletes and joints', () => {
  it('undoing a delete brings the body back with its shapes, materials, pose, colour and its joint', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 2, { shape: { type: 'circle', radius: 0.4 }, density: 2.5 }))
    const a = newest(sim)
    ok(sim, 1, spawnAt(1, 2, { friction: 0.1, restitution: 0.7, color: 0xabcdef, angle: 0.5 }))
    const b = newest(sim)
    ok(sim, 1, cmd('hinge', { a, b, x: 0.8, y: 2, lower: -0.5, upper: 0.5, torque: 3, speed: 1 }))
    const joint = sim.world.jointIds().at(-1) as number
    for (let i = 0; i < 30; i++) sim.runTick()
    const def = sim.world.getBodyDef(b)
    const jointDef = sim.world.getJointDef(joint)
    const wire = sim.userJoints.get(joint)
    ok(sim, 2, { k: 'delete', body: b })
    expect(sim.world.hasBody(b)).toBe(false)
    expect(sim.userJoints.size).toBe(0)
    ok(sim, 2, undo)
    const back = newest(sim)
    expect(back).toBeGreaterThan(b)
    expect(sim.world.getBodyDef(back)).toEqual(def)
    expect(sim.bodyColors.get(back)).toBe(0xabcdef)
    const joints = sim.world.jointIds()
    expect(joints).toHaveLength(1)
    expect(sim.world.getJointDef(joints[0])).toEqual({ ...jointDef, bodyB: back })
    // The joint is the maker's again (player 1 drives its motor), as it travels.
    expect(sim.userJoints.get(joints[0])).toMatchObject({ kind: 'pin', a, b: back, owner: 1, limit: true })
    expect(sim.userJoints.get(joints[0])?.speed).toBe(wire?.speed)
    // Redo deletes it again.
    ok(sim, 2, redo)
    expect(sim.world.hasBody(back)).toBe(false)
    expect(sim.world.jointIds()).toEqual([])
  })

  it('undoing a delete leaves out a joint whose other body is gone', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 2))
    const a = newest(sim)
    ok(sim, 1, spawnAt(1, 2))
    const b = newest(sim)
    ok(sim, 1, cmd('weld', { a, b, x: 0.5, y: 2 }))
    ok(sim, 2, { k: 'delete', body: b })
    ok(sim, 1, { k: 'delete', body: a })
    ok(sim, 2, undo)
    expect(built(sim)).toHaveLength(1)
    expect(sim.world.jointIds()).toEqual([])
  })

  it('undoes each joint command (remove the joint) and unjoint (rebuild it); redo does them again', () => {
    const made: Array<[string, { [key: string]: PlainData }]> = [
      ['weld', { x: 0.5, y: 2 }],
      ['hinge', { x: 0.5, y: 2 }],
      ['spring', { ax: 0, ay: 2, bx: 1, by: 2, hz: 3 }],
      ['slider', { x: 0.5, y: 2, dx: 1, dy: 0 }],
      ['wheel', {}],
    ]
    for (const [kind, args] of made) {
      const sim = room()
      ok(sim, 1, spawnAt(0, 2))
      const a = newest(sim)
      ok(sim, 1, spawnAt(1, 2))
      const b = newest(sim)
      ok(sim, 1, cmd(kind, { a, b, ...args }))
      const j = sim.world.jointIds().at(-1) as number
      const def = sim.world.getJointDef(j)
      ok(sim, 1, undo)
      expect(sim.world.jointIds(), kind).toEqual([])
      ok(sim, 1, redo)
      const j2 = sim.world.jointIds().at(-1) as number
      expect(sim.world.getJointDef(j2), kind).toEqual(def)
      ok(sim, 1, { k: 'unjoint', joint: j2 })
      ok(sim, 1, undo)
      expect(sim.world.getJointDef(sim.world.jointIds()[0]), kind).toEqual(def)
      ok(sim, 1, undo) // the redone joint command: removes the rebuilt joint (renamed)
      expect(sim.world.jointIds(), kind).toEqual([])
    }
  })

  it('undoes pin and rope, and a wheel that made its wheel removes the wheel too', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 2))
    const a = newest(sim)
    ok(sim, 1, spawnAt(1, 2))
    const b = newest(sim)
    ok(sim, 1, { k: 'pin', a, b, x: 0.6, y: 2 })
    ok(sim, 1, { k: 'rope', a: 0, b, ax: 1, ay: 5, bx: 1, by: 2 })
    expect(sim.userJoints.size).toBe(2)
    ok(sim, 1, undo)
    expect([...sim.userJoints.values()].map((j) => j.kind)).toEqual(['pin'])
    ok(sim, 1, undo)
    expect(sim.userJoints.size).toBe(0)
    ok(sim, 1, cmd('wheel', { a, radius: 0.3, x: 0, y: 1.5 }))
    expect(built(sim)).toHaveLength(3)
    ok(sim, 1, undo)
    expect(built(sim)).toEqual([a, b])
    expect(sim.userJoints.size).toBe(0)
  })

  it('refuses an undo whose body another player deleted, naming both; the other player’s undo makes it work again', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 3))
    const b = newest(sim)
    ok(sim, 2, { k: 'delete', body: b })
    const hash = sim.hash()
    expect(sim.apply(1, undo)).toBe(`cannot undo spawn: body ${b} was deleted by player 2`)
    expect(sim.hash()).toBe(hash)
    ok(sim, 2, undo)
    const back = newest(sim)
    // Player 1's entry now names the rebuilt body: undo removes it.
    ok(sim, 1, undo)
    expect(sim.world.hasBody(back)).toBe(false)
    expect(built(sim)).toEqual([])
  })

  it('refuses an undo of a joint that is gone; {skip: true} drops it and undoes the one before', () => {
    const sim = room()
    ok(sim, 1, spawnAt(0, 2))
    const a = newest(sim)
    ok(sim, 1, spawnAt(1, 2))
    const b = newest(sim)
    ok(sim, 1, cmd('weld', { a, b, x: 0.5, y: 2 }))
    const j = sim.world.jointIds().at(-1) as number
    ok(sim, 2, { k: 'unjoint', joint: j })
    expect(sim.apply(1, undo)).toBe(`cannot undo weld: joint ${j} was removed by player 2`)
    ok(sim, 1, cmd('undo', { skip: true }))
    expect(built(sim)).toEqual([a])
  })

  it('refuses a rebuild past the body limit, changing nothing', () => {
    const sim = new RoomSimulation({ ...options, maxBodies: 3 })
    sim.join(1, 'ada', '#f00')
    sim.join(2, 'bob', '#0f0')
    ok(sim, 1, spawnAt(0, 2))
    ok(sim, 1, { k: 'delete', body: newest(sim) })
    ok(sim, 2, spawnAt(1, 2))
    ok(sim, 2, spawnAt(2, 2))
    const hash = sim.hash()
    expect(sim.apply(1, undo)).toBe('cannot undo delete: body limit reached (3)')
    expect(sim.hash()).toBe(hash)
    ok(sim, 2, undo)
    ok(sim, 1, undo)
    expect(built(sim)).toHaveLength(2)
  })
})

describe("sandbox undo of the Edit tool's commands", () => {
  it('undoing an edit rebuilds the body with the material, colour and type it had; redo edits it again', () => {
    const sim = room()
    ok(sim, 1, spawnAt(1, 3, { density: 2, friction: 0.4, color: 0x334455 }))
    const id = newest(sim)
    const def = sim.world.getBodyDef(id)
    const shapeDef = sim.world.getShapeDef(sim.world.bodyShapes(id)[0])
    ok(sim, 1, cmd('edit', { body: id, density: 5, friction: 1.5, color: 0xabcdef, static: true }))
    expect(sim.world.getBodyType(id)).toBe('static')
    ok(sim, 1, undo)
    const back = newest(sim)
    expect(built(sim)).toEqual([back])
    expect(back).toBeGreaterThan(id)
    expect(sim.world.getBodyDef(back)).toEqual(def)
    expect(sim.world.getShapeDef(sim.world.bodyShapes(back)[0])).toEqual(shapeDef)
    expect(sim.bodyColors.get(back)).toBe(0x334455)
    ok(sim, 1, redo)
    const again = newest(sim)
    expect(sim.world.getBodyType(again)).toBe('static')
    expect(sim.world.getShapeDef(sim.world.bodyShapes(again)[0]).friction).toBe(1.5)
    expect(sim.bodyColors.get(again)).toBe(0xabcdef)
  })

  it('undoes a transform (pose and scale back), a duplicate (the copy goes) and a deleteMany (every body back)', () => {
    const sim = room()
    sim.apply(1, { k: 'gravity', x: 0, y: 0 })
    ok(sim, 1, spawnAt(-2, 3))
    const a = newest(sim)
    ok(sim, 1, spawnAt(2, 3))
    const b = newest(sim)
    ok(sim, 1, cmd('transform', { body: a, x: 4, y: 6, angle: 1, scale: 2 }))
    expect(sim.world.getPosition(a)).toEqual({ x: 4, y: 6 })
    ok(sim, 1, undo)
    const a2 = newest(sim)
    expect(sim.world.getPosition(a2)).toEqual({ x: -2, y: 3 })
    expect(sim.world.getAngle(a2)).toBe(0)
    const poly = sim.world.getShapeDef(sim.world.bodyShapes(a2)[0]).shape
    expect(poly.type === 'polygon' && poly.box).toEqual({ halfWidth: 0.5, halfHeight: 0.25 })
    ok(sim, 1, cmd('duplicate', { body: b, dx: 0, dy: 2 }))
    expect(built(sim)).toHaveLength(3)
    ok(sim, 1, undo)
    expect(built(sim).sort((x, y) => x - y)).toEqual([b, a2].sort((x, y) => x - y))
    ok(sim, 1, cmd('deleteMany', { bodies: [a2, b] }))
    expect(built(sim)).toEqual([])
    ok(sim, 1, undo)
    const back = built(sim)
    expect(back).toHaveLength(2)
    // Rebuilt in ascending id order of the deleted: b (older) first, then a2.
    expect(back.map((id) => sim.world.getPosition(id))).toEqual([
      { x: 2, y: 3 },
      { x: -2, y: 3 },
    ])
  })
})

/** A script of commands at ticks, for the continuation tests. */
const SCRIPT: Array<[number, number, SimCommand]> = [
  [1, 1, { k: 'gravity', x: 0, y: 0 }],
  [1, 1, spawnAt(-1, 3)], // body 2
  [2, 2, spawnAt(2, 3, { color: 0x00ff00 })], // body 3
  [4, 1, spawnAt(0, 3)], // body 4
  [6, 1, undo], // removes 4
  [8, 2, { k: 'delete', body: 3 }],
  [10, 1, redo], // body 5 at (0, 3)
  [30, 2, undo], // body 6 (3 rebuilt)
  [32, 1, { k: 'pin', a: 2, b: 5, x: -0.5, y: 3 }],
  [40, 1, undo], // the pin goes
  [41, 1, undo], // body 5 goes
  [50, 2, redo], // body 6 deleted again
  [52, 2, undo], // body 7
  [60, 1, redo], // body 8
  [62, 1, redo], // the pin again
  [70, 1, undo],
  [75, 2, redo],
  [76, 2, redo], // nothing to redo
]

/** Run the script from `from` (exclusive) to tick 90; the hash after every tick, and each command's result. */
function run(sim: RoomSimulation, from: number): { hashes: number[]; results: Array<string | null> } {
  const hashes: number[] = []
  const results: Array<string | null> = []
  for (let t = from + 1; t <= 90; t++) {
    for (const [at, player, c] of SCRIPT) if (at === t) results.push(sim.apply(player, c))
    sim.runTick()
    hashes.push(sim.hash())
  }
  return { hashes, results }
}

describe('undo history in saved and restored rooms', () => {
  it('a room saved and restored mid-script (state, sync payload, clone) continues with the same hash at every tick', () => {
    const whole = room()
    const all = run(whole, 0)
    // Some undos and redos were accepted and some refused: the script exercises both.
    expect(all.results.filter((r) => r === null).length).toBeGreaterThan(8)
    expect(all.results.filter((r) => r !== null)).toEqual(['nothing to redo'])
    for (const cut of [7, 20, 45, 61]) {
      const part = room()
      for (let t = 1; t <= cut; t++) {
        for (const [at, player, c] of SCRIPT) if (at === t) part.apply(player, c)
        part.runTick()
      }
      expect(part.hash()).toBe(all.hashes[cut - 1])
      expect(part.history.empty).toBe(false)
      const restored = new RoomSimulation(options)
      restored.restoreState(structuredClone(part.saveState()), loadWorld(part.world.save()))
      const synced = restoreSyncPayload(encodeSyncPayload(part), { ...options, games: () => sandbox })
      if (!synced.ok) throw new Error(synced.reason)
      const cloned = cloneSimulation(part, options)
      const tail = all.hashes.slice(cut)
      const tailResults = all.results.slice(SCRIPT.filter(([at]) => at <= cut).length)
      for (const [what, sim2] of [
        ['restoreState', restored],
        ['sync payload', synced.sim],
        ['clone', cloned],
        ['the original', part],
      ] as const) {
        const r = run(sim2, cut)
        expect(r.results, `${what} at ${cut}`).toEqual(tailResults)
        expect(r.hashes, `${what} at ${cut}`).toEqual(tail)
      }
    }
  })

  it('the hash covers the history: the same world and colours with the history left out hash differently', () => {
    const a = room()
    ok(a, 1, spawnAt(0, 3))
    const b = room()
    b.restoreState({ ...a.saveState(), history: [] }, loadWorld(a.world.save()))
    expect(b.world.hash()).toBe(a.world.hash())
    expect(b.colorList()).toEqual(a.colorList())
    expect(b.hash()).not.toBe(a.hash())
    b.restoreState(a.saveState(), loadWorld(a.world.save()))
    expect(b.hash()).toBe(a.hash())
  })
})
