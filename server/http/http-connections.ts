/*
 * Every TCP connection, before it is HTTP or WebSocket: counted against --max-connections (503
 * beyond) and, per client address (an IPv6 client by its /64: addressKey), against
 * --max-connections-per-ip (429 beyond), so raw sockets
 * that never upgrade take places like real players do. A connection that does not complete its
 * request (or upgrade) within --handshake-timeout-ms is answered 408 and closed by Node's own
 * header and request timers, which tuneHttpTimeouts sets; before, such sockets were held ~70 s.
 * Every request and upgrade also draws on its address's request rate (--max-requests-per-ip,
 * http-request-rate.ts): over it, 429 and the connection is closed.
 */
import type { IncomingMessage, Server, ServerResponse } from 'node:http'
import { isIP, type Socket } from 'node:net'
import type { Duplex } from 'node:stream'
import type { ServerConfig } from '../config/index.ts'
import type { LogLimiter, ServerMetrics } from '../hosting/index.ts'
import { SECURITY_HEADERS } from './http-headers.ts'
import { PENALTY_SECONDS, RequestRate } from './http-request-rate.ts'
import { rawHttpResponse } from './http-request-url.ts'

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

/** What a refused connection may send before it is closed without waiting (bytes: a request's worth). */
const REFUSED_READ_BYTES = 16 * 1024

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

/**
 * Counts open TCP connections, in total and per address, refuses those over the caps, and draws
 * every request and upgrade from its address's request rate.
 */
export class ConnectionGuard {
  private total = 0
  private readonly perAddress = new Map<string, number>()
  /** Each address's connections that are still plain HTTP (not upgraded to WebSocket). */
  private readonly plain = new Map<string, Set<Socket>>()
  private readonly refusedSockets = new WeakSet<Socket>()
  private readonly requests: RequestRate

  constructor(
    private readonly config: ServerConfig,
    private readonly metrics: ServerMetrics,
    private readonly warnings: LogLimiter,
  ) {
    this.requests = new RequestRate(config.maxRequestsPerIp)
  }

  /**
   * True for a connection refused after Node began parsing it (over the request rate): the
   * requests already pipelined behind the refused one still reach the handlers, which call this
   * first and then closeRefused. (A connection refused when it opens is never parsed at all.)
   */
  refused(socket: Socket | Duplex): boolean {
    return this.refusedSockets.has(socket as Socket)
  }

  /**
   * A request arrived pipelined behind a refused one: close the connection now (a client that
   * waits for its answers never gets here), so that Node reads nothing more from it.
   */
  closeRefused(socket: Socket | Duplex): void {
    socket.destroy()
  }

  /**
   * Draw an HTTP request from its address's request rate. Over the rate it is answered 429 with
   * `Connection: close` and false is returned: the connection is closed once the answer is
   * written, and the address's other plain HTTP connections at once (WebSockets stay), since each
   * could hold thousands of pipelined requests for Node to parse.
   */
  admitRequest(req: IncomingMessage, res: ServerResponse): boolean {
    const address = clientAddress(req.socket)
    const key = addressKey(address)
    if (this.requests.take(key)) return true
    this.refuseRequests(req.socket, address, key)
    res.once('finish', () => req.socket.destroy())
    res.writeHead(429, {
      ...SECURITY_HEADERS,
      'content-type': 'text/plain',
      'cache-control': 'no-store',
      'retry-after': String(PENALTY_SECONDS),
      connection: 'close',
    })
    res.end('too many requests from this address\n')
    return false
  }

  /**
   * Draw a WebSocket upgrade from its address's request rate; over it, 429 and false (as
   * admitRequest). An admitted upgrade stops being a plain HTTP connection.
   */
  admitUpgrade(req: IncomingMessage, socket: Duplex): boolean {
    const address = clientAddress(req.socket)
    const key = addressKey(address)
    if (this.requests.take(key)) {
      this.plain.get(key)?.delete(req.socket)
      return true
    }
    this.refuseRequests(req.socket, address, key)
    socket.end(rawHttpResponse(429, 'Too Many Requests', { 'Retry-After': String(PENALTY_SECONDS) }), () =>
      socket.destroy(),
    )
    return false
  }

