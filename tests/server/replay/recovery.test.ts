/*
 * Crash recovery against the real server process (server/main.ts in its own Node): bots play in
 * four rooms, the process is killed with SIGKILL at a random moment, and a new process started with
 * --recover on the same replay directory must reopen every room exactly at its log's last durable
 * checkpoint (the oracle is read from the file by this test: the last hash record, or the world of
 * a later keyframe). Each restarted process is also the next trial's victim, so 6 process lifetimes
 * give 5 kills x 4 rooms = 20 trials; fsync modes rotate, and some trials get a torn or zero-filled
 * tail appended (a kill mid-write). At the end a SIGTERM (with --keep-rooms false: a planned
 * restart that keeps rooms is planned-restart.test.ts) must close every log cleanly, each room's
 * one log (all incarnations appended to it) replays with every hash and keyframe matching, and a
 * restart does not resume anything.
 */
import { appendFile, mkdtemp, readFile, stat } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { inflateSync } from 'node:zlib'
import { afterAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { loadWorld, Prng } from '../../../engine/index.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { replayLog } from '../../../server/replay/replay-tool.ts'
import { colorsHash } from '../../../shared/index.ts'
import { decodeByteDelta } from '../../../shared/replay/byte-delta.ts'
import type { StoredWorld } from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { Histories } from '../../../shared/sim/history.ts'
import { ActiveBots } from '../../support/lockstep-bots.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const ROOMS = ['r0', 'r1', 'r2', 'r3']
const KILLS = 5
const FSYNC = ['always', 'interval', 'none'] as const
const SEED = Number(process.env.RECOVERY_SEED ?? 8)

const children: ServerProcess[] = []
afterAll(() => {
  for (const c of children)
    if (c.process.exitCode === null && c.process.signalCode === null) c.process.kill('SIGKILL')
})

async function start(dir: string, fsync: string): Promise<ServerProcess> {
  const server = await startServerProcess([
    ...['--record', 'true', '--recover', 'true', '--replay-dir', dir, '--replay-fsync', fsync],
    ...['--keyframe-ticks', '90', '--default-room', 'r0', '--default-scene', 'tower'],
    ...['--room-idle-seconds', '600', '--max-messages-per-second', '1000', '--keep-rooms', 'false'],
  ])
  children.push(server)
  return server
}

/** The newest log of a room. */
async function newestLog(dir: string, room: string): Promise<string | undefined> {
  return (await listLogNames(dir)).filter((n) => n.startsWith(`${room}-`)).pop()
}

/** A stored world's saved bytes; a delta (z = 2) is rebuilt against `base`, the previous keyframe's. */
const savedBytes = (w: StoredWorld, base: Uint8Array | null): Uint8Array => {
  if (w.z === 0) return w.world
  const inflated = new Uint8Array(inflateSync(w.world))
  if (w.z === 1) return inflated
  if (!base) throw new Error('a delta keyframe without a base')
  return decodeByteDelta(base, inflated)
}

/** The last checkpoint of a log's intact prefix, read independently of the server's recovery code. */
async function lastCheckpoint(
  path: string,
): Promise<{ tick: number; hash: number; bytes: Uint8Array; lastRecord: number }> {
  const bytes = await readFile(path)
  const reader = new ReplayLogReader()
  let checkpoint: { tick: number; hash: number } | null = null
  let lastRecord = 0
  let before = 16
  let base: Uint8Array | null = null
  reader.push(bytes, (r, end) => {
    if (r.type === 'hash') checkpoint = { tick: r.tick, hash: r.hash }
    else if (r.type === 'header' || r.type === 'keyframe') {
      base = savedBytes(r, base)
      // The state hash (PROTOCOL.md, Lockstep and predict): the world's, continued over the body
      // colours when there are any (the sandbox keeps no game state), then over the players' undo
      // histories when any player has one (a keyframe written after a spawn carries them; when the
      // kill comes between a keyframe and the hash record of its tick, the keyframe is the last
      // checkpoint).
      const world = loadWorld(base).hash()
      const colors = r.state.colors ?? []
      const colored = colors.length === 0 ? world : colorsHash(world, colors)
      const histories = new Histories()
      histories.restore(r.state.history ?? [])
      checkpoint = { tick: r.tick, hash: histories.empty ? colored : histories.mixInto(colored) }
    }
    // Records of one block share its end: lastRecord is the last frame's size.
    if (end > before) lastRecord = end - before
    before = end
  })
  expect(reader.finish().closed).toBe(false)
  if (!checkpoint) throw new Error(`${path} has no checkpoint`)
  return { ...(checkpoint as { tick: number; hash: number }), bytes, lastRecord }
}

/** The log lines of rooms recovered by a process. */
function recoveredLines(server: ServerProcess): Map<string, { tick: number; hash: number; log: string }> {
  const out = new Map<string, { tick: number; hash: number; log: string }>()
  for (const l of server.lines)
    if (l.msg === 'room recovered from its log')
      out.set(l.room as string, { tick: l.tick as number, hash: l.hash as number, log: l.log as string })
  return out
}

const dynamicIds = (bot: BotClient): number[] =>
  [...bot.mirror.bodies.values()].filter((b) => b.kind === 2).map((b) => b.id)

describe('crash recovery', { timeout: 180_000 }, () => {
  it('20 SIGKILL trials reopen every room at its last durable checkpoint; a client plays on; SIGTERM closes cleanly and does not resume', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-recover-'))
    const prng = new Prng(SEED)
    let server = await start(dir, FSYNC[0])
    let expected = new Map<string, { tick: number; hash: number }>()
    const logs = new Map<string, string>()
    let trials = 0
    let tornTails = 0
    for (let round = 0; round <= KILLS; round++) {
      // Check the previous round's crash: every room reopened exactly at its checkpoint.
      if (round > 0) {
        // Rooms on workers log their recovery from the worker's thread, whose output reaches
        // stdout after the main thread's "listening": wait for the lines (the rooms themselves
        // were rebuilt before the server listened), then compare.
        await until(
          () => ROOMS.every((room) => recoveredLines(server).has(room)),
          `round ${round}: every recovery logged`,
        ).catch(() => {})
        const lines = recoveredLines(server)
        expect([...lines.keys()].sort(), `round ${round}: rooms recovered`).toEqual(ROOMS)
        for (const room of ROOMS) {
          const want = expected.get(room)!
          const got = lines.get(room)!
          expect(got.log, `${room}: the same log continues`).toBe(logs.get(room))
          expect({ tick: got.tick, hash: got.hash }, `round ${round}, ${room}`).toEqual(want)
          trials++
        }
        // A client joins each recovered room and plays on: its spawn is applied and ticks advance.
        for (const room of ROOMS) {
          const want = expected.get(room)!
          const late = await BotClient.connect({ url: server.url, room, name: 'late' })
          expect(late.mirror.tick).toBeGreaterThanOrEqual(want.tick)
          const before = new Set(dynamicIds(late))
          late.command({ k: 'spawn', shape: { type: 'box', hw: 0.3, hh: 0.3 }, x: 1, y: 9 })
          await late.waitFor(() => dynamicIds(late).some((id) => !before.has(id)), `${room}: the late spawn`)
          await late.waitFor(() => late.mirror.tick >= want.tick + 30, `${room}: ticks advance`)
          await late.close()
        }
      }
      const bots = await Promise.all(
        ROOMS.map((room, i) => ActiveBots.start(server.url, room, 2, 20, round * 10 + i + 1)),
      )
      if (round === 0) {
        // Every room's log has its header on disk before the first kill is timed.
        for (const room of ROOMS)
          await until(async () => {
            const name = await newestLog(dir, room)
            return name !== undefined && (await stat(join(dir, name))).size > 100
          }, `${room}'s first log`)
        for (const room of ROOMS) logs.set(room, (await newestLog(dir, room))!)
      }
      if (round === KILLS) {
        // The clean end: SIGTERM.
        await new Promise((r) => setTimeout(r, 300 + prng.int(700)))
        server.process.kill('SIGTERM')
        expect((await server.exited).code).toBe(0)
        await Promise.all(bots.map((b) => b.stop()))
        break
      }
      await new Promise((r) => setTimeout(r, 300 + prng.int(1200)))
      server.process.kill('SIGKILL')
      await server.exited
      await Promise.all(bots.map((b) => b.stop()))
      expected = new Map()
      for (const [t, room] of ROOMS.entries()) {
        const path = join(dir, logs.get(room)!)
        expect(await newestLog(dir, room), `${room}: no new log was started`).toBe(logs.get(room))
        const cp = await lastCheckpoint(path)
        expected.set(room, { tick: cp.tick, hash: cp.hash })
        // Some trials: a kill mid-write, simulated as a torn record or a zero-filled tail.
        const kind = (round * ROOMS.length + t) % 3
        if (kind === 1) {
          await appendFile(
            path,
            cp.bytes.subarray(
              cp.bytes.length - cp.lastRecord,
              cp.bytes.length - 1 - prng.int(cp.lastRecord - 1),
            ),
          )
          tornTails++
        } else if (kind === 2) {
          await appendFile(path, new Uint8Array(1 + prng.int(64)))
          tornTails++
        }
      }
      server = await start(dir, FSYNC[(round + 1) % FSYNC.length])
    }
    expect(trials).toBeGreaterThanOrEqual(20)
    expect(tornTails).toBeGreaterThan(5)
    // Every room's single log (5 crashes and a clean end) replays straight through, all matching.
    for (const room of ROOMS) {
      const name = logs.get(room)!
      expect(await newestLog(dir, room)).toBe(name)
      const report = await replayLog(await readFile(join(dir, name)), { verify: true })
      expect(report.read, room).toMatchObject({ state: 'end', closed: true })
      expect(report.divergence, room).toBeNull()
      // Joins of a round killed before its first flush are lost with it; round 0's are on disk.
      expect(report.players, room).toBeGreaterThanOrEqual(2)
      expect(report.keyframesChecked, room).toBeGreaterThan(0)
      // At least one checkpoint per process lifetime (each crash's flush ends with one).
      expect(report.hashesChecked, room).toBeGreaterThan(KILLS)
    }
    // A restart after the clean shutdown resumes nothing: r0 (the default room) starts a new log
    // as a new room; the closed logs stay as they were.
    const sizes = await Promise.all(ROOMS.map(async (room) => (await stat(join(dir, logs.get(room)!))).size))
    const after = await start(dir, 'interval')
    await until(async () => (await newestLog(dir, 'r0')) !== logs.get('r0'), 'a new log for r0')
    expect(recoveredLines(after).size).toBe(0)
    const bot = await BotClient.connect({ url: after.url, room: 'r1', name: 'fresh' })
    expect(bot.mirror.tick).toBeLessThan(120)
    await bot.close()
    after.process.kill('SIGTERM')
    expect((await after.exited).code).toBe(0)
    expect(
      await Promise.all(ROOMS.map(async (room) => (await stat(join(dir, logs.get(room)!))).size)),
    ).toEqual(sizes)
    const fresh = await replayLog(await readFile(join(dir, (await newestLog(dir, 'r0'))!)), { verify: true })
    // A new room starts below tick 60 (the phase that spreads its checkpoints), not where r0's log stopped.
    expect(fresh.divergence).toBeNull()
    expect(fresh.firstTick).toBeLessThan(60)
  })
})
