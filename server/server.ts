/*
 * The server as a value: startServer(config) opens one HTTP server that carries the static client,
 * the probes, /metrics, /rooms, /replays and the WebSocket endpoint, reopens rooms from logs left
 * by a crash (recordings.ts), starts the room clock and the default room, and returns a handle whose
 * close() shuts everything down gracefully: stop accepting, tell clients why, stop the clock, close
 * every log cleanly, close the listener. main.ts wires it to the command line and
 * signals; the tests start it in-process on port 0.
 */
import { createServer, type Server } from 'node:http'
import type { AddressInfo } from 'node:net'
import { hostname } from 'node:os'
import pino, { type Logger } from 'pino'
import { CLOSE_CODES, TICK_RATE } from '../shared/index.ts'
import type { ServerConfig } from './config/index.ts'
import { addLoadedGames, loadedGameBundle, loadedGameBundles, loadGameDirectory } from './games/index.ts'
import {
  AgonesLink,
  agonesPresent,
  createMetrics,
  RoomDirectory,
  type ServerMetrics,
  TickHealth,
} from './hosting/index.ts'
import {
  ConnectionGuard,
  checkAccess,
  checkKeyedRoute,
  checkMetricsAccess,
  createRequestHandler,
  rawHttpResponse,
  SECURITY_HEADERS,
  timeoutCheckInterval,
  tuneHttpTimeouts,
} from './http/index.ts'
import { Transport } from './net/index.ts'
import { Recordings } from './replay/index.ts'
import { LocalRoomHost, type RoomHost, RoomManager } from './rooms/index.ts'
import { SceneStore } from './scenes/index.ts'
import { WorkerPool } from './workers/index.ts'

/** A running server. */
export interface RunningServer {
  /** The port actually bound (useful with port 0). */
  port: number
  url: string
  config: ServerConfig
  http: Server
  /** The rooms on this thread (all of them with --workers 0, none otherwise). */
  rooms: RoomManager
  /** Where rooms run: this thread's RoomManager or the worker pool. */
  host: RoomHost
  /** The room worker threads (--workers N), or null. */
  pool: WorkerPool | null
  /** The room recorders and the replay directory. */
  recordings: Recordings
  transport: Transport
  /** Every TCP connection, counted against the caps. */
  guard: ConnectionGuard
  metrics: ServerMetrics
  log: Logger
  /** Liveness of the tick loops (/healthz). */
  health: TickHealth
  /** The shared room directory (--redis), or null. */
  directory: RoomDirectory | null
  /** The Agones SDK link once connected (only under Agones), else null. */
  agones: () => AgonesLink | null
  /** Graceful shutdown: close clients with a reason, stop ticking, stop listening. */
  close(reason?: string): Promise<void>
}

/** Options beyond the config. */
export interface StartOptions {
  logger?: Logger
  /** Collect Node process metrics (off in tests that start many servers). */
  processMetrics?: boolean
  /** Environment to look for the Agones sidecar in (default process.env). */
  env?: NodeJS.ProcessEnv
}

/** Ends the close reason of a shutdown that keeps the rooms (PROTOCOL.md, close code 1001). */
const KEEP_NOTE = '; rooms are saved and reopen when the server is back'

/** How long shutdown waits for the Agones sidecar to acknowledge Shutdown() (ms). */
const AGONES_SHUTDOWN_WAIT_MS = 1000

