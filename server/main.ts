/*
 * The server's command line: `node dist/server.js [--port 8080 ...]` (see --help). Starts the
 * server (on a terminal it also prints "Concord sandbox at http://127.0.0.1:8080/" beside the JSON
 * log), and on SIGTERM or SIGINT shuts down gracefully: clients get a close frame with a reason,
 * logs are flushed (with --keep-rooms, every used room's log is left for the next start to reopen:
 * Recordings.closeAll), and the process exits within 5 s even if something hangs. A second signal
 * during the shutdown is logged and ignored; a third exits at once (code 130).
 */
import { helpText, loadConfig, type ServerConfig, sandboxBanner } from './config/index.ts'
import { ListenError, type RunningServer, startServer } from './server.ts'

/** Hard deadline for shutdown after the drain period (ms). */
const SHUTDOWN_DEADLINE_MS = 4500

/** Exit code after a third signal cut a shutdown short (128 + SIGINT, as a shell reports Ctrl-C). */
const FORCED_EXIT_CODE = 130

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
  // The signal handlers come first: a SIGTERM between the 'listening' line (logged inside
  // startServer) and the end of startup used to get Node's default action and end the process
  // with no shutdown at all. A signal during startup is kept and acted on once the server exists.
  let server: RunningServer | undefined
  let early: NodeJS.Signals | undefined
  process.on('SIGTERM', (signal) => (server ? onSignal(signal) : (early ??= signal)))
  process.on('SIGINT', (signal) => (server ? onSignal(signal) : (early ??= signal)))
  const running = await startServer(config)
  server = running
  // The JSON log is for machines; a person at a terminal gets the address to open.
  if (process.stdout.isTTY) process.stdout.write(`${sandboxBanner(config.host, running.port)}\n`)
  const shutdown = (signal: string): void => {
    setTimeout(() => process.exit(1), config.drainSeconds * 1000 + SHUTDOWN_DEADLINE_MS).unref()
    running.close(`server shutting down (${signal})`).then(
      () => process.exit(0),
      () => process.exit(1),
    )
  }
  // A terminal's Ctrl-C reaches `npm start` and Node together and npm passes its signal on: Node
  // sees two. The second must not end the shutdown the first began (clients would get no close
  // reason, and logs would end wherever the process stopped instead of closed, or kept for the next
  // start at a checkpoint at their last tick); a third ends the process at once, saying so.
  let signals = 0
  const onSignal = (signal: NodeJS.Signals): void => {
    signals++
    if (signals === 1) shutdown(signal)
    else if (signals === 2)
      running.log.warn(
        { signal },
        'already shutting down; a third signal ends the process without closing logs',
      )
    else {
      running.log.error(
        { signal },
        'third signal during shutdown: exiting now; logs without a clean close are reopened at the next start',
      )
      running.log.flush()
      process.exit(FORCED_EXIT_CODE)
    }
  }
  if (early) onSignal(early)
}

main().catch((error) => {
  // A listen failure or a refused game module (--games) is a bad setting or file, named in the
  // message; anything else is worth its stack. (The loader is a bundle of its own in dist/, so its
  // GameLoadError is recognised by name.)
  const named = error instanceof ListenError || (error as Error)?.name === 'GameLoadError'
  const text = named ? (error as Error).message : ((error as Error).stack ?? error)
  process.stderr.write(`concord: ${text}\n`)
  process.exit(1)
})
