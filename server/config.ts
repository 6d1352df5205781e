/*
 * Server settings. Every setting has a default, a command-line flag and an environment variable;
 * a flag beats the environment, which beats the default. Bad values are refused at startup with a
 * message naming the setting, never silently replaced.
 */

import { isIP } from 'node:net'
import { availableParallelism } from 'node:os'
import { SCENES } from '../engine/index.ts'
import { ROOM_NAME_PATTERN } from '../shared/index.ts'
import { checkSecurityConfig, SECURITY_SETTINGS } from './config-security.ts'

const LOG_LEVELS = ['fatal', 'error', 'warn', 'info', 'debug', 'trace', 'silent']

/** Everything the server can be configured with. */
export interface ServerConfig {
  port: number
  host: string
  maxRooms: number
  maxClientsPerRoom: number
  maxConnections: number
  maxBodies: number
  snapshotRate: number
  maxMessageBytes: number
  inputsPerTick: number
  clientBandwidth: number
  sendBufferBytes: number
  slowClientSeconds: number
  heartbeatMs: number
  joinTimeoutMs: number
  roomIdleSeconds: number
  reconnectSeconds: number
  maxRejects: number
  defaultRoom: string
  defaultScene: string
  roomControls: boolean
  staticDir: string
  replayDir: string
  record: boolean
  replayFsync: string
  keyframeTicks: number
  keyframeBudget: number
  replayMaxBytes: number
  replayKeep: number
  recover: boolean
  logLevel: string
  stallSeconds: number
  drainSeconds: number
  handshakeTimeoutMs: number
  maxConnectionsPerIp: number
  maxMessagesPerSecond: number
  allowedOrigins: string
  joinToken: string
  adminToken: string
  publicRooms: string
  roomTickBudgetMs: number
  roomOverrunTicks: number
  redisUrl: string
  publicUrl: string
  directoryTtlSeconds: number
  workers: number
}

/** When the recorder calls fsync: never, after each once-a-second flush, or after every tick's write. */
export const FSYNC_MODES = ['none', 'interval', 'always']

type Kind = 'int' | 'string' | 'bool'

/** One row of the settings table. */
export interface Setting {
  key: keyof ServerConfig
  flag: string
  env: string
  kind: Kind
  fallback: number | string | boolean
  min?: number
  max?: number
  /** How --help and the README state a default that depends on the machine (e.g. "one per core"). */
  shown?: string
  help: string
}

