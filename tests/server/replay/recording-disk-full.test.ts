/*
 * A replay directory on a disk that fills up, for real: a small tmpfs mounted over a temporary
 * directory (this needs root, as the test machines run; elsewhere the test says why it is
 * skipped, and recorder-failures.test.ts covers the same rules through the file seam). A real
 * server process records the lobby; a filler file takes the disk's free space down to 16 KiB, a
 * scene load makes the next keyframe the 300-body pile's (about 25 KB), and its write is short,
 * then ENOSPC.
 *
 * Oracles from the file and the process, not from the recorder: the log reads back to its last
 * whole record with no corruption (before: the part of a record that landed was followed by later
 * writes once space came back, and the rest of the log was unreadable), its last tick is at least
 * the checkpoint seen before the filler, concord_recorder_failures_total is 1 and one error line
 * names the log; once the filler is gone recording resumes in a new log whose header holds the
 * state at that moment; a second failure followed by SIGTERM leaves nothing that the next start
 * reopens (before: the next start rebuilt the room at the tick where recording stopped and
 * appended to the old file across the gap).
 */
import { execFileSync } from 'node:child_process'
import { mkdtemp, readFile, statfs, unlink, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const children: ServerProcess[] = []
const mounts: string[] = []
afterAll(() => {
  for (const c of children) if (c.process.exitCode === null) c.process.kill('SIGKILL')
  for (const dir of mounts) {
    try {
      execFileSync('umount', ['-l', dir])
    } catch {
      // Already gone.
    }
  }
})

/** Mount a tmpfs of `bytes` over a new temporary directory; null (with the reason) when not permitted. */
async function smallDisk(bytes: number): Promise<{ dir: string } | { reason: string }> {
  const dir = await mkdtemp(join(tmpdir(), 'concord-full-'))
  try {
    execFileSync('mount', ['-t', 'tmpfs', '-o', `size=${bytes}`, 'tmpfs', dir], { stdio: 'pipe' })
  } catch (error) {
    return { reason: `cannot mount a tmpfs (${(error as Error).message.split('\n')[0]})` }
  }
  mounts.push(dir)
  return { dir }
}

/** Fill the disk of `dir` until `leave` bytes are free (a file named `name`). */
async function fill(dir: string, name: string, leave: number): Promise<void> {
  const fs = await statfs(dir)
  await writeFile(join(dir, name), new Uint8Array(Math.max(0, fs.bavail * fs.bsize - leave)))
}

/** Read a log: its reader status once finished, the last record's tick, and the header's tick. */
async function readLog(path: string) {
  const reader = new ReplayLogReader()
  let headerTick = -1
  let lastTick = -1
  let closeReason = ''
  reader.push(await readFile(path), (r) => {
    if (r.type === 'header') headerTick = r.tick
    if (r.type === 'close') closeReason = r.reason
    lastTick = r.tick
  })
  return { status: reader.finish(), headerTick, lastTick, closeReason }
}

async function failures(server: ServerProcess): Promise<number> {
  const text = await (await fetch(`${server.url}/metrics`)).text()
  return text
    .split('\n')
    .filter((l) => l.startsWith('concord_recorder_failures_total'))
    .reduce((sum, l) => sum + Number(l.split(' ').pop()), 0)
}

const disk = await smallDisk(8 * 1024 * 1024)

describe('a disk that fills up', { timeout: 120_000 }, () => {
  it.skipIf('reason' in disk)(
    `a short write leaves a log readable to its last whole record, counted and logged; recording resumes in a new log; a failed room is not reopened after SIGTERM${'reason' in disk ? ` (skipped: ${disk.reason})` : ''}`,
    async () => {
      const dir = (disk as { dir: string }).dir
      const args = [
        ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--replay-fsync', 'interval'],
        ...['--default-room', 'lobby', '--default-scene', 'tower', '--workers', '1'],
      ]
      const server = await startServerProcess(args)
      children.push(server)
      const bot = await BotClient.connect({ url: server.url, room: 'lobby', name: 'filler' })
      // A checkpoint on disk before the disk fills.
      await until(async () => {
        const [name] = await listLogNames(dir)
        return name !== undefined && (await readLog(join(dir, name))).lastTick >= 120
      }, 'a checkpoint in the lobby log')
      const [first] = await listLogNames(dir)
      const before = (await readLog(join(dir, first))).lastTick

      // 1. The disk fills: the pile's keyframe (about 25 KB) meets 16 KiB of space.
      await fill(dir, 'filler', 16 * 1024)
      bot.command({ k: 'scene', name: 'pile' })
      await until(
        () => server.lines.some((l) => l.msg === 'recording stopped for this room; the room keeps running'),
        'the failure logged',
      )
      const stopped = server.lines.filter(
        (l) => l.msg === 'recording stopped for this room; the room keeps running',
      )
      expect(stopped.map((l) => [l.room, l.log])).toEqual([['lobby', first]])
      expect(String(stopped[0].err)).toMatch(/ENOSPC/)
      // The worker's metrics reach /metrics with its once-a-second stats.
      await until(async () => (await failures(server)) > 0, 'the failure counted')
      expect(await failures(server)).toBe(1)
      // Everything before the failure reads back; nothing after it is half a record.
      await until(
        async () => (await readLog(join(dir, first))).closeReason !== '',
        'the failed log closed',
      ).catch(() => {})
      const failed = await readLog(join(dir, first))
      expect(failed.status.state, JSON.stringify(failed.status)).toBe('end')
      expect(failed.lastTick).toBeGreaterThanOrEqual(before)
      expect(failed.status.closed).toBe(true)
      expect(failed.closeReason).toBe('recording failed')

      // 2. Space comes back: a new log, starting with a header (a whole keyframe) at the state then.
      const failTick = failed.lastTick
      await unlink(join(dir, 'filler'))
      await until(
        () => server.lines.some((l) => l.msg === 'recording resumed in a new log'),
        'recording resumed',
      )
      const logs = await listLogNames(dir)
      expect(logs.length).toBe(2)
      const second = logs[1]
      await until(async () => (await readLog(join(dir, second))).lastTick > 0, 'the new log written')
      const resumed = await readLog(join(dir, second))
      expect(resumed.headerTick).toBeGreaterThan(failTick)
      expect(resumed.status).toMatchObject({ state: 'end', closed: false })

      // 3. It fills again; a clean shutdown; the next start reopens nothing of the lobby.
      await fill(dir, 'filler', 16 * 1024)
      bot.command({ k: 'scene', name: 'pyramid' })
      await until(
        () =>
          server.lines.some(
            (l) => l.msg === 'recording stopped for this room; the room keeps running' && l.log === second,
          ),
        'the second failure',
      )
      await bot.close()
      server.process.kill('SIGTERM')
      expect((await server.exited).code).toBe(0)
      const sizes = await Promise.all([first, second].map(async (n) => (await readFile(join(dir, n))).length))
      await unlink(join(dir, 'filler'))
      const next = await startServerProcess(args)
      children.push(next)
      await until(async () => (await listLogNames(dir)).length === 3, 'a new lobby log')
      expect(next.lines.filter((l) => l.msg === 'room recovered from its log')).toEqual([])
      expect(
        await Promise.all([first, second].map(async (n) => (await readFile(join(dir, n))).length)),
      ).toEqual(sizes)
      next.process.kill('SIGTERM')
      expect((await next.exited).code).toBe(0)
    },
  )
})
