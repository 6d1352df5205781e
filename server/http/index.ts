/*
 * Plain HTTP and the gate before any WebSocket frame: the routes (static client, /healthz, /readyz,
 * /metrics, /rooms, /replays), who may upgrade, every TCP connection's limits, per-address request
 * rates and the token bucket they and the message rate share.
 */
export { type Access, checkAccess, checkKeyedRoute, checkMetricsAccess } from './http-access.ts'
export {
  addressKey,
  ConnectionGuard,
  clientAddress,
  timeoutCheckInterval,
  tuneHttpTimeouts,
} from './http-connections.ts'
export { SECURITY_HEADERS } from './http-headers.ts'
export { parseRequestTarget, rawHttpResponse } from './http-request-url.ts'
export { createRequestHandler } from './http-routes.ts'
export { MessageBudget } from './message-budget.ts'
