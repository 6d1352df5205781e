/*
 * King of the hill, written from docs/games.md alone (issue 29's stranger check; see
 * tests/games-from-docs/README.md). Up to four players each push their own puck around a walled
 * arena seen from above with `push {x, y}`; a sensor disc in the middle is the hill. Every tick
 * that exactly one player's puck is on the hill counts for that player; the first to WIN_TICKS
 * (3 s) wins. `restart {}` starts a new round once one is over. The client module (`client`,
 * below) shows each player's time and the king, and binds the arrow keys to full pushes.
 */
import {
  box,
  circle,
  defineGame,
  defineGameClient,
  type GameContext,
  type PlainData,
  type SensorEvents,
} from 'concord/game'
import {
  ARENA,
  HILL_RADIUS,
  PUCK_DAMPING,
  PUCK_DENSITY,
  PUCK_RADIUS,
  PUSH_COOLDOWN,
  PUSH_IMPULSE,
  SPOTS,
  TICK_HZ,
  WIN_TICKS,
} from './layout.ts'

interface Puck {
  [key: string]: PlainData
  body: number // the puck's body id
  shape: number // its shape id (what the hill's sensor sees)
  slot: number // index into SPOTS
  held: number // ticks this player has been king
  lastPush: number // room tick of the last push, -1 for none
}

interface Hill {
  [key: string]: PlainData
  phase: string // 'waiting' (fewer than two players), 'playing', 'over'
  winner: number // the winner's player id, 0 while none
  king: number // the player alone on the hill now, 0 for none
  hill: number // the hill's sensor shape id
  pucks: Record<string, Puck> // player id -> puck
  onHill: Record<string, boolean> // shape id -> true while that shape overlaps the hill
}

export const NAME = 'hill'

/** Puts every puck back on its spot, at rest. */
function resetPucks(ctx: GameContext<Hill>): void {
  for (const id of ctx.players) {
    const p = ctx.state.pucks[id]
    if (!p) continue
    ctx.world.setTransform(p.body, SPOTS[p.slot], 0)
    ctx.world.setLinearVelocity(p.body, { x: 0, y: 0 })
  }
}

