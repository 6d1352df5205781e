import { describe, expect, it } from 'vitest'
import { circle, loadWorld } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { type Command, KILL_PLANE_Y, type SimCommand } from '../../../shared/index.ts'
import { RoomSimulation, type SimulationObserver } from '../../../shared/sim/room-simulation.ts'

/** One recorded state change, as a recorder would log it. */
type Recorded =
  | { t: 'command'; tick: number; player: number; cmd: SimCommand }
  | { t: 'join'; tick: number; player: number; name: string; color: string }
  | { t: 'leave'; tick: number; player: number }

function recorder(into: Recorded[]): SimulationObserver {
  return {
    command: (tick, player, cmd) => into.push({ t: 'command', tick, player, cmd }),
    join: (tick, player, name, color) => into.push({ t: 'join', tick, player, name, color }),
    leave: (tick, player) => into.push({ t: 'leave', tick, player }),
    worldLoaded: () => {
      throw new Error('this session loads no external world')
    },
  }
}

const options = { game: sandbox, name: 'unit', scene: 'pyramid', maxBodies: 400, controls: true }

function dynamicBodies(sim: RoomSimulation): number[] {
  return sim.world.bodyIds().filter((id) => sim.world.getBodyType(id) === 'dynamic')
}

/**
 * A scripted session exercising every command kind, refusals included; returns the world hash
 * after every tick (index = room tick) and the refusals seen.
 */
function runSession(sim: RoomSimulation): { hashes: number[]; refusals: string[] } {
  const hashes = [sim.world.hash()]
  const refusals: string[] = []
  const apply = (player: number, cmd: Command): void => {
    const error = sim.apply(player, cmd)
    if (error) refusals.push(error)
  }
  let grabbed = 0
  let roped = 0
  let pinJoint = 0
  for (let t = 0; t < 420; t++) {
    switch (t) {
      case 0:
        sim.join(1, 'ada', '#e6194b')
        sim.join(2, 'bob', '#3cb44b')
        break
      case 5:
        apply(1, { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 14, vx: 3 })
        apply(2, { k: 'spawn', shape: { type: 'box', hw: 0.4, hh: 0.3 }, x: 2, y: 16, angle: 0.3, w: 2 })
        break
      case 10:
        grabbed = dynamicBodies(sim)[100]
        apply(1, { k: 'grab', body: grabbed, lx: 0.1, ly: 0.2 })
        apply(1, { k: 'grab', body: 99_999, lx: 0, ly: 0 })
        break
      case 20: {
        const body = dynamicBodies(sim)[150]
        const p = sim.world.getPosition(body)
        apply(2, { k: 'pin', a: 0, b: body, x: p.x, y: p.y })
        pinJoint = [...sim.userJoints.keys()].at(-1) ?? 0
        break
      }
      case 25: {
        const [a, b] = [dynamicBodies(sim)[3], dynamicBodies(sim)[40]]
        roped = b
        const pa = sim.world.getPosition(a)
        const pb = sim.world.getPosition(b)
        apply(2, { k: 'rope', a, b, ax: pa.x, ay: pa.y, bx: pb.x, by: pb.y })
        break
      }
      case 40:
        apply(2, { k: 'grab', body: grabbed, lx: -0.2, ly: 0 })
        break
      case 70:
        apply(1, { k: 'release' })
        apply(2, { k: 'unjoint', joint: 12_345 })
        break
      case 75:
        apply(2, { k: 'unjoint', joint: pinJoint })
        break
      case 80:
        apply(1, { k: 'delete', body: roped })
        apply(1, {
          k: 'delete',
          body: sim.world.bodyIds().find((id) => sim.world.getBodyType(id) === 'static')!,
        })
        break
      case 90:
        apply(1, { k: 'pause', paused: true })
        break
      case 95:
        apply(2, { k: 'step' })
        break
      case 100:
        apply(1, { k: 'pause', paused: false })
        break
      case 110:
        apply(2, { k: 'gravity', x: 1, y: -5 })
        break
      case 120:
        sim.leave(2)
        break
      case 130:
        apply(1, { k: 'scene', name: 'joints' })
        apply(1, { k: 'scene', name: 'pile' })
        apply(1, { k: 'scene', name: 'no-such-scene' })
        break
      case 150:
        apply(1, { k: 'grab', body: dynamicBodies(sim)[0], lx: 0, ly: 0 })
        break
      case 160:
        apply(1, { k: 'reset' })
        break
      case 170:
        sim.join(2, 'bob', '#3cb44b')
        apply(2, { k: 'spawn', shape: { type: 'polygon', v: [0, 0, 1, 0, 0, 1] }, x: 0, y: 8 })
        apply(2, { k: 'grab', body: dynamicBodies(sim).at(-1)!, lx: 0, ly: 0 })
        break
    }
    if ((t > 10 && t < 70) || (t > 150 && t < 400)) {
      apply(1, { k: 'move', x: 3 * Math.sin(t / 9), y: 8 + 2 * Math.cos(t / 7) })
      if (sim.players.has(2)) apply(2, { k: 'move', x: -2 + t / 100, y: 6 })
    }
    sim.runTick()
    hashes.push(sim.world.hash())
  }
  return { hashes, refusals }
}

