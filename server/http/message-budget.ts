/*
 * The per-client message rate: a token bucket that every frame draws from, whatever it is (moves,
 * acks, pings, inputs, garbage), so no kind of message is free. Moves still coalesce per tick in
 * the room and the per-tick input budget still applies to inputs; this bucket bounds the work a
 * client can cause at all (180,000 moves and acks per second were once accepted). It refills at
 * `perSecond` tokens a second and holds one second's worth, so bursts after a network stall pass.
 */

/** A token bucket of messages per second. */
export class MessageBudget {
  private tokens: number
  private last: number
  private lastStrike = Number.NEGATIVE_INFINITY
  private overSince = Number.NEGATIVE_INFINITY
  private over = 0

  constructor(
    /** Messages per second allowed on average, and the burst size. */
    private readonly perSecond: number,
    private readonly now: () => number,
  ) {
    this.tokens = perSecond
    this.last = now()
  }

  /** Take one message from the budget; false when it is exhausted (the message is to be dropped). */
  take(): boolean {
    if (!this.refill()) return false
    this.tokens--
    return true
  }

  /** Whether one message is left, without taking it. */
  left(): boolean {
    return this.refill()
  }

  /**
   * Count a message the bucket refused; true once more than twice the rate were refused within
   * one second (a client sending at three times the rate or more: a flood, not a burst).
   */
  flooded(): boolean {
    const now = this.now()
    if (now - this.overSince >= 1000) {
      this.overSince = now
      this.over = 0
    }
    this.over++
    return this.over > 2 * this.perSecond
  }

  /** Empty the bucket so that the next message is allowed only after `seconds` of refilling. */
  owe(seconds: number): void {
    this.refill()
    this.tokens = Math.min(this.tokens, 1 - this.perSecond * seconds)
  }

  /** Whether the bucket is full again (nothing taken in the last second). */
  full(): boolean {
    this.refill()
    return this.tokens >= this.perSecond
  }

  private refill(): boolean {
    const now = this.now()
    this.tokens = Math.min(this.perSecond, this.tokens + ((now - this.last) * this.perSecond) / 1000)
    this.last = now
    return this.tokens >= 1
  }

  /**
   * Whether an over-budget message should cost a strike: at most one per `intervalMs` (a tick), so
   * a short burst costs little while a sustained flood is disconnected within a second.
   */
  strikeDue(intervalMs: number): boolean {
    const now = this.now()
    if (now - this.lastStrike < intervalMs) return false
    this.lastStrike = now
    return true
  }
}
