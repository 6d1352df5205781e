/*
 * Spawns the player clicked, followed until the server answers for them, so that none is lost.
 * The page paces its inputs within the room's per-tick budget, but a server that stalls (a loaded
 * machine) reads the inputs of several frames in one tick and drops the excess, answering each
 * dropped input with an `input-budget` error carrying its `seq`. Each spawn sent is kept until an
 * `events` message adds the body it created (the add carries the spawner's player id and seq), or
 * the server refuses it for good (another error with its seq, e.g. a full room); a spawn dropped
 * over the budget is handed back to be sent again, at most MAX_SENDS times in all.
 */
import type { SpawnCommand, WireBody } from '../../shared/index.ts'

/**
 * How often one spawn is sent at most. A drop over the budget is a moment's congestion (the page
 * paces its inputs below the budget), so a spawn is worth several tries; a full CI run on a
 * loaded machine once lost one after three.
 */
export const MAX_SENDS = 8
/** Spawns followed at most (the oldest are forgotten beyond this). */
const MAX_PENDING = 256

/** The spawns sent and not yet answered for. */
export class SpawnTracker {
  private readonly pending = new Map<number, SpawnCommand>()
  private readonly sends = new WeakMap<SpawnCommand, number>()

  /** How many spawns are waiting for an answer. */
  get size(): number {
    return this.pending.size
  }

  /** A spawn went out with `seq` (again, if it is a spawn handed back by dropped()). */
  sent(seq: number, cmd: SpawnCommand): void {
    this.pending.set(seq, cmd)
    this.sends.set(cmd, (this.sends.get(cmd) ?? 0) + 1)
    if (this.pending.size > MAX_PENDING) this.pending.delete(this.pending.keys().next().value as number)
  }

  /** A body was added: if this player (`playerId`) spawned it, its spawn is answered. */
  added(body: WireBody, playerId: number): void {
    if (body.player === playerId && body.seq !== undefined) this.pending.delete(body.seq)
  }

  /** The server refused input `seq` for good: forget it if it was a spawn. */
  refused(seq: number): void {
    this.pending.delete(seq)
  }

  /** Whether input `seq` is a spawn waiting for an answer. */
  has(seq: number): boolean {
    return this.pending.has(seq)
  }

  /** The server dropped input `seq` over the budget: the spawn to send again, or null. */
  dropped(seq: number): SpawnCommand | null {
    const cmd = this.pending.get(seq)
    if (!cmd) return null
    this.pending.delete(seq)
    return (this.sends.get(cmd) ?? 0) < MAX_SENDS ? cmd : null
  }

  /** A new world or session: spawns sent into the old one are gone with it. */
  clear(): void {
    this.pending.clear()
  }
}