/** The settings table: flag, environment variable, default and meaning (printed by --help). */
export const SETTINGS: readonly Setting[] = [
  {
    key: 'port',
    flag: '--port',
    env: 'PORT',
    kind: 'int',
    fallback: 8080,
    min: 0,
    max: 65535,
    help: 'HTTP and WebSocket port (0 = any free port)',
  },
  {
    key: 'host',
    flag: '--host',
    env: 'HOST',
    kind: 'string',
    fallback: '127.0.0.1',
    help: 'address to listen on (0.0.0.0 in Docker)',
  },
  {
    key: 'maxRooms',
    flag: '--max-rooms',
    env: 'MAX_ROOMS',
    kind: 'int',
    fallback: 50,
    min: 1,
    max: 10000,
    help: 'rooms open at once',
  },
  {
    key: 'maxClientsPerRoom',
    flag: '--max-clients',
    env: 'MAX_CLIENTS_PER_ROOM',
    kind: 'int',
    fallback: 32,
    min: 1,
    max: 1000,
    help: 'players per room',
  },
  {
    key: 'maxConnections',
    flag: '--max-connections',
    env: 'MAX_CONNECTIONS',
    kind: 'int',
    fallback: 1000,
    min: 1,
    max: 100000,
    help: 'TCP connections per process (WebSocket, HTTP, unfinished handshakes); more get 503',
  },
  {
    key: 'maxBodies',
    flag: '--max-bodies',
    env: 'MAX_BODIES',
    kind: 'int',
    fallback: 1500,
    min: 1,
    max: 100000,
    help: 'bodies per room (spawns beyond are refused)',
  },
  {
    key: 'snapshotRate',
    flag: '--snapshot-rate',
    env: 'SNAPSHOT_RATE',
    kind: 'int',
    fallback: 30,
    min: 1,
    max: 60,
    help: 'snapshots per second, a divisor of 60 (60, 30, 20, 15, ...)',
  },
  {
    key: 'maxMessageBytes',
    flag: '--max-message-bytes',
    env: 'MAX_MESSAGE_BYTES',
    kind: 'int',
    fallback: 4096,
    min: 256,
    max: 1048576,
    help: 'largest client frame; larger ones close the socket with 1009',
  },
  {
    key: 'inputsPerTick',
    flag: '--inputs-per-tick',
    env: 'INPUTS_PER_TICK',
    kind: 'int',
    fallback: 8,
    min: 1,
    max: 1000,
    help: 'input commands per client per tick; more are refused',
  },
  {
    key: 'clientBandwidth',
    flag: '--client-bandwidth',
    env: 'CLIENT_BANDWIDTH',
    kind: 'int',
    fallback: 28000,
    min: 1000,
    max: 100000000,
    help: 'snapshot byte budget per client per second',
  },
  {
    key: 'sendBufferBytes',
    flag: '--send-buffer-bytes',
    env: 'SEND_BUFFER_BYTES',
    kind: 'int',
    fallback: 262144,
    min: 1,
    max: 1073741824,
    help: "unread bytes (unsent, or sent since the last ack) above which a client's snapshots are skipped",
  },
  {
    key: 'slowClientSeconds',
    flag: '--slow-client-seconds',
    env: 'SLOW_CLIENT_SECONDS',
    kind: 'int',
    fallback: 5,
    min: 1,
    max: 3600,
    help: 'how long a client may stay over the send buffer before it is closed',
  },
  {
    key: 'heartbeatMs',
    flag: '--heartbeat-ms',
    env: 'HEARTBEAT_MS',
    kind: 'int',
    fallback: 5000,
    min: 10,
    max: 600000,
    help: 'WebSocket ping interval; a peer missing one pong is closed',
  },
  {
    key: 'joinTimeoutMs',
    flag: '--join-timeout-ms',
    env: 'JOIN_TIMEOUT_MS',
    kind: 'int',
    fallback: 5000,
    min: 10,
    max: 600000,
    help: 'time a new socket has to send join',
  },
  {
    key: 'roomIdleSeconds',
    flag: '--room-idle-seconds',
    env: 'ROOM_IDLE_SECONDS',
    kind: 'int',
    fallback: 60,
    min: 0,
    max: 86400,
    help: 'an empty room is disposed after this long',
  },
  {
    key: 'reconnectSeconds',
    flag: '--reconnect-seconds',
    env: 'RECONNECT_SECONDS',
    kind: 'int',
    fallback: 30,
    min: 0,
    max: 86400,
    help: 'a player reconnecting with its token within this keeps its id',
  },
  {
    key: 'maxRejects',
    flag: '--max-rejects',
    env: 'MAX_REJECTS',
    kind: 'int',
    fallback: 20,
    min: 1,
    max: 100000,
    help: 'invalid messages per heartbeat interval before a client is disconnected',
  },
  {
    key: 'defaultRoom',
    flag: '--default-room',
    env: 'DEFAULT_ROOM',
    kind: 'string',
    fallback: 'lobby',
    help: 'room that always exists and that a join without a room name enters',
  },
  {
    key: 'defaultScene',
    flag: '--default-scene',
    env: 'DEFAULT_SCENE',
    kind: 'string',
    fallback: 'pyramid',
    help: 'scene a new room starts with (a name from SCENES)',
  },
  {
    key: 'roomControls',
    flag: '--room-controls',
    env: 'ROOM_CONTROLS',
    kind: 'bool',
    fallback: true,
    help: 'let every player load scenes, pause, step, reset and set gravity',
  },
  {
    key: 'staticDir',
    flag: '--static-dir',
    env: 'STATIC_DIR',
    kind: 'string',
    fallback: 'dist/client',
    help: 'directory of the built browser client',
  },
  {
    key: 'replayDir',
    flag: '--replay-dir',
    env: 'REPLAY_DIR',
    kind: 'string',
    fallback: 'replays',
    help: 'where rooms write input logs (replay recorder)',
  },
  {
    key: 'record',
    flag: '--record',
    env: 'RECORD',
    kind: 'bool',
    fallback: true,
    help: 'record every room into an input log in the replay directory',
  },
  {
    key: 'replayFsync',
    flag: '--replay-fsync',
    env: 'REPLAY_FSYNC',
    kind: 'string',
    fallback: 'interval',
    help: 'fsync of logs: none, interval (after each flush, at least once a second) or always (every tick)',
  },
  {
    key: 'keyframeTicks',
    flag: '--keyframe-ticks',
    env: 'KEYFRAME_TICKS',
    kind: 'int',
    fallback: 600,
    min: 60,
    max: 216_000,
    help: 'ticks between saved-world keyframes in a log (seek and recovery start points)',
  },
  {
    key: 'keyframeBudget',
    flag: '--keyframe-budget',
    env: 'KEYFRAME_BUDGET',
    kind: 'int',
    fallback: 32,
    min: 0,
    max: 100_000,
    help: 'MB of keyframes a log may hold per hour (a busy room gets fewer keyframes; worlds over 128 KB a proportionally smaller budget); 0 for no limit',
  },
  {
    key: 'replayMaxBytes',
    flag: '--replay-max-bytes',
    env: 'REPLAY_MAX_BYTES',
    kind: 'int',
    fallback: 256 * 1024 * 1024,
    min: 65_536,
    help: 'size at which a room log is closed and a new one started',
  },
  {
    key: 'replayKeep',
    flag: '--replay-keep',
    env: 'REPLAY_KEEP',
    kind: 'int',
    fallback: 200,
    min: 1,
    help: 'logs kept in the replay directory; the oldest closed ones are deleted',
  },
  {
    key: 'recover',
    flag: '--recover',
    env: 'RECOVER',
    kind: 'bool',
    fallback: true,
    help: 'at start, reopen rooms whose log has no clean close (after a crash) where the log ends',
  },
  {
    key: 'logLevel',
    flag: '--log-level',
    env: 'LOG_LEVEL',
    kind: 'string',
    fallback: 'info',
    help: 'pino level: fatal, error, warn, info, debug, trace, silent',
  },
  {
    key: 'stallSeconds',
    flag: '--stall-seconds',
    env: 'STALL_SECONDS',
    kind: 'int',
    fallback: 5,
    min: 1,
    max: 3600,
    help: '/healthz fails when a tick loop has not ticked for this long',
  },
  {
    key: 'drainSeconds',
    flag: '--drain-seconds',
    env: 'DRAIN_SECONDS',
    kind: 'int',
    fallback: 0,
    min: 0,
    max: 300,
    help: 'on SIGTERM, answer /readyz 503 and refuse new sockets this long before closing clients',
  },
  ...SECURITY_SETTINGS,
  {
    key: 'roomTickBudgetMs',
    flag: '--room-tick-budget-ms',
    env: 'ROOM_TICK_BUDGET_MS',
    kind: 'int',
    fallback: 50,
    min: 0,
    max: 1000,
    help: 'a room tick longer than this counts against the room (0 = no budget)',
  },
  {
    key: 'roomOverrunTicks',
    flag: '--room-overrun-ticks',
    env: 'ROOM_OVERRUN_TICKS',
    kind: 'int',
    fallback: 30,
    min: 1,
    max: 60,
    help: 'a room over its tick budget this many times within a second is closed',
  },
  {
    key: 'workers',
    flag: '--workers',
    env: 'WORKERS',
    kind: 'int',
    fallback: Math.min(256, availableParallelism()),
    min: 0,
    max: 256,
    shown: 'one per core',
    help: 'room worker threads, one per core by default; rooms are spread over them (0 = every room on the main thread)',
  },
  {
    key: 'redisUrl',
    flag: '--redis',
    env: 'REDIS_URL',
    kind: 'string',
    fallback: '',
    help: 'redis://HOST:PORT of the room directory shared by several servers (empty: none)',
  },
  {
    key: 'publicUrl',
    flag: '--public-url',
    env: 'PUBLIC_URL',
    kind: 'string',
    fallback: '',
    help: "ws:// or wss:// base URL other servers send this server's players to (default ws://HOST:PORT)",
  },
  {
    key: 'directoryTtlSeconds',
    flag: '--directory-ttl-seconds',
    env: 'DIRECTORY_TTL_SECONDS',
    kind: 'int',
    fallback: 10,
    min: 1,
    max: 3600,
    help: "a dead server's rooms are released after this long",
  },
]

