/*
 * The server's step time for the HUD. The protocol does not carry it, so the page reads the
 * server's Prometheus endpoint (/metrics, same origin) every few seconds and takes the mean room
 * tick time over the interval from the tick-time histogram's _sum and _count: the time one room
 * tick takes (inputs, world step, snapshot encoding), averaged over every room of the process. If
 * /metrics is not reachable (a deployment that hides it), polling stops and the HUD shows "-".
 */

const SUM = /^concord_room_tick_seconds_sum(?:\{[^}]*\})? ([0-9.eE+-]+)$/m
const COUNT = /^concord_room_tick_seconds_count(?:\{[^}]*\})? ([0-9.eE+-]+)$/m
/** Polling interval (ms). */
const INTERVAL_MS = 5000

/** Mean room tick time (ms) from a /metrics text and the previous totals. */
export function meanTickMs(
  text: string,
  previous: { sum: number; count: number } | null,
): { sum: number; count: number; meanMs: number | null } | null {
  const sum = SUM.exec(text)
  const count = COUNT.exec(text)
  if (!sum || !count) return null
  const s = Number(sum[1])
  const c = Number(count[1])
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
        const result = meanTickMs(text, this.previous)
        if (!result) throw new Error('no tick histogram')
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
