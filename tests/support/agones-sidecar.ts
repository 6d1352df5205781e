/*
 * A stand-in for the Agones SDK sidecar for tests: a gRPC server on 127.0.0.1 that serves the
 * agones.dev.sdk.SDK service from the official SDK package's own generated service definition
 * (lib/sdk_grpc_pb.js, the same one the client side uses), so it speaks exactly the wire protocol
 * the real sidecar speaks. It records every Ready, Health message and Shutdown it receives.
 */
import { createRequire } from 'node:module'
import { Server, ServerCredentials, type ServerWritableStream, type ServiceDefinition } from '@grpc/grpc-js'

const require = createRequire(import.meta.url)
const services = require('@google-cloud/agones-sdk/lib/sdk_grpc_pb.js') as Record<string, ServiceDefinition>
const messages = require('@google-cloud/agones-sdk/lib/sdk_pb.js') as { Empty: new () => unknown }

/** One call the stand-in received. */
export interface SidecarCall {
  method: 'Ready' | 'Health' | 'Shutdown'
  at: number
}

type Unary = (call: unknown, callback: (error: Error | null, response: unknown) => void) => void

/** A running stand-in sidecar. */
export interface FakeSidecar {
  port: number
  calls: SidecarCall[]
  count(method: SidecarCall['method']): number
  /** Run when Shutdown arrives, before it is answered. */
  onShutdown: (() => void) | null
  stop(): Promise<void>
}

/** Start the stand-in on a free port of 127.0.0.1. */
export async function startFakeSidecar(): Promise<FakeSidecar> {
  const server = new Server()
  const calls: SidecarCall[] = []
  const sidecar: FakeSidecar = {
    port: 0,
    calls,
    count: (method) => calls.filter((c) => c.method === method).length,
    onShutdown: null,
    stop: () => new Promise((resolve) => server.tryShutdown(() => resolve())),
  }
  const unary =
    (method: 'Ready' | 'Shutdown'): Unary =>
    (_call, callback) => {
      calls.push({ method, at: Date.now() })
      if (method === 'Shutdown') sidecar.onShutdown?.()
      callback(null, new messages.Empty())
    }
  const notImplemented: Unary = (_call, callback) =>
    callback(new Error('not implemented by the stand-in'), null)
  const handlers: Record<string, unknown> = {}
  for (const name of Object.keys(services['agones.dev.sdk.SDK'])) handlers[name] = notImplemented
  handlers.ready = unary('Ready')
  handlers.shutdown = unary('Shutdown')
  handlers.health = (
    call: ServerWritableStream<unknown, unknown> & NodeJS.ReadableStream,
    callback: (e: Error | null, r: unknown) => void,
  ) => {
    call.on('data', () => calls.push({ method: 'Health', at: Date.now() }))
    call.on('end', () => callback(null, new messages.Empty()))
    call.on('error', () => {})
  }
  server.addService(services['agones.dev.sdk.SDK'], handlers as never)
  sidecar.port = await new Promise<number>((resolve, reject) =>
    server.bindAsync('127.0.0.1:0', ServerCredentials.createInsecure(), (error, port) =>
      error ? reject(error) : resolve(port),
    ),
  )
  return sidecar
}
