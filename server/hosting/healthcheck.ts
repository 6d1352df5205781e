/*
 * The container health check (Dockerfile HEALTHCHECK): GET /healthz on this container's own port
 * and exit 0 when it answers 200 within the timeout, 1 otherwise. /healthz itself fails when a
 * tick loop has stalled (see server/health.ts), so a wedged server is restarted.
 * Usage: node dist/healthcheck.js   (reads PORT, default 8080)
 */

/** How long the probe waits for an answer (ms). */
const PROBE_TIMEOUT_MS = 2500

/** Probe /healthz; resolves with the process exit code (0 healthy, 1 not). */
export async function probe(): Promise<number> {
  const port = Number(process.env.PORT ?? 8080)
  if (!Number.isInteger(port) || port <= 0 || port > 65535) {
    process.stderr.write(`healthcheck: PORT must be an integer in [1, 65535], got "${process.env.PORT}"\n`)
    return 1
  }
  try {
    const res = await fetch(`http://127.0.0.1:${port}/healthz`, {
      signal: AbortSignal.timeout(PROBE_TIMEOUT_MS),
    })
    const body = await res.text()
    if (res.status === 200) return 0
    process.stderr.write(`healthcheck: /healthz answered ${res.status}: ${body.trim()}\n`)
    return 1
  } catch (error) {
    process.stderr.write(`healthcheck: /healthz on port ${port} failed: ${(error as Error).message}\n`)
    return 1
  }
}

process.exitCode = await probe()
