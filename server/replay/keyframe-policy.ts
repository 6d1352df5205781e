/*
 * When a recorder writes a keyframe, and whether whole or as a delta against the previous one.
 *
 * Measured (bench/replay-bench.ts, docs/replay-format.md): a resting room's keyframes barely
 * change (a sleeping 210-box pyramid: 113 KB deflated whole, about 30 bytes as a delta), but a
 * pile of 1,000 bodies dragged by five players stays awake (997 to 1,000 bodies at every keyframe)
 * and a delta saves only 2-5 % of its 370 KB. So two rules:
 * - Budget: at every multiple of `ticks`, a keyframe is written only while the keyframe bytes of
 *   this log stay within `budget` bytes per hour of the log's age (0: no budget). Quiet rooms get a
 *   keyframe every `ticks`; a busy one gets as many as the budget pays for, never more than one
 *   keyframe over it.
 * - Chain: a delta when the deltas since the last whole keyframe plus the next (predicted as the
 *   last delta's size) stay under one whole keyframe and the chain is shorter than MAX_CHAIN;
 *   otherwise a whole one. A seek or recovery decodes at most MAX_CHAIN deltas.
 */

/** Whole keyframes up to this many bytes get the whole budget; bigger ones a proportionally smaller one. */
export const FULL_BUDGET_BYTES = 128_000

/** Longest run of delta keyframes after a whole one (seek and recovery decode at most this many). */
export const MAX_CHAIN = 60

/** What to write at a tick. */
export type KeyframeKind = 'none' | 'full' | 'delta'

/** Keyframe timing and kind for one log (see the file comment). */
export class KeyframePolicy {
  private startTick = 0
  private written = 0
  private fullBytes = 0
  private chain = 0
  private chainBytes = 0
  private lastDelta = 0
  private hasBase = false

  constructor(
    /** Ticks between keyframe opportunities (--keyframe-ticks). */
    readonly ticks: number,
    /** Keyframe bytes allowed per hour of log (--keyframe-budget in bytes, scaled down for worlds over FULL_BUDGET_BYTES), 0 for no limit. */
    readonly budgetPerHour: number,
    /** Room ticks per second. */
    readonly tickRate: number,
  ) {}

  /** A new log starts at `tick`; `base` says whether the recorder holds its header's saved world. */
  reset(tick: number, base: boolean, headerBytes: number): void {
    this.startTick = tick
    this.written = 0
    this.fullBytes = headerBytes
    this.chain = 0
    this.chainBytes = 0
    this.lastDelta = 0
    this.hasBase = base
  }

  /** What to write after room tick `tick`. */
  decide(tick: number): KeyframeKind {
    if (tick % this.ticks !== 0) return 'none'
    if (this.budgetPerHour > 0) {
      const scale = this.fullBytes > FULL_BUDGET_BYTES ? FULL_BUDGET_BYTES / this.fullBytes : 1
      const allowed = (this.budgetPerHour * scale * (tick - this.startTick)) / (3600 * this.tickRate)
      if (this.written > allowed) return 'none'
    }
    const delta = this.hasBase && this.chain < MAX_CHAIN && this.chainBytes + this.lastDelta < this.fullBytes
    return delta ? 'delta' : 'full'
  }

  /**
   * A keyframe of about `bytes` (its record, compressed) is being written; settle() corrects the
   * figure once compression is done.
   */
  record(kind: 'full' | 'delta', bytes: number): void {
    this.written += bytes
    this.hasBase = true
    if (kind === 'full') {
      this.fullBytes = bytes
      this.chain = 0
      this.chainBytes = 0
      this.lastDelta = 0
    } else {
      this.chain++
      this.chainBytes += bytes
      this.lastDelta = bytes
    }
  }

  /** The keyframe last recorded as `estimate` bytes is `actual` bytes. */
  settle(kind: 'full' | 'delta', estimate: number, actual: number): void {
    this.written += actual - estimate
    if (kind === 'full') this.fullBytes += actual - estimate
    else {
      this.chainBytes += actual - estimate
      this.lastDelta += actual - estimate
    }
  }
}