/** A DNS host name (RFC 1123 labels of letters, digits and inner hyphens), for --host. */
const HOST_NAME =
  /^(?=.{1,253}$)[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?)*$/

/** The defaults alone. */
export function defaultConfig(): ServerConfig {
  const config: Record<string, unknown> = {}
  for (const s of SETTINGS) config[s.key] = s.fallback
  return config as unknown as ServerConfig
}

function parseValue(s: Setting, raw: string, source: string): number | string | boolean {
  if (s.kind === 'string') return raw
  if (s.kind === 'bool') {
    if (['1', 'true', 'yes', 'on'].includes(raw)) return true
    if (['0', 'false', 'no', 'off'].includes(raw)) return false
    throw new Error(`${source} must be true or false, got "${raw}"`)
  }
  const n = Number(raw)
  if (
    !/^\d+$/.test(raw) ||
    !Number.isSafeInteger(n) ||
    n < (s.min ?? 0) ||
    n > (s.max ?? Number.MAX_SAFE_INTEGER)
  ) {
    throw new Error(`${source} must be an integer in [${s.min}, ${s.max}], got "${raw}"`)
  }
  return n
}

/** Settings from flags (`--port 8080` or `--port=8080`), then env, then defaults; throws on bad input. */
export function loadConfig(
  argv: readonly string[],
  env: NodeJS.ProcessEnv,
  overrides: Partial<ServerConfig> = {},
): ServerConfig {
  const config = defaultConfig() as unknown as Record<string, unknown>
  for (const s of SETTINGS) {
    const raw = env[s.env]
    if (raw !== undefined && raw !== '') config[s.key] = parseValue(s, raw, s.env)
  }
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i]
    const [flag, inline] = arg.includes('=')
      ? [arg.slice(0, arg.indexOf('=')), arg.slice(arg.indexOf('=') + 1)]
      : [arg, undefined]
    const s = SETTINGS.find((x) => x.flag === flag)
    if (!s) throw new Error(`unknown option ${flag} (try --help)`)
    const raw =
      inline ??
      (s.kind === 'bool' && (argv[i + 1] === undefined || argv[i + 1].startsWith('--')) ? 'true' : argv[++i])
    if (raw === undefined) throw new Error(`${flag} needs a value`)
    config[s.key] = parseValue(s, raw, flag)
  }
  Object.assign(config, overrides)
  const result = config as unknown as ServerConfig
  if (60 % result.snapshotRate !== 0)
    throw new Error(`snapshot rate must divide 60, got ${result.snapshotRate}`)
  if (!ROOM_NAME_PATTERN.test(result.defaultRoom)) {
    throw new Error(`default room must be 1-32 letters, digits, "-" or "_", got "${result.defaultRoom}"`)
  }
  if (!Object.hasOwn(SCENES, result.defaultScene)) {
    throw new Error(
      `default scene must be one of ${Object.keys(SCENES).join(', ')}, got "${result.defaultScene}"`,
    )
  }
  if (result.redisUrl !== '' && !/^rediss?:\/\/[^\s]+$/.test(result.redisUrl)) {
    throw new Error(`redis URL must look like redis://HOST:PORT, got "${result.redisUrl}"`)
  }
  if (result.publicUrl !== '' && !/^wss?:\/\/[^\s/?#]+$/.test(result.publicUrl)) {
    throw new Error(`public URL must be ws://HOST:PORT or wss://HOST (no path), got "${result.publicUrl}"`)
  }
  if (isIP(result.host) === 0 && !HOST_NAME.test(result.host)) {
    throw new Error(`host (--host, HOST) must be an IP address or a host name, got "${result.host}"`)
  }
  if (!FSYNC_MODES.includes(result.replayFsync)) {
    throw new Error(`replay fsync must be one of ${FSYNC_MODES.join(', ')}, got "${result.replayFsync}"`)
  }
  if (!LOG_LEVELS.includes(result.logLevel)) {
    throw new Error(`log level must be one of ${LOG_LEVELS.join(', ')}, got "${result.logLevel}"`)
  }
  checkSecurityConfig(result)
  return result
}

/** The settings as a help text table. */
export function helpText(): string {
  const rows = SETTINGS.map(
    (s) =>
      `  ${`${s.flag} <${s.kind}>`.padEnd(28)} ${s.env.padEnd(22)} ${(s.shown ?? String(s.fallback)).padEnd(12)} ${s.help}`,
  )
  return [
    'Usage: node dist/server.js [options]',
    '',
    `  ${'flag'.padEnd(28)} ${'env'.padEnd(22)} ${'default'.padEnd(12)} meaning`,
    ...rows,
  ].join('\n')
}

/** Unsent bytes at which a client is dropped at once: 8 send-buffer budgets, at least 1 MiB. */
export function hardBufferLimit(config: ServerConfig): number {
  return Math.max(config.sendBufferBytes * 8, 1 << 20)
}
