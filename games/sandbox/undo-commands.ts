/*
 * Undo and redo in the sandbox (issue 31): each player's own actions, from the history the room
 * simulation keeps (shared/sim's history.ts, ctx.history), applied as commands, so every replica
 * undoes the same way. What is undoable is what records itself; today: spawn (and drawn and
 * static shapes, which are spawns), delete, pin, rope, weld, hinge, spring, slider, wheel (with the
 * wheel it made), unjoint (the Cut tool), editJoint (joint-commands.ts), and edit-commands.ts's
 * edit, transform, duplicate and deleteMany. Grabs, moves, explode, slow motion, lock, pause,
 * step, gravity and scene loads are not undoable (a scene load or reset clears every history).
 *
 * Items are saved in the scene file's forms (games/scenes: saveSceneBody, saveSceneJoint; the
 * joint's bodies in the form are the ids at saving, the entry's `a` and `b` are the current ones),
 * so a rebuilt body has the shapes, materials, pose, velocities and colour it had when saved.
 *
 * A command makes itself undoable with one call after it changed the world (see docs/games.md,
 * "Undo and redo"):
 *   const before = captureBodies(ctx, [id])                 // what it will change, or NO_ITEMS
 *   ... change the world ...
 *   recordAction(ctx, player, 'edit', before, captureBodies(ctx, [newId]))
 * which is ctx.history.record(player, { kind, before, after }).
 *
 * undo: the player's last action: the `after` items that still exist are removed (a body with the
 * joints on it) and the `before` items rebuilt (bodies first, with new ids, then the joints whose
 * two bodies exist). Refused, changing nothing, when the player has nothing to undo, when a body
 * of `after` is gone ("body 12 was deleted by player 2", "body 12 was removed by player 2's undo",
 * "body 12 no longer exists"), when the
 * rebuilt bodies would pass the body limit, or when nothing would change (a joint that broke).
 * redo: the same with `before` and `after` swapped. With `{skip: true}` a stale action on top (one
 * that would be refused for a gone body or joint) is dropped first, as many as there are, and the
 * next one is undone (redone).
 */
import type { World } from '../../engine/index.ts'
import type {
  GameContext,
  HistoryBody,
  HistoryEntry,
  HistoryItems,
  HistoryJoint,
  HistoryList,
  PlainData,
  WireJointDef,
} from '../../shared/index.ts'
import { NO_ITEMS } from '../../shared/index.ts'
import type { GameCommandDefinition } from '../game-api.ts'
import {
  type SceneBody,
  type SceneJoint,
  saveSceneBody,
  saveSceneJoint,
  sceneBodyDef,
  sceneJointDef,
} from '../scenes/index.ts'

/** A copy of a value without its undefined fields (a saved form as plain data). */
function plain(value: unknown): PlainData {
  if (Array.isArray(value)) return value.map(plain)
  if (typeof value === 'object' && value !== null) {
    const out: { [key: string]: PlainData } = {}
    for (const [k, v] of Object.entries(value)) if (v !== undefined) out[k] = plain(v)
    return out
  }
  return value as PlainData
}

/** A body as an entry keeps it: saved now, in the scene file's form. */
function captureBody(ctx: GameContext<unknown>, id: number): HistoryBody {
  return { id, color: ctx.bodyColor(id), def: plain(saveSceneBody(ctx.world, id, undefined)) }
}

/** A joint of the room (scene or player joint) as an entry keeps it; null for one not in the room. */
function captureJoint(ctx: GameContext<unknown>, id: number): HistoryJoint | null {
  const wire = ctx.userJoint(id)
  if (!wire || !ctx.world.hasJoint(id)) return null
  const index = new Map<number, number>([
    [wire.a, wire.a],
    [wire.b, wire.b],
  ])
  const saved = saveSceneJoint(ctx.world.getJointDef(id), index)
  if (!saved) return null
  return { id, a: wire.a, b: wire.b, owner: wire.owner, def: plain(saved) }
}

/** The room's joints (not grabs) on any of `bodies`, ascending ids. */
function jointsOn(ctx: GameContext<unknown>, bodies: readonly number[]): number[] {
  const out: number[] = []
  for (const jid of ctx.world.jointIds()) {
    const j = ctx.userJoint(jid)
    if (j && (bodies.includes(j.a) || bodies.includes(j.b))) out.push(jid)
  }
  return out
}

/** Bodies as they are now, with every room joint on them: one side of an action. */
export function captureBodies(ctx: GameContext<unknown>, bodies: readonly number[]): HistoryItems {
  const joints: HistoryJoint[] = []
  for (const jid of jointsOn(ctx, bodies)) {
    const j = captureJoint(ctx, jid)
    if (j) joints.push(j)
  }
  return { bodies: bodies.filter((id) => ctx.world.hasBody(id)).map((id) => captureBody(ctx, id)), joints }
}

