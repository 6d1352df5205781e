import { spawnSync } from 'node:child_process'
import { mkdtemp, readFile, writeFile } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { deflateSync } from 'node:zlib'
import { beforeAll, describe, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import { listLogNames } from '../../../server/replay/replay-files.ts'
import { crc32 } from '../../../shared/replay/crc32.ts'
import {
  type BlockableRecord,
  decodeRecordBody,
  encodeBlockEntries,
  frameBlock,
  PREAMBLE_BYTES,
} from '../../../shared/replay/replay-log.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { startTestServer } from '../../support/test-server.ts'

let dir: string
let log: Uint8Array
/** Byte offset just past each framed record, in order (found by walking the length prefixes). */
let ends: number[]
/** Records in each framed record: 1, or a block's count (found by decoding each frame alone). */
let counts: number[]

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-cli-'))
  const server = await startTestServer({
    record: true,
    replayDir: dir,
    keyframeTicks: 60,
    keyframeBudget: 0,
    defaultScene: 'tower',
  })
  const bot = await BotClient.connect({ url: server.url, room: 'cli', name: 'ada' })
  bot.command({ k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 0, y: 12 })
  // The room's tick as ada sees it: the room runs (and records) on a worker thread.
  for (let i = 0; bot.mirror.tick < 200; i++) {
    bot.command({ k: 'move', x: i % 7, y: 3 })
    await new Promise((r) => setTimeout(r, 30))
  }
  await bot.close()
  await server.close()
  const name = (await listLogNames(dir)).find((n) => n.startsWith('cli-'))!
  log = new Uint8Array(await readFile(join(dir, name)))
  ends = []
  const view = new DataView(log.buffer, log.byteOffset, log.byteLength)
  counts = []
  for (let at = PREAMBLE_BYTES; at < log.length; ) {
    const length = view.getUint32(at, true)
    counts.push(decodeRecordBody(log.subarray(at + 4, at + 4 + length)).length)
    at += 4 + length + 4
    ends.push(at)
  }
  expect(counts.some((n) => n > 1)).toBe(true)
  expect(ends.at(-1)).toBe(log.length)
}, 60_000)

function cli(...args: string[]): { status: number | null; stdout: string; stderr: string } {
  const r = spawnSync(process.execPath, ['--import', 'tsx', 'server/replay/replay-cli.ts', ...args], {
    encoding: 'utf8',
  })
  return { status: r.status, stdout: r.stdout, stderr: r.stderr }
}

async function variant(name: string, bytes: Uint8Array): Promise<string> {
  const path = join(dir, name)
  await writeFile(path, bytes)
  return path
}

function read(bytes: Uint8Array) {
  const reader = new ReplayLogReader()
  const records = reader.push(bytes)
  return { records, status: reader.finish() }
}

