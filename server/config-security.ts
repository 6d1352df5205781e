/*
 * The security settings of the server (issue 11): connection caps and timeouts, the per-client
 * message rate, the origin allowlist, and the join and admin tokens with the rooms that stay
 * public. They join the SETTINGS table (config-settings.ts) (flag, environment variable, default, help), and
 * checkSecurityConfig refuses bad values at startup with a message naming the setting.
 *
 * Room access policy: without --join-token every room is public. With it, every room is
 * token-only (the WebSocket upgrade must carry `key=<join token>` or `key=<admin token>`) except
 * the rooms listed in --public-rooms. With --admin-token, room controls (scene, reset, pause,
 * step, gravity) are admin-only: only a connection that presented the admin token may use them.
 * The room list and the replay logs follow the join token: with it, GET /rooms, /replays and
 * /replays/NAME need either key (http-access.ts checkKeyedRoute), --public-rooms or not.
 * --metrics-token puts /metrics behind its own bearer token (checkMetricsAccess).
 */
import { ROOM_NAME_PATTERN } from '../shared/index.ts'
import type { ServerConfig } from './config.ts'
import type { Setting } from './config-settings.ts'

/** Shortest accepted token (characters): shorter secrets are guessable. */
export const MIN_KEY_LENGTH = 8
/** Longest accepted token (characters). */
export const MAX_KEY_LENGTH = 256

/** The security rows of the settings table. */
export const SECURITY_SETTINGS: readonly Setting[] = [
  {
    key: 'handshakeTimeoutMs',
    flag: '--handshake-timeout-ms',
    env: 'HANDSHAKE_TIMEOUT_MS',
    kind: 'int',
    fallback: 5000,
    min: 100,
    max: 600000,
    help: 'time a TCP connection has to send a complete HTTP request or upgrade (408 after)',
  },
  {
    key: 'maxConnectionsPerIp',
    flag: '--max-connections-per-ip',
    env: 'MAX_CONNECTIONS_PER_IP',
    kind: 'int',
    fallback: 128,
    min: 0,
    max: 100000,
    help: 'TCP connections per client address (IPv6: per /64), 0 = no cap; more get HTTP 429',
  },
  {
    key: 'maxRequestsPerIp',
    flag: '--max-requests-per-ip',
    env: 'MAX_REQUESTS_PER_IP',
    kind: 'int',
    fallback: 200,
    min: 0,
    max: 1000000,
    help: 'HTTP requests and WebSocket upgrades per client address per second (1 s burst), 0 = no limit; more get HTTP 429 and the connection is closed',
  },
  {
    key: 'maxMessagesPerSecond',
    flag: '--max-messages-per-second',
    env: 'MAX_MESSAGES_PER_SECOND',
    kind: 'int',
    fallback: 600,
    min: 10,
    max: 1000000,
    help: 'messages of every kind per client per second (1 s burst); more are dropped with strikes',
  },
  {
    key: 'allowedOrigins',
    flag: '--allowed-origins',
    env: 'ALLOWED_ORIGINS',
    kind: 'string',
    fallback: '',
    help: 'comma-separated origins whose pages may connect (empty = any); others get 403',
  },
  {
    key: 'joinToken',
    flag: '--join-token',
    env: 'JOIN_TOKEN',
    kind: 'string',
    fallback: '',
    help: 'when set, rooms and replays are token-only: the WebSocket URL, /rooms and /replays need key=TOKEN (401/403 otherwise)',
  },
  {
    key: 'adminToken',
    flag: '--admin-token',
    env: 'ADMIN_TOKEN',
    kind: 'string',
    fallback: '',
    help: 'when set, room controls need key=ADMIN_TOKEN (which also admits to every room)',
  },
  {
    key: 'metricsToken',
    flag: '--metrics-token',
    env: 'METRICS_TOKEN',
    kind: 'string',
    fallback: '',
    help: 'when set, /metrics needs the header Authorization: Bearer METRICS_TOKEN (401/403 otherwise)',
  },
  {
    key: 'publicRooms',
    flag: '--public-rooms',
    env: 'PUBLIC_ROOMS',
    kind: 'string',
    fallback: '',
    help: 'comma-separated rooms anyone may join without a key even with --join-token',
  },
]

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
