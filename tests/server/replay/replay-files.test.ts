import { chmod, mkdtemp, unlink, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import pino from 'pino'
import { Counter } from 'prom-client'
import { describe, expect, it } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import {
  cachedLogPaths,
  LogPruner,
  listLogNames,
  listLogs,
  PRUNE_QUIET_MS,
  pruneLogs,
} from '../../../server/replay/replay-files.ts'
import { encodePreamble, REPLAY_FORMAT_VERSION } from '../../../shared/replay/replay-log.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { until } from '../../support/wait.ts'

describe('GET /replays summaries', () => {
  it('a log cut before its header is whole is listed as empty, a file that is no log as invalid', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-replay-files-'))
    const preamble = encodePreamble({ format: REPLAY_FORMAT_VERSION, engine: 1, protocol: 2, tickRate: 60 })
    // A header record cut after its length and type bytes (the writer died mid-write).
    const cutHeader = new Uint8Array([...preamble, 200, 0, 0, 0, 1])
    const files: Array<[string, Uint8Array, string]> = [
      ['a-20261123T000000000Z.cclog', new Uint8Array(0), 'empty'],
      ['b-20261123T000000000Z.cclog', preamble.subarray(0, 5), 'empty'],
      ['c-20261123T000000000Z.cclog', preamble, 'empty'],
      ['d-20261123T000000000Z.cclog', cutHeader, 'empty'],
      ['e-20261123T000000000Z.cclog', new TextEncoder().encode('CNCx'), 'invalid'],
      ['f-20261123T000000000Z.cclog', new TextEncoder().encode('not a replay log at all'), 'invalid'],
    ]
    for (const [name, bytes] of files) await writeFile(join(dir, name), bytes)
    const listed = await listLogs(dir, new Set())
    for (const [name, bytes, status] of files) {
      const entry = listed.find((l) => l.name === name)
      expect(entry, name).toMatchObject({ status, size: bytes.length })
      expect(entry?.ticks ?? 0, name).toBe(0)
      if (status === 'empty') expect(entry?.problem, name).toMatch(/^nothing recorded: .*\(\d+ bytes\)$/)
    }
  })
})

describe('the listing cache', () => {
  it('forgets the logs deleted from the directory at the next listing, keeps the others and other directories', async () => {
    const [dir, other] = await Promise.all([
      mkdtemp(join(tmpdir(), 'concord-replay-cache-')),
      mkdtemp(join(tmpdir(), 'concord-replay-cache-')),
    ])
    const names = ['a', 'b', 'c'].map((room) => `${room}-20261123T000000000Z.cclog`)
    for (const name of names) await writeFile(join(dir, name), 'not a log')
    await writeFile(join(other, names[0]), 'not a log')
    await listLogs(dir, new Set())
    await listLogs(other, new Set())
    const cached = (d: string): string[] => cachedLogPaths().filter((p) => p.startsWith(`${d}/`))
    expect(cached(dir).sort()).toEqual(names.map((n) => join(dir, n)))
    await unlink(join(dir, names[0]))
    await unlink(join(dir, names[2]))
    expect((await listLogs(dir, new Set())).map((l) => l.name)).toEqual([names[1]])
    expect(cached(dir)).toEqual([join(dir, names[1])])
    expect(cached(other)).toEqual([join(other, names[0])])
  })
})

describe('pruning (--replay-keep)', () => {
  /** A real log of a tower room started at `start`, closed cleanly or left as a crash leaves it. */
  async function makeLog(dir: string, room: string, start: number, closed: boolean): Promise<string> {
    const sim = new RoomSimulation({
      game: sandbox,
      name: room,
      scene: 'tower',
      maxBodies: 100,
      controls: true,
    })
    const recorder = new RoomRecorder(room, sim, {
      dir,
      fsync: 'none',
      keyframeTicks: 600,
      maxBytes: 1 << 30,
      compress: true,
      log: pino({ level: 'silent' }),
      failures: new Counter({ name: 'test_prune_failures', help: 'test', registers: [] }),
      openNames: new Set(),
    })
    recorder.start(start)
    for (let i = 0; i < 70; i++) sim.runTick()
    await recorder.flush()
    if (closed) await recorder.close('room closed')
    return recorder.name
  }

  it('deletes closed, superseded, empty and given-up logs oldest first, never an open, recent or recoverable one', async () => {
    const dir = await mkdtemp(join(tmpdir(), 'concord-prune-rules-'))
    const t = Date.UTC(2026, 10, 23)
    const closed = await makeLog(dir, 'a', t, true)
    const givenUpLog = await makeLog(dir, 'f', t + 500, false)
    await chmod(join(dir, givenUpLog), 0o444)
    const recoverable = await makeLog(dir, 'b', t + 1000, false)
    const superseded = await makeLog(dir, 'c', t + 2000, false)
    const empty = 'd-20261123T000003000Z.cclog'
    await writeFile(join(dir, empty), new Uint8Array(0))
    const newer = await makeLog(dir, 'c', t + 4000, true)
    const open = await makeLog(dir, 'e', t + 5000, false)
    expect(await listLogNames(dir)).toEqual([closed, givenUpLog, recoverable, superseded, empty, newer, open])
    // Written just now: only closed logs may go, and not c's newer one while its older unclosed one
    // is there (recovery would then reopen room c from that stale log).
    expect(await pruneLogs(dir, 1, new Set([open]))).toEqual([closed])
    // Quiet for longer than PRUNE_QUIET_MS: the given-up, superseded and empty ones go too, then
    // c's closed log; the room's newest unclosed log (recovery reopens it) and the open log stay,
    // even over --replay-keep.
    const later = Date.now() + PRUNE_QUIET_MS
    expect(await pruneLogs(dir, 1, new Set([open]), later)).toEqual([givenUpLog, superseded, empty, newer])
    expect(await listLogNames(dir)).toEqual([recoverable, open])
  })

  it('one pruner at a time: requests during a prune make one more run after it, never a second prune at once', async () => {
    let running = 0
    let most = 0
    let runs = 0
    let release: () => void = () => {}
    const pruner = new LogPruner(
      '/nonexistent',
      10,
      new Set(),
      (error) => {
        throw error
      },
      async () => {
        runs++
        running++
        most = Math.max(most, running)
        await new Promise<void>((resolve) => {
          release = resolve
        })
        running--
        return []
      },
    )
    pruner.request()
    for (let i = 0; i < 14; i++) pruner.request()
    await until(() => runs === 1, 'the first prune')
    release()
    await until(() => runs === 2, 'one more prune for the requests made during the first')
    release()
    await pruner.idle()
    expect({ runs, most }).toEqual({ runs: 2, most: 1 })
  })
})
