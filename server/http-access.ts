/*
 * Who may open a WebSocket, decided at the upgrade before any frame is read: the origin allowlist
 * (--allowed-origins; a browser page from another origin gets 403, a request without an Origin
 * header, which only non-browser clients send, is let through), then the key in the URL
 * (`/ws?room=NAME&key=KEY`). A key that matches neither token is refused (403) wherever it is
 * sent; without a key, a token-only room is refused (401) and a public room admits the
 * connection to that room only. The room policy is described in config-security.ts.
 */
import { timingSafeEqual } from 'node:crypto'
import type { IncomingMessage } from 'node:http'
import type { ServerConfig } from './config.ts'
import { listSetting } from './config-security.ts'

/** What a connection may do once upgraded. */
export interface Access {
  /** The one room it may join, or null for any room. */
  room: string | null
  /** Whether it may use room controls (scene, reset, pause, step, gravity). */
  controls: boolean
}

/** The upgrade decision: access, or an HTTP status with the reason (for the log and metrics). */
export type AccessResult =
  | { ok: true; access: Access }
  | { ok: false; status: 401 | 403; text: string; reason: string }

/** Constant-time string equality (a token compare must not leak how many characters matched). */
export function sameSecret(given: string, secret: string): boolean {
  const a = Buffer.from(given, 'utf8')
  const b = Buffer.from(secret, 'utf8')
  return a.length === b.length && timingSafeEqual(a, b)
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
    return { ok: false, status: 403, text: 'Forbidden', reason: 'origin' }
  }
  const key = url.searchParams.get('key') ?? ''
  const admin = config.adminToken !== '' && key !== '' && sameSecret(key, config.adminToken)
  const member = admin || (config.joinToken !== '' && key !== '' && sameSecret(key, config.joinToken))
  const tokensSet = config.adminToken !== '' || config.joinToken !== ''
  if (key !== '' && tokensSet && !member) {
    return { ok: false, status: 403, text: 'Forbidden', reason: 'bad-key' }
  }
  const controls = config.adminToken === '' || admin
  if (config.joinToken === '' || member) return { ok: true, access: { room: null, controls } }
  const target = room || config.defaultRoom
  if (!listSetting(config.publicRooms).includes(target)) {
    return { ok: false, status: 401, text: 'Unauthorized', reason: 'no-key' }
  }
  return { ok: true, access: { room: target, controls } }
}
