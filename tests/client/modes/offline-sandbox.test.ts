/*
 * The offline sandbox (client/modes/offline-sandbox.ts) runs the room as a server room runs it:
 * against a bare RoomSimulation of the sandbox game driven the way server/rooms/room.ts drives
 * one (a player joined, each tick's commands applied in order through apply(), then runTick()),
 * the page fed the same commands before the same frames reaches the same simulation hash at every
 * tick, through spawns, a hinge, an edit, undo and redo, slow motion and an explosion. Commands
 * wait for the next tick; a refused one becomes a notice with the game's own words; and in slow
 * motion a falling body is drawn moving down smoothly between the world's steps (never jumping
 * back up between two steps, as a per-tick interpolation would draw it).
 */
import { describe, expect, it } from 'vitest'
import { OfflineSandbox } from '../../../client/modes/offline-sandbox.ts'
import { sandbox } from '../../../games/index.ts'
import { type PlainData, RoomSimulation, type SimCommand } from '../../../shared/index.ts'

const FRAME_MS = 1000 / 60

/** A server-style room: player 1 joined, commands applied at a tick before its step. */
function referenceRoom(scene: string): RoomSimulation {
  const sim = new RoomSimulation({ game: sandbox, name: 'reference', scene, maxBodies: 1500, controls: true })
  sim.join(1, 'you', '#e6194b')
  return sim
}

/** Send a command to the page as the tools do (game commands through sendGame). */
function sendTo(page: OfflineSandbox, cmd: SimCommand): void {
  if (cmd.k === 'cmd') page.sendGame(cmd.kind, cmd.a as { [key: string]: PlainData })
  else page.send(cmd)
}

describe('the offline sandbox', () => {
  it('applies commands at the next tick exactly as a room does: equal simulation hashes at every tick', () => {
    const page = new OfflineSandbox('empty')
    const room = referenceRoom('empty')
    // Commands by the frame before which the page is sent them (one frame = one tick).
    const script = new Map<number, SimCommand[]>([
      [
        2,
        [
          { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0, y: 3 },
          { k: 'spawn', shape: { type: 'box', hw: 0.5, hh: 0.5 }, x: 0.6, y: 3 },
        ],
      ],
      [5, [{ k: 'pause', paused: true }]],
      [6, [{ k: 'cmd', kind: 'hinge', a: { a: 2, b: 3, x: 0.3, y: 3 } }]],
      [8, [{ k: 'cmd', kind: 'undo', a: {} }]],
      [10, [{ k: 'cmd', kind: 'redo', a: {} }]],
      [12, [{ k: 'cmd', kind: 'edit', a: { body: 2, density: 2.5, color: 0x33cc66 } }]],
      [14, [{ k: 'cmd', kind: 'undo', a: {} }]],
      [15, [{ k: 'cmd', kind: 'redo', a: {} }]],
      [
        16,
        [
          { k: 'pause', paused: false },
          { k: 'cmd', kind: 'slow', a: { every: 2 } },
        ],
      ],
      [40, [{ k: 'cmd', kind: 'explode', a: { x: 0.3, y: 2, radius: 3, impulse: 20 } }]],
      [60, [{ k: 'cmd', kind: 'slow', a: { every: 1 } }]],
    ])
    let now = 0
    page.update(now)
    const jointsAt = new Map<number, string[]>()
    for (let frame = 1; frame <= 150; frame++) {
      const cmds = script.get(frame) ?? []
      for (const cmd of cmds) sendTo(page, cmd)
      now += FRAME_MS
      page.update(now)
      for (const cmd of cmds) expect(room.apply(1, cmd), `${cmd.k} at frame ${frame}`).toBeNull()
      room.runTick()
      jointsAt.set(
        frame,
        page.joints().map((j) => j.kind),
      )
      expect(page.sim.tick).toBe(room.tick)
      expect(page.sim.hash(), `hash at tick ${room.tick}`).toBe(room.hash())
    }
    // Undo took the hinge away at frame 8 (applied in that frame's tick), redo brought it back.
    expect(jointsAt.get(8)).toEqual([])
    expect(jointsAt.get(10)).toEqual(['pin'])
    // The edit was undone and redone (each rebuilds the body, with a new id and its hinge): the
    // page draws the body recoloured, hinged, with mass = 2.5 kg/m^2 x 1 m^2.
    const edited = page.bodies().find((b) => b.color === '#33cc66')
    expect(edited).toBeDefined()
    expect(page.lab(edited?.id ?? 0)?.mass).toBeCloseTo(2.5, 9)
    expect(page.joints().length).toBe(1)
    expect([page.joints()[0].spec.a, page.joints()[0].spec.b]).toContain(edited?.id)
    expect(page.notices().count).toBe(0)
  })

  it('waits for the next tick before a command acts, and reports a refusal in the game’s words', () => {
    const page = new OfflineSandbox('empty')
    const room = referenceRoom('empty')
    page.update(0)
    const before = page.bodies().length
    page.send({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 2 })
    expect(page.sim.world.bodyCount).toBe(before)
    page.update(FRAME_MS / 2) // half a tick: nothing yet
    expect(page.sim.world.bodyCount).toBe(before)
    page.update(FRAME_MS)
    expect(page.sim.world.bodyCount).toBe(before + 1)
    // The scene's ground may not be deleted; a hinge to a missing body is refused by the game.
    const ground = page.bodies().find((b) => b.kind === 0)!.id
    const refused: SimCommand[] = [
      { k: 'delete', body: ground },
      { k: 'cmd', kind: 'hinge', a: { a: 0, b: 999, x: 0, y: 0 } },
    ]
    for (const cmd of refused) sendTo(page, cmd)
    page.update(2 * FRAME_MS)
    const reasons = refused.map((cmd) => room.apply(1, cmd))
    expect(reasons.every((r) => typeof r === 'string' && r.length > 0)).toBe(true)
    expect(page.notices().count).toBe(2)
    expect(page.notices().recent).toEqual(reasons)
  })

  it('draws a falling body moving down between steps in slow motion, never back up', () => {
    const page = new OfflineSandbox('empty')
    page.update(0)
    page.send({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 8 })
    page.sendGame('slow', { every: 4 })
    let now = 0
    const drawn: number[] = []
    const world: number[] = []
    // Frames of a quarter tick for 2 s: the world steps once every 4 ticks, 16 frames.
    for (let frame = 0; frame < 480; frame++) {
      now += FRAME_MS / 4
      page.update(now)
      const ball = page.bodies().find((b) => b.kind === 2)
      if (!ball) continue
      drawn.push(ball.y)
      world.push(page.sim.world.getPosition(ball.id).y)
    }
    expect(page.roomControl().slow).toBe(4)
    // It fell (about g t^2 / 2 in world time: 30 steps of 1/60 s) ...
    expect(drawn[0] - drawn[drawn.length - 1]).toBeGreaterThan(0.5)
    // ... and every frame drew it lower than or level with the frame before.
    for (let i = 1; i < drawn.length; i++)
      expect(drawn[i], `frame ${i}`).toBeLessThanOrEqual(drawn[i - 1] + 1e-12)
    // Drawn poses lie between the world's poses (it is drawn behind the world by at most a step).
    for (let i = 0; i < drawn.length; i++) expect(drawn[i]).toBeGreaterThanOrEqual(world[i] - 1e-12)
    // Most frames between two steps draw a new height (smooth, not one jump per step).
    let moved = 0
    for (let i = 1; i < drawn.length; i++) if (drawn[i] < drawn[i - 1]) moved++
    expect(moved).toBeGreaterThan(drawn.length * 0.8)
  })
})