describe('the replay CLI', { timeout: 120_000 }, () => {
  it('verifies a recorded log and reports what it replayed', async () => {
    const path = await variant('good.cclog', log)
    const r = cli(path, '--verify', '--json')
    expect(r.status, r.stderr).toBe(0)
    const report = JSON.parse(r.stdout)
    expect(report.divergence).toBeNull()
    expect(report.lastTick).toBeGreaterThanOrEqual(200)
    expect(report.hashesChecked).toBeGreaterThanOrEqual(3)
    expect(report.keyframesChecked).toBeGreaterThanOrEqual(3)
    expect(report.players).toBe(1)
    const text = cli(path, '--to', '120', '--hash-every', '30')
    expect(text.status).toBe(0)
    expect(text.stdout).toMatch(/ticks\s+\d+ to 120/)
    expect(text.stdout.match(/^tick \d+ 0x[0-9a-f]{8}$/gm)?.length).toBeGreaterThanOrEqual(3)
  })

  it('--progress N writes how far it got every N ticks to standard error, and nothing without it', async () => {
    const path = await variant('progress.cclog', log)
    const { records, status } = read(log)
    const first = records[0].tick
    const r = cli(path, '--progress', '50', '--json')
    expect(r.status, r.stderr).toBe(0)
    const lines = r.stderr.trim().split('\n')
    const ticks = lines.map((line) => {
      const m = /^replay: tick (\d+) of (\d+) \((\d+) %\)$/.exec(line)
      expect(m, line).not.toBeNull()
      expect(Number(m![2])).toBe(status.lastTick)
      expect(Number(m![3])).toBe(Math.floor((100 * Number(m![1])) / status.lastTick))
      return Number(m![1])
    })
    // One line at every 50th tick after the header's, up to the last one replayed.
    const expected: number[] = []
    for (let t = first + 50; t <= status.lastTick; t += 50) expected.push(t)
    expect(ticks).toEqual(expected)
    expect(JSON.parse(r.stdout).lastTick).toBe(status.lastTick)
    expect(cli(path).stderr).toBe('')
    const bad = cli(path, '--progress', 'x')
    expect(bad.status).toBe(2)
    expect(bad.stderr).toBe('replay: --progress needs a non-negative integer, got "x"\n')
  })

  it('a tampered hash (in a block rebuilt with a valid CRC) is reported as the first mismatch, exit 1', async () => {
    let start = PREAMBLE_BYTES
    for (const end of ends) {
      const records = decodeRecordBody(log.subarray(start + 4, end - 4))
      const hash = records.find((r) => r.type === 'hash')
      if (log[start + 4] === 9 && hash?.type === 'hash') {
        const tick = hash.tick
        hash.hash = (hash.hash ^ 1) >>> 0
        const block = frameBlock(
          records[0].tick,
          deflateSync(encodeBlockEntries(records as BlockableRecord[])),
        )
        expect(crc32(block, 0, block.length - 4)).toBe(
          new DataView(block.buffer).getUint32(block.length - 4, true),
        )
        const bytes = new Uint8Array(Buffer.concat([log.subarray(0, start), block, log.subarray(end)]))
        const r = cli(await variant('tampered.cclog', bytes), '--verify')
        expect(r.status).toBe(1)
        expect(r.stdout).toMatch(
          new RegExp(`MISMATCH at tick ${tick}: hash 0x[0-9a-f]{8}, log 0x[0-9a-f]{8}`),
        )
        return
      }
      start = end
    }
    throw new Error('no hash record in the log')
  })

  it('truncated, corrupted, wrong-version and non-log files get one clear line and a non-zero exit', async () => {
    const cases: Array<[string, Uint8Array, number, RegExp]> = [
      ['empty', new Uint8Array(0), 2, /too short for a replay log/],
      ['text', new TextEncoder().encode('hello, this is not a log at all\n'), 2, /not a Concord replay log/],
      ['format', Object.assign(log.slice(), { 8: 9 }), 2, /unsupported replay format version 9/],
      ['engine', Object.assign(log.slice(), { 10: 77 }), 2, /engine save-format version 77/],
      // docs/replay-format.md: logs of the three earlier save formats are refused with this line.
      ...[1, 2, 3].map((v): [string, Uint8Array, number, RegExp] => [
        `engine-${v}`,
        Object.assign(log.slice(), { 10: v }),
        2,
        new RegExp(`log written with engine save-format version ${v}; this build reads version 4`),
      ]),
      ['header-cut', log.slice(0, ends[0] - 3), 2, /no header|torn/],
      ['torn', log.slice(0, ends[5] + 7), 3, /torn tail/],
      [
        'flipped',
        Object.assign(log.slice(), { [ends[3] + 6]: log[ends[3] + 6] ^ 0x10 }),
        3,
        new RegExp(`record \\d+ at byte ${ends[3]}: checksum mismatch`),
      ],
    ]
    for (const [name, bytes, status, message] of cases) {
      const r = cli(await variant(`${name}.cclog`, bytes))
      expect(r.status, name).toBe(status)
      expect(`${r.stdout}${r.stderr}`, name).toMatch(message)
      expect(r.stderr, name).not.toMatch(/\n\s+at /)
      if (status === 2) expect(r.stderr.trim().split('\n'), name).toHaveLength(1)
    }
    const missing = cli(join(dir, 'absent.cclog'))
    expect(missing.status).toBe(2)
    expect(missing.stderr).toMatch(/cannot read .*ENOENT/)
  })

  it('the reader keeps exactly the intact prefix of torn, bit-flipped and zero-filled logs', () => {
    let seed = 12345
    const random = (n: number): number => {
      seed = (seed * 1103515245 + 12345) % 2147483648
      return seed % n
    }
    const recordsBefore = (frames: number): number => counts.slice(0, frames).reduce((a, b) => a + b, 0)
    const intactBefore = (cut: number): number => recordsBefore(ends.filter((e) => e <= cut).length)
    for (let trial = 0; trial < 200; trial++) {
      const cut = PREAMBLE_BYTES + random(log.length - PREAMBLE_BYTES)
      const torn = read(log.slice(0, cut))
      expect(torn.records.length, `cut at ${cut}`).toBe(intactBefore(cut))
      const frames = ends.filter((e) => e <= cut).length
      expect(torn.status.intactBytes).toBe(frames ? ends[frames - 1] : PREAMBLE_BYTES)
      const zeroed = log.slice()
      zeroed.fill(0, cut)
      const z = read(zeroed)
      expect(z.records.length, `zeros from ${cut}`).toBe(intactBefore(cut))
      const flipped = log.slice()
      flipped[cut] ^= 1 << random(8)
      const f = read(flipped)
      const hit = ends.findIndex((e) => e > cut)
      expect(f.records.length, `bit flip at ${cut}`).toBe(recordsBefore(hit))
      // A flipped length bit can also make the record look incomplete (torn): never accepted either way.
      expect(['corrupt', 'invalid', 'torn']).toContain(f.status.state)
    }
    const whole = read(log)
    expect(whole.status).toMatchObject({ state: 'end', closed: true, records: recordsBefore(ends.length) })
  })
})
