/*
 * Every TCP connection, before it is HTTP or WebSocket: counted against --max-connections (503
 * beyond) and, per client address (an IPv6 client by its /64: addressKey), against
 * --max-connections-per-ip (429 beyond), so raw sockets
 * that never upgrade take places like real players do. A connection that does not complete its
 * request (or upgrade) within --handshake-timeout-ms is answered 408 and closed by Node's own
 * header and request timers, which tuneHttpTimeouts sets; before, such sockets were held ~70 s.
 */
import type { Server } from 'node:http'
import { isIP, type Socket } from 'node:net'
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

/** The eight 16-bit groups of an IPv6 address (compressed, zone id or IPv4 tail allowed), or null. */
function ipv6Groups(address: string): number[] | null {
  let text = address.split('%')[0]
  if (isIP(text) !== 6) return null
  const cut = text.lastIndexOf(':')
  if (text.includes('.')) {
    // An IPv4 tail (::ffff:1.2.3.4) is the last two groups.
    const [a, b, c, d] = text
      .slice(cut + 1)
      .split('.')
      .map(Number)
    text = `${text.slice(0, cut + 1)}${((a << 8) | b).toString(16)}:${((c << 8) | d).toString(16)}`
  }
  const [head, tail] = text.split('::')
  const parse = (part: string | undefined): number[] =>
    part ? part.split(':').map((g) => Number.parseInt(g, 16)) : []
  const front = parse(head)
  const back = parse(tail)
  return [...front, ...new Array<number>(8 - front.length - back.length).fill(0), ...back]
}

/**
 * What the per-address limits count a client address as: an IPv4 address as itself (also when
 * IPv4-mapped, ::ffff:1.2.3.4), an IPv6 address as its /64 prefix ("2001:db8:0:1::/64"), since one
 * subscriber usually holds a whole /64 and could otherwise take a fresh address per connection.
 * Anything else (no address) as it is.
 */
export function addressKey(address: string): string {
  if (isIP(address) === 4) return address
  const groups = ipv6Groups(address)
  if (!groups) return address
  if (groups.slice(0, 5).every((g) => g === 0) && groups[5] === 0xffff) {
    return [groups[6] >> 8, groups[6] & 0xff, groups[7] >> 8, groups[7] & 0xff].join('.')
  }
  return `${groups
    .slice(0, 4)
    .map((g) => g.toString(16))
    .join(':')}::/64`
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

  /** Open TCP connections of one address (of its /64, for an IPv6 address). */
  countOf(address: string): number {
    return this.perAddress.get(addressKey(address)) ?? 0
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
    const key = addressKey(address)
    const perIp = this.config.maxConnectionsPerIp
    if (this.total >= this.config.maxConnections) {
      this.refuse(socket, address, 503, 'Service Unavailable', 'max-connections')
      return
    }
    if (perIp > 0 && this.countOf(key) >= perIp) {
      this.refuse(socket, address, 429, 'Too Many Requests', 'max-connections-per-ip')
      return
    }
    this.total++
    this.perAddress.set(key, this.countOf(key) + 1)
    socket.once('close', () => {
      this.total--
      const n = this.countOf(key) - 1
      if (n > 0) this.perAddress.set(key, n)
      else this.perAddress.delete(key)
    })
  }

  private refuse(socket: Socket, address: string, status: number, text: string, reason: string): void {
    this.refusedSockets.add(socket)
    this.metrics.connectionsRefused.inc({ reason })
    this.warnings.warn(addressKey(address), { address, status, reason }, 'connection refused')
    // Answer at once. The socket is destroyed once its request has been read (closeRefused), so
    // the close is a FIN the client reads after the answer, or after 1 s for a silent socket.
    socket.end(rawHttpResponse(status, text, status === 429 ? { 'Retry-After': '5' } : {}))
    setTimeout(() => socket.destroy(), 1000).unref()
  }
}