export default defineGame<Hill>({
  name: NAME,
  minPlayers: 2,
  maxPlayers: SPOTS.length,
  state: { phase: 'waiting', winner: 0, king: 0, hill: 0, pucks: {}, onHill: {} },
  setup(ctx) {
    ctx.setGravity(0, 0)
    const wall = ARENA + 0.5
    ctx.createBody({ type: 'static', position: { x: 0, y: -wall }, shape: box(wall + 0.5, 0.5) })
    ctx.createBody({ type: 'static', position: { x: 0, y: wall }, shape: box(wall + 0.5, 0.5) })
    ctx.createBody({ type: 'static', position: { x: -wall, y: 0 }, shape: box(0.5, wall + 0.5) })
    ctx.createBody({ type: 'static', position: { x: wall, y: 0 }, shape: box(0.5, wall + 0.5) })
    const hill = ctx.createBody({
      type: 'static',
      position: { x: 0, y: 0 },
      shapes: [{ shape: circle(HILL_RADIUS), sensor: true }],
    })
    if (typeof hill === 'string') throw new Error(`hill refused: ${hill}`)
    ctx.state.hill = ctx.world.bodyShapes(hill)[0]
  },
  commands: {
    push: {
      args: {
        type: 'object',
        properties: {
          x: { type: 'number', minimum: -1, maximum: 1 },
          y: { type: 'number', minimum: -1, maximum: 1 },
        },
        required: ['x', 'y'],
        additionalProperties: false,
      },
      apply(ctx, player, args: { x: number; y: number }) {
        if (ctx.state.phase === 'over') return 'the round is over'
        const p = ctx.state.pucks[player]
        if (!p) return 'you have no puck'
        if (args.x * args.x + args.y * args.y > 1) return 'a push is at most 1 long'
        if (p.lastPush >= 0 && ctx.tick - p.lastPush < PUSH_COOLDOWN) return 'one push every 10 ticks'
        const at = ctx.world.getPosition(p.body)
        ctx.world.applyLinearImpulse(p.body, { x: args.x * PUSH_IMPULSE, y: args.y * PUSH_IMPULSE }, at)
        p.lastPush = ctx.tick
      },
    },
    restart: {
      args: { type: 'object', properties: {}, additionalProperties: false },
      apply(ctx) {
        if (ctx.state.phase !== 'over') return 'the round is not over'
        for (const id of Object.keys(ctx.state.pucks)) {
          ctx.state.pucks[id].held = 0
          ctx.state.pucks[id].lastPush = -1
        }
        ctx.state.winner = 0
        ctx.state.king = 0
        ctx.state.phase = Object.keys(ctx.state.pucks).length >= 2 ? 'playing' : 'waiting'
        resetPucks(ctx)
      },
    },
  },
  onJoin(ctx, player) {
    const used = Object.keys(ctx.state.pucks).map((id) => ctx.state.pucks[id].slot)
    let slot = 0
    while (used.includes(slot)) slot += 1
    if (slot >= SPOTS.length) return
    const body = ctx.createBody(
      {
        type: 'dynamic',
        position: SPOTS[slot],
        shapes: [{ shape: circle(PUCK_RADIUS), density: PUCK_DENSITY, restitution: 0.3, friction: 0.2 }],
        linearDamping: PUCK_DAMPING,
        fixedRotation: true,
      },
      [0xe04040, 0x4060e0, 0x40b040, 0xd0a020][slot],
    )
    if (typeof body === 'string') return // at the body limit: the player watches
    ctx.state.pucks[player] = { body, shape: ctx.world.bodyShapes(body)[0], slot, held: 0, lastPush: -1 }
  },
  onLeave(ctx, player) {
    const p = ctx.state.pucks[player]
    if (!p) return
    delete ctx.state.onHill[p.shape]
    ctx.destroyBody(p.body)
    delete ctx.state.pucks[player]
    if (ctx.state.king === player) ctx.state.king = 0
  },
  view(ctx, player) {
    const mine = ctx.state.pucks[player]
    const last = mine?.lastPush ?? -1
    // How far this player's puck is from the hill's centre, in tenths of a metre (-1: no puck).
    let away = -1
    if (mine) {
      const at = ctx.world.getPosition(mine.body)
      away = Math.round(Math.sqrt(at.x * at.x + at.y * at.y) * 10)
    }
    const held: Record<string, number> = {}
    for (const id of Object.keys(ctx.state.pucks)) held[id] = ctx.state.pucks[id].held
    return {
      phase: ctx.state.phase,
      held,
      need: WIN_TICKS,
      king: ctx.state.king,
      winner: ctx.state.winner,
      me: ctx.state.pucks[player] ? player : 0,
      // the room tick from which this player may push again (0: now)
      nextPush: last < 0 ? 0 : last + PUSH_COOLDOWN,
      away,
    }
  },
  tick(ctx) {
    const s = ctx.state
    if (s.phase === 'waiting' && Object.keys(s.pucks).length >= 2) {
      s.phase = 'playing'
      ctx.emit({ start: ctx.tick })
    }
    const sensors = ctx.events.sensors as SensorEvents | null
    if (sensors !== null) {
      for (const e of sensors.begin) if (e.sensor === s.hill) s.onHill[e.visitor] = true
      for (const e of sensors.end) if (e.sensor === s.hill) delete s.onHill[e.visitor]
    }
    let king = 0
    let count = 0
    for (const id of ctx.players) {
      const p = s.pucks[id]
      if (p && s.onHill[p.shape]) {
        king = id
        count += 1
      }
    }
    if (count !== 1) king = 0
    if (king !== s.king) {
      s.king = king
      if (s.phase === 'playing') ctx.emit({ king })
    }
    if (s.phase !== 'playing' || king === 0) return
    const p = s.pucks[king]
    p.held += 1
    if (p.held >= WIN_TICKS) {
      s.phase = 'over'
      s.winner = king
      ctx.emit({ over: king, seconds: p.held / TICK_HZ })
    }
  },
})

/** Tenths of a second held, as text with integer arithmetic (the determinism check forbids locale formatting). */
export function heldText(ticks: number): string {
  const tenths = Math.floor((ticks * 10) / TICK_HZ)
  return `${Math.floor(tenths / 10)}.${tenths % 10} s`
}

interface HillView {
  phase: string
  held: Record<string, number>
  need: number
  king: number
  winner: number
  me: number
  nextPush: number
  away: number
}

function isHillView(state: unknown): state is HillView {
  const v = state as HillView | null
  return typeof v === 'object' && v !== null && typeof v.held === 'object' && typeof v.need === 'number'
}

const push = (x: number, y: number) => (): { kind: string; args: { x: number; y: number } } => ({
  kind: 'push',
  args: { x, y },
})

export const client = defineGameClient({
  game: NAME,
  hud(state, me) {
    if (!isHillView(state)) return []
    const items = [{ label: 'hill', value: `hold ${heldText(state.need)} alone` }]
    for (const id of Object.keys(state.held).sort((a, b) => Number(a) - Number(b))) {
      const who = Number(id) === me ? `you (${id})` : `player ${id}`
      items.push({ label: who, value: heldText(state.held[id]) })
    }
    const status =
      state.phase === 'over'
        ? `${state.winner === me ? 'you win' : `player ${state.winner} wins`} (R: restart)`
        : state.phase === 'waiting'
          ? 'waiting for a second player'
          : state.king === 0
            ? 'nobody is king'
            : `king: ${state.king === me ? 'you' : `player ${state.king}`}`
    items.push({ label: 'round', value: status })
    if (state.away >= 0)
      items.push({ label: 'to the hill', value: `${Math.floor(state.away / 10)}.${state.away % 10} m` })
    return items.slice(0, 8)
  },
  keys: {
    arrowleft: push(-1, 0),
    arrowright: push(1, 0),
    arrowup: push(0, 1),
    arrowdown: push(0, -1),
    r: ({ state }) => (isHillView(state) && state.phase === 'over' ? { kind: 'restart', args: {} } : null),
  },
})
