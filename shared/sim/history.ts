/*
 * Each player's undo and redo history (issue 31), kept by the room simulation so that the server,
 * lockstep and predict clients, replays and crash recovery all hold the same one: it is saved
 * with the room (SimulationState.history, the sync payload's `history`), hashed with it (once any
 * player has history), and cleared when the world is replaced (a scene load, a reset, a scene
 * file opened). Only the commands a game records are undoable; `undo` and `redo` are the game's
 * commands (the sandbox's: games/sandbox/undo-commands.ts), which read and move these entries.
 *
 * An entry is one action: its kind (the command's), and what it changed as two lists of items,
 * `before` (the bodies and joints as they were, now gone) and `after` (as the action left them):
 *   spawn      before: nothing            after: the body
 *   delete     before: the body + joints  after: nothing
 *   a joint    before: nothing            after: the joint
 *   unjoint    before: the joint          after: nothing
 *   an edit    before: the body (old)     after: the body (new)
 * Undo removes the `after` items and rebuilds the `before` ones; redo the other way round. An item
 * holds its id and the body's or joint's saved definition (`def`, plain data the game writes and
 * reads: the sandbox uses the scene file's body and joint forms), a body its colour and a joint
 * its bodies (`a`, 0 for the world, and `b`) and maker.
 *
 * Ids are never reused, so a rebuilt body or joint has a new id: renameBody / renameJoint rewrite
 * every entry of every player (undo and redo lists) from the old id to the new one, so each entry
 * always names bodies and joints by their current ids, whoever rebuilt them. Entries are never
 * changed in place (a rename makes new objects), so a predicting client's copies may share them.
 *
 * Bounded: at most MAX_HISTORY entries per player in each list, the oldest dropped; a new action
 * clears that player's redo list; a player's history goes when the player leaves.
 */
import { continueHash, copyPlainData, hashPlainData, type PlainData } from './game.ts'

/** The most undoable actions kept per player (older ones are dropped): 32. */
export const MAX_HISTORY = 32

/** A body as an entry keeps it: its id, colour (0xRRGGBB or null) and saved definition. */
export interface HistoryBody {
  id: number
  color: number | null
  def: PlainData
}

/** A joint as an entry keeps it: its id, bodies (a = 0: the world), maker and saved definition. */
export interface HistoryJoint {
  id: number
  a: number
  b: number
  owner: number
  def: PlainData
}

/** The bodies and joints on one side of an action. */
export interface HistoryItems {
  bodies: HistoryBody[]
  joints: HistoryJoint[]
}

/** One undoable action (see the file comment). */
export interface HistoryEntry {
  kind: string
  before: HistoryItems
  after: HistoryItems
}

/** Which list: the actions to undo, or the undone ones to redo. */
export type HistoryList = 'undo' | 'redo'

/** One player's history as it is saved: undo and redo lists, oldest first (the last is the next). */
export interface SavedHistory {
  player: number
  undo: HistoryEntry[]
  redo: HistoryEntry[]
}

/** No items: one side of a spawn or a delete. */
export const NO_ITEMS: HistoryItems = Object.freeze({ bodies: [], joints: [] }) as HistoryItems

/** What a game sees of the histories (GameContext.history). */
export interface GameHistory {
  /** Record an action of `player` (see the file comment); clears its redo list, drops the oldest past MAX_HISTORY. */
  record(player: number, entry: HistoryEntry): void
  /** The entry `player` would undo or redo next, or undefined. */
  next(player: number, list: HistoryList): HistoryEntry | undefined
  /** Move `player`'s next entry from `list` to the other list (after undoing or redoing it). */
  move(player: number, list: HistoryList): void
  /** Drop `player`'s next entry from `list`. */
  drop(player: number, list: HistoryList): void
  /** Every player's history, ascending player ids (read only). */
  all(): readonly SavedHistory[]
  /** A rebuilt body: every entry that names `from` names `to` instead. */
  renameBody(from: number, to: number): void
  /** A rebuilt joint: every entry that names `from` names `to` instead. */
  renameJoint(from: number, to: number): void
}

const renameItems = (items: HistoryItems, body: (id: number) => number, joint: (id: number) => number) => ({
  bodies: items.bodies.map((b) => ({ ...b, id: body(b.id) })),
  joints: items.joints.map((j) => ({ ...j, id: joint(j.id), a: body(j.a), b: body(j.b) })),
})

const mentionsBody = (items: HistoryItems, id: number): boolean =>
  items.bodies.some((b) => b.id === id) || items.joints.some((j) => j.a === id || j.b === id)

/** The histories of a room's players (see the file comment). */
export class Histories implements GameHistory {
  private readonly byPlayer = new Map<number, { undo: HistoryEntry[]; redo: HistoryEntry[] }>()
  /** The hash of the saved form, or null when it must be computed again. */
  private digest: number | null = null

  record(player: number, entry: HistoryEntry): void {
    checkEntry(entry, 'history entry')
    const h = this.of(player)
    // A copy: the caller's objects are not kept, and anything that is not plain data is refused.
    h.undo.push(copyPlainData(entry, 'history entry') as unknown as HistoryEntry)
    if (h.undo.length > MAX_HISTORY) h.undo.shift()
    h.redo.length = 0
    this.digest = null
  }

  next(player: number, list: HistoryList): HistoryEntry | undefined {
    const l = this.byPlayer.get(player)?.[list]
    return l?.[l.length - 1]
  }

  move(player: number, list: HistoryList): void {
    const h = this.byPlayer.get(player)
    const entry = h?.[list].pop()
    if (!h || !entry) return
    const other = h[list === 'undo' ? 'redo' : 'undo']
    other.push(entry)
    if (other.length > MAX_HISTORY) other.shift()
    this.digest = null
  }

