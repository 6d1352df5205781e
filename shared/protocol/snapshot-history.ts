/*
 * The client's side of snapshot delta compression: its states at recent snapshot ticks, so that it
 * holds whatever baseline the server writes the next snapshot against. The server's baseline tick
 * never decreases, so states older than the newest baseline seen can be dropped; what remains is
 * a handful of frames (one round trip's worth of snapshots).
 */
import { QuantizedFrame } from './quantized-frame.ts'
import { readUpdates } from './snapshot-codec.ts'

/** Most states held; only a client that stops acknowledging reaches it. */
const MAX_STATES = 256

/** The result of applying one snapshot. */
export interface AppliedSnapshot {
  tick: number
  /** The full quantized state at `tick` (owned by the history; copy it to keep it). */
  frame: QuantizedFrame
  /** Ids written by this snapshot, ascending. */
  updated: number[]
}

/** Recent client states keyed by tick; decodes snapshots against them. */
export class SnapshotHistory {
  private readonly states = new Map<number, QuantizedFrame>()
  private spare: QuantizedFrame[] = []
  /** Tick of the newest state. */
  latestTick = -1

  /** Forget everything and start from a full state (welcome or state message). */
  reset(frame: QuantizedFrame, tick: number): void {
    for (const f of this.states.values()) this.spare.push(f)
    this.states.clear()
    const copy = this.take()
    copy.copyFrom(frame)
    this.states.set(tick, copy)
    this.latestTick = tick
  }

  private take(): QuantizedFrame {
    return this.spare.pop() ?? new QuantizedFrame()
  }

  /** The state at `tick`, if held. */
  get(tick: number): QuantizedFrame | undefined {
    return this.states.get(tick)
  }

  /**
   * Decode a snapshot at `tick` written against `base`. Returns null when the baseline is not held
   * or the snapshot is older than the newest state (do not ack those). Throws on corrupt data.
   */
  apply(tick: number, base: number, data: Uint8Array): AppliedSnapshot | null {
    const baseline = this.states.get(base)
    if (!baseline || tick <= this.latestTick) return null
    const frame = this.take()
    let updated: number[]
    try {
      updated = readUpdates(data, baseline, frame)
    } catch (error) {
      this.spare.push(frame)
      throw error
    }
    this.states.set(tick, frame)
    this.latestTick = tick
    for (const [t, f] of this.states) {
      // Drop what the server can no longer use; cap what a client that never acks would hoard.
      if (t < base || (this.states.size > MAX_STATES && t !== base)) {
        this.states.delete(t)
        this.spare.push(f)
      }
    }
    return { tick, frame, updated }
  }

  /** A body was destroyed: drop it from every held state. */
  removeBody(id: number): void {
    for (const f of this.states.values()) f.remove(id)
  }

  /** Number of held states (bounded by a round trip of snapshots). */
  get size(): number {
    return this.states.size
  }
}
