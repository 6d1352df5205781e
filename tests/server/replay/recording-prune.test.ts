/*
 * Pruning the replay directory (--replay-keep) against a real server process with two room
 * workers: many short rooms (join, leave, closed after 1 s idle) churn past the keep limit while
 * the lobby's log stays open on one of the workers. The oracles come from the kernel and the
 * directory, not from the server: no file the process holds open in the replay directory is ever
 * "(deleted)" in /proc/PID/fd (checked every 50 ms), the directory never holds fewer logs than
 * --replay-keep once it reached it (two pruners at once deleted twice the excess), and once the
 * churn is over it holds exactly --replay-keep, the lobby's open log among them.
 */
import { mkdtemp, readdir, readlink } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const KEEP = 5
const ROOMS = 40

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children) if (c.process.exitCode === null) c.process.kill('SIGKILL')
})

/** The files of the replay directory the process holds open, as the kernel names them. */
async function openFiles(pid: number, dir: string): Promise<string[]> {
  const out: string[] = []
  for (const fd of await readdir(`/proc/${pid}/fd`).catch(() => [])) {
    const target = await readlink(`/proc/${pid}/fd/${fd}`).catch(() => '')
    if (target.startsWith(`${dir}/`)) out.push(target.slice(dir.length + 1))
  }
  return out
}

/**
 * One applied command, so the room keeps its log: a room where no command was ever applied is
 * closed at once and its log removed (issue 30 point 8), which would leave nothing to prune.
 */
async function spawnOne(bot: BotClient): Promise<void> {
  const before = bot.mirror.bodies.size
  bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 3 })
  await bot.waitFor(() => bot.mirror.bodies.size > before, 'the spawn applied')
}

describe('pruning the replay directory', { timeout: 120_000 }, () => {
  it('with two workers and many short rooms, never deletes an open log and keeps exactly --replay-keep', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-prune-'))
    const server = await startServerProcess([
      ...['--record', 'true', '--replay-dir', dir, '--replay-keep', String(KEEP), '--workers', '2'],
      ...[
        '--room-idle-seconds',
        '1',
        '--reconnect-seconds',
        '0',
        '--default-room',
        'lobby',
        '--default-scene',
        'empty',
      ],
      // Every room here comes from 127.0.0.1: no per-address limit on new rooms.
      ...['--max-rooms', '1000', '--max-new-rooms-per-ip', '0'],
    ])
    children.push(server)
    const pid = server.process.pid!
    const deletedOpen = new Set<string>()
    let fewest = Number.POSITIVE_INFINITY
    let reachedKeep = false
    let watching = true
    const watch = (async () => {
      while (watching) {
        for (const name of await openFiles(pid, dir)) if (name.endsWith(' (deleted)')) deletedOpen.add(name)
        const count = (await listLogNames(dir)).length
        if (reachedKeep) fewest = Math.min(fewest, count)
        if (count >= KEEP) reachedKeep = true
        await new Promise((resolve) => setTimeout(resolve, 50))
      }
    })()
    // A player stays in the lobby (the room whose log was deleted under its writer).
    const lobby = await BotClient.connect({ url: server.url, room: 'lobby', name: 'stays' })
    // Short rooms, four at a time: join, wait for the first snapshot, leave.
    for (let i = 0; i < ROOMS; i += 4) {
      await Promise.all(
        [0, 1, 2, 3].map(async (k) => {
          const bot = await BotClient.connect({ url: server.url, room: `short${i + k}`, name: 'p' })
          await spawnOne(bot)
          await bot.close()
        }),
      )
    }
    // The churn is over once only the lobby is open; then one more room's log prunes the rest.
    await until(async () => {
      const rooms = (await (await fetch(`${server.url}/rooms`)).json()) as Array<{ name: string }>
      return rooms.length === 1
    }, 'the short rooms to close')
    // A log closed under a second ago may still count as open on the main thread (the workers
    // report their open logs once a second): a new room's log prunes again, at most every 1.5 s.
    let extra = 0
    let lastTrigger = 0
    await until(
      async () => {
        if ((await listLogNames(dir)).length === KEEP) return true
        if (Date.now() - lastTrigger < 1500) return false
        lastTrigger = Date.now()
        const bot = await BotClient.connect({ url: server.url, room: `late${extra++}`, name: 'p' })
        await spawnOne(bot)
        await bot.close()
        return false
      },
      `exactly ${KEEP} logs`,
      30_000,
    )
    watching = false
    await watch
    expect([...deletedOpen], 'open logs deleted under their writer').toEqual([])
    expect(fewest, `logs in the directory once it held ${KEEP}`).toBeGreaterThanOrEqual(KEEP)
    const logs = await listLogNames(dir)
    const lobbyLogs = logs.filter((n) => n.startsWith('lobby-'))
    expect(lobbyLogs.length, 'the lobby log is kept').toBe(1)
    expect(await openFiles(pid, dir)).toContain(lobbyLogs[0])
    await lobby.close()
    server.process.kill('SIGTERM')
    expect((await server.exited).code).toBe(0)
  })
})