  drop(player: number, list: HistoryList): void {
    if (this.byPlayer.get(player)?.[list].pop()) this.digest = null
  }

  all(): readonly SavedHistory[] {
    return this.save()
  }

  renameBody(from: number, to: number): void {
    const body = (id: number) => (id === from ? to : id)
    this.rename(
      (items) => mentionsBody(items, from),
      (items) => renameItems(items, body, (id) => id),
    )
  }

  renameJoint(from: number, to: number): void {
    const joint = (id: number) => (id === from ? to : id)
    this.rename(
      (items) => items.joints.some((j) => j.id === from),
      (items) => renameItems(items, (id) => id, joint),
    )
  }

  /** Forget a player's history (it left the room). */
  forget(player: number): void {
    if (this.byPlayer.delete(player)) this.digest = null
  }

  /** Forget every history (the world was replaced). */
  clear(): void {
    if (this.byPlayer.size > 0) this.digest = null
    this.byPlayer.clear()
  }

  /** Whether no player has any history (then the room's hash leaves it out). */
  get empty(): boolean {
    for (const h of this.byPlayer.values()) if (h.undo.length > 0 || h.redo.length > 0) return false
    return true
  }

  /** The saved form: players with history in ascending ids, lists copied (entries are never changed in place). */
  save(): SavedHistory[] {
    const ids = [...this.byPlayer.keys()].sort((a, b) => a - b)
    const out: SavedHistory[] = []
    for (const player of ids) {
      const h = this.byPlayer.get(player) as { undo: HistoryEntry[]; redo: HistoryEntry[] }
      if (h.undo.length === 0 && h.redo.length === 0) continue
      out.push({ player, undo: [...h.undo], redo: [...h.redo] })
    }
    return out
  }

  /** Replace every history with a saved form (checked: checkSavedHistory). */
  restore(saved: readonly SavedHistory[]): void {
    this.byPlayer.clear()
    for (const h of saved) this.byPlayer.set(h.player, { undo: [...h.undo], redo: [...h.redo] })
    this.digest = null
  }

  /**
   * `hash` continued over the histories: FNV-1a of `hash` (u32), then of H as plain data, where H
   * is FNV-1a of the saved form (save()) as plain data; H is cached until the histories change.
   */
  mixInto(hash: number): number {
    if (this.digest === null) this.digest = hashPlainData(this.save() as unknown as PlainData)
    return continueHash(hash, this.digest)
  }

  private of(player: number) {
    let h = this.byPlayer.get(player)
    if (!h) {
      h = { undo: [], redo: [] }
      this.byPlayer.set(player, h)
    }
    return h
  }

  private rename(touches: (items: HistoryItems) => boolean, map: (items: HistoryItems) => HistoryItems) {
    for (const h of this.byPlayer.values()) {
      for (const list of [h.undo, h.redo]) {
        for (let i = 0; i < list.length; i++) {
          const e = list[i]
          if (!touches(e.before) && !touches(e.after)) continue
          list[i] = { kind: e.kind, before: map(e.before), after: map(e.after) }
          this.digest = null
        }
      }
    }
  }
}

const isId = (v: unknown): boolean => Number.isSafeInteger(v) && (v as number) >= 0
const isMap = (v: unknown): v is Record<string, unknown> =>
  typeof v === 'object' && v !== null && !Array.isArray(v)

function checkItems(v: unknown, where: string): void {
  if (!isMap(v) || !Array.isArray(v.bodies) || !Array.isArray(v.joints))
    throw new RangeError(`${where} must be a map with bodies and joints lists`)
  v.bodies.forEach((b, i) => {
    if (!isMap(b) || !isId(b.id) || !(b.color === null || isId(b.color)) || b.def === undefined)
      throw new RangeError(`${where}.bodies[${i}] must be {id, color (integer or nil), def}`)
  })
  v.joints.forEach((j, i) => {
    if (!isMap(j) || !isId(j.id) || !isId(j.a) || !isId(j.b) || !isId(j.owner) || j.def === undefined)
      throw new RangeError(`${where}.joints[${i}] must be {id, a, b, owner, def}`)
  })
}

function checkEntry(v: unknown, where: string): void {
  if (!isMap(v) || typeof v.kind !== 'string')
    throw new RangeError(`${where} must be a map {kind, before, after} with a string kind`)
  checkItems(v.before, `${where}.before`)
  checkItems(v.after, `${where}.after`)
}

/**
 * Check a decoded saved history (a sync payload's, a replay keyframe's): null, or what is wrong,
 * naming the place. Definitions are plain data and are not checked here (the game reads them).
 */
export function checkSavedHistory(v: unknown): string | null {
  if (!Array.isArray(v)) return 'history must be a list'
  try {
    v.forEach((h, i) => {
      if (!isMap(h) || !isId(h.player) || !Array.isArray(h.undo) || !Array.isArray(h.redo))
        throw new RangeError(`history[${i}] must be {player, undo, redo}`)
      if (h.undo.length > MAX_HISTORY || h.redo.length > MAX_HISTORY)
        throw new RangeError(`history[${i}] holds more than ${MAX_HISTORY} entries in a list`)
      for (const list of ['undo', 'redo'] as const) {
        const entries = h[list] as unknown[]
        for (let k = 0; k < entries.length; k++) checkEntry(entries[k], `history[${i}].${list}[${k}]`)
      }
    })
  } catch (e) {
    return (e as Error).message
  }
  return null
}