/** Replay recorded changes into a fresh simulation; returns the hash after every tick. */
function replay(records: Recorded[], ticks: number): number[] {
  const sim = new RoomSimulation(options)
  const hashes = [sim.world.hash()]
  let next = 0
  for (let t = 0; t < ticks; t++) {
    while (next < records.length && records[next].tick === t) {
      const r = records[next++]
      if (r.t === 'join') sim.join(r.player, r.name, r.color)
      else if (r.t === 'leave') sim.leave(r.player)
      else expect(sim.apply(r.player, r.cmd), `replayed ${r.cmd.k} at tick ${t}`).toBeNull()
    }
    sim.runTick()
    hashes.push(sim.world.hash())
  }
  expect(next).toBe(records.length)
  return hashes
}

describe('RoomSimulation', { timeout: 60_000 }, () => {
  it('replaying the accepted commands, joins and leaves reproduces the world hash at every tick', () => {
    const records: Recorded[] = []
    const sim = new RoomSimulation(options)
    sim.observers.push(recorder(records))
    const { hashes, refusals } = runSession(sim)
    // The refusals happened and were not recorded.
    expect(refusals).toEqual([
      'body 99999 cannot be grabbed',
      'joint 12345 is not a joint in this room',
      expect.stringMatching(/^body \d+ does not exist or is static$/),
      'scene loads are limited to 6 per second',
      'unknown scene "no-such-scene"',
    ])
    const kinds = new Set(records.map((r) => (r.t === 'command' ? r.cmd.k : r.t)))
    for (const k of ['spawn', 'grab', 'move', 'release', 'delete', 'pin', 'rope', 'unjoint', 'scene'])
      expect(kinds).toContain(k)
    for (const k of ['reset', 'pause', 'step', 'gravity', 'join', 'leave']) expect(kinds).toContain(k)
    // The session really changed the world in every phase (the hash is not constant).
    expect(new Set(hashes).size).toBeGreaterThan(400)
    const replayed = replay(records, hashes.length - 1)
    for (let t = 0; t < hashes.length; t++) expect(replayed[t], `hash at tick ${t}`).toBe(hashes[t])
  })

  it('a player leaving while grabbing releases the grab; grab counts follow grabs', () => {
    const sim = new RoomSimulation(options)
    sim.join(1, 'a', '#fff')
    sim.join(2, 'b', '#fff')
    const body = dynamicBodies(sim)[7]
    expect(sim.apply(1, { k: 'grab', body, lx: 0, ly: 0 })).toBeNull()
    expect(sim.apply(2, { k: 'grab', body, lx: 0, ly: 0 })).toBeNull()
    expect(sim.grabCounts.get(body)).toBe(2)
    expect(sim.world.joints().filter((j) => j.type === 'mouse')).toHaveLength(2)
    sim.leave(2)
    expect(sim.grabCounts.get(body)).toBe(1)
    expect(sim.world.joints().filter((j) => j.type === 'mouse')).toHaveLength(1)
    expect(sim.apply(1, { k: 'delete', body })).toBeNull()
    expect(sim.grabCounts.size).toBe(0)
    expect(sim.players.get(1)?.grab).toBeNull()
    expect(sim.apply(2, { k: 'release' })).toBe('player 2 is not in this room')
  })

  it('room controls can be turned off; inspect is not a simulation command', () => {
    const sim = new RoomSimulation({ ...options, controls: false })
    sim.join(1, 'a', '#fff')
    const seen: string[] = []
    sim.observers.push({ ...recorder([]), command: (_t, _p, cmd) => seen.push(cmd.k) })
    for (const cmd of [
      { k: 'pause', paused: true },
      { k: 'gravity', x: 0, y: 0 },
      { k: 'reset' },
      { k: 'step' },
      { k: 'scene', name: 'empty' },
    ] as Command[])
      expect(sim.apply(1, cmd)).toBe('room controls are disabled in room unit')
    expect(sim.apply(1, { k: 'inspect', body: 3 })).not.toBeNull()
    expect(sim.apply(1, { k: 'move', x: 1, y: 2 })).toBeNull()
    expect(seen).toEqual(['move'])
  })

  it('the once-a-second sweep removes bodies beyond the kill distance, below the kill plane, and with non-finite positions', () => {
    const removed: number[] = []
    const sim = new RoomSimulation({
      ...options,
      scene: 'empty',
      listener: {
        bodyAdded: () => {},
        bodyRemoved: (id) => removed.push(id),
        jointAdded: () => {},
        jointRemoved: () => {},
        roomChanged: () => {},
        cursorChanged: () => {},
        worldReplaced: () => {},
      },
    })
    const far = sim.world.createBody({
      type: 'dynamic',
      shape: circle(1),
      position: { x: 1001, y: 0 },
    })
    const near = sim.world.createBody({
      type: 'dynamic',
      shape: circle(1),
      position: { x: 999, y: 0 },
    })
    const lost = sim.world.createBody({
      type: 'dynamic',
      shape: circle(1),
      position: { x: 0, y: 50 },
    })
    const fallen = sim.world.createBody({
      type: 'dynamic',
      shape: circle(1),
      position: { x: 3, y: KILL_PLANE_Y - 0.5 },
    })
    const above = sim.world.createBody({
      type: 'dynamic',
      shape: circle(1),
      position: { x: 6, y: KILL_PLANE_Y + 0.5 },
    })
    sim.world.setGravity({ x: 0, y: 0 })
    // No public API makes a position non-finite (a solver blow-up would): write the body's field.
    const internal = sim.world as unknown as { body(id: number): { x: number; cx: number } }
    internal.body(lost).x = Number.NaN
    internal.body(lost).cx = Number.NaN
    for (let t = 0; t < 59; t++) sim.runTick()
    expect(removed).toEqual([])
    sim.runTick()
    expect(removed.sort()).toEqual([far, lost, fallen].sort())
    expect(sim.world.hasBody(near)).toBe(true)
    expect(sim.world.hasBody(above)).toBe(true)
  })
})

