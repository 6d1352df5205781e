/*
 * Agones (agones.dev) integration through the official Node SDK, @google-cloud/agones-sdk, which
 * speaks gRPC to the SDK sidecar Agones runs beside every GameServer. It is active only when the
 * sidecar's environment variables are present (AGONES_SDK_GRPC_PORT or AGONES_SDK_HTTP_PORT);
 * a plain install never loads it. Lifecycle:
 *   listening        -> Ready()     (the GameServer becomes Ready and can be allocated)
 *   every second     -> Health()    (one message on the Health stream, sent from the tick loop and
 *                                    only while no tick loop is stalled; Agones marks a GameServer
 *                                    that stops pinging Unhealthy and replaces it)
 *   SIGTERM, drained -> Shutdown()  (Agones deletes the GameServer's pod)
 * Why the gRPC SDK rather than the sidecar's REST gateway: it is the SDK Agones publishes and
 * documents for Node, its two dependencies (@grpc/grpc-js, google-protobuf) are Google's own, and
 * the test stand-in (tests/server/hosting/agones.test.ts) serves the SDK package's own service definition.
 */
import type { Logger } from 'pino'

/** True when the Agones SDK sidecar's environment variables are present. */
export function agonesPresent(env: NodeJS.ProcessEnv): boolean {
  return Boolean(env.AGONES_SDK_GRPC_PORT || env.AGONES_SDK_HTTP_PORT)
}

/** The SDK calls the server makes (the official SDK's methods, narrowed). */
interface AgonesClient {
  connect(): Promise<void>
  ready(): Promise<unknown>
  health(errorCallback: (error: unknown) => void): void
  shutdown(): Promise<unknown>
  close(): void
}

/** Errors logged per minute at most (a lost sidecar would otherwise log every second). */
const ERROR_LOG_INTERVAL_MS = 60_000

/** A connection to the Agones SDK sidecar. */
export class AgonesLink {
  /** Ready() has been acknowledged. */
  isReady = false
  /** Health pings sent. */
  pings = 0
  private lastErrorLog = Number.NEGATIVE_INFINITY
  private closed = false

  private constructor(
    private readonly sdk: AgonesClient,
    private readonly log: Logger,
  ) {}

  /** Load the SDK and connect to the sidecar (the SDK waits up to 30 s for it). */
  static async connect(log: Logger): Promise<AgonesLink> {
    const module = (await import('@google-cloud/agones-sdk')) as unknown as {
      default: new () => AgonesClient
    }
    const sdk = new module.default()
    await sdk.connect()
    return new AgonesLink(sdk, log)
  }

  /** Tell Agones this GameServer is Ready. */
  async markReady(): Promise<void> {
    await this.sdk.ready()
    this.isReady = true
    this.log.info('agones: marked Ready')
  }

  /** One health ping (called once a second from the tick loop while healthy). */
  health(): void {
    if (this.closed) return
    this.pings++
    this.sdk.health((error) => this.logError('health ping failed', error))
  }

  /** Ask Agones to shut this GameServer down (after draining), then close the connection. */
  async shutdown(): Promise<void> {
    if (this.closed) return
    try {
      await this.sdk.shutdown()
      this.log.info('agones: Shutdown requested')
    } finally {
      this.close()
    }
  }

  /** Close the gRPC channel. */
  close(): void {
    if (this.closed) return
    this.closed = true
    this.sdk.close()
  }

  private logError(what: string, error: unknown): void {
    const now = Date.now()
    if (now - this.lastErrorLog < ERROR_LOG_INTERVAL_MS) return
    this.lastErrorLog = now
    this.log.warn({ err: error instanceof Error ? error.message : String(error) }, `agones: ${what}`)
  }
}
