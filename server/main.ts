/*
 * The server's command line: `node dist/server.js [--port 8080 ...]` (see --help). Starts the
 * server (on a terminal it also prints "Concord sandbox at http://127.0.0.1:8080/" beside the JSON
 * log), and on SIGTERM or SIGINT shuts down gracefully: clients get a close frame with a reason,
 * logs are flushed, and the process exits within 5 s even if something hangs.
 */
import { helpText, loadConfig, type ServerConfig, sandboxBanner } from './config/index.ts'
import { ListenError, startServer } from './server.ts'

/** Hard deadline for shutdown after the drain period (ms). */
const SHUTDOWN_DEADLINE_MS = 4500

async function main(): Promise<void> {
  const argv = process.argv.slice(2)
  if (argv.includes('--help') || argv.includes('-h')) {
    process.stdout.write(`${helpText()}\n`)
    return
  }
  let config: ServerConfig
  try {
    config = loadConfig(argv, process.env)
  } catch (error) {
    process.stderr.write(`concord: ${(error as Error).message}\n`)
    process.exit(2)
  }
  const server = await startServer(config)
  // The JSON log is for machines; a person at a terminal gets the address to open.
  if (process.stdout.isTTY) process.stdout.write(`${sandboxBanner(config.host, server.port)}\n`)
  const shutdown = (signal: string): void => {
    setTimeout(() => process.exit(1), config.drainSeconds * 1000 + SHUTDOWN_DEADLINE_MS).unref()
    server.close(`server shutting down (${signal})`).then(
      () => process.exit(0),
      () => process.exit(1),
    )
  }
  process.once('SIGTERM', () => shutdown('SIGTERM'))
  process.once('SIGINT', () => shutdown('SIGINT'))
}

main().catch((error) => {
  // A listen failure is a bad setting, named in the message; anything else is worth its stack.
  const text = error instanceof ListenError ? error.message : ((error as Error).stack ?? error)
  process.stderr.write(`concord: ${text}\n`)
  process.exit(1)
})