/** Start a server; resolves once it listens. */
export async function startServer(config: ServerConfig, options: StartOptions = {}): Promise<RunningServer> {
  const log = options.logger ?? pino({ level: config.logLevel })
  // Games from --games DIR first: a bad module stops the start before anything opens.
  if (config.gamesDir) {
    const loaded = await loadGameDirectory(config.gamesDir)
    addLoadedGames(loaded)
    log.info({ dir: config.gamesDir, games: loaded.map((g) => g.game.name) }, 'games loaded')
  }
  const metrics = createMetrics(options.processMetrics ?? true)
  const rooms = new RoomManager(config, metrics, log)
  const recordings = new Recordings(config, metrics, log)
  const health = new TickHealth(config.stallSeconds * 1000)
  const pool =
    config.workers > 0
      ? new WorkerPool(config, metrics, log, health, recordings, config.workers, loadedGameBundles())
      : null
  const host: RoomHost = pool ?? new LocalRoomHost(rooms, config.maxRooms)
  // Listen only once every worker runs its loop: a booting worker is neither joinable nor healthy.
  await pool?.ready.catch(async (error: Error) => {
    await pool.stop('a room worker failed to start')
    throw error
  })
  // With workers, the worker that holds a crashed room's new copy rebuilds it from the log.
  await recordings.start(rooms, pool ? (room, logName) => pool.reopen(room, logName) : undefined)
  const transport = new Transport(config, host, metrics, log)
  const directory = config.redisUrl
    ? new RoomDirectory(config.redisUrl, config.directoryTtlSeconds * 1000, log)
    : null
  await directory?.connect()
  let agones: AgonesLink | null = null
  rooms.onTick = (tick) => {
    health.beat('main')
    // Agones health: once a second, from the tick loop, only while no loop is stalled.
    if (agones && tick % TICK_RATE === 0 && health.problem() === null) agones.health()
  }
  let ready = true
  const guard = new ConnectionGuard(config, metrics, transport.warnings)
  transport.policy.onFlood = (address) => guard.penalize(address)
  const routes = createRequestHandler({
    staticDir: config.staticDir,
    gameBundle: (name) => loadedGameBundle(name)?.code,
    rooms: host,
    recordings,
    scenes: new SceneStore(config.sceneDir, config.maxSavedScenes, config.maxSavedSceneBytes),
    keyAccess: (url, what) => checkKeyedRoute(config, url, what),
    metricsAccess: (req) => checkMetricsAccess(config, req),
    wsAccess: (req, url) => {
      const decision = checkAccess(config, req, url, url.searchParams.get('room') ?? '')
      return decision.ok ? { controls: decision.access.controls } : decision
    },
    metrics,
    metricsText: pool ? () => pool.metricsText() : undefined,
    log,
    notReady: () => {
      if (!ready) return 'shutting down'
      return config.requireRecording ? recordings.problem : null
    },
    health: () => health.problem(),
  })
  const http = createServer({ connectionsCheckingInterval: timeoutCheckInterval(config) }, (req, res) => {
    if (guard.refused(req.socket)) return guard.closeRefused(req.socket)
    if (!guard.admitRequest(req, res)) return
    try {
      routes(req, res)
    } catch (error) {
      // A request must never end the process; the route is a bug to fix, the client gets a 500.
      log.error({ err: error, url: req.url }, 'request handler failed')
      if (!res.headersSent) res.writeHead(500, SECURITY_HEADERS)
      res.end()
    }
  })
  tuneHttpTimeouts(http, config)
  guard.attach(http)
  http.on('upgrade', (req, socket, head) => {
    if (guard.refused(socket)) return guard.closeRefused(socket)
    if (!guard.admitUpgrade(req, socket)) return
    transport.handleUpgrade(req, socket, head)
  })
  http.on('connect', (_req, socket) => {
    // CONNECT (a proxy tunnel request): this is not a proxy. Without a listener Node closed the
    // socket without an answer.
    if (guard.refused(socket)) return guard.closeRefused(socket)
    socket.end(rawHttpResponse(405, 'Method Not Allowed', { Allow: 'GET, HEAD' }))
    setTimeout(() => socket.destroy(), 1000).unref()
  })
  http.on('clientError', (error: NodeJS.ErrnoException, socket) => {
    // Unparseable requests and Node's own timeouts: answer when the socket can still take it.
    if (socket.writable && !guard.refused(socket)) {
      const timeout = error.code === 'ERR_HTTP_REQUEST_TIMEOUT'
      socket.end(timeout ? rawHttpResponse(408, 'Request Timeout') : rawHttpResponse(400, 'Bad Request'))
      setTimeout(() => socket.destroy(), 1000).unref()
    } else socket.destroy()
  })
  if (!config.redisUrl) host.open(config.defaultRoom)
  health.beat('main')
  rooms.clock.start()
  await new Promise<void>((resolve, reject) => {
    const refused = (error: Error): void =>
      reject(
        new ListenError(`cannot listen on --host ${config.host} --port ${config.port}: ${error.message}`),
      )
    http.once('error', refused)
    http.listen(config.port, config.host, () => {
      http.off('error', refused)
      resolve()
    })
  })
  const port = (http.address() as AddressInfo).port
  if (directory) {
    // Several servers share rooms: the default room too is opened only by the server that claims it.
    const shared = directory
    await shared.register(publicUrl(config, port))
    transport.directory = shared
    const release = (name: string): void => void shared.release(name).catch(() => {})
    rooms.onRoomDisposed = release
    if (pool) pool.onRoomDisposed = release
    shared.onLost = (name, url) => transport.moveRoom(name, url)
    if ((await shared.claim(config.defaultRoom)).holder === 'self') host.open(config.defaultRoom)
  }
  log.info({ port, host: config.host }, 'listening')
  const env = options.env ?? process.env
  if (agonesPresent(env)) {
    // Not awaited: the SDK waits up to 30 s for the sidecar; shutdown uses the link once connected.
    AgonesLink.connect(log)
      .then(async (link) => {
        agones = link
        if (config.requireRecording && recordings.problem) {
          // As /readyz: a GameServer that must record and cannot is never offered to players.
          log.error({ problem: recordings.problem }, 'agones: not marking Ready: --require-recording')
          return
        }
        if (!closing) await link.markReady()
      })
      .catch((error: Error) =>
        log.error({ err: error.message }, 'agones: cannot reach the SDK sidecar or mark Ready'),
      )
  }
  let closing: Promise<void> | null = null
  const close = (why = 'server shutting down'): Promise<void> => {
    closing ??= (async () => {
      // A planned stop keeps every used room for the next start, when that start can reopen it
      // (Recordings.closeAll); the players are told so.
      const keep = recordings.keepsRooms
      const reason = keep ? `${why}${KEEP_NOTE}` : why
      ready = false
      transport.accepting = false
      log.info({ reason, drainSeconds: config.drainSeconds }, 'shutting down')
      // Draining: /readyz answers 503 and new sockets are refused while load balancers notice.
      if (config.drainSeconds > 0)
        await new Promise((resolve) => setTimeout(resolve, config.drainSeconds * 1000))
      const listenerClosed = new Promise<void>((resolve) => http.close(() => resolve()))
      await transport.closeAll(CLOSE_CODES.goingAway, reason, 2000)
      rooms.clock.stop()
      health.remove('main')
      await pool?.stop(reason, keep)
      await recordings.closeAll(reason, keep)
      http.closeAllConnections()
      await listenerClosed
      await directory?.close()
      if (agones) {
        const link: AgonesLink = agones
        const timeout = new Promise<void>((resolve) => setTimeout(resolve, AGONES_SHUTDOWN_WAIT_MS).unref())
        await Promise.race([
          link
            .shutdown()
            .catch((error: Error) => log.error({ err: error.message }, 'agones: Shutdown failed')),
          timeout,
        ])
        link.close()
      }
      log.info('closed')
      log.flush()
    })()
    return closing
  }
  return {
    port,
    url: `http://${config.host}:${port}`,
    config,
    http,
    rooms,
    host,
    pool,
    recordings,
    transport,
    guard,
    metrics,
    log,
    health,
    directory,
    agones: () => agones,
    close,
  }
}

/**
 * The server could not listen where its settings say (a --host that does not resolve or is not an
 * address of this machine, a --port in use): the command line prints its one-line message.
 */
export class ListenError extends Error {}

/** The URL other servers send this server's players to: --public-url, else ws://HOST:PORT. */
function publicUrl(config: ServerConfig, port: number): string {
  if (config.publicUrl) return config.publicUrl
  const host = config.host === '0.0.0.0' || config.host === '::' ? hostname() : config.host
  return `ws://${host.includes(':') ? `[${host}]` : host}:${port}`
}
