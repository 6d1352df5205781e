/*
 * The goal game (games/goal/) played headless in a RoomSimulation with scripted commands, each
 * outcome against a hand computation from the rules in docs/games.md: a full-power kick from rest
 * gives the ball KICK_IMPULSE / (pi r^2 rho) along the line of centres; a disc driven by `run`
 * gains MAX_FORCE / 60 N s a tick until it reaches the target speed, clamped to MAX_SPEED; a ball
 * placed wholly inside a goal scores exactly once and goes back to the centre spot, one short of
 * the sensor does not; a striker against a team that stays out of the way wins WIN_SCORE to 0 and
 * the match ends; idle teams draw when the clock runs out; and a save/load copy plays on bit for bit.
 */
import { describe, expect, it } from 'vitest'
import {
  BALL_DENSITY,
  BALL_RADIUS,
  FIELD_X,
  findGame,
  GOAL_DEPTH,
  type GoalState,
  goal,
  KICK_COOLDOWN,
  KICK_IMPULSE,
  MATCH_TICKS,
  MAX_FORCE,
  MAX_SPEED,
  PLAYER_DENSITY,
  PLAYER_RADIUS,
  WIN_SCORE,
} from '../../games/index.ts'
import {
  cloneSimulation,
  encodeSyncPayload,
  type PlainData,
  RoomSimulation,
  restoreSyncPayload,
} from '../../shared/index.ts'
import { benchCommands, strikerCommands } from './scripted-players.ts'

const ROOM = { maxBodies: 100, controls: false, name: 'goal' }
const BALL_MASS = Math.PI * BALL_RADIUS * BALL_RADIUS * BALL_DENSITY
const DISC_MASS = Math.PI * PLAYER_RADIUS * PLAYER_RADIUS * PLAYER_DENSITY

/** A goal room with players 1 (red) and 2 (blue) and the game's events. */
function match(): { sim: RoomSimulation; events: PlainData[]; state: () => GoalState } {
  const events: PlainData[] = []
  const sim = new RoomSimulation({
    ...ROOM,
    game: goal,
    scene: 'empty',
    listener: {
      bodyAdded: () => {},
      bodyRemoved: () => {},
      jointAdded: () => {},
      jointRemoved: () => {},
      roomChanged: () => {},
      cursorChanged: () => {},
      worldReplaced: () => {},
      gameEvent: (_t, e) => events.push(e),
    },
  })
  sim.join(1, 'red', '#f00')
  sim.join(2, 'blue', '#00f')
  return { sim, events, state: () => sim.gameState as GoalState }
}

const run = (x: number, y: number) => ({ k: 'cmd' as const, kind: 'run', a: { x, y } })
const kick = (power: number) => ({ k: 'cmd' as const, kind: 'kick', a: { power } })
const goals = (events: PlainData[]) => events.filter((e) => (e as { goal?: string }).goal !== undefined)

