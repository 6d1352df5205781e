import { mkdtemp, unlink, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { describe, expect, it } from 'vitest'
import { cachedLogPaths, listLogs } from '../../../server/replay/replay-files.ts'
import { encodePreamble, REPLAY_FORMAT_VERSION } from '../../../shared/replay/replay-log.ts'

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
