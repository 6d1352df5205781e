/*
 * Replaying a log through a RoomSimulation: the header's keyframe starts the simulation, then
 * every record is applied at its tick (the simulation runs its ticks up to the record's tick
 * first). Hash records are checked against the replayed world; with `verify`, keyframes are
 * checked too (their world and state must equal the replayed ones), so a seek through a keyframe
 * lands exactly where playing through would. The first divergence is kept, replay goes on.
 *
 * Pure and browser-safe. Saved worlds may be deflated; the caller injects `inflate` (Node's zlib on
 * the server, DecompressionStream('deflate') in a browser). A keyframe stored as a delta (z = 2)
 * is decoded against the previous keyframe's (or the header's) saved world: the runner keeps the
 * last one it passed, and a seek restores a chain from a whole keyframe (deltaChain).
 */
import { loadWorld, SAVE_FORMAT_VERSION, type World } from '../../engine/index.ts'
import { PROTOCOL_VERSION, TICK_RATE } from '../protocol/index.ts'
import {
  type GameCatalog,
  RoomSimulation,
  type SimulationListener,
  type SimulationState,
} from '../sim/index.ts'
import { decodeByteDelta } from './byte-delta.ts'
import { type Preamble, REPLAY_FORMAT_VERSION, type ReplayRecord, type StoredWorld } from './replay-log.ts'

/** Inflate a zlib stream (RFC 1950). */
export type Inflate = (bytes: Uint8Array) => Uint8Array | Promise<Uint8Array>

/** The header record. */
export type HeaderRecord = Extract<ReplayRecord, { type: 'header' }>
/** A keyframe record. */
export type KeyframeRecord = Extract<ReplayRecord, { type: 'keyframe' }>

/**
 * A runner's position taken while replaying, to resume from later (the replay player's own
 * snapshots): the simulation's state and saved world, and the saved world a delta keyframe met
 * after it decodes against (the last header or keyframe passed; shared, never written to).
 */
export interface RunnerSnapshot {
  state: SimulationState
  world: Uint8Array
  base: Uint8Array | null
}

/** The first place a replay differs from its log. */
export interface Divergence {
  tick: number
  /** What differed, e.g. "hash 0x1234abcd, log 0x9876fedc". */
  reason: string
  /** The replayed and recorded hashes, when a hash differed. */
  actual?: number
  expected?: number
}

/** Why a log cannot be replayed by this build (wrong versions); null when it can. */
export function incompatibility(preamble: Preamble): string | null {
  if (preamble.format < REPLAY_FORMAT_VERSION)
    return `log written with replay format version ${preamble.format}; this build replays version ${REPLAY_FORMAT_VERSION} (room hashes cover the players' undo histories since version 3)`
  if (preamble.engine !== SAVE_FORMAT_VERSION)
    return `log written with engine save-format version ${preamble.engine}; this build reads version ${SAVE_FORMAT_VERSION}`
  if (preamble.protocol !== PROTOCOL_VERSION)
    return `log written with protocol version ${preamble.protocol}; this build speaks version ${PROTOCOL_VERSION}`
  if (preamble.tickRate !== TICK_RATE)
    return `log written at ${preamble.tickRate} ticks per second; this build runs at ${TICK_RATE}`
  return null
}

/** JSON with map keys sorted, so equal states compare equal whatever order their fields were built in. */
function canonical(value: unknown): string {
  return JSON.stringify(value, (_key, v: unknown) =>
    v && typeof v === 'object' && !Array.isArray(v)
      ? Object.fromEntries(
          Object.entries(v as Record<string, unknown>).sort(([x], [y]) => (x < y ? -1 : x > y ? 1 : 0)),
        )
      : v,
  )
}

/**
 * The keyframes to decode to restore `list[i]`: from the newest whole one (z 0 or 1; the header is
 * always whole) at or before i, through the deltas, to i. `list` is the header and keyframes in
 * log order.
 */
export function deltaChain<T extends StoredWorld>(list: readonly T[], i: number): T[] {
  let from = i
  while (from > 0 && list[from].z === 2) from--
  return list.slice(from, i + 1)
}

/** Hex form of a 32-bit hash. */
export const hex = (h: number): string => `0x${h.toString(16).padStart(8, '0')}`

/** Replays records into a RoomSimulation (see the file comment). */
export class ReplayRunner {
  readonly sim: RoomSimulation
  /** The first divergence from the log, or null while everything matched. */
  divergence: Divergence | null = null
  /** Hash records checked, and keyframes checked (with verify). */
  hashesChecked = 0
  keyframesChecked = 0
  /** World steps and commands replayed. */
  steps = 0
  commands = 0
  /** Called after every replayed tick (the simulation's tick is the new room tick). */
  onTick: ((sim: RoomSimulation) => void) | null = null
  /** Saved world of the last header or keyframe passed (a delta keyframe's base). */
  private base: Uint8Array | null = null

