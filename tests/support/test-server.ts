/*
 * Starting a real server for integration tests: in-process on 127.0.0.1 port 0, silent logs,
 * short heartbeats and timeouts so the suite stays fast. Rooms run where they run by default, on
 * one worker thread per core; a test that inspects the rooms themselves (`server.rooms`: worlds,
 * players, the main tick clock) asks for them on the main thread with `inProcessRooms`, and says why.
 */
import pino, { type Logger } from 'pino'
import { loadConfig, type ServerConfig } from '../../server/config/config.ts'
import { type RunningServer, startServer } from '../../server/server.ts'

/**
 * `--workers 0`: every room on the main thread, in `server.rooms`, for tests that read a room's
 * world, players or tick, or drive the main tick clock by hand (rooms on workers are out of reach).
 */
export const inProcessRooms: Partial<ServerConfig> = { workers: 0 }

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
      // close() ends a test, not a planned restart: every log is closed (planned-restart.test.ts
      // runs the real process with the default, --keep-rooms true).
      keepRooms: false,
      heartbeatMs: 1000,
      joinTimeoutMs: 2000,
      roomIdleSeconds: 1,
      staticDir: 'tests/support/fixtures/static',
      logLevel: 'silent',
      ...overrides,
    },
  )
  return startServer(config, {
    logger: logger ?? pino({ level: process.env.TEST_LOG ?? 'silent' }),
    processMetrics: false,
  })
}
