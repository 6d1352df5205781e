/*
 * Warnings caused by clients are rate limited: a misbehaving peer must not be able to turn its
 * frames into log lines (one raw socket once made the server write 140 MB of warnings in 3 s).
 * The tick loop's overrun warnings are limited the same way, so a loaded machine does not log
 * one line per late tick.
 * Each key (a client id, an IP address) may log `perWindow` warnings per window; further ones are
 * counted, and the first warning of a later window reports how many were suppressed, so nothing is
 * silently lost and the log grows by at most perWindow lines per key per window.
 */
import type { Logger } from 'pino'

/** Rate-limits warnings per key. */
export class LogLimiter {
  private counts = new Map<string | number, number>()
  private suppressed = 0
  private windowStart: number

  constructor(
    private readonly log: Logger,
    /** Warnings per key per window; usually 3. */
    private readonly perWindow = 3,
    /** Window length (ms); usually 10 s. */
    private readonly windowMs = 10_000,
    private readonly now: () => number = Date.now,
    /** The line that reports suppressed warnings at the start of a later window. */
    private readonly suppressedMsg = 'warnings about misbehaving clients were suppressed',
  ) {
    this.windowStart = now()
  }

  /** Log `msg` at warn level unless `key` has used up its warnings in this window. */
  warn(key: string | number, fields: Record<string, unknown>, msg: string): void {
    const now = this.now()
    if (now - this.windowStart >= this.windowMs) {
      if (this.suppressed > 0) {
        this.log.warn({ suppressed: this.suppressed }, this.suppressedMsg)
      }
      this.counts.clear()
      this.suppressed = 0
      this.windowStart = now
    }
    const n = this.counts.get(key) ?? 0
    if (n >= this.perWindow) {
      this.suppressed++
      return
    }
    this.counts.set(key, n + 1)
    this.log.warn(fields, msg)
  }
}
