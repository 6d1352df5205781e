/*
 * The server as a value: startServer(config) opens one HTTP server that carries the static client,
 * the probes, /metrics, /rooms and the WebSocket endpoint, starts the room clock and the default
 * room, and returns a handle whose close() shuts everything down gracefully: stop accepting, tell
 * clients why, stop the clock, close the listener. main.ts wires it to the command line and
 * signals; the tests start it in-process on port 0.
 */
import { createServer, type Server } from 'node:http'
import type { AddressInfo } from 'node:net'
import pino, { type Logger } from 'pino'
import { CLOSE_CODES } from '../shared/index.ts'
import type { ServerConfig } from './config.ts'
import { createRequestHandler } from './http-routes.ts'
import { createMetrics, type ServerMetrics } from './metrics.ts'
import { RoomManager } from './room-manager.ts'
import { Transport } from './transport.ts'

/** A running server. */
export interface RunningServer {
  /** The port actually bound (useful with port 0). */
  port: number
  url: string
  config: ServerConfig
  http: Server
  rooms: RoomManager
  transport: Transport
  metrics: ServerMetrics
  log: Logger
  /** Graceful shutdown: close clients with a reason, stop ticking, stop listening. */
  close(reason?: string): Promise<void>
}

/** Options beyond the config. */
export interface StartOptions {
  logger?: Logger
  /** Collect Node process metrics (off in tests that start many servers). */
  processMetrics?: boolean
}

/** Start a server; resolves once it listens. */
export async function startServer(config: ServerConfig, options: StartOptions = {}): Promise<RunningServer> {
  const log = options.logger ?? pino({ level: config.logLevel })
  const metrics = createMetrics(options.processMetrics ?? true)
  const rooms = new RoomManager(config, metrics, log)
  const transport = new Transport(config, rooms, metrics, log)
  let ready = true
  const http = createServer(
    createRequestHandler({ staticDir: config.staticDir, rooms, metrics, log, ready: () => ready }),
  )
  http.on('upgrade', (req, socket, head) => transport.handleUpgrade(req, socket, head))
  http.on('clientError', (_error, socket) => socket.destroy())
  rooms.getOrCreate(config.defaultRoom)
  rooms.clock.start()
  await new Promise<void>((resolve, reject) => {
    http.once('error', reject)
    http.listen(config.port, config.host, () => {
      http.off('error', reject)
      resolve()
    })
  })
  const port = (http.address() as AddressInfo).port
  log.info({ port, host: config.host }, 'listening')
  let closing: Promise<void> | null = null
  const close = (reason = 'server shutting down'): Promise<void> => {
    closing ??= (async () => {
      ready = false
      log.info({ reason }, 'shutting down')
      const listenerClosed = new Promise<void>((resolve) => http.close(() => resolve()))
      await transport.closeAll(CLOSE_CODES.goingAway, reason, 2000)
      rooms.clock.stop()
      http.closeAllConnections()
      await listenerClosed
      log.info('closed')
      log.flush()
    })()
    return closing
  }
  return { port, url: `http://${config.host}:${port}`, config, http, rooms, transport, metrics, log, close }
}
