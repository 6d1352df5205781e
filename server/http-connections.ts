/*
 * Every TCP connection, before it is HTTP or WebSocket: counted against --max-connections (503
 * beyond) and, per client address, against --max-connections-per-ip (429 beyond), so raw sockets
 * that never upgrade take places like real players do. A connection that does not complete its
 * request (or upgrade) within --handshake-timeout-ms is answered 408 and closed by Node's own
 * header and request timers, which tuneHttpTimeouts sets; before, such sockets were held ~70 s.
 */
import type { Server } from 'node:http'
import type { Socket } from 'node:net'
import type { Duplex } from 'node:stream'
import type { ServerConfig } from './config.ts'
import { rawHttpResponse } from './http-request-url.ts'
import type { LogLimiter } from './log-limiter.ts'
import type { ServerMetrics } from './metrics.ts'

/** An IPv4 client seen through an IPv6 socket ("::ffff:1.2.3.4") counts as 1.2.3.4. */
export function clientAddress(socket: Socket): string {
  const address = socket.remoteAddress ?? 'unknown'
  return address.startsWith('::ffff:') ? address.slice(7) : address
}

/** Set Node's header, request and keep-alive timers from the handshake timeout. */
export function tuneHttpTimeouts(http: Server, config: ServerConfig): void {
  http.headersTimeout = config.handshakeTimeoutMs
  http.requestTimeout = config.handshakeTimeoutMs * 2
  http.keepAliveTimeout = Math.min(5000, config.handshakeTimeoutMs)
}

/** How often Node checks the header and request timers (ms); its default is 30 s. */
export function timeoutCheckInterval(config: ServerConfig): number {
  return Math.max(50, Math.min(1000, Math.floor(config.handshakeTimeoutMs / 4)))
}

/** Counts open TCP connections, in total and per address, and refuses those over the caps. */
export class ConnectionGuard {
  private total = 0
  private readonly perAddress = new Map<string, number>()
  private readonly refusedSockets = new WeakSet<Socket>()

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly warnings: LogLimiter,
  ) {}

  /**
   * True for a connection already answered 429 or 503: Node still parses what it sends, so the
   * request and upgrade handlers call this first and do nothing more (the socket closes itself).
   */
  refused(socket: Socket | Duplex): boolean {
    return this.refusedSockets.has(socket as Socket)
  }

  /** Close a refused connection whose request Node has read (its answer was written at connect). */
  closeRefused(socket: Socket | Duplex): void {
    if (socket.writableFinished) socket.destroy()
    else socket.once('finish', () => socket.destroy())
  }

  /** Open TCP connections of one address. */
  countOf(address: string): number {
    return this.perAddress.get(address) ?? 0
  }

  /** Open TCP connections in all. */
  get count(): number {
    return this.total
  }

  /** Start counting the connections of an HTTP server. */
  attach(http: Server): void {
    http.on('connection', (socket: Socket) => this.admit(socket))
  }

  private admit(socket: Socket): void {
    socket.on('error', () => socket.destroy())
    const address = clientAddress(socket)
    const perIp = this.config.maxConnectionsPerIp
    if (this.total >= this.config.maxConnections) {
      this.refuse(socket, address, 503, 'Service Unavailable', 'max-connections')
      return
    }
    if (perIp > 0 && this.countOf(address) >= perIp) {
      this.refuse(socket, address, 429, 'Too Many Requests', 'max-connections-per-ip')
      return
    }
    this.total++
    this.perAddress.set(address, this.countOf(address) + 1)
    socket.once('close', () => {
      this.total--
      const n = this.countOf(address) - 1
      if (n > 0) this.perAddress.set(address, n)
      else this.perAddress.delete(address)
    })
  }

  private refuse(socket: Socket, address: string, status: number, text: string, reason: string): void {
    this.refusedSockets.add(socket)
    this.metrics.connectionsRefused.inc({ reason })
    this.warnings.warn(address, { address, status, reason }, 'connection refused')
    // Answer at once. The socket is destroyed once its request has been read (closeRefused), so
    // the close is a FIN the client reads after the answer, or after 1 s for a silent socket.
    socket.end(rawHttpResponse(status, text, status === 429 ? { 'Retry-After': '5' } : {}))
    setTimeout(() => socket.destroy(), 1000).unref()
  }
}
