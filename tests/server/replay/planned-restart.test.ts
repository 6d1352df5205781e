/*
 * A planned restart keeps the rooms (issue 31, fix 4): on SIGTERM every room where something was
 * done is left at a checkpoint at its last tick, and the next start on the same replay directory
 * reopens it with the same bodies, joints, gravity and pause; players are told both times. The
 * oracle for "the same world" is the whole-world hash: the live room's, written at the stop,
 * against the rebuilt room's at the next start; and a client's view before and after.
 */
import { mkdtemp, readFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames, roomOfLog } from '../../../server/replay/replay-files.ts'
import type { WelcomeMessage } from '../../../shared/index.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children) if (c.process.exitCode === null) c.process.kill('SIGKILL')
})

/** What a client sees of a room: bodies (quantized poses), joints, gravity, pause. */
function view(bot: BotClient): unknown {
  const m = bot.mirror
  return {
    bodies: [...m.bodies.values()]
      .map((b) => ({ id: b.id, kind: b.kind, x: b.x, y: b.y, angle: b.angle, shapes: b.shapes }))
      .sort((a, b) => a.id - b.id),
    joints: [...m.joints.values()].map((j) => ({ id: j.id, kind: j.kind, a: j.a, b: j.b })),
    gravity: m.gravity,
    paused: m.paused,
  }
}

describe('a planned restart (SIGTERM) keeps the rooms', { timeout: 90_000 }, () => {
  for (const workers of ['0', '1']) {
    it(`reopens a used room with the same world and says so (--workers ${workers})`, async () => {
      const dir = await mkdtemp(join(tmpdir(), 'concord-planned-'))
      const args = [
        ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--workers', workers],
        ...['--default-room', 'lobby', '--default-scene', 'empty'],
      ]
      const first = await startServerProcess(args)
      children.push(first)
      const a = await BotClient.connect({ url: first.url, room: 'work', name: 'a' })
      for (let i = 0; i < 6; i++)
        a.command({ k: 'spawn', shape: { type: 'box', hw: 0.4, hh: 0.3 }, x: -3 + i * 1.1, y: 1 + i * 0.5 })
      await a.waitFor(() => a.mirror.bodies.size >= 7, 'the six boxes')
      const box = [...a.mirror.bodies.values()].find((b) => b.kind === 2)!
      a.command({ k: 'pin', a: 0, b: box.id, x: box.x, y: box.y + 0.2 })
      a.command({ k: 'gravity', x: 1.5, y: -7 })
      await a.waitFor(() => a.mirror.joints.size === 1 && a.mirror.gravity[0] === 1.5, 'the pin and gravity')
      // Let the boxes fall a while, then pause: the world stops where the client last saw it.
      const t0 = a.mirror.tick
      await a.waitFor(() => a.mirror.tick > t0 + 30, 'half a second of falling')
      a.command({ k: 'pause', paused: true })
      await a.waitFor(() => a.mirror.paused, 'paused')
      const tp = a.mirror.tick
      await a.waitFor(() => a.mirror.tick > tp + 10, 'snapshots after the pause')
      const before = view(a)

      first.process.kill('SIGTERM')
      expect((await first.exited).code).toBe(0)
      await a.closed
      expect(a.closeCode).toBe(1001)
      expect(a.closeReason).toBe(
        'server shutting down (SIGTERM); rooms are saved and reopen when the server is back',
      )
      // The live room's last checkpoint, as its writer hashed it at the stop.
      const logs = (await listLogNames(dir)).filter((n) => roomOfLog(n) === 'work')
      expect(logs.length).toBe(1)
      const records = new ReplayLogReader().push(await readFile(join(dir, logs[0])))
      const last = records.at(-1)!
      expect(last.type).toBe('hash')
      expect(records.some((r) => r.type === 'close')).toBe(false)

      const second = await startServerProcess(args)
      children.push(second)
      const recoveredLine = () =>
        second.lines.find((l) => l.msg === 'room recovered from its log' && l.room === 'work')
      await until(() => recoveredLine() !== undefined, 'the room recovered')
      const recovered = recoveredLine()!
      expect({ tick: recovered.tick, hash: recovered.hash }).toEqual({
        tick: last.tick,
        hash: (last as { hash: number }).hash,
      })
      // The default room had nothing done in it: closed cleanly, not reopened.
      expect(second.lines.some((l) => l.msg === 'room recovered from its log' && l.room === 'lobby')).toBe(
        false,
      )

      const b = await BotClient.connect({ url: second.url, room: 'work', name: 'b' })
      const welcome = b.received.find((m) => m.t === 'welcome') as WelcomeMessage
      expect(welcome.notice).toBe(
        'This room was restored after a server restart: what was built here is back.',
      )
      expect(view(b)).toEqual(before)
      // A room opened fresh after the restart is not "restored".
      const c = await BotClient.connect({ url: second.url, room: 'fresh', name: 'c' })
      expect((c.received.find((m) => m.t === 'welcome') as WelcomeMessage).notice).toBeUndefined()
      second.process.kill('SIGTERM')
      expect((await second.exited).code).toBe(0)
    })
  }
})
