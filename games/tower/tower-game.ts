/*
 * Tower: a building race (docs/games.md, "Tower"). Each player gets a lane with a platform and
 * drops blocks onto it with `block` (a kind and an offset along the platform; one block every
 * DROP_COOLDOWN ticks), each appearing at rest DROP_CLEARANCE above the top of the player's highest
 * block. Every tick the game measures each tower from the world: the highest top edge of the
 * player's blocks that are at rest (moving slower than SETTLED_SPEED), above the platform top. A
 * block whose centre falls below FALL_LINE is removed and costs its owner FALL_PENALTY. When the
 * round's ROUND_TICKS are over, the best score (height less penalties) wins; `restart` clears the
 * blocks and starts another round.
 *
 * Blocks are visited in ascending body id and players in join order, with exact arithmetic only
 * (a turned box's top is y + |hw sin| + |hh cos|, from the engine's exact rotation pair).
 */
import { box } from '../../engine/index.ts'
import type { GameContext, PlainData } from '../../shared/index.ts'
import { defineGame } from '../game-api.ts'

/** Lanes (and so players) and the distance between lane centres (m). */
export const LANES = 4
export const LANE_SPACING = 10
/** Half-width of a lane's platform (m); its top is at y = 0. */
export const PLATFORM_HALF_WIDTH = 2
/** A block whose centre is below this height (m) has fallen. */
export const FALL_LINE = -2
/** Score lost per fallen block (m). */
export const FALL_PENALTY = 0.5
/** Ticks between a player's blocks, the gap under a new block (m), the resting speed (m/s). */
export const DROP_COOLDOWN = 40
export const DROP_CLEARANCE = 1
export const SETTLED_SPEED = 0.05
/** Length of a round (ticks): one minute at 60 Hz. */
export const ROUND_TICKS = 3600
/** The block kinds: half-width and half-height (m). */
export const BLOCKS: Readonly<Record<string, readonly [number, number]>> = Object.freeze({
  slab: Object.freeze([1, 0.25] as const),
  square: Object.freeze([0.5, 0.5] as const),
  post: Object.freeze([0.25, 0.75] as const),
})

/** A block's owner and kind. */
export interface TowerBlock {
  [key: string]: PlainData
  owner: number
  kind: string
}

/** The tower game's state. */
export interface TowerState {
  [key: string]: PlainData
  /** 'waiting' for the first player, 'building', then 'over'. */
  phase: 'waiting' | 'building' | 'over'
  /** Room tick the round started at, or -1. */
  startTick: number
  /** Lane index by player id. */
  lanes: Record<string, number>
  /** Every block by body id. */
  blocks: Record<string, TowerBlock>
  /** Measured height (m) and fallen blocks, by player id. */
  height: Record<string, number>
  fallen: Record<string, number>
  /** Room tick of each player's last block. */
  lastDrop: Record<string, number>
  /** The players with the best score once the round is over. */
  winners: number[]
}

type Ctx = GameContext<TowerState>

/** The x of a lane's centre (m). */
export function laneX(lane: number): number {
  return (lane - (LANES - 1) / 2) * LANE_SPACING
}

/** A player's score: height less the penalties for fallen blocks (m). */
export function towerScore(state: TowerState, player: number): number {
  return (state.height[player] ?? 0) - FALL_PENALTY * (state.fallen[player] ?? 0)
}

/** Block ids in ascending order. */
function blockIds(state: TowerState): number[] {
  return Object.keys(state.blocks)
    .map(Number)
    .sort((a, b) => a - b)
}

/** The world y of a block's highest point (m). */
function blockTop(ctx: Ctx, id: number, kind: string): number {
  const [hw, hh] = BLOCKS[kind]
  const r = ctx.world.getRotation(id)
  return ctx.world.getPosition(id).y + Math.abs(hw * r.s) + Math.abs(hh * r.c)
}

function startRound(ctx: Ctx): void {
  ctx.state.phase = 'building'
  ctx.state.startTick = ctx.tick
  ctx.state.winners = []
  ctx.emit({ round: ctx.tick })
}

function endRound(ctx: Ctx): void {
  let best = Number.NEGATIVE_INFINITY
  for (const id of ctx.players) best = Math.max(best, towerScore(ctx.state, id))
  ctx.state.phase = 'over'
  ctx.state.winners = ctx.players.filter((id) => towerScore(ctx.state, id) === best)
  const scores: Record<string, number> = {}
  for (const id of ctx.players) scores[id] = towerScore(ctx.state, id)
  ctx.emit({ over: ctx.state.winners, scores })
}

