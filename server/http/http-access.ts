/*
 * Who may open a WebSocket, decided at the upgrade before any frame is read: the origin allowlist
 * (--allowed-origins; a browser page from another origin gets 403, a request without an Origin
 * header, which only non-browser clients send, is let through), then the key in the URL
 * (`/ws?room=NAME&key=KEY`). A key that matches neither token is refused (403) wherever it is
 * sent, on a server without tokens too; without a key, a token-only room is refused (401) and a public room admits the
 * connection to that room only. The room policy is described in config-security.ts.
 *
 * The replay logs (GET /replays, GET /replays/NAME) hold every command of every room and the
 * players' names, and the room list (GET /rooms) names every room, token-only ones included, so
 * with a join token they need a key too (`?key=KEY`, the join or the admin token), whichever
 * room they name: checkKeyedRoute. Before, a token-only server served the recording of its rooms
 * (and the names of its private rooms) to anyone. /metrics has its own token (--metrics-token),
 * sent as `Authorization: Bearer TOKEN` as Prometheus does: checkMetricsAccess.
 */
import { timingSafeEqual } from 'node:crypto'
import type { IncomingMessage } from 'node:http'
import { listSetting, type ServerConfig } from '../config/index.ts'

/** What a connection may do once upgraded. */
export interface Access {
  /** The one room it may join, or null for any room. */
  room: string | null
  /** Whether it may use room controls (scene, reset, pause, step, gravity). */
  controls: boolean
}

/**
 * The upgrade decision: access, or an HTTP status with the reason (for the log and metrics) and a
 * sentence for a person (`detail`, the body of a plain GET /ws: how a page learns why its socket
 * was refused, since a browser hides the status of a failed upgrade).
 */
export type AccessResult =
  | { ok: true; access: Access }
  | { ok: false; status: 401 | 403; text: string; reason: string; detail: string }

/** Constant-time string equality (a token compare must not leak how many characters matched). */
export function sameSecret(given: string, secret: string): boolean {
  const a = Buffer.from(given, 'utf8')
  const b = Buffer.from(secret, 'utf8')
  return a.length === b.length && timingSafeEqual(a, b)
}

/** What a key in a URL is: the admin token, the join token, none given, or a key matching neither. */
function keyRole(config: ServerConfig, key: string): 'admin' | 'member' | 'none' | 'forged' {
  if (key === '') return 'none'
  if (config.adminToken !== '' && sameSecret(key, config.adminToken)) return 'admin'
  if (config.joinToken !== '' && sameSecret(key, config.joinToken)) return 'member'
  // On a server without tokens too: a key there matches nothing, and ignoring it would hide a
  // missing --join-token from the clients that expected one (PROTOCOL.md, Access).
  return 'forged'
}

/** A refused HTTP request for a keyed route: status, a one-line answer, the reason for the log. */
export interface RouteRefusal {
  status: 401 | 403
  text: string
  reason: string
  /** Headers the answer needs (WWW-Authenticate for /metrics). */
  headers?: Record<string, string>
}

/**
 * Whether a keyed route (the room list or the replay logs, `what`) may answer a request for
 * `url`: null when it may (no join token, or the URL's `key=` is the join or the admin token),
 * else the refusal. A key that matches neither token is refused (403) as it is at the upgrade,
 * even on a server whose routes are public (a server without tokens included).
 */
export function checkKeyedRoute(
  config: ServerConfig,
  url: URL,
  what: 'rooms' | 'replays' | 'scenes',
): RouteRefusal | null {
  const role = keyRole(config, url.searchParams.get('key') ?? '')
  if (role === 'forged')
    return {
      status: 403,
      text:
        config.joinToken === '' && config.adminToken === ''
          ? 'the key matches no token: this server has none, so send no key'
          : 'the key matches neither the join token nor the admin token',
      reason: 'bad-key',
    }
  if (config.joinToken === '' || role !== 'none') return null
  return {
    status: 401,
    text: `the ${what === 'rooms' ? 'room list' : what === 'scenes' ? 'saved scenes' : 'replays'} of this server need its join or admin key: add key=KEY to the URL`,
    reason: 'no-key',
  }
}

/**
 * Whether /metrics may answer `request`: null without --metrics-token, or when the request carries
 * `Authorization: Bearer TOKEN`; else 401 (no or another scheme) or 403 (a wrong token).
 */
export function checkMetricsAccess(config: ServerConfig, request: IncomingMessage): RouteRefusal | null {
  if (config.metricsToken === '') return null
  const header = request.headers.authorization ?? ''
  const match = /^Bearer +(\S+) *$/i.exec(header)
  if (!match)
    return {
      status: 401,
      text: 'the metrics of this server need its metrics token: send Authorization: Bearer TOKEN',
      reason: 'no-key',
      headers: { 'www-authenticate': 'Bearer realm="metrics"' },
    }
  if (!sameSecret(match[1], config.metricsToken))
    return { status: 403, text: 'the bearer token is not the metrics token', reason: 'bad-key' }
  return null
}

/** Decide an upgrade request for `room` (the URL's room, or '' when the join will name it). */
export function checkAccess(
  config: ServerConfig,
  request: IncomingMessage,
  url: URL,
  room: string,
): AccessResult {
  const origins = listSetting(config.allowedOrigins)
  const origin = request.headers.origin
  if (origins.length > 0 && origin !== undefined && !origins.includes(origin)) {
    return {
      ok: false,
      status: 403,
      text: 'Forbidden',
      reason: 'origin',
      detail: `this server does not accept pages from ${origin} (--allowed-origins)`,
    }
  }
  const role = keyRole(config, url.searchParams.get('key') ?? '')
  const admin = role === 'admin'
  const member = admin || role === 'member'
  if (role === 'forged') {
    return {
      ok: false,
      status: 403,
      text: 'Forbidden',
      reason: 'bad-key',
      detail: 'the key matches neither the join token nor the admin token',
    }
  }
  const controls = config.adminToken === '' || admin
  if (config.joinToken === '' || member) return { ok: true, access: { room: null, controls } }
  const target = room || config.defaultRoom
  if (!listSetting(config.publicRooms).includes(target)) {
    return {
      ok: false,
      status: 401,
      text: 'Unauthorized',
      reason: 'no-key',
      detail: `room "${target}" is open only with this server's join or admin key`,
    }
  }
  return { ok: true, access: { room: target, controls } }
}
