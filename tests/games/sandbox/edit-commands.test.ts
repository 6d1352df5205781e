/*
 * The sandbox's edit commands (games/sandbox/edit-commands.ts; docs/games.md "The sandbox's edit
 * commands") in a RoomSimulation, against hand computations: the mass after a density change is
 * area x density; a moved body's pose is the one asked; a box scaled by k has k times its half
 * extents and k^2 times its mass; a duplicate has the original's shapes; deleteMany removes exactly
 * the listed bodies and their joints; layers pass through each other as documented. Every bad
 * argument is refused naming the field or the body. A recorded session replayed in a fresh
 * simulation, and one resumed from a saved state midway, keep the same hash every tick.
 */
import { describe, expect, it } from 'vitest'
import { circle } from '../../../engine/index.ts'
import { sandbox } from '../../../games/index.ts'
import { type Command, playerBodyColor, RoomSimulation, type SimCommand } from '../../../shared/index.ts'
import { commandKinds, expectReplays, recordSession } from './recorded-session.ts'

const options = { game: sandbox, name: 'edit', scene: 'empty', maxBodies: 100, controls: true }

function room(): RoomSimulation {
  const sim = new RoomSimulation(options)
  sim.join(1, 'ada', '#e6194b')
  sim.join(2, 'bob', '#3cb44b')
  return sim
}

const cmd = (kind: string, a: Record<string, unknown>): SimCommand => ({ k: 'cmd', kind, a }) as SimCommand

/** Spawn a body (player 1) and return its id. */
function spawn(sim: RoomSimulation, c: Omit<Extract<Command, { k: 'spawn' }>, 'k'>, player = 1): number {
  const before = new Set(sim.world.bodyIds())
  expect(sim.apply(player, { k: 'spawn', ...c })).toBeNull()
  return sim.world.bodyIds().find((id) => !before.has(id)) as number
}

const GROUND = 1 // the empty scene's one body: static scenery

