/*
 * The payload of a lockstep `sync`: everything a client needs to continue a room's simulation
 * bit for bit from a tick. The engine's saved world (world.save(): bodies, contacts with their
 * warm-start impulses, joints, sleep timers, id counters) plus the room state that RoomSimulation
 * keeps around it: the room tick, scene name, pause and single-step flags, the scene-load rate
 * limit, each player's grab (mouse joint and body) and cursor, the user joints, and the game's
 * name, state (plain data, nil for a game without state) and PRNG position. Grab counts are not
 * sent: they are the number of players grabbing each body.
 *
 * One MessagePack map (PROTOCOL.md, `sync`), deflated by the server when that pays. Restoring
 * never throws: a payload that does not decode, or a world that does not load, comes back as a
 * reason and the client asks again.
 */
import { loadWorld } from '../../engine/index.ts'
import { decodeValue, encodeValue, type WireJoint } from '../protocol/index.ts'
import { copyPlainData, type GameCatalog, type PlainData } from './game.ts'
import { checkSavedHistory, type SavedHistory } from './history.ts'
import { RoomSimulation, type SimulationListener } from './room-simulation.ts'

/** The decoded payload. */
export interface SyncPayload {
  /** Room tick the state is at (ticks completed). */
  tick: number
  scene: string
  paused: boolean
  step: boolean
  /** Slow motion (the world steps on room ticks that are multiples of it: 1, 2 or 4); absent: 1. */
  slow?: number
  /** The room's creator (first player to join, 0 before) and whether it locked the controls; absent: 0, false. */
  creator?: number
  locked?: boolean
  /** Room tick of the last scene load or reset, or null for never. */
  lastLoad: number | null
  /** Flat [player id, grab joint or 0, grabbed body or 0, cursor x, cursor y, ...] in join order. */
  players: number[]
  joints: WireJoint[]
  /** world.save() bytes. */
  world: Uint8Array
  /** The game's name, its state (nil for a game without state) and its PRNG position. */
  game: string
  state: PlainData
  random: number
  /** Body colours, flat [body id, 0xRRGGBB, ...] in ascending ids. */
  colors: number[]
  /** The players' undo and redo histories (history.ts), players with history only; absent: none. */
  history?: SavedHistory[]
}

/** The payload of a room simulation as MessagePack bytes (not yet compressed). */
export function encodeSyncPayload(sim: RoomSimulation): Uint8Array {
  const players: number[] = []
  for (const [id, p] of sim.players) {
    players.push(id, p.grab?.joint ?? 0, p.grab?.body ?? 0, p.cursorX, p.cursorY)
  }
  const payload: SyncPayload = {
    tick: sim.tick,
    scene: sim.scene,
    paused: sim.paused,
    step: sim.stepRequested,
    slow: sim.slowMotion,
    creator: sim.creator,
    locked: sim.controlsLocked,
    lastLoad: Number.isFinite(sim.lastLoadTick) ? sim.lastLoadTick : null,
    players,
    joints: [...sim.userJoints.values()],
    world: sim.world.save(),
    game: sim.game.name,
    state: sim.gameState ?? null,
    random: sim.random.position(),
    colors: sim.colorList(),
  }
  const history = sim.history.save()
  if (history.length > 0) payload.history = history
  return encodeValue(payload)
}

/** A restored simulation, or why the payload was refused. */
export type RestoreResult = { ok: true; sim: RoomSimulation } | { ok: false; reason: string }

/** Rules a restored simulation needs besides the payload (from the welcome's RoomRules), and where to find its game. */
export interface RestoreOptions {
  maxBodies: number
  controls: boolean
  name: string
  listener?: SimulationListener
  /** The games this build knows (games/'s findGame). */
  games: GameCatalog
}

const isInt = (v: unknown): v is number => Number.isSafeInteger(v)
const isNum = (v: unknown): v is number => typeof v === 'number' && Number.isFinite(v)

