/*
 * The lockstep tick stream: the ordered list of everything that changed a room's simulation at
 * each tick (accepted commands, joins, leaves), exactly as the server applied it. A lockstep or
 * predicting client replays it on its own RoomSimulation and must reach the same state hash; the
 * recorder writes the same entries to its log. One source, one order.
 *
 * On the wire (PROTOCOL.md, `ticks`) an entry is a short MessagePack array
 * [tick offset, player id, kind code, ...arguments] rather than the `input` command map, because
 * move commands dominate a busy room and the map form costs half again as many bytes. Numbers are
 * carried unchanged (float64 where the client sent float64): the client must apply exactly the
 * values the server applied. Decoding checks every argument and never throws: a bad entry comes
 * back as a reason, which a client treats like a desync (it asks for a fresh sync).
 */
import { type SpawnCommand, validateClientMessage, type WireShape } from '../protocol/index.ts'
import { copyPlainData, type SimCommand } from './game.ts'

/** A player joining the simulation (its cursor and grab slot exist from this tick). */
export interface JoinEntry {
  k: 'join'
}
/** A player leaving (its grab is released). */
export interface LeaveEntry {
  k: 'leave'
}
/** What one stream entry does: a command, or a player joining or leaving. */
export type StreamAction = SimCommand | JoinEntry | LeaveEntry

/** One entry: at `tick`, `player` did `action`. */
export interface StreamEntry {
  tick: number
  player: number
  action: StreamAction
}

/** Kind codes of stream entries, in the order PROTOCOL.md lists them. */
export const ENTRY_CODES = {
  join: 0,
  leave: 1,
  spawn: 2,
  grab: 3,
  move: 4,
  release: 5,
  delete: 6,
  pin: 7,
  rope: 8,
  unjoint: 9,
  scene: 10,
  pause: 11,
  step: 12,
  reset: 13,
  gravity: 14,
  cmd: 15,
} as const

type Code = (typeof ENTRY_CODES)[keyof typeof ENTRY_CODES]

/** The arguments after the kind code, in order, for each kind (spawn's optional ones may be nil). */
export function entryArguments(action: StreamAction): unknown[] {
  switch (action.k) {
    case 'join':
    case 'leave':
    case 'release':
    case 'step':
    case 'reset':
      return []
    case 'spawn': {
      const args = [
        // The geometry: the Shape map, the list of Shape maps, or {outline: [x0, y0, ...]}.
        action.shapes ?? action.shape ?? { outline: action.outline },
        action.x,
        action.y,
        action.angle ?? null,
        action.vx ?? null,
        action.vy ?? null,
        action.w ?? null,
      ]
      const later = [
        action.density ?? null,
        action.friction ?? null,
        action.restitution ?? null,
        action.color ?? null,
        action.static ?? null,
      ]
      // The optional rest only when given, so entries without it keep their 7 arguments.
      return later.every((v) => v === null) ? args : [...args, ...later]
    }
    case 'grab':
      return [action.body, action.lx, action.ly]
    case 'move':
    case 'gravity':
      return [action.x, action.y]
    case 'delete':
      return [action.body]
    case 'pin':
      return [action.a, action.b, action.x, action.y]
    case 'rope':
      return [action.a, action.b, action.ax, action.ay, action.bx, action.by]
    case 'unjoint':
      return [action.joint]
    case 'scene':
      return [action.name]
    case 'pause':
      return [action.paused]
    case 'cmd':
      return [action.kind, action.a]
    case 'inspect':
      throw new RangeError('inspect changes nothing in the simulation and is never streamed')
  }
}

/** The wire form of an entry: [tick - firstTick, player, code, ...arguments]. */
export function encodeEntry(entry: StreamEntry, firstTick: number): unknown[] {
  return [
    entry.tick - firstTick,
    entry.player,
    ENTRY_CODES[entry.action.k as keyof typeof ENTRY_CODES],
    ...entryArguments(entry.action),
  ]
}

class EntryError extends Error {}

const num = (v: unknown, what: string): number => {
  if (typeof v !== 'number' || !Number.isFinite(v)) throw new EntryError(`${what} must be a finite number`)
  return v
}
const int = (v: unknown, what: string): number => {
  if (!Number.isSafeInteger(v) || (v as number) < 0)
    throw new EntryError(`${what} must be a non-negative integer`)
  return v as number
}
const opt = (v: unknown, what: string): number | undefined =>
  v === null || v === undefined ? undefined : num(v, what)

/**
 * A spawn's geometry from its entry: a Shape map, a list of them, or {outline}. The room checks
 * it as the server did (validateClientMessage), so here only its form.
 */
function geometry(v: unknown): Pick<SpawnCommand, 'shape' | 'shapes' | 'outline'> {
  if (Array.isArray(v)) return { shapes: v.map((s) => shape(s)) }
  if (typeof v !== 'object' || v === null) throw new EntryError('spawn geometry must be a map or a list')
  const m = v as Record<string, unknown>
  if (Array.isArray(m.outline)) return { outline: m.outline.map((c, i) => num(c, `outline[${i}]`)) }
  return { shape: shape(v) }
}

