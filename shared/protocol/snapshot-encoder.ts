/*
 * One client's side of snapshot delta compression, kept by the server.
 *
 * `reference` is the client's state at the last snapshot it acknowledged (or at its welcome), the
 * baseline the next snapshot is written against. Sent snapshots are remembered (tick -> baseline
 * tick and the updates) so that an ack can advance the reference exactly as the client did: an ack
 * whose snapshot was written against the current reference moves the reference to that snapshot;
 * any other ack is ignored. The client keeps every state newer than the last baseline it saw, so
 * it always holds the baseline the server picks (snapshot-history.ts).
 *
 * Bodies that differ from the reference are candidates. When they fit the byte budget all are
 * sent; otherwise each candidate's priority grows every snapshot (faster when awake or important,
 * e.g. grabbed) and the highest-priority bodies that fit are sent and reset to zero (Fiedler,
 * "State Synchronization"), so every body is refreshed eventually and bandwidth stays bounded.
 *
 * Clients of one room usually acknowledge the same snapshots, so their references are equal. An
 * encode that fitted the budget depends only on the frame and the reference, so another client
 * with an equal reference can take it over (`follow`): the same update bytes, and the same
 * bookkeeping as its own encode would have done, without writing anything again.
 */
import type { ByteWriter } from './byte-io.ts'
import { FRAME_AWAKE, QuantizedFrame } from './quantized-frame.ts'
import { updateSize, writeUpdates } from './snapshot-codec.ts'

/** Distinct priority levels told apart when choosing; higher ones count as the top level. */
const PRIORITY_BUCKETS = 4096

/** Sent snapshots remembered per client, waiting for acks. */
const MAX_PENDING = 64

/** An empty update list (the placeholder of a free pending slot). */
const NO_UPDATES: Int32Array = new Int32Array(0)

/** What one encode did. */
export interface EncodeStats {
  /** Bodies that differed from the client's baseline. */
  candidates: number
  /** Bodies written. */
  sent: number
  /** Longest wait (ticks) of a body written this time since it was last written or became dirty. */
  maxStaleness: number
}

/** Server-side delta state for one client: its reference frame, pending snapshots, priorities. */
export class SnapshotEncoder {
  /** The client's acknowledged state. */
  readonly reference = new QuantizedFrame()
  /** Tick of the reference (the baseline of the next snapshot). */
  referenceTick = 0
  /**
   * Sent snapshots waiting for an ack, oldest first: tick, baseline tick and the flat
   * [id, x, y, a, flags] updates of each, in parallel arrays (a Map here allocated on every
   * delete; the encoder runs 20 times a second per client).
   */
  private readonly pendingTicks = new Int32Array(MAX_PENDING + 1)
  private readonly pendingBases = new Int32Array(MAX_PENDING + 1)
  private readonly pendingUpdates: Int32Array[] = new Array(MAX_PENDING + 1).fill(NO_UPDATES)
  private pendingSize = 0
  private priority = new Float64Array(64)
  private waitingSince = new Int32Array(64).fill(-1)
  private candidates = new Int32Array(64)
  private sizes = new Int32Array(64)
  private readonly histogram = new Int32Array(PRIORITY_BUCKETS)
  private chosen = new Int32Array(64)
  /** The last encode: its tick, whether every candidate fitted, its updates and stats. */
  private readonly last: {
    tick: number
    complete: boolean
    updates: Int32Array
    candidates: number
    bytes: number
  } = {
    tick: -1,
    complete: false,
    updates: NO_UPDATES,
    candidates: 0,
    bytes: 0,
  }

  /** Start over from a full state the client received (welcome or state message). */
  reset(frame: QuantizedFrame, tick: number): void {
    this.reference.copyFrom(frame)
    this.referenceTick = tick
    this.removePending(0, this.pendingSize)
    this.priority.fill(0)
    this.waitingSince.fill(-1)
  }

  private grow(capacity: number, count: number): void {
    if (this.priority.length < capacity) {
      const p = new Float64Array(capacity)
      p.set(this.priority)
      this.priority = p
      const w = new Int32Array(capacity).fill(-1)
      w.set(this.waitingSince)
      this.waitingSince = w
    }
    if (this.candidates.length < count) {
      this.candidates = new Int32Array(count)
      this.sizes = new Int32Array(count)
      this.chosen = new Int32Array(count)
    }
  }

