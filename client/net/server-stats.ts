/*
 * The server's step time for the HUD. The protocol does not carry it, so the page reads the
 * server's Prometheus endpoint (/metrics, same origin) every few seconds and takes the mean room
 * tick time over the interval from the tick-time histogram's _sum and _count: the time one room
 * tick takes (inputs, world step, snapshot encoding), averaged over every room of the process. With
 * rooms on worker threads the histogram has one series per worker (label `worker`), summed here; a
 * worker's series appears only after its first report, so a /metrics without the histogram is
 * polled again. If /metrics is not reachable (a deployment that hides it), polling stops and the
 * HUD shows "-".
 */

const SUM = /^concord_room_tick_seconds_sum(?:\{[^}]*\})? ([0-9.eE+-]+)$/gm
const COUNT = /^concord_room_tick_seconds_count(?:\{[^}]*\})? ([0-9.eE+-]+)$/gm

/** The sum of every series of one metric line pattern, or null when there is none. */
function total(pattern: RegExp, text: string): number | null {
  let sum: number | null = null
  for (const match of text.matchAll(pattern)) sum = (sum ?? 0) + Number(match[1])
  return sum
}
/** Polling interval (ms). */
const INTERVAL_MS = 5000

/** Mean room tick time (ms) from a /metrics text and the previous totals. */
export function meanTickMs(
  text: string,
  previous: { sum: number; count: number } | null,
): { sum: number; count: number; meanMs: number | null } | null {
  const s = total(SUM, text)
  const c = total(COUNT, text)
  if (s === null || c === null) return null
  const ds = previous ? s - previous.sum : s
  const dc = previous ? c - previous.count : c
  return { sum: s, count: c, meanMs: dc > 0 ? (ds / dc) * 1000 : null }
}

/** Polls the server's metrics for the HUD's step time. */
export class ServerStats {
  /** Mean room tick time over the last interval (ms), or null. */
  tickMs: number | null = null
  private previous: { sum: number; count: number } | null = null
  private last = Number.NEGATIVE_INFINITY
  private busy = false
  private disabled = false

  constructor(private readonly httpBase: string) {}

  /** Call once per frame; fetches at most every INTERVAL_MS. */
  poll(nowMs: number): void {
    if (this.disabled || this.busy || nowMs - this.last < INTERVAL_MS) return
    this.last = nowMs
    this.busy = true
    fetch(`${this.httpBase}/metrics`, { cache: 'no-store' })
      .then((r) => (r.ok ? r.text() : Promise.reject(new Error(`HTTP ${r.status}`))))
      .then((text) => {
        // No histogram yet (no worker has reported): read again at the next interval.
        const result = meanTickMs(text, this.previous)
        if (!result) return
        if (result.meanMs !== null) this.tickMs = result.meanMs
        this.previous = { sum: result.sum, count: result.count }
      })
      .catch(() => {
        this.disabled = true
      })
      .finally(() => {
        this.busy = false
      })
  }
}