describe('body colours are part of the simulation', () => {
  const spawnIn = (color?: number): RoomSimulation => {
    const sim = new RoomSimulation({ ...options, scene: 'empty' })
    sim.join(1, 'a', '#e6194b')
    const cmd: Command = { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 3 }
    expect(sim.apply(1, color === undefined ? cmd : { ...cmd, color })).toBeNull()
    return sim
  }

  it("a spawn takes its player's roster colour, or its own; another colour changes the hash, not the world", () => {
    const mine = spawnIn()
    const red = spawnIn(0xe6194b)
    const blue = spawnIn(0x0000ff)
    // Player 1's roster colour is #e6194b (the palette's first).
    expect(mine.colorList()).toEqual([2, 0xe6194b])
    expect(red.hash()).toBe(mine.hash())
    expect(blue.world.hash()).toBe(mine.world.hash())
    expect(blue.hash()).not.toBe(mine.hash())
    // A room without coloured bodies keeps the world's hash.
    const none = new RoomSimulation({ ...options, scene: 'empty' })
    expect(none.hash()).toBe(none.world.hash())
  })

  it('saveState and restoreState keep the colours, so the hash continues', () => {
    const a = spawnIn(0x123456)
    const b = new RoomSimulation({ ...options, scene: 'empty' })
    b.restoreState(a.saveState(), loadWorld(a.world.save()))
    expect(b.colorList()).toEqual([2, 0x123456])
    expect(b.hash()).toBe(a.hash())
    a.removeBody(2)
    expect(a.colorList()).toEqual([])
  })
})