describe("the sandbox's edit commands", () => {
  it('edit: density sets the mass to area x density (box and circle), friction and restitution every shape', () => {
    const sim = room()
    const b = spawn(sim, { shape: { type: 'box', hw: 0.5, hh: 0.25 }, x: 0, y: 5 })
    const c = spawn(sim, { shape: { type: 'circle', radius: 0.5 }, x: 3, y: 5 })
    expect(sim.world.getMass(b)).toBe(0.5) // 1 x 0.5 m^2 at density 1
    expect(sim.apply(1, cmd('edit', { body: b, density: 3, friction: 0.1, restitution: 0.8 }))).toBeNull()
    expect(sim.world.getMass(b)).toBeCloseTo(1.5, 14)
    expect(sim.apply(2, cmd('edit', { body: c, density: 2 }))).toBeNull()
    expect(sim.world.getMass(c)).toBeCloseTo(2 * Math.PI * 0.25, 14)
    const def = sim.world.getShapeDef(sim.world.bodyShapes(b)[0])
    expect([def.density, def.friction, def.restitution]).toEqual([3, 0.1, 0.8])
    // Fields not given are kept.
    expect(sim.world.getShapeDef(sim.world.bodyShapes(c)[0]).friction).toBe(0.6)
  })

  it('edit: colour, static (a body made static stops and stays; dynamic again falls), layer filters', () => {
    const sim = room()
    const b = spawn(sim, { shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 5 })
    expect(sim.bodyColors.get(b)).toBe(playerBodyColor(1))
    expect(sim.apply(2, cmd('edit', { body: b, color: 0x123456, static: true, layer: 3 }))).toBeNull()
    expect(sim.bodyColors.get(b)).toBe(0x123456)
    expect(sim.world.getBodyType(b)).toBe('static')
    expect(sim.world.getFilter(sim.world.bodyShapes(b)[0])).toEqual({
      categoryBits: 8,
      maskBits: 9,
      groupIndex: 0,
    })
    for (let i = 0; i < 60; i++) sim.runTick()
    expect(sim.world.getPosition(b)).toEqual({ x: 0, y: 5 })
    // Static and coloured: a player's, so still editable; made dynamic it falls (1 s: 5 m under -10 g, less drag).
    expect(sim.apply(1, cmd('edit', { body: b, static: false, layer: 0 }))).toBeNull()
    for (let i = 0; i < 30; i++) sim.runTick()
    expect(sim.world.getPosition(b).y).toBeLessThan(4)
    expect(sim.world.getFilter(sim.world.bodyShapes(b)[0]).maskBits).toBe(0xffffffff)
  })

  it('edit: a scene body made static takes the editor colour, so it stays editable', () => {
    const sim = room()
    const b = sim.world.createBody({ type: 'dynamic', position: { x: 0, y: 3 }, shape: circle(0.3) })
    expect(sim.bodyColors.has(b)).toBe(false)
    expect(sim.apply(2, cmd('edit', { body: b, static: true }))).toBeNull()
    expect(sim.bodyColors.get(b)).toBe(playerBodyColor(2))
    expect(sim.apply(1, cmd('edit', { body: b, static: false }))).toBeNull()
  })

  it('layers: different non-zero layers pass through each other; each rests on layer 0 and on its own layer', () => {
    const sim = room()
    // Two boxes dropped onto a box resting on the ground: a top box on another layer falls through it.
    const low = spawn(sim, { shape: { type: 'box', hw: 1, hh: 0.5 }, x: 0, y: 0.5 })
    const same = spawn(sim, { shape: { type: 'box', hw: 0.3, hh: 0.3 }, x: -0.5, y: 2 })
    const other = spawn(sim, { shape: { type: 'box', hw: 0.3, hh: 0.3 }, x: 0.5, y: 2 })
    expect(sim.apply(1, cmd('edit', { body: low, layer: 2 }))).toBeNull()
    expect(sim.apply(1, cmd('edit', { body: same, layer: 2 }))).toBeNull()
    expect(sim.apply(1, cmd('edit', { body: other, layer: 5 }))).toBeNull()
    for (let i = 0; i < 120; i++) sim.runTick()
    // low rests on the ground (layer 0): centre at 0.5; same rests on low: 1 + 0.3; other on the ground: 0.3.
    expect(sim.world.getPosition(low).y).toBeCloseTo(0.5, 1)
    expect(sim.world.getPosition(same).y).toBeCloseTo(1.3, 1)
    expect(sim.world.getPosition(other).y).toBeCloseTo(0.3, 1)
  })

  it('transform: the pose asked, at rest; scale k multiplies half extents by k and the mass by k^2', () => {
    const sim = room()
    const b = spawn(sim, { shape: { type: 'box', hw: 0.5, hh: 0.25 }, x: 0, y: 5, vx: 3, density: 2 })
    sim.runTick()
    expect(sim.apply(1, cmd('transform', { body: b, x: 4, y: 7, angle: Math.PI / 2, scale: 2 }))).toBeNull()
    expect(sim.world.getPosition(b)).toEqual({ x: 4, y: 7 })
    expect(sim.world.getAngle(b)).toBeCloseTo(Math.PI / 2, 12)
    expect(sim.world.getLinearVelocity(b)).toEqual({ x: 0, y: 0 })
    expect(sim.world.getAngularVelocity(b)).toBe(0)
    const shapes = sim.world.bodyShapes(b)
    expect(shapes).toHaveLength(1)
    const g = sim.world.getShapeGeometry(shapes[0])
    expect(g.type === 'polygon' && g.box).toEqual({ halfWidth: 1, halfHeight: 0.5 })
    expect(sim.world.getShapeDef(shapes[0]).density).toBe(2) // material kept
    expect(sim.world.getMass(b)).toBeCloseTo(2 * 2 * 1, 14) // 2 m x 1 m at density 2
    // A circle and an offset polygon scale about the body origin.
    const c = spawn(sim, {
      shapes: [
        { type: 'circle', radius: 0.2, x: 0.5, y: 0 },
        { type: 'polygon', v: [0, 0, 1, 0, 0, 1] },
      ],
      x: -3,
      y: 5,
    })
    expect(sim.apply(1, cmd('transform', { body: c, x: -3, y: 5, angle: 0, scale: 0.5 }))).toBeNull()
    const [circleShape, triangle] = sim.world.bodyShapes(c).map((s) => sim.world.getShapeGeometry(s))
    expect(circleShape.radius).toBe(0.1)
    expect(circleShape.centroid).toEqual({ x: 0.25, y: 0 })
    expect(triangle.vertices.map((v) => [v.x, v.y])).toEqual([
      [0, 0],
      [0.5, 0],
      [0, 0.5],
    ])
  })

  it('transform: what is not given is kept; a scale alone keeps the pose and velocities bit for bit', () => {
    const sim = room()
    const b = spawn(sim, { shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 1, y: 5, vx: 2, angle: 0.3 })
    sim.runTick()
    const p = sim.world.getPosition(b)
    const r = sim.world.getRotation(b)
    const v = sim.world.getLinearVelocity(b)
    expect(sim.apply(1, cmd('transform', { body: b, scale: 2 }))).toBeNull()
    expect([sim.world.getPosition(b), sim.world.getRotation(b), sim.world.getLinearVelocity(b)]).toEqual([
      p,
      r,
      v,
    ])
    expect(sim.apply(1, cmd('transform', { body: b, angle: 1 }))).toBeNull()
    expect(sim.world.getPosition(b)).toEqual(p)
    expect(sim.world.getAngle(b)).toBeCloseTo(1, 12)
    expect(sim.world.getLinearVelocity(b)).toEqual({ x: 0, y: 0 })
    expect(sim.apply(1, cmd('transform', { body: b, x: -2, y: 3 }))).toBeNull()
    expect(sim.world.getPosition(b)).toEqual({ x: -2, y: 3 })
    expect(sim.world.getAngle(b)).toBeCloseTo(1, 12)
    expect(sim.apply(1, cmd('transform', { body: b, x: 1 }))).toBe('transform refused: give x and y together')
    expect(sim.apply(1, cmd('transform', { body: b }))).toBe(
      'transform refused: give x and y, angle or scale',
    )
  })

  it('duplicate: the same shapes and materials, offset, at rest, with the colour; joints not copied', () => {
    const sim = room()
    const b = spawn(sim, {
      shapes: [
        { type: 'box', hw: 0.5, hh: 0.2 },
        { type: 'circle', radius: 0.3, x: 0.5, y: 0.2, friction: 0.1 },
      ],
      x: 0,
      y: 5,
      angle: 0.4,
      density: 3,
      color: 0xabcdef,
    })
    expect(sim.apply(1, { k: 'pin', a: 0, b, x: 0, y: 5 })).toBeNull()
    const joints = sim.userJoints.size
    const before = new Set(sim.world.bodyIds())
    expect(sim.apply(2, cmd('duplicate', { body: b, dx: 3, dy: -1 }))).toBeNull()
    const copy = sim.world.bodyIds().find((id) => !before.has(id)) as number
    const strip = (id: number) => sim.world.bodyShapes(id).map((s) => sim.world.getShapeDef(s))
    expect(strip(copy)).toEqual(strip(b))
    expect(sim.world.getPosition(copy)).toEqual({ x: 3, y: 4 })
    expect(sim.world.getRotation(copy)).toEqual(sim.world.getRotation(b))
    expect(sim.world.getMass(copy)).toBe(sim.world.getMass(b))
    expect(sim.bodyColors.get(copy)).toBe(0xabcdef)
    expect(sim.userJoints.size).toBe(joints)
  })

  it('deleteMany removes exactly the listed bodies and their joints, nothing else', () => {
    const sim = room()
    const ids = [0, 1, 2, 3, 4].map((i) => spawn(sim, { shape: { type: 'circle', radius: 0.3 }, x: i, y: 3 }))
    expect(sim.apply(1, { k: 'pin', a: ids[0], b: ids[1], x: 0.5, y: 3 })).toBeNull()
    expect(sim.apply(1, { k: 'pin', a: ids[2], b: ids[3], x: 2.5, y: 3 })).toBeNull()
    const kept = [...sim.userJoints.keys()].find((j) => sim.userJoints.get(j)?.a === ids[2])
    expect(sim.apply(2, cmd('deleteMany', { bodies: [ids[4], ids[0]] }))).toBeNull()
    expect(sim.world.bodyIds()).toEqual([GROUND, ids[1], ids[2], ids[3]])
    expect([...sim.userJoints.keys()]).toEqual([kept])
  })

  it('refuses bad arguments naming the field, and bodies naming the body; a refusal changes nothing', () => {
    const sim = room()
    const b = spawn(sim, { shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 5 })
    const hash = sim.hash()
    const refusals: Array<[string, Record<string, unknown>, string]> = [
      ['edit', { body: 99 }, 'body 99 does not exist'],
      [
        'edit',
        { body: GROUND, friction: 0 },
        `body ${GROUND} is the scene's static scenery: it cannot be edited`,
      ],
      ['edit', { body: b, density: 0 }, 'edit refused: density must be >= 0.05'],
      ['edit', { body: b, friction: 3 }, 'edit refused: friction must be <= 2'],
      ['edit', { body: b, layer: 8 }, 'edit refused: layer must be <= 7'],
      ['edit', { body: b, color: 0x1000000 }, 'edit refused: color must be <= 16777215'],
      ['edit', { body: b, mass: 1 }, 'edit refused: mass is not allowed'],
      ['edit', { friction: 1 }, 'edit refused: body is required'],
      ['transform', { body: b, x: 0, y: 0, angle: 0, scale: 0 }, 'transform refused: scale must be >= 0.1'],
      ['transform', { body: b, x: 0, y: 0, angle: 0, scale: 11 }, 'transform refused: scale must be <= 10'],
      ['transform', { body: b, x: 0, y: 0, angle: 4 }, 'transform refused: angle must be <= 3.14'],
      [
        'transform',
        { body: GROUND, x: 0, y: 0, angle: 0 },
        `body ${GROUND} is the scene's static scenery: it cannot be edited`,
      ],
      ['duplicate', { body: b, dx: 101, dy: 0 }, 'duplicate refused: dx must be <= 100'],
      ['duplicate', { body: 77, dx: 1, dy: 0 }, 'body 77 does not exist'],
      ['deleteMany', { bodies: [] }, 'deleteMany refused: bodies must NOT have fewer than 1 items'],
      ['deleteMany', { bodies: [b, b] }, 'deleteMany refused: bodies must NOT have duplicate items'],
      ['deleteMany', { bodies: [1.5] }, 'deleteMany refused: bodies[0] must be integer'],
      [
        'deleteMany',
        { bodies: [b, GROUND] },
        `body ${GROUND} is the scene's static scenery: it cannot be edited`,
      ],
      [
        'deleteMany',
        { bodies: Array.from({ length: 257 }, (_, i) => i + 1) },
        'deleteMany refused: bodies must NOT have more than 256 items',
      ],
    ]
    for (const [kind, a, reason] of refusals) {
      const got = sim.apply(1, cmd(kind, a))
      expect(got, `${kind} ${JSON.stringify(a).slice(0, 60)}`).not.toBeNull()
      expect(got).toContain(reason)
    }
    expect(sim.hash()).toBe(hash)
    // Too big: the 0.5 m box's corner reaches sqrt(0.5) = 0.7071 m; 10 x gives 7.071 m (accepted),
    // 10 x again 70.71 m (over 50).
    expect(sim.apply(1, cmd('transform', { body: b, x: 0, y: 5, angle: 0, scale: 10 }))).toBeNull()
    const big = sim.hash()
    expect(sim.apply(1, cmd('transform', { body: b, x: 0, y: 5, angle: 0, scale: 10 }))).toBe(
      `scale 10 would make body ${b} reach 70.71 m from its origin; at most 50 m`,
    )
    // A held body is neither moved nor made static.
    expect(sim.apply(2, { k: 'grab', body: b, lx: 0, ly: 0 })).toBeNull()
    const held = sim.hash()
    expect(sim.apply(1, cmd('transform', { body: b, x: 0, y: 5, angle: 0 }))).toBe(
      `body ${b} is held by player 2: it cannot be moved`,
    )
    expect(sim.apply(1, cmd('edit', { body: b, static: true }))).toBe(
      `body ${b} is held by player 2: it cannot be made static`,
    )
    expect(sim.hash()).toBe(held)
    expect(held).not.toBe(big) // the grab changed the world; the refusals did not
  })

  it('a recorded session replays with the same hash every tick, also resumed from a saved state midway', () => {
    const ids: number[] = []
    const session = recordSession(options, 240, 100, (live, t) => {
      if (t < 10) {
        const id = spawn(
          live,
          { shape: { type: 'box', hw: 0.3 + t * 0.02, hh: 0.2 }, x: t - 5, y: 4 + (t % 3) },
          1 + (t % 2),
        )
        ids.push(id)
      }
      if (t === 20) live.apply(1, cmd('edit', { body: ids[0], density: 5, friction: 0.05, layer: 2 }))
      if (t === 25) live.apply(2, cmd('transform', { body: ids[1], x: 1.5, y: 6, angle: 0.7, scale: 1.7 }))
      if (t === 30) live.apply(1, cmd('duplicate', { body: ids[2], dx: 0.5, dy: 3 }))
      if (t === 40) live.apply(2, cmd('edit', { body: ids[3], static: true, color: 0x00ff00 }))
      if (t === 60) live.apply(1, cmd('deleteMany', { bodies: [ids[4], ids[6], ids[8]] }))
      if (t === 130) live.apply(2, cmd('edit', { body: ids[3], static: false, restitution: 0.9 }))
      if (t === 150) live.apply(1, cmd('transform', { body: ids[5], x: -2, y: 8, angle: -1, scale: 0.6 }))
    })
    // Every scripted edit was accepted (logged), besides the spawns.
    expect(commandKinds(session)).toEqual([
      'edit',
      'transform',
      'duplicate',
      'edit',
      'deleteMany',
      'edit',
      'transform',
    ])
    expectReplays(session)
  })
})
