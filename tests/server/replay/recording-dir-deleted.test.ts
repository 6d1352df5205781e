/*
 * The replay directory deleted under a running server (rm -rf, a cleanup job): writes into the
 * deleted files went on without an error, so the open recordings were lost silently. Against a
 * real server process with two rooms on two workers: the directory comes back, each room gets a
 * new log that starts with a header (a whole keyframe) and goes on with its checkpoints,
 * concord_recorder_failures_total counts one failure per room, and the process holds no deleted
 * file open (/proc/PID/fd).
 */
import { mkdtemp, readdir, readFile, readlink, rm } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children) if (c.process.exitCode === null) c.process.kill('SIGKILL')
})

async function failures(server: ServerProcess): Promise<number> {
  const text = await (await fetch(`${server.url}/metrics`)).text()
  return text
    .split('\n')
    .filter((l) => l.startsWith('concord_recorder_failures_total'))
    .reduce((sum, l) => sum + Number(l.split(' ').pop()), 0)
}

describe('a deleted replay directory', { timeout: 60_000 }, () => {
  it('is made again, every open room starts a new log with a header, and the failure is counted', async () => {
    const parent = await mkdtemp(join(tmpdir(), 'concord-rmdir-'))
    const dir = join(parent, 'replays')
    const server = await startServerProcess([
      ...['--record', 'true', '--replay-dir', dir, '--workers', '2'],
      ...['--default-room', 'lobby', '--default-scene', 'tower'],
    ])
    children.push(server)
    const bot = await BotClient.connect({ url: server.url, room: 'other', name: 'p' })
    await until(async () => (await listLogNames(dir)).length === 2, 'two logs')
    await rm(dir, { recursive: true })
    await until(async () => (await listLogNames(dir)).length === 2, 'two new logs')
    const rooms = (await listLogNames(dir)).map((n) => n.split('-')[0]).sort()
    expect(rooms).toEqual(['lobby', 'other'])
    // Each new log starts with a header and goes on (a hash record every 60 ticks).
    for (const name of await listLogNames(dir))
      await until(async () => {
        const records = new ReplayLogReader().push(await readFile(join(dir, name)))
        return records[0]?.type === 'header' && records.some((r) => r.type === 'hash')
      }, `${name}: a header and a checkpoint`)
    await until(async () => (await failures(server)) === 2, 'two failures counted')
    const open: string[] = []
    for (const fd of await readdir(`/proc/${server.process.pid}/fd`))
      open.push(await readlink(`/proc/${server.process.pid}/fd/${fd}`).catch(() => ''))
    expect(open.filter((t) => t.startsWith(dir) && t.endsWith('(deleted)'))).toEqual([])
    await bot.close()
    server.process.kill('SIGTERM')
    expect((await server.exited).code).toBe(0)
  })
})
