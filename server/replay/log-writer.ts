/*
 * Whether the process that wrote a log still runs, so crash recovery leaves its log alone. A log's
 * header names its writer (host name, process id) and its start time. `kill(pid, 0)` is not an
 * answer: a SIGKILLed process that its parent has not reaped yet is a zombie that `kill` reports
 * alive (PID 1 of these machines reaps orphans about 2 s late), and a pid is reused by the next
 * process that gets it. So on Linux the answer comes from /proc/PID/stat, as the kernel keeps it:
 * a zombie ('Z') or a dead task ('X') has closed its files and writes nothing more, and a process
 * that started after the log did (field 22, start time in clock ticks after boot, plus the boot
 * time from /proc/stat) cannot have written its header: the pid was reused. Elsewhere (no /proc)
 * the old signal-0 test is the only one there is.
 */
import { readFileSync } from 'node:fs'
import { hostname } from 'node:os'

/** Clock ticks per second of /proc's start times (USER_HZ: 100 on every Linux architecture Node runs on). */
const USER_HZ = 100

/**
 * Slack when comparing a process's start with a log's (ms): the boot time is given in whole
 * seconds, and the log's start is read from the wall clock just after the process started it.
 */
const START_SLACK_MS = 2000

/** Seconds since the epoch at boot (/proc/stat btime), or null without /proc. */
function bootSeconds(): number | null {
  try {
    const line = readFileSync('/proc/stat', 'latin1')
      .split('\n')
      .find((l) => l.startsWith('btime '))
    return line ? Number(line.slice(6)) : null
  } catch {
    return null
  }
}

/** A process as /proc/PID/stat shows it: its state letter and start (ms since the epoch); null when there is none. */
export function processInfo(pid: number): { state: string; startMs: number } | null {
  let text: string
  try {
    text = readFileSync(`/proc/${pid}/stat`, 'latin1')
  } catch {
    return null
  }
  // "pid (comm) state ppid ...": comm may hold spaces and parentheses, so fields count from the last ')'.
  const fields = text.slice(text.lastIndexOf(')') + 2).split(' ')
  const boot = bootSeconds() ?? 0
  return { state: fields[0], startMs: boot * 1000 + (Number(fields[19]) * 1000) / USER_HZ }
}

/** Whether /proc describes processes here (Linux). */
function procAvailable(): boolean {
  return processInfo(process.pid) !== null
}

/**
 * Whether the process that started a log at `logStartMs` (its header's `start`) as `writer` still
 * runs: on this host, not this process, not a zombie, and started before the log did.
 */
export function writerAlive(writer: { host: string; pid: number }, logStartMs: number): boolean {
  if (writer.host !== hostname() || writer.pid === process.pid) return false
  if (!procAvailable()) {
    try {
      process.kill(writer.pid, 0)
      return true
    } catch (error) {
      return (error as NodeJS.ErrnoException).code === 'EPERM'
    }
  }
  const info = processInfo(writer.pid)
  if (!info || info.state === 'Z' || info.state === 'X') return false
  return info.startMs <= logStartMs + START_SLACK_MS
}