/** Joints as they are now (no bodies): one side of a joint's creation or removal. */
export function captureJoints(ctx: GameContext<unknown>, joints: readonly number[]): HistoryItems {
  const out: HistoryJoint[] = []
  for (const jid of joints) {
    const j = captureJoint(ctx, jid)
    if (j) out.push(j)
  }
  return { bodies: [], joints: out }
}

/** Record an undoable action of `player`: ctx.history.record(player, { kind, before, after }). */
export function recordAction(
  ctx: GameContext<unknown>,
  player: number,
  kind: string,
  before: HistoryItems,
  after: HistoryItems,
): void {
  ctx.history.record(player, { kind, before, after })
}

/**
 * Who removed body or joint `id`, by the histories: a player whose undo list holds an action that
 * removed it (a delete, an unjoint), or whose redo list holds one whose undo removed it (an undone
 * spawn); null when no history says (it fell out of the world, broke, or the entry is gone).
 */
function remover(ctx: GameContext<unknown>, id: number, what: 'bodies' | 'joints'): string | null {
  for (const h of ctx.history.all()) {
    for (const e of h.undo)
      if (e.before[what].some((x) => x.id === id) && !e.after[what].some((x) => x.id === id))
        return `${what === 'bodies' ? 'deleted' : 'removed'} by player ${h.player}`
    for (const e of h.redo)
      if (e.after[what].some((x) => x.id === id) && !e.before[what].some((x) => x.id === id))
        return `removed by player ${h.player}'s undo`
  }
  return null
}

/** Why body `id` is gone, for a refusal. */
function goneBody(ctx: GameContext<unknown>, id: number): string {
  const by = remover(ctx, id, 'bodies')
  return by === null ? `body ${id} no longer exists` : `body ${id} was ${by}`
}

/** Why joint `id` is gone, for a refusal. */
function goneJoint(ctx: GameContext<unknown>, id: number): string {
  const by = remover(ctx, id, 'joints')
  return by === null
    ? `joint ${id} no longer exists (it broke, or a body it held was deleted)`
    : `joint ${id} was ${by}`
}

/**
 * Why going from `from` back to `to` (undo: after -> before) cannot start, or null: a body of
 * `from` is gone, or the bodies of `to` would pass the body limit. A stale reason (a gone body)
 * comes back flagged so `skip` may drop the entry.
 */
function startRefusal(
  ctx: GameContext<unknown>,
  from: HistoryItems,
  to: HistoryItems,
): { reason: string; stale: boolean } | null {
  for (const b of from.bodies)
    if (!ctx.world.hasBody(b.id)) return { reason: goneBody(ctx, b.id), stale: true }
  const count = ctx.world.bodyCount - from.bodies.length + to.bodies.length
  if (to.bodies.length > 0 && count > ctx.maxBodies)
    return { reason: `body limit reached (${ctx.maxBodies})`, stale: false }
  return null
}

/** Rebuild one saved body (a new id; every entry is renamed to it); the id, or a refusal. */
function rebuildBody(ctx: GameContext<unknown>, b: HistoryBody): number | string {
  let def: ReturnType<typeof sceneBodyDef>
  try {
    def = sceneBodyDef(b.def as unknown as SceneBody)
  } catch (e) {
    return `body ${b.id} cannot be rebuilt: ${(e as Error).message}`
  }
  const id = ctx.createBody(def, b.color ?? undefined)
  if (typeof id === 'number') ctx.history.renameBody(b.id, id)
  return id
}

/** Rebuild one saved joint on its bodies' current ids; the id, or a refusal. */
function rebuildJoint(ctx: GameContext<unknown>, j: HistoryJoint): number | string {
  const world: World = ctx.world
  if (j.a !== 0 && !world.hasBody(j.a)) return goneBody(ctx, j.a)
  if (!world.hasBody(j.b)) return goneBody(ctx, j.b)
  const saved = { ...(j.def as unknown as SceneJoint), bodyA: j.a === 0 ? null : j.a, bodyB: j.b }
  let def: WireJointDef
  try {
    def = sceneJointDef(world, saved, (id) => id) as WireJointDef
  } catch (e) {
    return `joint ${j.id} cannot be rebuilt: ${(e as Error).message}`
  }
  const id = ctx.createJoint(j.owner, def, 'joint')
  if (typeof id === 'number') ctx.history.renameJoint(j.id, id)
  return id
}

/**
 * Go from `from` to `to` (undo: an entry's after -> before; redo: before -> after): remove what of
 * `from` exists, rebuild `to`. Returns null when something changed, else why nothing did.
 */
