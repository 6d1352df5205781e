/*
 * Where a benchmark's CPU goes, per window, as fractions of one core: the server's main thread
 * (sockets, routing, metrics), the server's other threads (room workers, GC helpers, libuv), and
 * the bot processes that stand in for clients on other machines. On a 2-core machine the three
 * share the cores, so a room worker's tick times depend on what the other two take.
 *
 * Sources (Linux): the main thread's time on a CPU from /proc/self/task/<pid>/schedstat (ns), the
 * whole process from process.cpuUsage() (us), a child process from /proc/<pid>/stat (utime and
 * stime, in the kernel's USER_HZ of 100 per second, all its threads).
 */
import { readFileSync } from 'node:fs'

/** Kernel clock ticks per second in /proc/<pid>/stat (USER_HZ, 100 on Linux). */
const USER_HZ = 100

/** CPU seconds used so far: the main thread, the whole server process, and the bot processes. */
export interface CpuSample {
  atMs: number
  mainThread: number
  process: number
  bots: number
}

/** A window's CPU in cores (1 = one core busy for the whole window). */
export interface CpuSplit {
  mainThread: number
  otherServerThreads: number
  bots: number
}

/** Reads the CPU used so far by this process's main thread, this process, and `botPids`. */
export function sampleCpu(botPids: readonly number[]): CpuSample {
  const usage = process.cpuUsage()
  let bots = 0
  for (const pid of botPids) bots += processSeconds(pid)
  return {
    atMs: performance.now(),
    mainThread: mainThreadSeconds(),
    process: (usage.user + usage.system) / 1e6,
    bots,
  }
}

/** The CPU of a window between two samples, in cores. */
export function cpuSplit(from: CpuSample, to: CpuSample): CpuSplit {
  const seconds = (to.atMs - from.atMs) / 1000
  if (!(seconds > 0)) throw new Error(`cpuSplit: window of ${seconds} s`)
  const main = to.mainThread - from.mainThread
  return {
    mainThread: round(main / seconds),
    otherServerThreads: round((to.process - from.process - main) / seconds),
    bots: round((to.bots - from.bots) / seconds),
  }
}

function round(x: number): number {
  return Number(x.toFixed(3))
}

/** Seconds on a CPU of this process's main thread (0 where /proc is missing). */
function mainThreadSeconds(): number {
  try {
    const fields = readFileSync(`/proc/self/task/${process.pid}/schedstat`, 'utf8').split(' ')
    return Number(fields[0]) / 1e9
  } catch {
    return 0
  }
}

/** User and system seconds of a process and its threads (0 once it has exited). */
function processSeconds(pid: number): number {
  let stat: string
  try {
    stat = readFileSync(`/proc/${pid}/stat`, 'utf8')
  } catch {
    return 0
  }
  // The command name (field 2) is in parentheses and may hold spaces: count fields after it.
  const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ')
  // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
  return (Number(fields[11]) + Number(fields[12])) / USER_HZ
}
