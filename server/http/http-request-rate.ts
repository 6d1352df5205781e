/*
 * The per-address HTTP request rate (--max-requests-per-ip): every HTTP request and every
 * WebSocket upgrade draws one token from its client address's bucket (an IPv6 client's /64:
 * addressKey), which holds one second's worth and refills continuously. Before, one client that
 * pipelined requests on a keep-alive connection (`GET /metrics` 2,000 times per write) held the
 * main thread for 5 s while every player's snapshots waited, and the requests it had queued kept
 * it busy for 20 s after it left. Over the rate, the request is answered 429 and its connection
 * closed (ConnectionGuard), and the address owes a pause: for PENALTY_SECONDS it has no request
 * left, so every new connection from it is refused at once, before Node parses anything on it.
 * (Without the pause an address that kept reconnecting got a request every 1/rate seconds, and
 * Node parsed a whole 64 KiB read of pipelined requests, about 1,900, on each such connection.)
 */
import { MessageBudget } from './message-budget.ts'

/** How often buckets that have filled up again are forgotten (ms). */
const SWEEP_MS = 10_000
/** How long an address that went over the rate is refused (s; the 429's Retry-After). */
export const PENALTY_SECONDS = 5

/** Request buckets per address key. */
export class RequestRate {
  private readonly buckets = new Map<string, MessageBudget>()
  private sweptAt: number

  constructor(
    /** Requests per second per address, and the burst; 0 = no limit. */
    private readonly perSecond: number,
    private readonly now: () => number = () => performance.now(),
  ) {
    this.sweptAt = now()
  }

  /**
   * Take one request from the address's bucket; false when it has none left, and then the address
   * has none for PENALTY_SECONDS.
   */
  take(key: string): boolean {
    if (this.perSecond <= 0) return true
    this.sweep()
    const bucket = this.bucket(key)
    if (bucket.take()) return true
    bucket.owe(PENALTY_SECONDS)
    return false
  }

  /** Refuse the address's requests for PENALTY_SECONDS (it flooded a WebSocket). */
  penalize(key: string): void {
    if (this.perSecond > 0) this.bucket(key).owe(PENALTY_SECONDS)
  }

  /** Whether the address has a request left (without taking it). */
  allows(key: string): boolean {
    return this.perSecond <= 0 || (this.buckets.get(key)?.left() ?? true)
  }

  /** Addresses with a bucket (those that made a request within about the last sweep period). */
  get size(): number {
    return this.buckets.size
  }

  private bucket(key: string): MessageBudget {
    let bucket = this.buckets.get(key)
    if (!bucket) {
      bucket = new MessageBudget(this.perSecond, this.now)
      this.buckets.set(key, bucket)
    }
    return bucket
  }

  /** Forget full buckets now and then, so the map holds only recently active addresses. */
  private sweep(): void {
    if (this.now() - this.sweptAt < SWEEP_MS) return
    this.sweptAt = this.now()
    for (const [key, bucket] of this.buckets) if (bucket.full()) this.buckets.delete(key)
  }
}
