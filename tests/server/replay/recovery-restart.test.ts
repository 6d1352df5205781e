/*
 * A restart right after a SIGKILL recovers the room, 20 times in a row. Each server runs under a
 * parent that never reaps it (`sh -c 'node server & exec sleep'`: the shell becomes `sleep`, which
 * never waits), so the killed server stays a zombie while the next one starts, as a process does
 * under a PID 1 that reaps orphans late: `kill(pid, 0)` calls a zombie alive, and the old server
 * skipped the log as "another live process writes it". The test checks the zombie is there (state
 * 'Z' in /proc) before each restart, so every round exercises that case.
 */
import { type ChildProcess, spawn } from 'node:child_process'
import { readFileSync } from 'node:fs'
import { mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { createInterface } from 'node:readline'
import { afterAll, describe, expect, it } from 'vitest'
import { listLogNames, logFileName } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { type LogLine, type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const ROUNDS = 20

/** A server under a parent that does not reap it: the wrapper, the server's pid and its log lines. */
interface Unreaped {
  wrapper: ChildProcess
  pid: number
  lines: LogLine[]
}

const wrappers: ChildProcess[] = []
const children: ServerProcess[] = []
afterAll(() => {
  for (const w of wrappers) if (w.exitCode === null && w.signalCode === null) w.kill('SIGKILL')
  for (const c of children) if (c.process.exitCode === null) c.process.kill('SIGKILL')
})

function startUnreaped(dir: string): Promise<Unreaped> {
  const args = [
    ...['--import', 'tsx', 'server/main.ts', '--port', '0', '--log-level', 'info'],
    ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--replay-fsync', 'always'],
    ...['--default-room', 'lobby', '--default-scene', 'tower', '--workers', '1'],
  ]
  const quoted = [process.execPath, ...args].map((a) => `'${a}'`).join(' ')
  const wrapper = spawn('sh', ['-c', `${quoted} & exec sleep 600`], { stdio: ['ignore', 'pipe', 'inherit'] })
  wrappers.push(wrapper)
  const lines: LogLine[] = []
  return new Promise((resolve, reject) => {
    wrapper.once('exit', (code) => reject(new Error(`wrapper exited early (${code})`)))
    createInterface({ input: wrapper.stdout! }).on('line', (text) => {
      let entry: LogLine
      try {
        entry = JSON.parse(text) as LogLine
      } catch {
        return
      }
      lines.push(entry)
      if (entry.msg === 'listening') resolve({ wrapper, pid: entry.pid as number, lines })
    })
  })
}

/** The state letter of a process in /proc (Z: a zombie), or '' when there is none. */
function procState(pid: number): string {
  try {
    const text = readFileSync(`/proc/${pid}/stat`, 'latin1')
    return text.slice(text.lastIndexOf(')') + 2).split(' ')[0]
  } catch {
    return ''
  }
}

const recovered = (server: Unreaped): LogLine | undefined =>
  server.lines.find((l) => l.msg === 'room recovered from its log' && l.room === 'lobby')

describe('restart right after SIGKILL', { timeout: 300_000 }, () => {
  it(`recovers the room ${ROUNDS} times in a row while the killed server is still a zombie`, async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-restart-'))
    let server = await startUnreaped(dir)
    await until(async () => {
      const [name] = await listLogNames(dir)
      if (!name) return false
      const records = new ReplayLogReader().push(await readFile(join(dir, name)))
      return records[0]?.type === 'header' && records.some((r) => r.type === 'hash')
    }, 'the lobby log with its header and a checkpoint')
    const log = (await listLogNames(dir))[0]
    let ticks = -1
    let zombies = 0
    for (let round = 0; round < ROUNDS; round++) {
      process.kill(server.pid, 'SIGKILL')
      await until(() => procState(server.pid) === 'Z', `round ${round}: the killed server is a zombie`)
      zombies++
      const next = await startUnreaped(dir)
      await until(() => recovered(next) !== undefined, `round ${round}: the lobby recovered`).catch(
        (error) => {
          throw new Error(
            `${(error as Error).message}: ${JSON.stringify(next.lines.filter((l) => (l.level as number) >= 40))}`,
          )
        },
      )
      const line = recovered(next)!
      expect(line.log, `round ${round}: the same log continues`).toBe(log)
      expect(
        line.tick as number,
        `round ${round}: recovered at or after the last round's tick`,
      ).toBeGreaterThanOrEqual(ticks)
      ticks = line.tick as number
      // Reap the zombie now that the next server has started.
      server.wrapper.kill('SIGKILL')
      server = next
    }
    expect(zombies).toBe(ROUNDS)
    expect(await listLogNames(dir)).toEqual([log])
    process.kill(server.pid, 'SIGTERM')
    await until(() => procState(server.pid) === 'Z' || procState(server.pid) === '', 'the last server ends')
    server.wrapper.kill('SIGKILL')
  })
})

describe('a crash right after a rotation', { timeout: 120_000 }, () => {
  it('recovers the room from the older, unclosed log when the newest one is empty or cut before its header', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-rotated-'))
    const args = [
      ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--workers', '1'],
      ...['--default-room', 'lobby', '--default-scene', 'tower'],
    ]
    const first = await startServerProcess(args)
    children.push(first)
    await until(async () => {
      const logs = (await (await fetch(`${first.url}/replays`)).json()) as Array<{ ticks: number }>
      return logs.length === 1 && logs[0].ticks >= 60
    }, 'a checkpoint in the lobby log')
    const [log] = await listLogNames(dir)
    first.process.kill('SIGKILL')
    await first.exited
    // What the rotation left when the process died: the next log, created, with nothing (or only
    // the start of its preamble) written. Both are newer than the lobby's log.
    const start = Date.parse(new Date().toISOString())
    await writeFile(join(dir, logFileName('lobby', start + 1000)), new Uint8Array(0))
    await writeFile(join(dir, logFileName('lobby', start + 2000)), new Uint8Array([0x43, 0x4e]))
    const second = await startServerProcess(args)
    children.push(second)
    await until(
      () => second.lines.some((l) => l.msg === 'room recovered from its log' && l.room === 'lobby'),
      'the lobby recovered',
    )
    const line = second.lines.find((l) => l.msg === 'room recovered from its log')!
    expect(line.log).toBe(log)
    second.process.kill('SIGTERM')
    expect((await second.exited).code).toBe(0)
  })
})