describe('goal', () => {
  it('each player sees the score, phase, whole seconds left (ceil of ticks left / 60), team, winner and disc', () => {
    const { sim, state } = match()
    const disc = (id: number) => state().players[id].disc
    const view = { score: { red: 0, blue: 0 }, phase: 'waiting', secondsLeft: 120, team: 'red', winner: null }
    expect(sim.playerView(1)).toEqual({ ...view, disc: disc(1) })
    expect(sim.playerView(2)).toEqual({ ...view, team: 'blue', disc: disc(2) })
    expect(disc(1)).not.toBe(disc(2))
    expect(sim.world.hasBody(disc(1)) && sim.world.hasBody(disc(2))).toBe(true)
    sim.runTick() // the kickoff, at tick 1
    expect(sim.playerView(1)).toEqual({ ...view, phase: 'playing', disc: disc(1) })
    for (let i = 0; i < 60; i++) sim.runTick() // 60 ticks played: 7140 left, exactly 119 s
    expect(sim.playerView(1)).toMatchObject({ secondsLeft: 119 })
    sim.runTick() // 7139 left: 118.98 s, shown as 119
    expect(sim.playerView(1)).toMatchObject({ secondsLeft: 119 })
    for (let i = 0; i < 59; i++) sim.runTick() // 7080 left: 118 s
    expect(sim.playerView(1)).toMatchObject({ secondsLeft: 118 })
  })

  it('puts the two players on opposite teams on their kickoff spots and starts the match at the first tick', () => {
    const { sim, events, state } = match()
    expect(state().players[1]).toMatchObject({ team: 'red', vx: 0, vy: 0 })
    expect(state().players[2]).toMatchObject({ team: 'blue' })
    expect(sim.world.getPosition(state().players[1].disc)).toEqual({ x: -4, y: 0 })
    expect(sim.world.getPosition(state().players[2].disc)).toEqual({ x: 4, y: 0 })
    expect(state().phase).toBe('waiting')
    sim.runTick()
    expect(state()).toMatchObject({ phase: 'playing', startTick: 1 })
    expect(events).toEqual([{ kickoff: 1 }])
  })

  it('a full-power kick from rest gives the ball KICK_IMPULSE / mass along the line of centres', () => {
    const { sim, state } = match()
    sim.runTick()
    const { ball, players } = state()
    // Touching along x: centres PLAYER_RADIUS + BALL_RADIUS apart, 5 cm inside the reach.
    sim.world.setTransform(players[1].disc, { x: -(PLAYER_RADIUS + BALL_RADIUS + 0.05), y: 0 }, 0)
    expect(sim.apply(1, kick(1))).toBeNull()
    const v = sim.world.getLinearVelocity(ball)
    expect(v.x).toBeCloseTo(KICK_IMPULSE / BALL_MASS, 12) // 7.0736 m/s
    expect(v.y).toBe(0)
    // The ball's damping over the tick's 4 substeps: v / (1 + h c)^4 with h = 1/240 s, c = 0.5/s.
    sim.runTick()
    expect(sim.world.getLinearVelocity(ball).x).toBeCloseTo(
      KICK_IMPULSE / BALL_MASS / (1 + 0.5 / 240) ** 4,
      9,
    )
    // Half power on a diagonal, from another rest: half the speed, along (1, 1) / sqrt(2).
    sim.world.setTransform(ball, { x: 0, y: 0 }, 0)
    sim.world.setLinearVelocity(ball, { x: 0, y: 0 })
    const k = (PLAYER_RADIUS + BALL_RADIUS) / Math.SQRT2
    sim.world.setTransform(players[1].disc, { x: -k, y: -k }, 0)
    for (let i = 0; i < KICK_COOLDOWN - 1; i++) {
      sim.world.setTransform(ball, { x: 0, y: 0 }, 0)
      sim.world.setLinearVelocity(ball, { x: 0, y: 0 })
      expect(sim.apply(1, kick(0.5))).toBe('one kick every half second')
      sim.runTick()
    }
    sim.world.setTransform(ball, { x: 0, y: 0 }, 0)
    sim.world.setLinearVelocity(ball, { x: 0, y: 0 })
    sim.world.setTransform(players[1].disc, { x: -k, y: -k }, 0)
    expect(sim.apply(1, kick(0.5))).toBeNull()
    const w = sim.world.getLinearVelocity(ball)
    expect(w.x).toBeCloseTo((0.5 * KICK_IMPULSE) / BALL_MASS / Math.SQRT2, 12)
    expect(w.y).toBeCloseTo((0.5 * KICK_IMPULSE) / BALL_MASS / Math.SQRT2, 12)
  })

  it('refuses a kick out of reach and bad arguments by field', () => {
    const { sim } = match()
    sim.runTick()
    // The kickoff spots are 4 m from the ball.
    expect(sim.apply(1, kick(1))).toBe('the ball is out of reach')
    expect(sim.apply(1, kick(2))).toBe('kick refused: power must be <= 1')
    expect(sim.apply(1, run(7, 0))).toBe('run refused: x must be <= 6')
    expect(sim.apply(1, { k: 'cmd', kind: 'run', a: { x: 1 } })).toBe('run refused: y is required')
    expect(sim.apply(9, run(1, 0))).toBe('player 9 is not in this room')
  })

  it('run drives the disc with MAX_FORCE until the target speed, clamped to MAX_SPEED', () => {
    const { sim, state } = match()
    const disc = state().players[2].disc
    // Blue runs up and right at (6, 6): clamped to 6 m/s along (1, 1) / sqrt(2).
    expect(sim.apply(2, run(6, 6))).toBeNull()
    expect(state().players[2].vx).toBeCloseTo(MAX_SPEED / Math.SQRT2, 12)
    expect(state().players[2].vy).toBeCloseTo(MAX_SPEED / Math.SQRT2, 12)
    const perTick = MAX_FORCE / 60 / DISC_MASS // m/s gained per tick at the force cap
    for (let t = 1; t <= 5; t++) {
      sim.runTick()
      const v = sim.world.getLinearVelocity(disc)
      expect(Math.sqrt(v.x * v.x + v.y * v.y)).toBeCloseTo(t * perTick, 9)
      expect(v.x).toBeCloseTo(v.y, 12)
    }
    // MAX_SPEED / perTick = 14.1 ticks: reached at tick 15 and held.
    for (let t = 6; t <= 20; t++) sim.runTick()
    const v = sim.world.getLinearVelocity(disc)
    expect(v.x).toBeCloseTo(MAX_SPEED / Math.SQRT2, 9)
    expect(v.y).toBeCloseTo(MAX_SPEED / Math.SQRT2, 9)
  })

  it('a ball placed wholly inside a goal scores exactly once and goes back to the centre; one short of it does not', () => {
    const { sim, events, state } = match()
    sim.runTick()
    const ball = state().ball
    // Centre 2 cm short of where the ball is wholly over the line (x = FIELD_X + 2 r): no goal.
    sim.world.setTransform(ball, { x: -(FIELD_X + BALL_RADIUS - 0.02), y: 0 }, 0)
    for (let i = 0; i < 60; i++) sim.runTick()
    expect(goals(events)).toEqual([])
    expect(sim.world.getPosition(ball).x).toBeCloseTo(-(FIELD_X + BALL_RADIUS - 0.02), 9)
    // Inside the left goal box (red defends it): blue scores one, once.
    sim.world.setTransform(ball, { x: -(FIELD_X + GOAL_DEPTH / 2), y: 0.5 }, 0)
    for (let i = 0; i < 120; i++) sim.runTick()
    expect(goals(events)).toEqual([{ goal: 'blue', score: { red: 0, blue: 1 } }])
    expect(state().score).toEqual({ red: 0, blue: 1 })
    expect(sim.world.getPosition(ball)).toEqual({ x: 0, y: 0 })
    expect(sim.world.getLinearVelocity(ball)).toEqual({ x: 0, y: 0 })
    // And the right goal for red.
    sim.world.setTransform(ball, { x: FIELD_X + GOAL_DEPTH / 2, y: -0.5 }, 0)
    for (let i = 0; i < 120; i++) sim.runTick()
    expect(state().score).toEqual({ red: 1, blue: 1 })
    expect(goals(events).length).toBe(2)
  })

  it(`a striker against a team that keeps out of the way wins ${WIN_SCORE}-0; the match ends and a rematch starts over`, () => {
    const { sim, events, state } = match()
    let kicks = 0
    for (let i = 0; i < MATCH_TICKS && state().phase !== 'over'; i++) {
      for (const c of strikerCommands(sim, 1)) if (sim.apply(1, c) === null && c.kind === 'kick') kicks++
      for (const c of benchCommands(sim, 2)) sim.apply(2, c)
      sim.runTick()
    }
    expect(state()).toMatchObject({ phase: 'over', winner: 'red', score: { red: WIN_SCORE, blue: 0 } })
    expect(goals(events).map((e) => (e as { goal: string }).goal)).toEqual(Array(WIN_SCORE).fill('red'))
    expect(events[events.length - 1]).toEqual({ over: 'red', score: { red: WIN_SCORE, blue: 0 } })
    expect(kicks).toBeGreaterThan(0)
    console.log(`striker: ${WIN_SCORE}-0 at tick ${sim.tick} with ${kicks} kicks`)
    expect(sim.apply(1, run(1, 0))).toBe('the match is over')
    expect(sim.apply(1, kick(1))).toBe('the match is over')
    expect(sim.apply(2, { k: 'cmd', kind: 'rematch', a: {} })).toBeNull()
    expect(state()).toMatchObject({ phase: 'waiting', score: { red: 0, blue: 0 }, winner: null })
    expect(sim.world.getPosition(state().players[1].disc)).toEqual({ x: -4, y: 0 })
    sim.runTick()
    expect(state()).toMatchObject({ phase: 'playing', startTick: sim.tick })
    expect(sim.apply(2, { k: 'cmd', kind: 'rematch', a: {} })).toBe('the match is not over')
  })

  it('idle teams draw 0-0 when the clock runs out, at exactly MATCH_TICKS after the kickoff', () => {
    const { sim, events, state } = match()
    sim.runTick()
    const start = state().startTick
    while (sim.tick < start + MATCH_TICKS - 1) sim.runTick()
    expect(state().phase).toBe('playing')
    sim.runTick()
    expect(state()).toMatchObject({ phase: 'over', winner: 'draw' })
    expect(events[events.length - 1]).toEqual({ over: 'draw', score: { red: 0, blue: 0 } })
  })

  it('copies made mid-match (a clone, as a predicting client makes; a sync payload, as a lockstep client gets) play on with the same hashes', () => {
    const { sim } = match()
    const script = (s: RoomSimulation) => {
      for (const c of strikerCommands(s, 1)) s.apply(1, c)
      for (const c of strikerCommands(s, 2)) s.apply(2, c)
      s.runTick()
    }
    for (let i = 0; i < 300; i++) script(sim)
    const copy = cloneSimulation(sim, ROOM)
    const restored = restoreSyncPayload(encodeSyncPayload(sim), { ...ROOM, games: findGame })
    if (!restored.ok) throw new Error(restored.reason)
    const synced = restored.sim
    // The game drives discs of ctx.players (join order): the copies must list them alike.
    expect([...copy.players.keys()]).toEqual([1, 2])
    const hashes: number[][] = [[], [], []]
    for (let i = 0; i < 600; i++) {
      for (const [k, s] of [sim, copy, synced].entries()) {
        script(s)
        hashes[k].push(s.hash())
      }
    }
    expect(hashes[1]).toEqual(hashes[0])
    expect(hashes[2]).toEqual(hashes[0])
    expect(copy.gameState).toEqual(sim.gameState)
  })

  it('a player who leaves takes their disc along; a newcomer joins the smaller team', () => {
    const { sim, state } = match()
    const disc = state().players[1].disc
    sim.leave(1)
    expect(sim.world.hasBody(disc)).toBe(false)
    expect(state().players[1]).toBeUndefined()
    sim.join(3, 'c', '#0f0')
    expect(state().players[3]).toMatchObject({ team: 'red' })
    expect(sim.world.getPosition(state().players[3].disc)).toEqual({ x: -4, y: 0 })
  })
})
