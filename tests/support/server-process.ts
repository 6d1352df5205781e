/*
 * Starting server/main.ts in its own Node process (through tsx, as `npm start` runs the built
 * server) for tests that need a real process: signals, crashes, restarts. Its stdout log lines
 * (pino JSON) are collected so a test can wait for one.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { createInterface } from 'node:readline'

/** One pino log line of the child. */
export type LogLine = { msg?: string } & Record<string, unknown>

/** A running server process. */
export interface ServerProcess {
  process: ChildProcess
  port: number
  /** http://127.0.0.1:PORT */
  url: string
  /** Every stdout log line so far. */
  lines: LogLine[]
  /** Resolves with the exit code (null after a signal) and the signal. */
  exited: Promise<{ code: number | null; signal: NodeJS.Signals | null }>
}

/**
 * Start the server with `args` (after `--port 0 --log-level info`) and extra environment; resolves
 * once it logs "listening". Rejects if it exits first, or, given `listenTimeoutMs`, kills it and
 * rejects when it has not listened by then (a server that hangs at startup). `user` runs it as
 * another uid and gid (a test running as root standing in for a container's unprivileged user).
 */
export function startServerProcess(
  args: string[] = [],
  env: Record<string, string> = {},
  listenTimeoutMs?: number,
  user?: { uid: number; gid: number },
): Promise<ServerProcess> {
  const proc = spawn(
    process.execPath,
    ['--import', 'tsx', 'server/main.ts', '--port', '0', '--log-level', 'info', ...args],
    {
      stdio: ['ignore', 'pipe', 'inherit'],
      env: { ...process.env, ...env },
      ...user,
    },
  )
  const lines: LogLine[] = []
  const exited = new Promise<{ code: number | null; signal: NodeJS.Signals | null }>((resolve) =>
    proc.once('exit', (code, signal) => resolve({ code, signal })),
  )
  return new Promise((resolve, reject) => {
    exited.then(({ code, signal }) =>
      reject(new Error(`server exited early (code ${code}, signal ${signal})`)),
    )
    const timer =
      listenTimeoutMs === undefined
        ? undefined
        : setTimeout(() => {
            reject(new Error(`server did not listen within ${listenTimeoutMs} ms`))
            proc.kill('SIGKILL')
          }, listenTimeoutMs)
    createInterface({ input: proc.stdout! }).on('line', (text) => {
      let entry: LogLine
      try {
        entry = JSON.parse(text) as LogLine
      } catch {
        return
      }
      lines.push(entry)
      if (entry.msg === 'listening' && typeof entry.port === 'number') {
        clearTimeout(timer)
        resolve({ process: proc, port: entry.port, url: `http://127.0.0.1:${entry.port}`, lines, exited })
      }
    })
  })
}