  /**
   * Write the snapshot of `frame` at `tick` into `out` within `budget` bytes of updates.
   * `weight(id)` is the extra priority of a body: 0 for ordinary ones, more for
   * grabbed ones.
   */
  encode(
    out: ByteWriter,
    frame: QuantizedFrame,
    tick: number,
    budget: number,
    weight?: (id: number) => number,
  ): EncodeStats {
    this.grow(frame.capacity, frame.count)
    const ref = this.reference
    let n = 0
    let bytes = 0
    for (let i = 0; i < frame.count; i++) {
      const id = frame.ids[i]
      if (frame.sameAs(ref, id)) {
        this.waitingSince[id] = -1
        this.priority[id] = 0
        continue
      }
      if (this.waitingSince[id] < 0) this.waitingSince[id] = tick
      const awake = (frame.flags[id] & FRAME_AWAKE) !== 0
      this.priority[id] += 1 + (awake ? 1 : 0) + (ref.has(id) ? 0 : 4) + (weight ? weight(id) : 0)
      const size = updateSize(frame, ref, id)
      this.candidates[n] = id
      this.sizes[n] = size
      n++
      bytes += size
    }
    let count = n
    let ids = this.candidates
    if (bytes > budget) {
      count = this.choose(n, budget)
      ids = this.chosen
    }
    let maxStaleness = 0
    const updates = new Int32Array(count * 5)
    for (let i = 0; i < count; i++) {
      const id = ids[i]
      maxStaleness = Math.max(maxStaleness, tick - this.waitingSince[id])
      this.waitingSince[id] = tick
      this.priority[id] = 0
      const k = i * 5
      updates[k] = id
      updates[k + 1] = frame.x[id]
      updates[k + 2] = frame.y[id]
      updates[k + 3] = frame.a[id]
      updates[k + 4] = frame.flags[id]
    }
    writeUpdates(out, frame, ref, ids, count)
    this.remember(tick, updates)
    this.setLast(tick, count === n, updates, n, bytes)
    return { candidates: n, sent: count, maxStaleness }
  }

  /**
   * Take over `leader`'s encode of `frame` at `tick` when it applies to this client too: the
   * leader encoded this tick, every candidate fitted its budget and fits `budget` (this client's),
   * and both references are equal (same tick and same poses). Then this client's encode would
   * write the same bytes (the caller sends the leader's message), and this does that encode's
   * bookkeeping: pending snapshot, priorities and waiting times. Returns the stats, or null when
   * the encode does not apply (then call encode).
   */
  follow(leader: SnapshotEncoder, frame: QuantizedFrame, tick: number, budget: number): EncodeStats | null {
    const last = leader.last
    if (last.tick !== tick || !last.complete || last.bytes > budget) return null
    if (leader.referenceTick !== this.referenceTick || !this.reference.equals(leader.reference)) return null
    this.grow(frame.capacity, frame.count)
    // The leader's updates are exactly the bodies that differ from this reference (it is equal to
    // the leader's), and all were sent: they wait from now; every other body is not waiting.
    const u = last.updates
    let maxStaleness = 0
    for (let k = 0; k < u.length; k += 5) {
      const since = this.waitingSince[u[k]]
      maxStaleness = Math.max(maxStaleness, since < 0 ? 0 : tick - since)
    }
    for (let i = 0; i < frame.count; i++) {
      const id = frame.ids[i]
      this.priority[id] = 0
      this.waitingSince[id] = -1
    }
    for (let k = 0; k < u.length; k += 5) this.waitingSince[u[k]] = tick
    this.remember(tick, u)
    this.setLast(tick, true, u, last.candidates, last.bytes)
    return { candidates: last.candidates, sent: last.candidates, maxStaleness }
  }

