/*
 * Starting a real server for integration tests: in-process on 127.0.0.1 port 0, silent logs,
 * short heartbeats and timeouts so the suite stays fast.
 */
import pino, { type Logger } from 'pino'
import { loadConfig, type ServerConfig } from '../../server/config.ts'
import { type RunningServer, startServer } from '../../server/server.ts'

/** A server for one test file; close it in afterAll. `logger` replaces the silent one (to read its lines). */
export async function startTestServer(
  overrides: Partial<ServerConfig> = {},
  logger?: Logger,
): Promise<RunningServer> {
  const config = loadConfig(
    [],
    {},
    {
      port: 0,
      host: '127.0.0.1',
      defaultScene: 'empty',
      record: false,
      heartbeatMs: 1000,
      joinTimeoutMs: 2000,
      roomIdleSeconds: 1,
      staticDir: 'tests/server/fixtures/static',
      logLevel: 'silent',
      ...overrides,
    },
  )
  return startServer(config, {
    logger: logger ?? pino({ level: process.env.TEST_LOG ?? 'silent' }),
    processMetrics: false,
  })
}
