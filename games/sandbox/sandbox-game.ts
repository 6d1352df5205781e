/*
 * The sandbox: Concord's building game, on the game module API. Its commands are the built-in
 * ones and its joint commands (joint-commands.ts: weld, hinge, spring, slider, wheel, jointMotor, editJoint),
 * and each does to the world exactly what docs/games.md ("The sandbox's commands") says;
 * the engine-level parts (clamps, the grab's mouse joint and force cap, anchor and rope rules, the
 * body limit) are shared/sim's primitives that every game's ctx offers. The sandbox keeps no state
 * of its own (its hash is the world's) and never draws from the PRNG.
 *
 * sandboxCommands is exported so that other games can reuse a command or wrap it with a rule of
 * their own (a goal game that lets players grab only in their half).
 */
import { SCENES } from '../../engine/index.ts'
import { isMovable, NO_ITEMS } from '../../shared/index.ts'
import { builtin, defineGame, type GameCommandDefinition } from '../game-api.ts'
import { editCommands } from './edit-commands.ts'
import { jointCommands } from './joint-commands.ts'
import {
  captureBodies,
  captureJoints,
  newestJoint,
  recordAction,
  recordJoint,
  undoCommands,
} from './undo-commands.ts'

/** Ticks between scene loads or resets in one room: building a scene is the costliest command. */
export const MIN_TICKS_BETWEEN_LOADS = 10

/** The largest explosion radius (m); the blast fades to nothing over as much again beyond it. */
export const MAX_EXPLOSION_RADIUS = 20
/** The largest explosion impulse per metre of a shape's width across the blast (N s/m). */
export const MAX_EXPLOSION_IMPULSE = 100

/** Why a scene load or reset must wait (at most one per MIN_TICKS_BETWEEN_LOADS ticks), or null. */
function loadTooSoon(tick: number, lastLoadTick: number): string | null {
  return tick - lastLoadTick < MIN_TICKS_BETWEEN_LOADS ? 'scene loads are limited to 6 per second' : null
}

/** The sandbox's commands, one per built-in kind. */
export const sandboxCommands = {
  spawn: builtin('spawn', (ctx, player, cmd) => {
    const spawned = ctx.spawn(cmd, player)
    if (typeof spawned === 'string') return spawned
    recordAction(ctx, player, 'spawn', NO_ITEMS, captureBodies(ctx, [spawned]))
    return null
  }),
  grab: builtin('grab', (ctx, player, cmd) => ctx.grab(player, cmd.body, cmd.lx, cmd.ly)),
  move: builtin('move', (ctx, player, cmd) => ctx.moveCursor(player, cmd.x, cmd.y)),
  release: builtin('release', (ctx, player) => ctx.release(player)),
  delete: builtin('delete', (ctx, player, cmd) => {
    // Static bodies players drew (they have a colour) may be deleted; the scene's may not.
    if (!isMovable(ctx.world, cmd.body) && !(ctx.world.hasBody(cmd.body) && ctx.bodyColor(cmd.body) !== null))
      return `body ${cmd.body} does not exist or is static`
    const before = captureBodies(ctx, [cmd.body])
    ctx.destroyBody(cmd.body)
    recordAction(ctx, player, 'delete', before, NO_ITEMS)
    return null
  }),
  pin: builtin('pin', (ctx, player, cmd) => {
    const refusal = ctx.addJoint(cmd)
    if (refusal !== null) return refusal
    recordJoint(ctx, player, 'pin', newestJoint(ctx.world))
  }),
  rope: builtin('rope', (ctx, player, cmd) => {
    const refusal = ctx.addJoint(cmd)
    if (refusal !== null) return refusal
    recordJoint(ctx, player, 'rope', newestJoint(ctx.world))
  }),
  unjoint: builtin('unjoint', (ctx, player, cmd) => {
    const before = captureJoints(ctx, [cmd.joint])
    const refusal = ctx.removeJoint(cmd.joint)
    if (refusal !== null) return refusal
    recordAction(ctx, player, 'unjoint', before, NO_ITEMS)
  }),
  scene: builtin(
    'scene',
    (ctx, _player, cmd) => {
      if (!Object.hasOwn(SCENES, cmd.name)) return `unknown scene "${cmd.name}"`
      return loadTooSoon(ctx.tick, ctx.lastLoadTick) ?? ctx.loadScene(cmd.name)
    },
    { control: true },
  ),
  reset: builtin('reset', (ctx) => loadTooSoon(ctx.tick, ctx.lastLoadTick) ?? ctx.loadScene(ctx.scene), {
    control: true,
  }),
  pause: builtin(
    'pause',
    (ctx, _player, cmd) => {
      ctx.paused = cmd.paused
    },
    { control: true },
  ),
  step: builtin('step', (ctx) => ctx.requestStep(), { control: true }),
  gravity: builtin('gravity', (ctx, _player, cmd) => ctx.setGravity(cmd.x, cmd.y), { control: true }),
  explode: <GameCommandDefinition<undefined, { x: number; y: number; radius: number; impulse: number }>>{
    args: {
      type: 'object',
      properties: {
        x: { type: 'number', minimum: -500, maximum: 500 },
        y: { type: 'number', minimum: -500, maximum: 500 },
        radius: { type: 'number', exclusiveMinimum: 0, maximum: MAX_EXPLOSION_RADIUS },
        impulse: { type: 'number', minimum: 0, maximum: MAX_EXPLOSION_IMPULSE },
      },
      required: ['x', 'y', 'radius', 'impulse'],
      additionalProperties: false,
    },
    apply(ctx, _player, a: { x: number; y: number; radius: number; impulse: number }) {
      ctx.world.explode({
        position: { x: a.x, y: a.y },
        radius: a.radius,
        falloff: a.radius,
        impulsePerLength: a.impulse,
      })
    },
  },
  slow: <GameCommandDefinition<undefined, { every: number }>>{
    args: {
      type: 'object',
      properties: { every: { enum: [1, 2, 4] } },
      required: ['every'],
      additionalProperties: false,
    },
    control: true,
    apply(ctx, _player, a: { every: number }) {
      ctx.slowMotion = a.every
    },
  },
  lock: <GameCommandDefinition<undefined, { locked: boolean }>>{
    args: {
      type: 'object',
      properties: { locked: { type: 'boolean' } },
      required: ['locked'],
      additionalProperties: false,
    },
    control: true,
    apply(ctx, player, a: { locked: boolean }) {
      if (player !== ctx.creator)
        return `only the room's creator (player ${ctx.creator}) can lock the controls`
      ctx.controlsLocked = a.locked
    },
  },
}

/** The sandbox game: the room's scene (the server's default, or the one a test asks for) and every built-in command. */
export const sandbox = defineGame({
  name: 'sandbox',
  setup(ctx, options) {
    ctx.loadScene(options.scene)
  },
  commands: { ...sandboxCommands, ...jointCommands, ...editCommands, ...undoCommands },
})
