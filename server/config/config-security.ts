/*
 * The security settings of the server (issue 11): connection caps and timeouts, the per-client
 * message rate, the origin allowlist, and the join and admin tokens with the rooms that stay
 * public. Their rows are in the settings table (config-settings.ts); checkSecurityConfig refuses
 * bad values at startup with a message naming the setting.
 *
 * Room access policy: without --join-token every room is public. With it, every room is
 * token-only (the WebSocket upgrade must carry `key=<join token>` or `key=<admin token>`) except
 * the rooms listed in --public-rooms. With --admin-token, room controls (scene, reset, pause,
 * step, gravity) are admin-only: only a connection that presented the admin token may use them.
 * The room list and the replay logs follow the join token: with it, GET /rooms, /replays and
 * /replays/NAME need either key (http-access.ts checkKeyedRoute), --public-rooms or not.
 * --metrics-token puts /metrics behind its own bearer token (checkMetricsAccess).
 */
import { ROOM_NAME_PATTERN } from '../../shared/index.ts'
import type { ServerConfig } from './config-settings.ts'

/** Shortest accepted token (characters): shorter secrets are guessable. */
export const MIN_KEY_LENGTH = 8
/** Longest accepted token (characters). */
export const MAX_KEY_LENGTH = 256

/** A comma-separated setting as a list, blanks dropped. */
export function listSetting(raw: string): string[] {
  return raw
    .split(',')
    .map((s) => s.trim())
    .filter((s) => s !== '')
}

function checkToken(name: string, token: string): void {
  if (token === '') return
  if (token.length < MIN_KEY_LENGTH || token.length > MAX_KEY_LENGTH) {
    throw new Error(
      `${name} must be ${MIN_KEY_LENGTH}-${MAX_KEY_LENGTH} characters, got ${token.length} characters`,
    )
  }
  if (!/^[\x21-\x7e]+$/.test(token)) throw new Error(`${name} must be printable ASCII without spaces`)
}

/** Throws, naming the setting, when a security setting is malformed. */
export function checkSecurityConfig(config: ServerConfig): void {
  for (const origin of listSetting(config.allowedOrigins)) {
    let parsed: string | null = null
    try {
      parsed = new URL(origin).origin
    } catch {
      parsed = null
    }
    if (parsed !== origin) {
      throw new Error(`allowed origins must look like https://example.com[:port], got "${origin}"`)
    }
  }
  checkToken('join token', config.joinToken)
  checkToken('admin token', config.adminToken)
  checkToken('metrics token', config.metricsToken)
  if (config.joinToken !== '' && config.joinToken === config.adminToken) {
    throw new Error('join token and admin token must differ (the admin token grants room controls)')
  }
  for (const room of listSetting(config.publicRooms)) {
    if (!ROOM_NAME_PATTERN.test(room)) {
      throw new Error(`public rooms must be 1-32 letters, digits, "-" or "_", got "${room}"`)
    }
  }
}
