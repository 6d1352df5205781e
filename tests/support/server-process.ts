/*
 * Starting server/main.ts in its own Node process (through tsx, as `npm start` runs the built
 * server) for tests that need a real process: signals, crashes, restarts. Its stdout log lines
 * (pino JSON) are collected so a test can wait for one.
 *
 * A server given neither `--replay-dir` nor `--record` records into one temporary folder per test
 * process (shared by the servers a test file starts, so a restarted server recovers its rooms as it
 * would in production), never into the repository's replays/, where `npm start` would recover the
 * tests' rooms as its own (a fresh clone's `npm test` left 8 logs there, lobby's among them).
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { mkdirSync, readdirSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { createInterface } from 'node:readline'

/** The test processes' replay folders: one per process, named by its pid. */
const TEST_REPLAYS = join(tmpdir(), 'concord-test-replays')
let testReplayDir: string | null = null

/**
 * This test process's replay folder, made at first use. Vitest ends its worker processes without
 * their exit handlers, so each first use also removes the folders of processes no longer running.
 */
function replayDirOfTests(): string {
  if (testReplayDir !== null) return testReplayDir
  mkdirSync(TEST_REPLAYS, { recursive: true })
  for (const name of readdirSync(TEST_REPLAYS))
    if (!running(Number(name))) rmSync(join(TEST_REPLAYS, name), { recursive: true, force: true })
  testReplayDir = join(TEST_REPLAYS, String(process.pid))
  mkdirSync(testReplayDir, { recursive: true })
  return testReplayDir
}

/** Whether a process with this pid runs (signal 0 checks without sending anything). */
function running(pid: number): boolean {
  if (!Number.isInteger(pid) || pid <= 0) return false
  try {
    process.kill(pid, 0)
    return true
  } catch (error) {
    return (error as NodeJS.ErrnoException).code === 'EPERM'
  }
}

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
  const recording =
    args.includes('--replay-dir') || args.includes('--record') ? [] : ['--replay-dir', replayDirOfTests()]
  const proc = spawn(
    process.execPath,
    ['--import', 'tsx', 'server/main.ts', '--port', '0', '--log-level', 'info', ...recording, ...args],
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
