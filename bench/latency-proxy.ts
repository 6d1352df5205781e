/*
 * A TCP proxy on 127.0.0.1 that delays every chunk by a fixed time in each direction: the
 * benchmarks' stand-in for a network path with latency (never part of the product). HTTP and the
 * WebSocket upgrade pass through untouched, so a page loaded from the proxy opens its WebSocket
 * through it too. Chunks keep their order: a constant delay and Node's timers, which fire timers
 * of equal duration in the order they were set.
 */

import { type AddressInfo, connect, createServer, type Server, type Socket } from 'node:net'

/** A running proxy. */
export interface LatencyProxy {
  /** Port the proxy listens on (127.0.0.1). */
  readonly port: number
  /** Stop listening and close every proxied connection. */
  close(): Promise<void>
}

/** Forward `from` to `to`, each chunk `delayMs` later; an end or error closes both sides then. */
function pipeDelayed(from: Socket, to: Socket, delayMs: number): void {
  from.on('data', (chunk) => {
    setTimeout(() => {
      if (!to.destroyed) to.write(chunk)
    }, delayMs)
  })
  from.on('end', () => setTimeout(() => to.end(), delayMs))
  from.on('error', () => to.destroy())
  from.on('close', () => setTimeout(() => to.destroy(), delayMs))
}

/** Listen on a free port and forward to 127.0.0.1:`targetPort` with `delayMs` added each way. */
export async function startLatencyProxy(targetPort: number, delayMs: number): Promise<LatencyProxy> {
  if (!Number.isInteger(targetPort) || targetPort <= 0 || targetPort > 65535)
    throw new Error(`latency proxy: target port ${targetPort} is not a TCP port`)
  if (!Number.isFinite(delayMs) || delayMs < 0)
    throw new Error(`latency proxy: delay ${delayMs} ms is not >= 0`)
  const sockets = new Set<Socket>()
  const server: Server = createServer((client) => {
    const upstream = connect(targetPort, '127.0.0.1')
    for (const s of [client, upstream]) {
      s.setNoDelay(true)
      sockets.add(s)
      s.on('close', () => sockets.delete(s))
    }
    pipeDelayed(client, upstream, delayMs)
    pipeDelayed(upstream, client, delayMs)
  })
  await new Promise<void>((resolve) => server.listen(0, '127.0.0.1', resolve))
  return {
    port: (server.address() as AddressInfo).port,
    close: () =>
      new Promise<void>((resolve) => {
        for (const s of sockets) s.destroy()
        server.close(() => resolve())
      }),
  }
}