/** Rebuild a RoomSimulation from payload bytes (decompressed); never throws. */
export function restoreSyncPayload(bytes: Uint8Array, options: RestoreOptions): RestoreResult {
  const decoded = decodeValue(bytes)
  if (!decoded.ok) return { ok: false, reason: `sync payload: ${decoded.reason}` }
  const p = decoded.value as Partial<SyncPayload> | null
  if (typeof p !== 'object' || p === null) return { ok: false, reason: 'sync payload must be a map' }
  if (
    !isInt(p.tick) ||
    typeof p.scene !== 'string' ||
    typeof p.paused !== 'boolean' ||
    typeof p.step !== 'boolean'
  )
    return { ok: false, reason: 'sync payload lacks tick, scene, paused or step' }
  if (!(p.world instanceof Uint8Array)) return { ok: false, reason: 'sync payload world must be binary' }
  if (!Array.isArray(p.players) || p.players.length % 5 !== 0 || !p.players.every(isNum))
    return { ok: false, reason: 'sync payload players must be a flat list of 5 numbers each' }
  if (!Array.isArray(p.joints)) return { ok: false, reason: 'sync payload joints must be a list' }
  if (p.slow !== undefined && p.slow !== 1 && p.slow !== 2 && p.slow !== 4)
    return { ok: false, reason: 'sync payload slow must be 1, 2 or 4' }
  if (
    (p.creator !== undefined && (!isInt(p.creator) || p.creator < 0)) ||
    (p.locked !== undefined && typeof p.locked !== 'boolean')
  )
    return { ok: false, reason: 'sync payload creator must be a non-negative integer and locked a boolean' }
  if (p.lastLoad !== null && !isInt(p.lastLoad))
    return { ok: false, reason: 'sync payload lastLoad must be an integer or nil' }
  if (typeof p.game !== 'string' || !isInt(p.random) || p.random < 0 || p.random > 0xffffffff)
    return { ok: false, reason: 'sync payload lacks game or random' }
  if (
    p.colors !== undefined &&
    (!Array.isArray(p.colors) || p.colors.length % 2 !== 0 || !p.colors.every(isInt))
  )
    return { ok: false, reason: 'sync payload colors must be a flat list of [body id, colour] integers' }
  const badHistory = p.history === undefined ? null : checkSavedHistory(p.history)
  if (badHistory !== null) return { ok: false, reason: `sync payload: ${badHistory}` }
  const game = options.games(p.game)
  if (!game) return { ok: false, reason: `sync payload: game ${p.game} is not in this build` }
  let sim: RoomSimulation
  try {
    sim = new RoomSimulation({ ...options, game, scene: 'empty' })
    sim.world = loadWorld(p.world)
    sim.restoreGame(copyPlainData(p.state ?? null), p.random)
  } catch (error) {
    return { ok: false, reason: `sync payload: ${(error as Error).message}` }
  }
  sim.tick = p.tick
  sim.scene = p.scene
  sim.paused = p.paused
  sim.stepRequested = p.step
  sim.slowMotion = p.slow ?? 1
  sim.creator = p.creator ?? 0
  sim.controlsLocked = p.locked ?? false
  sim.lastLoadTick = p.lastLoad ?? Number.NEGATIVE_INFINITY
  sim.setColors(p.colors ?? [])
  sim.history.restore(p.history ?? [])
  for (let i = 0; i < p.players.length; i += 5) {
    const [id, joint, body, cursorX, cursorY] = p.players.slice(i, i + 5)
    sim.restorePlayer(id, { grab: joint === 0 ? null : { joint, body }, cursorX, cursorY })
    if (joint !== 0) sim.grabCounts.set(body, (sim.grabCounts.get(body) ?? 0) + 1)
  }
  for (const j of p.joints) {
    if (typeof j !== 'object' || j === null || !isInt((j as WireJoint).id))
      return { ok: false, reason: 'sync payload joint must be a map with an integer id' }
    sim.userJoints.set(j.id, j)
  }
  return { ok: true, sim }
}

/** Inflate zlib (RFC 1950) bytes with the platform's DecompressionStream (browsers and Node 18+). */
export async function inflate(bytes: Uint8Array): Promise<Uint8Array> {
  const stream = new Blob([bytes as Uint8Array<ArrayBuffer>])
    .stream()
    .pipeThrough(new DecompressionStream('deflate'))
  return new Uint8Array(await new Response(stream).arrayBuffer())
}

/**
 * An independent copy of a simulation (the world through save/load, the room state copied), for
 * a predicting client's present state; it steps bit-identically to the original.
 */
export function cloneSimulation(sim: RoomSimulation, options: Omit<RestoreOptions, 'games'>): RoomSimulation {
  const copy = new RoomSimulation({ ...options, game: sim.game, scene: 'empty' })
  copy.world = loadWorld(sim.world.save())
  copy.restoreGame(sim.gameState ?? null, sim.random.position())
  copy.tick = sim.tick
  copy.scene = sim.scene
  copy.paused = sim.paused
  copy.stepRequested = sim.stepRequested
  copy.slowMotion = sim.slowMotion
  copy.creator = sim.creator
  copy.controlsLocked = sim.controlsLocked
  copy.lastLoadTick = sim.lastLoadTick
  for (const [id, p] of sim.players)
    copy.restorePlayer(id, { grab: p.grab && { ...p.grab }, cursorX: p.cursorX, cursorY: p.cursorY })
  for (const [id, j] of sim.userJoints) copy.userJoints.set(id, j)
  for (const [id, n] of sim.grabCounts) copy.grabCounts.set(id, n)
  for (const [id, c] of sim.bodyColors) copy.bodyColors.set(id, c)
  copy.history.restore(sim.history.save())
  copy.bodyEdits = sim.bodyEdits
  return copy
}
