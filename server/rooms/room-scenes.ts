/*
 * Scene files in a room (docs/scene-format.md): the room commands `openScene` and `saveScene`,
 * which every room accepts as `cmd` messages besides its game's commands (PROTOCOL.md, `cmd`).
 * They are the room's, not the game's, because a game's commands run in every replica and a
 * scene file lives on the server: opening one replaces the world from outside a command
 * (RoomSimulation.loadWorld), which the recorder writes as a saved world and which sends every
 * lockstep and predict player a fresh sync, so replays and replicas get the very world the server
 * built. Saving writes the world into the scene directory and tells the sender the id.
 */
import { MIN_TICKS_BETWEEN_LOADS, saveRoomScene, sceneForRoom, sceneText } from '../../games/index.ts'
import type { PlainData, RoomSimulation } from '../../shared/index.ts'
import { SCENE_ID, SceneStore } from '../scenes/index.ts'

/** The room command kinds (`cmd` kinds every room accepts). */
export const ROOM_COMMANDS = ['openScene', 'saveScene'] as const

/** Ticks between two saves of one room's world (a save writes up to 4 MiB to disk). */
export const MIN_TICKS_BETWEEN_SAVES = 60

/** Whether a `cmd` kind is a room command. */
export function isRoomCommand(kind: string): boolean {
  return kind === 'openScene' || kind === 'saveScene'
}

/** Why a room command's arguments are refused (naming the field), or null. */
export function roomCommandArgs(kind: string, args: PlainData): string | null {
  const a = args as Record<string, PlainData>
  const keys = Object.keys(a)
  if (kind === 'saveScene') return keys.length === 0 ? null : `${keys[0]} is not allowed`
  for (const key of keys) if (key !== 'id') return `${key} is not allowed`
  if (typeof a.id !== 'string') return 'id is required (a saved scene id: 16 hex digits)'
  return SCENE_ID.test(a.id) ? null : 'id must be a saved scene id (16 hex digits)'
}

/** A room's scene files: its store and the time of its last save. */
export class RoomScenes {
  private readonly store: SceneStore
  private lastSaveTick = Number.NEGATIVE_INFINITY

  constructor(
    dir: string,
    maxScenes: number,
    maxBytes: number,
    private readonly sim: RoomSimulation,
  ) {
    this.store = new SceneStore(dir, maxScenes, maxBytes)
  }

  /** Open saved scene `id` in the room (a room control); null, or why not. */
  open(id: string, controls: boolean, hasScenes: boolean): string | null {
    const sim = this.sim
    if (!hasScenes) return `game ${sim.game.name} does not open scene files`
    if (!controls) return `room controls are disabled in room ${sim.name}`
    if (sim.tick - sim.lastLoadTick < MIN_TICKS_BETWEEN_LOADS)
      return 'scene loads are limited to 6 per second'
    const stored = this.store.read(id)
    if (!stored.ok) return stored.error
    if (stored.scene.bodies.length > sim.maxBodies)
      return `scene ${id} has ${stored.scene.bodies.length} bodies; this room holds at most ${sim.maxBodies}`
    const built = sceneForRoom(stored.scene)
    if (!built.ok) return `saved scene ${id} no longer opens: ${built.error}`
    sim.loadWorld(`file:${id}`, built.world, built.joints, built.colors)
    return null
  }

  /** Save the room's world as a scene file: its id, or why not. */
  save(roomName: string): { id: string } | { error: string } {
    const sim = this.sim
    if (sim.tick - this.lastSaveTick < MIN_TICKS_BETWEEN_SAVES)
      return { error: 'scene saves are limited to one per second per room' }
    const text = sceneText(saveRoomScene(sim, roomName))
    let stored: ReturnType<SceneStore['save']>
    try {
      stored = this.store.save(text, false)
    } catch (e) {
      // A directory that cannot be made or written (EACCES, ENOSPC): refuse, never fail the tick.
      return { error: `the scene could not be written on the server: ${(e as Error).message}` }
    }
    if (!stored.ok) return { error: stored.error }
    this.lastSaveTick = sim.tick
    return { id: stored.id }
  }
}
