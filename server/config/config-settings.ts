/*
 * The one settings table (config.ts reads it, config-security.ts checks its security rows): the
 * ServerConfig it fills, and every setting's flag, environment variable, kind, default, bounds and
 * help line, in the order --help and the README list them.
 */
import { availableParallelism } from 'node:os'
import { DEFAULT_SCENE } from '../../engine/index.ts'

/** Everything the server can be configured with. */
export interface ServerConfig {
  port: number
  host: string
  maxRooms: number
  maxNewRoomsPerIp: number
  maxClientsPerRoom: number
  maxSpectatorsPerRoom: number
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
  gamesDir: string
  replayDir: string
  record: boolean
  replayFsync: string
  keyframeTicks: number
  keyframeBudget: number
  replayMaxBytes: number
  replayKeep: number
  sceneDir: string
  maxSavedScenes: number
  maxSavedSceneBytes: number
  recover: boolean
  keepRooms: boolean
  requireRecording: boolean
  logLevel: string
  stallSeconds: number
  drainSeconds: number
  handshakeTimeoutMs: number
  maxConnectionsPerIp: number
  maxRequestsPerIp: number
  maxMessagesPerSecond: number
  allowedOrigins: string
  joinToken: string
  adminToken: string
  metricsToken: string
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

/**
 * Smallest --replay-max-bytes (4 MiB): a rotated log starts with a header holding the whole saved
 * world: 113 KB deflated for the awake 210-box pyramid (about 540 bytes a body), so about 0.8 MB
 * for a room at the default 1,500 bodies.
 * Below a header's size every tick rotated (65,536 gave 104 files in 2 s). Bigger worlds (a higher
 * --max-bodies) are held back by the recorder instead: a log rotates only once it holds half the
 * limit beyond its header.
 */
export const REPLAY_MAX_BYTES_FLOOR = 4 * 1024 * 1024

/** One row of the settings table. */
export interface Setting {
  key: keyof ServerConfig
  flag: string
  env: string
  kind: Kind
  fallback: number | string | boolean
  min?: number
  max?: number
  /** Why the bounds are what they are, added to the error for a value outside them. */
  bounds?: string
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
    key: 'maxNewRoomsPerIp',
    flag: '--max-new-rooms-per-ip',
    env: 'MAX_NEW_ROOMS_PER_IP',
    kind: 'int',
    fallback: 30,
    min: 0,
    max: 1000000,
    help: 'rooms one client address (IPv6: per /64) may open per minute, 0 = no limit; beyond, the join gets full (4001)',
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
    key: 'maxSpectatorsPerRoom',
    flag: '--max-spectators',
    env: 'MAX_SPECTATORS_PER_ROOM',
    kind: 'int',
    fallback: 64,
    min: 0,
    max: 1000,
    help: 'spectators per room besides its players (join.spectate; 0 = none)',
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
    fallback: DEFAULT_SCENE,
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
    key: 'gamesDir',
    flag: '--games',
    env: 'GAMES_DIR',
    kind: 'string',
    fallback: '',
    help: 'load the game modules in DIR/NAME/index.ts at start, beside the built-in games (docs/games.md)',
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
    min: REPLAY_MAX_BYTES_FLOOR,
    bounds:
      'a new log starts with a header holding the whole saved world (about 0.8 MB for a room of 1,500 awake bodies), and a log must hold several times that',
    help: 'size at which a room log is closed and a new one started (at least 4 MiB)',
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
    key: 'sceneDir',
    flag: '--scene-dir',
    env: 'SCENE_DIR',
    kind: 'string',
    fallback: 'scenes',
    help: 'where saved scene files are kept (docs/scene-format.md)',
  },
  {
    key: 'maxSavedScenes',
    flag: '--max-saved-scenes',
    env: 'MAX_SAVED_SCENES',
    kind: 'int',
    fallback: 1000,
    min: 0,
    max: 1000000,
    help: 'saved scene files kept (4 MiB each at most; the ones used longest ago make way for new ones); 0 turns saving off',
  },
  {
    key: 'maxSavedSceneBytes',
    flag: '--max-saved-scene-bytes',
    env: 'MAX_SAVED_SCENE_BYTES',
    kind: 'int',
    fallback: 268435456,
    min: 65536,
    max: 1099511627776,
    help: 'bytes of saved scene files kept in all (the ones used longest ago make way for new ones)',
  },
  {
    key: 'recover',
    flag: '--recover',
    env: 'RECOVER',
    kind: 'bool',
    fallback: true,
    help: 'at start, reopen rooms whose log has no clean close (after a crash or a planned restart) where the log ends',
  },
  {
    key: 'keepRooms',
    flag: '--keep-rooms',
    env: 'KEEP_ROOMS',
    kind: 'bool',
    fallback: true,
    help: 'on SIGTERM or SIGINT, leave each used room in its log for the next start to reopen (with --record and --recover); false: close every log, start afresh',
  },
  {
    key: 'requireRecording',
    flag: '--require-recording',
    env: 'REQUIRE_RECORDING',
    kind: 'bool',
    fallback: false,
    help: 'with --record, /readyz answers 503 (naming why) while the replay directory cannot be written',
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
  // Security (config-security.ts checks them at startup).
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
