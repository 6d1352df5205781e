/*
 * Operations: Prometheus metrics, the tick loops' liveness, rate-limited warnings, the Redis room
 * directory shared by a deployment's servers, Agones, and the container health check.
 */
export { AgonesLink, agonesPresent } from './agones.ts'
export { LogLimiter } from './log-limiter.ts'
export { createMetrics, type ServerMetrics } from './metrics.ts'
export { RoomDirectory } from './room-directory.ts'
export { TickHealth } from './tick-health.ts'
