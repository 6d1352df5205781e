/*
 * Log writer liveness (server/replay/log-writer.ts) against real processes: a running process that
 * started before a log did is its writer; one that started after it holds a reused pid; a pid with
 * no process, and this very process, are not writers. The zombie case runs in
 * recovery-restart.test.ts.
 */
import { spawn } from 'node:child_process'
import { hostname } from 'node:os'
import { describe, expect, it } from 'vitest'
import { processInfo, writerAlive } from '../../../server/replay/log-writer.ts'
import { until } from '../../support/wait.ts'

describe('log writer liveness', () => {
  it('a live process is the writer of a log started after it, never of one started before it', async () => {
    const child = spawn('sleep', ['30'], { stdio: 'ignore' })
    const pid = child.pid!
    const exited = new Promise((resolve) => child.once('exit', resolve))
    await until(() => processInfo(pid)?.state === 'S', 'the child sleeping')
    const started = processInfo(pid)!.startMs
    // /proc's start time agrees with the wall clock at spawn within its boot-time rounding (1 s).
    expect(Math.abs(started - Date.now())).toBeLessThan(5000)
    const writer = { host: hostname(), pid }
    expect(writerAlive(writer, Date.now())).toBe(true)
    // A log that started a minute before this process did was written by an earlier holder of the pid.
    expect(writerAlive(writer, started - 60_000)).toBe(false)
    expect(writerAlive({ host: `${hostname()}-elsewhere`, pid }, Date.now())).toBe(false)
    expect(writerAlive({ host: hostname(), pid: process.pid }, Date.now())).toBe(false)
    child.kill('SIGKILL')
    await exited
    await until(() => processInfo(pid) === null, 'the child reaped')
    expect(writerAlive(writer, Date.now())).toBe(false)
  })
})
