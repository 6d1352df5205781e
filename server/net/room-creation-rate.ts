/*
 * Room names are a resource (issue 30, point 8): every new name a client joins opens a room, which
 * holds a place under --max-rooms and, when recording, starts a log that pushes real recordings
 * toward --replay-keep. 50 anonymous connections that each joined a fresh name and left filled the
 * room limit for the idle minute. So each client address (an IPv6 client's /64, as for the other
 * per-address limits) may open at most --max-new-rooms-per-ip rooms per minute: a bucket of that
 * many, refilled evenly over 60 s. Joining a room that is already open costs nothing.
 */

/** The window the limit counts over (ms). */
const WINDOW_MS = 60_000
/** How often buckets that have filled up again are forgotten (ms). */
const SWEEP_MS = 60_000

/** Room openings per address key (see the file comment). */
export class RoomCreationRate {
  private readonly buckets = new Map<string, { tokens: number; at: number }>()
  private sweptAt: number

  constructor(
    /** Rooms an address may open per minute; 0 = no limit. */
    readonly perMinute: number,
    private readonly now: () => number = () => performance.now(),
  ) {
    this.sweptAt = now()
  }

  /** Whether the address may open a room now (nothing is taken). */
  allows(key: string): boolean {
    return this.perMinute <= 0 || this.refill(key).tokens >= 1
  }

  /** Take one opening from the address's bucket; false when it has none left. */
  take(key: string): boolean {
    if (this.perMinute <= 0) return true
    this.sweep()
    const bucket = this.refill(key)
    if (bucket.tokens < 1) return false
    bucket.tokens--
    return true
  }

  /** Whole seconds until the address may open a room again (0 when it may now). */
  waitSeconds(key: string): number {
    if (this.perMinute <= 0) return 0
    const missing = 1 - this.refill(key).tokens
    return missing <= 0 ? 0 : Math.ceil((missing * WINDOW_MS) / this.perMinute / 1000)
  }

  private refill(key: string): { tokens: number; at: number } {
    const now = this.now()
    let bucket = this.buckets.get(key)
    if (!bucket) {
      bucket = { tokens: this.perMinute, at: now }
      this.buckets.set(key, bucket)
    }
    bucket.tokens = Math.min(this.perMinute, bucket.tokens + ((now - bucket.at) * this.perMinute) / WINDOW_MS)
    bucket.at = now
    return bucket
  }

  /** Forget full buckets now and then, so the map holds only recently active addresses. */
  private sweep(): void {
    if (this.now() - this.sweptAt < SWEEP_MS) return
    this.sweptAt = this.now()
    for (const [key, bucket] of this.buckets) {
      this.refill(key)
      if (bucket.tokens >= this.perMinute) this.buckets.delete(key)
    }
  }
}