/** Remove fallen blocks (with their penalty) and measure every tower. */
function measure(ctx: Ctx): void {
  const heights: Record<string, number> = {}
  const v = { x: 0, y: 0 }
  for (const id of blockIds(ctx.state)) {
    const block = ctx.state.blocks[id]
    if (!ctx.world.hasBody(id)) {
      delete ctx.state.blocks[id]
      continue
    }
    if (ctx.world.getPosition(id).y < FALL_LINE) {
      ctx.destroyBody(id)
      delete ctx.state.blocks[id]
      if (ctx.state.fallen[block.owner] !== undefined) ctx.state.fallen[block.owner] += 1
      ctx.emit({ fell: block.owner, block: id })
      continue
    }
    ctx.world.getLinearVelocity(id, v)
    if (v.x * v.x + v.y * v.y >= SETTLED_SPEED * SETTLED_SPEED) continue
    heights[block.owner] = Math.max(heights[block.owner] ?? 0, blockTop(ctx, id, block.kind))
  }
  for (const id of ctx.players) {
    if (ctx.state.lanes[id] !== undefined) ctx.state.height[id] = heights[id] ?? 0
  }
}

export const tower = defineGame<TowerState>({
  name: 'tower',
  maxPlayers: LANES,
  state: {
    phase: 'waiting',
    startTick: -1,
    lanes: {},
    blocks: {},
    height: {},
    fallen: {},
    lastDrop: {},
    winners: [],
  },
  setup(ctx) {
    for (let lane = 0; lane < LANES; lane++) {
      ctx.createBody({
        type: 'static',
        position: { x: laneX(lane), y: -0.25 },
        shape: box(PLATFORM_HALF_WIDTH, 0.25),
        friction: 0.8,
      })
    }
  },
  commands: {
    block: {
      args: {
        type: 'object',
        properties: {
          kind: { enum: ['slab', 'square', 'post'] },
          x: { type: 'number', minimum: -PLATFORM_HALF_WIDTH, maximum: PLATFORM_HALF_WIDTH },
        },
        required: ['kind', 'x'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { kind: string; x: number }) {
        if (ctx.state.phase !== 'building') return 'the round is over'
        const lane = ctx.state.lanes[player]
        if (lane === undefined) return 'you have no lane'
        const last = ctx.state.lastDrop[player]
        if (last !== undefined && ctx.tick - last < DROP_COOLDOWN)
          return `one block every ${DROP_COOLDOWN} ticks`
        let top = 0
        for (const id of blockIds(ctx.state)) {
          const block = ctx.state.blocks[id]
          if (block.owner === player && ctx.world.hasBody(id))
            top = Math.max(top, blockTop(ctx, id, block.kind))
        }
        const [hw, hh] = BLOCKS[args.kind]
        const id = ctx.createBody({
          type: 'dynamic',
          position: { x: laneX(lane) + args.x, y: top + DROP_CLEARANCE + hh },
          shape: box(hw, hh),
          friction: 0.8,
        })
        if (typeof id === 'string') return id
        ctx.state.blocks[id] = { owner: player, kind: args.kind }
        ctx.state.lastDrop[player] = ctx.tick
      },
    },
    restart: {
      args: { type: 'object', properties: {}, additionalProperties: false },
      apply(ctx) {
        if (ctx.state.phase !== 'over') return 'the round is not over'
        for (const id of blockIds(ctx.state)) ctx.destroyBody(id)
        ctx.state.blocks = {}
        ctx.state.lastDrop = {}
        for (const id of ctx.players) {
          if (ctx.state.lanes[id] === undefined) continue
          ctx.state.height[id] = 0
          ctx.state.fallen[id] = 0
        }
        startRound(ctx)
      },
    },
  },
  onJoin(ctx, player) {
    const taken = new Set(Object.values(ctx.state.lanes))
    let lane = 0
    while (taken.has(lane)) lane++
    ctx.state.lanes[player] = lane
    ctx.state.height[player] = 0
    ctx.state.fallen[player] = 0
    if (ctx.state.phase === 'waiting') startRound(ctx)
  },
  onLeave(ctx, player) {
    for (const id of blockIds(ctx.state)) {
      if (ctx.state.blocks[id].owner !== player) continue
      ctx.destroyBody(id)
      delete ctx.state.blocks[id]
    }
    delete ctx.state.lanes[player]
    delete ctx.state.height[player]
    delete ctx.state.fallen[player]
    delete ctx.state.lastDrop[player]
  },
  view(ctx, player) {
    const s = ctx.state
    const elapsed = s.phase === 'building' ? ctx.tick - s.startTick : s.phase === 'over' ? ROUND_TICKS : 0
    // Heights to the centimetre, so the view (sent when it changes) does not change every tick.
    const heights: Record<string, number> = {}
    for (const id of ctx.players) heights[id] = Math.round((s.height[id] ?? 0) * 100) / 100
    let blocks = 0
    for (const id of blockIds(s)) if (s.blocks[id].owner === player) blocks++
    return {
      phase: s.phase,
      secondsLeft: Math.ceil(Math.max(0, ROUND_TICKS - elapsed) / 60),
      heights,
      blocks,
      fallen: s.fallen[player] ?? 0,
      winners: [...s.winners],
    }
  },
  tick(ctx) {
    measure(ctx)
    if (ctx.state.phase === 'building' && ctx.tick - ctx.state.startTick >= ROUND_TICKS) endRound(ctx)
  },
})