function shape(v: unknown): WireShape {
  const checked = validateClientMessage({ t: 'input', seq: 0, cmd: { k: 'spawn', shape: v, x: 0, y: 0 } })
  if (!checked.ok) throw new EntryError(`spawn ${checked.reason}`)
  const cmd = checked.value.t === 'input' ? checked.value.cmd : null
  if (cmd?.k !== 'spawn' || !cmd.shape) throw new EntryError('spawn shape must be a Shape map')
  return cmd.shape
}

function decodeAction(code: Code, a: unknown[]): StreamAction {
  const arity = (n: number): void => {
    if (a.length !== n) throw new EntryError(`entry kind ${code} needs ${n} arguments, got ${a.length}`)
  }
  switch (code) {
    case 0:
      arity(0)
      return { k: 'join' }
    case 1:
      arity(0)
      return { k: 'leave' }
    case 2: {
      if (a.length !== 10 && a.length !== 12) arity(7)
      const cmd: SimCommand = { k: 'spawn', ...geometry(a[0]), x: num(a[1], 'x'), y: num(a[2], 'y') }
      const [angle, vx, vy, w] = [opt(a[3], 'angle'), opt(a[4], 'vx'), opt(a[5], 'vy'), opt(a[6], 'w')]
      if (angle !== undefined) cmd.angle = angle
      if (vx !== undefined) cmd.vx = vx
      if (vy !== undefined) cmd.vy = vy
      if (w !== undefined) cmd.w = w
      const [density, friction, restitution, color] = [
        opt(a[7], 'density'),
        opt(a[8], 'friction'),
        opt(a[9], 'restitution'),
        opt(a[10], 'color'),
      ]
      if (density !== undefined) cmd.density = density
      if (friction !== undefined) cmd.friction = friction
      if (restitution !== undefined) cmd.restitution = restitution
      if (color !== undefined) cmd.color = color
      if (a[11] === true) cmd.static = true
      return cmd
    }
    case 3:
      arity(3)
      return { k: 'grab', body: int(a[0], 'body'), lx: num(a[1], 'lx'), ly: num(a[2], 'ly') }
    case 4:
      arity(2)
      return { k: 'move', x: num(a[0], 'x'), y: num(a[1], 'y') }
    case 5:
      arity(0)
      return { k: 'release' }
    case 6:
      arity(1)
      return { k: 'delete', body: int(a[0], 'body') }
    case 7:
      arity(4)
      return { k: 'pin', a: int(a[0], 'a'), b: int(a[1], 'b'), x: num(a[2], 'x'), y: num(a[3], 'y') }
    case 8:
      arity(6)
      return {
        k: 'rope',
        a: int(a[0], 'a'),
        b: int(a[1], 'b'),
        ax: num(a[2], 'ax'),
        ay: num(a[3], 'ay'),
        bx: num(a[4], 'bx'),
        by: num(a[5], 'by'),
      }
    case 9:
      arity(1)
      return { k: 'unjoint', joint: int(a[0], 'joint') }
    case 10:
      arity(1)
      if (typeof a[0] !== 'string') throw new EntryError('scene name must be a string')
      return { k: 'scene', name: a[0] }
    case 11:
      arity(1)
      if (typeof a[0] !== 'boolean') throw new EntryError('paused must be true or false')
      return { k: 'pause', paused: a[0] }
    case 12:
      arity(0)
      return { k: 'step' }
    case 13:
      arity(0)
      return { k: 'reset' }
    case 14:
      arity(2)
      return { k: 'gravity', x: num(a[0], 'gravity x'), y: num(a[1], 'gravity y') }
    case 15: {
      arity(2)
      if (typeof a[0] !== 'string') throw new EntryError('game command kind must be a string')
      try {
        return { k: 'cmd', kind: a[0], a: copyPlainData(a[1], 'game command arguments') }
      } catch (error) {
        throw new EntryError((error as Error).message)
      }
    }
  }
}

/** Decoded entries, or the reason they could not be decoded. */
export type EntriesResult = { ok: true; entries: StreamEntry[] } | { ok: false; reason: string }

/**
 * Decode a `ticks` message's `c` list against its first tick and tick count: every entry must lie
 * within [firstTick, firstTick + count), in non-decreasing tick order.
 */
export function decodeEntries(list: unknown, firstTick: number, count: number): EntriesResult {
  if (!Array.isArray(list)) return { ok: false, reason: 'ticks c must be a list' }
  const entries: StreamEntry[] = []
  let last = 0
  try {
    for (let i = 0; i < list.length; i++) {
      const e = list[i]
      if (!Array.isArray(e) || e.length < 3) throw new EntryError(`entry ${i} must be a list of at least 3`)
      const offset = int(e[0], `entry ${i} tick offset`)
      if (offset >= count || offset < last)
        throw new EntryError(`entry ${i} tick offset ${offset} out of order`)
      last = offset
      const code = e[2]
      if (!Number.isInteger(code) || code < 0 || code > 15)
        throw new EntryError(`entry ${i} has unknown kind ${String(code)}`)
      entries.push({
        tick: firstTick + offset,
        player: int(e[1], `entry ${i} player`),
        action: decodeAction(code as Code, e.slice(3)),
      })
    }
  } catch (error) {
    if (error instanceof EntryError) return { ok: false, reason: error.message }
    throw error
  }
  return { ok: true, entries }
}