  /**
   * Pick the highest-priority candidates that fit the budget into `chosen`, in ascending id order.
   * Priorities are small integers, so a histogram of bytes per priority finds the cut-off in one
   * pass (a counting sort, no comparison sort): every candidate above the cut-off priority is
   * sent, and those at it are sent while bytes remain.
   */
  private choose(n: number, budget: number): number {
    const histogram = this.histogram
    histogram.fill(0)
    for (let i = 0; i < n; i++) histogram[this.bucket(this.candidates[i])] += this.sizes[i]
    let bytes = 0
    let cutoff = 0
    for (let b = PRIORITY_BUCKETS - 1; b >= 0; b--) {
      if (bytes + histogram[b] > budget) {
        cutoff = b
        break
      }
      bytes += histogram[b]
    }
    let remaining = budget - bytes
    let count = 0
    for (let i = 0; i < n; i++) {
      const id = this.candidates[i]
      const b = this.bucket(id)
      if (b > cutoff) {
        this.chosen[count++] = id
      } else if (b === cutoff && this.sizes[i] <= remaining) {
        remaining -= this.sizes[i]
        this.chosen[count++] = id
      }
    }
    return count
  }

  private bucket(id: number): number {
    return Math.min(PRIORITY_BUCKETS - 1, Math.floor(this.priority[id]))
  }

  private setLast(
    tick: number,
    complete: boolean,
    updates: Int32Array,
    candidates: number,
    bytes: number,
  ): void {
    const last = this.last
    last.tick = tick
    last.complete = complete
    last.updates = updates
    last.candidates = candidates
    last.bytes = bytes
  }

  /** Index of the pending snapshot of `tick`, or -1. */
  private findPending(tick: number): number {
    for (let i = 0; i < this.pendingSize; i++) if (this.pendingTicks[i] === tick) return i
    return -1
  }

  /** Forget pending snapshots [from, from + n), keeping the order of the rest. */
  private removePending(from: number, n: number): void {
    const size = this.pendingSize
    for (let i = from + n; i < size; i++) {
      this.pendingTicks[i - n] = this.pendingTicks[i]
      this.pendingBases[i - n] = this.pendingBases[i]
      this.pendingUpdates[i - n] = this.pendingUpdates[i]
    }
    for (let i = size - n; i < size; i++) this.pendingUpdates[i] = NO_UPDATES
    this.pendingSize = size - n
  }

  /** Remember a sent snapshot (a second one of the same tick replaces the first); at most MAX_PENDING, oldest dropped. */
  private remember(tick: number, updates: Int32Array): void {
    let i = this.findPending(tick)
    if (i < 0) i = this.pendingSize++
    this.pendingTicks[i] = tick
    this.pendingBases[i] = this.referenceTick
    this.pendingUpdates[i] = updates
    if (this.pendingSize > MAX_PENDING) this.removePending(0, 1)
  }

  /** The client acknowledged the snapshot at `tick`; returns true if the reference advanced. */
  ack(tick: number): boolean {
    const i = this.findPending(tick)
    if (i < 0) return false
    const base = this.pendingBases[i]
    const u = this.pendingUpdates[i]
    this.removePending(i, 1)
    if (base !== this.referenceTick) return false
    for (let k = 0; k < u.length; k += 5) {
      this.reference.put(u[k], u[k + 1], u[k + 2], u[k + 3], (u[k + 4] & FRAME_AWAKE) !== 0)
    }
    this.referenceTick = tick
    // Snapshots older than the acknowledged one can no longer advance the reference.
    let kept = 0
    for (let k = 0; k < this.pendingSize; k++) {
      if (this.pendingTicks[k] < tick) continue
      this.pendingTicks[kept] = this.pendingTicks[k]
      this.pendingBases[kept] = this.pendingBases[k]
      this.pendingUpdates[kept] = this.pendingUpdates[k]
      kept++
    }
    for (let k = kept; k < this.pendingSize; k++) this.pendingUpdates[k] = NO_UPDATES
    this.pendingSize = kept
    return true
  }

  /** A body was destroyed: forget it (its id is never reused in this epoch). */
  removeBody(id: number): void {
    this.reference.remove(id)
    if (id < this.priority.length) {
      this.priority[id] = 0
      this.waitingSince[id] = -1
    }
  }

  /** Snapshots sent and not yet acknowledged or dropped. */
  get pendingCount(): number {
    return this.pendingSize
  }
}