function swapItems(ctx: GameContext<unknown>, from: HistoryItems, to: HistoryItems): string | null {
  let changed = false
  let reason: string | null = null
  for (const b of from.bodies) {
    if (!ctx.world.hasBody(b.id)) continue
    ctx.destroyBody(b.id)
    changed = true
  }
  for (const j of from.joints) {
    if (!ctx.userJoint(j.id)) {
      reason ??= goneJoint(ctx, j.id)
      continue
    }
    ctx.removeJoint(j.id)
    changed = true
  }
  // Rebuilding renames the entries, `to` included: read each item's current id from a fresh look-up.
  const bodies = to.bodies.map((b) => b.id)
  for (let i = 0; i < bodies.length; i++) {
    const made = rebuildBody(ctx, to.bodies[i])
    if (typeof made === 'string') reason ??= made
    else {
      bodies[i] = made
      changed = true
    }
  }
  for (const j of to.joints) {
    const a = renamed(j.a, to.bodies, bodies)
    const b = renamed(j.b, to.bodies, bodies)
    const made = rebuildJoint(ctx, { ...j, a, b })
    if (typeof made === 'string') reason ??= made
    else changed = true
  }
  return changed ? null : (reason ?? 'nothing would change')
}

/** A body id of a joint after the bodies of `saved` were rebuilt as `made` (same order). */
function renamed(id: number, saved: readonly HistoryBody[], made: readonly number[]): number {
  const i = saved.findIndex((b) => b.id === id)
  return i < 0 ? id : made[i]
}

/** Undo (list 'undo') or redo (list 'redo') `player`'s next action; null, or why not. */
function step(ctx: GameContext<unknown>, player: number, list: HistoryList, skip: boolean): string | null {
  const verb = list
  for (;;) {
    const entry: HistoryEntry | undefined = ctx.history.next(player, list)
    if (!entry) return `nothing to ${verb}`
    const [from, to] = list === 'undo' ? [entry.after, entry.before] : [entry.before, entry.after]
    const refusal = startRefusal(ctx, from, to)
    if (refusal?.stale && skip) {
      ctx.history.drop(player, list)
      continue
    }
    if (refusal) return `cannot ${verb} ${entry.kind}: ${refusal.reason}`
    const nothing = wouldChangeNothing(ctx, from, to)
    if (nothing !== null) {
      if (skip) {
        ctx.history.drop(player, list)
        continue
      }
      return `cannot ${verb} ${entry.kind}: ${nothing}`
    }
    // A reason back means nothing changed (a rebuild the engine refused): refuse, the entry stays.
    const failed = swapItems(ctx, from, to)
    if (failed !== null) return `cannot ${verb} ${entry.kind}: ${failed}`
    ctx.history.move(player, list)
    return null
  }
}

/**
 * Why going from `from` to `to` would change nothing (no body of `from` exists, no joint of
 * `from` is still in the room, and no item of `to` can be rebuilt), or null when something would.
 */
function wouldChangeNothing(ctx: GameContext<unknown>, from: HistoryItems, to: HistoryItems): string | null {
  if (from.bodies.length > 0 || to.bodies.length > 0) return null
  if (from.joints.some((j) => ctx.userJoint(j.id) !== undefined)) return null
  for (const j of to.joints) {
    if (j.a !== 0 && !ctx.world.hasBody(j.a)) continue
    if (!ctx.world.hasBody(j.b)) continue
    return null
  }
  const gone = from.joints[0]
  if (gone) return goneJoint(ctx, gone.id)
  const j = to.joints[0]
  if (j) return j.a !== 0 && !ctx.world.hasBody(j.a) ? goneBody(ctx, j.a) : goneBody(ctx, j.b)
  return 'it changed nothing'
}

const undoArgs = {
  type: 'object',
  properties: { skip: { type: 'boolean' } },
  additionalProperties: false,
} as const

/** The sandbox's undo and redo commands (see the file comment). */
export const undoCommands: Record<string, GameCommandDefinition<undefined>> = {
  undo: {
    args: undoArgs,
    apply: (ctx, player, a: { skip?: boolean }) => step(ctx, player, 'undo', a.skip === true),
  },
  redo: {
    args: undoArgs,
    apply: (ctx, player, a: { skip?: boolean }) => step(ctx, player, 'redo', a.skip === true),
  },
}

/** Record a joint command's new joint (the id createJoint gave) as undoable; passes a refusal through. */
export function recordJoint(
  ctx: GameContext<unknown>,
  player: number,
  kind: string,
  made: number | string,
): string | null {
  if (typeof made === 'string') return made
  recordAction(ctx, player, kind, NO_ITEMS, captureJoints(ctx, [made]))
  return null
}

/** The newest joint of the world (ids ascending, never reused): the one a pin or rope just made. */
export function newestJoint(world: World): number {
  const ids = world.jointIds()
  return ids[ids.length - 1] ?? 0
}
