/*
 * Room names that look like log names. A log is named ROOM-STAMP.cclog, and `lobby-99999999T` is a
 * valid room name: its log, lobby-99999999T-20261124T132706400Z.cclog, was once read as a log of
 * room `lobby` (the room was cut at the first "-DDDDDDDDT"). After a crash, recovery took it for
 * the lobby's newest log: the lobby's own log was never recovered, and with rooms on workers the
 * restarted server waited forever for a `lobby` the worker rebuilt as `lobby-99999999T`, and never
 * listened. Against real server processes: a player in the lobby and one in the look-alike room,
 * SIGKILL, restart on the same replay directory. Likewise a room named `z-99999999T999999999Z`
 * made its logs the newest for pruning (--replay-keep), so the oldest real logs went first while
 * its own were never pruned.
 */
import { mkdtemp, readdir, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { PRUNE_QUIET_MS, pruneLogs } from '../../../server/replay/replay-files.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const LOOK_ALIKE = 'lobby-99999999T'

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children)
    if (c.process.exitCode === null && c.process.signalCode === null) c.process.kill('SIGKILL')
})

async function start(dir: string): Promise<ServerProcess> {
  const args = [
    ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--workers', '1'],
    ...['--default-room', 'lobby', '--default-scene', 'tower', '--room-idle-seconds', '600'],
  ]
  const server = await startServerProcess(args, {}, 90_000)
  children.push(server)
  return server
}

describe('a room named like a log of another room', { timeout: 40_000 }, () => {
  it('after a crash, each room is rebuilt from its own log and the server listens', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-log-names-'))
    const first = await start(dir)
    await BotClient.connect({ url: first.url, room: 'lobby', name: 'player' })
    await BotClient.connect({ url: first.url, room: LOOK_ALIKE, name: 'attacker' })
    // Both logs hold a checkpoint after the header.
    await until(async () => {
      const logs = (await (await fetch(`${first.url}/replays`)).json()) as Array<{ ticks: number }>
      return logs.length === 2 && logs.every((l) => l.ticks >= 60)
    }, 'two logs with a checkpoint')
    first.process.kill('SIGKILL')
    await first.exited

    const second = await start(dir)
    const rebuilt = second.lines.filter((l) => l.msg === 'room rebuilt from its log on a worker')
    expect(rebuilt.map((l) => [l.room, String(l.log).startsWith(`${l.room}-2`)]).sort()).toEqual([
      ['lobby', true],
      [LOOK_ALIKE, true],
    ])
    second.process.kill('SIGTERM')
    expect((await second.exited).code).toBe(0)
  })
})

describe('a room name holding a start stamp', () => {
  it('does not decide which logs --replay-keep deletes: the start stamp at the end of the name does', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-log-prune-'))
    const forged = 'z-99999999T999999999Z-20261124T100000000Z.cclog'
    const real = 'lobby-20261124T110000000Z.cclog'
    for (const name of [forged, real]) await writeFile(join(dir, name), '')
    // Both are empty files (no header): pruning takes such a log once it has been quiet a while.
    expect(await pruneLogs(dir, 1, new Set(), Date.now() + PRUNE_QUIET_MS)).toEqual([forged])
    expect(await readdir(dir)).toEqual([real])
  })
})