  private constructor(
    readonly header: HeaderRecord,
    private readonly inflate: Inflate,
    private readonly verify: boolean,
    games: GameCatalog,
    listener?: SimulationListener,
  ) {
    const game = games(header.state.game)
    if (!game) throw new RangeError(`the log's game ${header.state.game} is not in this build`)
    this.sim = new RoomSimulation({
      game,
      name: header.room,
      scene: 'empty',
      maxBodies: header.maxBodies,
      controls: header.controls,
      listener,
    })
  }

  /** A runner at the header's state. Throws a RangeError for a log this build cannot replay. */
  static async start(
    preamble: Preamble,
    header: HeaderRecord,
    options: { inflate: Inflate; games: GameCatalog; verify?: boolean; listener?: SimulationListener },
  ): Promise<ReplayRunner> {
    const problem = incompatibility(preamble)
    if (problem) throw new RangeError(problem)
    const runner = new ReplayRunner(
      header,
      options.inflate,
      options.verify ?? false,
      options.games,
      options.listener,
    )
    await runner.restore([header])
    return runner
  }

  /** A stored world's World.save() bytes: inflated, and a delta decoded against `base`. */
  async savedBytes(stored: StoredWorld, base: Uint8Array | null): Promise<Uint8Array> {
    if (stored.z === 0) return stored.world
    const inflated = await this.inflate(stored.world)
    if (stored.z === 1) return inflated
    if (!base) throw new RangeError('a delta keyframe with no keyframe before it')
    return decodeByteDelta(base, inflated)
  }

  /** Load a stored world (inflating it if needed; not a delta). */
  async world(stored: StoredWorld): Promise<World> {
    return loadWorld(await this.savedBytes(stored, null))
  }

  /** Run ticks until the room tick is `tick`. */
  advanceTo(tick: number): void {
    while (this.sim.tick < tick) {
      const before = this.sim.world.tick
      this.sim.runTick()
      this.steps += this.sim.world.tick - before
      this.onTick?.(this.sim)
    }
  }

  /** Apply one record (after the header) at its tick. */
  async apply(r: ReplayRecord): Promise<void> {
    if (r.type === 'header') throw new RangeError('a header can only start a replay')
    this.advanceTo(r.tick)
    switch (r.type) {
      case 'command': {
        this.commands++
        const refused = this.sim.applyAccepted(r.player, r.cmd)
        if (refused)
          this.diverged({ tick: r.tick, reason: `recorded ${r.cmd.k} refused in replay: ${refused}` })
        return
      }
      case 'join':
        this.sim.join(r.player, r.name, r.color)
        return
      case 'leave':
        this.sim.leave(r.player)
        return
      case 'world':
        this.sim.loadWorld(r.scene, await this.world(r), r.joints ?? [], r.colors ?? [])
        return
      case 'hash': {
        this.hashesChecked++
        const actual = this.sim.hash()
        if (actual !== r.hash)
          this.diverged({
            tick: r.tick,
            reason: `hash ${hex(actual)}, log ${hex(r.hash)}`,
            actual,
            expected: r.hash,
          })
        else if (this.sim.world.tick !== r.step)
          this.diverged({ tick: r.tick, reason: `world step ${this.sim.world.tick}, log ${r.step}` })
        return
      }
      case 'keyframe': {
        const bytes = await this.savedBytes(r, this.base)
        this.base = bytes
        if (this.verify) this.checkKeyframe(r, loadWorld(bytes))
        return
      }
      case 'close':
        return
    }
  }

  /**
   * Jump to the last keyframe of `chain` (for seeking; see deltaChain): afterwards the simulation
   * is exactly the recorded one.
   */
  async restore(chain: ReadonlyArray<KeyframeRecord | HeaderRecord>): Promise<void> {
    let bytes: Uint8Array | null = null
    for (const k of chain) bytes = await this.savedBytes(k, bytes)
    const last = chain[chain.length - 1]
    if (!bytes || !last) throw new RangeError('restore needs at least one keyframe')
    this.base = bytes
    this.sim.restoreState(last.state, loadWorld(bytes))
  }

  /** The runner as of now (see RunnerSnapshot); costs a world.save(). */
  save(): RunnerSnapshot {
    return { state: this.sim.saveState(), world: this.sim.world.save(), base: this.base }
  }

  /** Go back (or on) to a snapshot from save(): afterwards the simulation is exactly the saved one. */
  resume(snapshot: RunnerSnapshot): void {
    this.base = snapshot.base
    this.sim.restoreState(snapshot.state, loadWorld(snapshot.world))
  }

  private checkKeyframe(k: KeyframeRecord, world: World): void {
    this.keyframesChecked++
    const actual = this.sim.world.hash()
    const expected = world.hash()
    if (actual !== expected) {
      this.diverged({
        tick: k.tick,
        reason: `keyframe hash ${hex(expected)}, replayed ${hex(actual)}`,
        actual,
        expected,
      })
      return
    }
    const a = canonical(this.sim.saveState())
    const b = canonical(k.state)
    if (a !== b) this.diverged({ tick: k.tick, reason: 'keyframe room state differs from the replayed one' })
  }

  private diverged(d: Divergence): void {
    if (!this.divergence) this.divergence = d
  }
}