  /**
   * Refuse the address's requests and upgrades for the penalty (PENALTY_SECONDS): one of its
   * WebSockets was closed for flooding, and each new one would cost a read of frames.
   */
  penalize(address: string): void {
    this.requests.penalize(addressKey(address))
  }

  /** Open TCP connections of one address (of its /64, for an IPv6 address). */
  countOf(address: string): number {
    return this.perAddress.get(addressKey(address)) ?? 0
  }

  /** Open TCP connections in all. */
  get count(): number {
    return this.total
  }

  /**
   * Guard the connections of an HTTP server. Node's own 'connection' listeners (the one that
   * attaches the HTTP parser) run only for admitted connections, so what a refused connection
   * sends is never parsed: one 64 KiB read holds about 1,900 pipelined requests, which took Node
   * about 30 ms to parse and hand to the handlers in a test run.
   */
  attach(http: Server): void {
    const parsers = http.listeners('connection') as Array<(socket: Socket) => void>
    http.removeAllListeners('connection')
    http.on('connection', (socket: Socket) => {
      if (this.admit(socket)) for (const parse of parsers) parse.call(http, socket)
    })
  }

  private admit(socket: Socket): boolean {
    socket.on('error', () => socket.destroy())
    const address = clientAddress(socket)
    const key = addressKey(address)
    const perIp = this.config.maxConnectionsPerIp
    if (this.total >= this.config.maxConnections) {
      this.refuse(socket, address, 503, 'Service Unavailable', 'max-connections')
      return false
    }
    if (perIp > 0 && this.countOf(key) >= perIp) {
      this.refuse(socket, address, 429, 'Too Many Requests', 'max-connections-per-ip')
      return false
    }
    if (!this.requests.allows(key)) {
      this.refuse(socket, address, 429, 'Too Many Requests', 'max-requests-per-ip')
      return false
    }
    this.total++
    this.perAddress.set(key, this.countOf(key) + 1)
    let plain = this.plain.get(key)
    if (!plain) {
      plain = new Set()
      this.plain.set(key, plain)
    }
    plain.add(socket)
    socket.once('close', () => {
      this.total--
      const n = this.countOf(key) - 1
      if (n > 0) this.perAddress.set(key, n)
      else this.perAddress.delete(key)
      const open = this.plain.get(key)
      open?.delete(socket)
      if (open?.size === 0) this.plain.delete(key)
    })
    return true
  }

  /** A connection refused as it opens: answered at once, never parsed. */
  private refuse(socket: Socket, address: string, status: number, text: string, reason: string): void {
    this.countRefusal(address, status, reason)
    const retry = reason === 'max-requests-per-ip' ? PENALTY_SECONDS : 5
    socket.end(rawHttpResponse(status, text, status === 429 ? { 'Retry-After': String(retry) } : {}))
    // What the client sends is read and dropped, so that the close is a FIN it reads after the
    // answer: the socket closes when the client is done, when it sends more than a request's
    // worth, or after 1 s.
    let unread = REFUSED_READ_BYTES
    socket.on('data', (data: Buffer) => {
      unread -= data.length
      if (unread < 0) socket.destroy()
    })
    socket.on('end', () => socket.destroy())
    setTimeout(() => socket.destroy(), 1000).unref()
  }

  /** The address went over its request rate on `socket`: refuse it and close its other HTTP connections. */
  private refuseRequests(socket: Socket, address: string, key: string): void {
    this.refusedSockets.add(socket)
    this.countRefusal(address, 429, 'max-requests-per-ip')
    setTimeout(() => socket.destroy(), 1000).unref()
    for (const other of this.plain.get(key) ?? []) {
      if (other === socket) continue
      this.refusedSockets.add(other)
      other.destroy()
    }
  }

  private countRefusal(address: string, status: number, reason: string): void {
    this.metrics.connectionsRefused.inc({ reason })
    this.warnings.warn(addressKey(address), { address, status, reason }, 'connection refused')
  }
}
