/*
 * A recorder on a failing disk, through the file seam (replay-files.ts LogFile): a disk of a fixed
 * size that takes what fits of a write (a short write, as write(2) does) and then answers ENOSPC.
 * The real-disk version is recording-disk-full.test.ts (a tmpfs, root only). Oracles: the bytes
 * of the file, read back by the log reader; the failure counter; the log lines.
 */
import { Counter } from 'prom-client'
import { describe, expect, it } from 'vitest'
import { sandbox } from '../../../games/index.ts'
import { RoomRecorder } from '../../../server/replay/recorder.ts'
import type { LogFile } from '../../../server/replay/replay-files.ts'
import { ReplayLogReader } from '../../../shared/replay/replay-log-reader.ts'
import { RoomSimulation } from '../../../shared/sim/room-simulation.ts'
import { capturingLogger } from '../../support/raw-client.ts'
import { until } from '../../support/wait.ts'

/** Files in memory on a disk of `space` bytes (shared by all files). */
function smallDisk(space: number) {
  const disk = {
    space,
    files: new Map<string, { bytes: Buffer; givenUp: boolean; linked: boolean }>(),
  }
  const used = (): number => [...disk.files.values()].reduce((n, f) => n + f.bytes.length, 0)
  const openLog = async (path: string): Promise<LogFile> => {
    const file = { bytes: Buffer.alloc(0), givenUp: false, linked: true }
    disk.files.set(path, file)
    return {
      write: async (b) => {
        const free = disk.space - used()
        if (free <= 0)
          throw Object.assign(new Error('ENOSPC: no space left on device, write'), { code: 'ENOSPC' })
        const n = Math.min(free, b.length)
        file.bytes = Buffer.concat([file.bytes, b.subarray(0, n)])
        return { bytesWritten: n }
      },
      sync: async () => {},
      close: async () => {},
      truncate: async (size) => {
        file.bytes = file.bytes.subarray(0, size)
      },
      linked: async () => file.linked,
      giveUp: async () => {
        file.givenUp = true
      },
      remove: async () => {
        disk.files.delete(path)
      },
    }
  }
  return { disk, openLog }
}

function recorderOn(openLog: (path: string) => Promise<LogFile>, retryMs: number) {
  const sim = new RoomSimulation({
    game: sandbox,
    name: 'full',
    scene: 'tower',
    maxBodies: 500,
    controls: true,
  })
  const { logger, lines } = capturingLogger('info')
  const failures = new Counter({ name: 'test_disk_failures', help: 'test', registers: [] })
  const recorder = new RoomRecorder('full', sim, {
    dir: '/nonexistent',
    fsync: 'interval',
    keyframeTicks: 600,
    maxBytes: 1 << 30,
    retryMs,
    compress: true,
    log: logger,
    failures,
    openNames: new Set(),
    openLog,
  })
  return { sim, recorder, lines, failures }
}

function read(bytes: Uint8Array) {
  const reader = new ReplayLogReader()
  const records = reader.push(bytes)
  return { status: reader.finish(), records }
}

describe('a recorder on a disk that fills up', () => {
  it('cuts a short write back to the last whole record, closes the log ("recording failed"), counts and logs it once', async () => {
    const { disk, openLog } = smallDisk(1 << 20)
    const { sim, recorder, lines, failures } = recorderOn(openLog, 60_000)
    recorder.start(0)
    sim.join(1, 'p', '#ffffff')
    for (let i = 0; i < 120; i++) sim.runTick()
    await recorder.flush()
    const [path] = disk.files.keys()
    const whole = disk.files.get(path)!.bytes.length
    const lastTick = read(disk.files.get(path)!.bytes).status.lastTick
    // 200 bytes of room left, then a scene load and the keyframe at tick 600 (the pyramid's saved
    // world, kilobytes) does not fit.
    disk.space = whole + 200
    expect(sim.apply(1, { k: 'scene', name: 'pyramid' })).toBeNull()
    while (sim.tick < 610) sim.runTick()
    await recorder.flush()
    await until(() => recorder.failed, 'the recorder fails')
    await recorder.flush()
    const file = disk.files.get(path)!
    const { status, records } = read(file.bytes)
    // Everything that was whole is there, then the close record (it fits in the 200 bytes freed).
    expect(status).toMatchObject({ state: 'end', closed: true })
    expect(records.at(-1)).toMatchObject({ type: 'close', reason: 'recording failed', tick: lastTick })
    expect(file.bytes.length).toBeGreaterThan(whole)
    expect(file.bytes.length).toBeLessThanOrEqual(whole + 200)
    expect((await failures.get()).values[0].value).toBe(1)
    const errors = lines.filter((l) => l.msg === 'recording stopped for this room; the room keeps running')
    expect(errors).toHaveLength(1)
    expect(String(errors[0].err)).toMatch(/ENOSPC.*after a short write: 200 of \d+ bytes/)
    await recorder.close('test over')
  })

  it('gives the log up (read-only mark) when not even a close record fits, and resumes in a new log with a header once there is room', async () => {
    const { disk, openLog } = smallDisk(1 << 20)
    const { sim, recorder, lines, failures } = recorderOn(openLog, 50)
    recorder.start(0)
    sim.join(1, 'p', '#ffffff')
    for (let i = 0; i < 120; i++) sim.runTick()
    await recorder.flush()
    const [path] = disk.files.keys()
    const whole = disk.files.get(path)!.bytes.length
    disk.space = whole + 3
    expect(sim.apply(1, { k: 'scene', name: 'pyramid' })).toBeNull()
    while (sim.tick < 610) sim.runTick()
    await recorder.flush()
    await until(() => disk.files.get(path)!.givenUp, 'the log given up')
    // Cut back to its last whole record: no part of a record stays.
    expect(disk.files.get(path)!.bytes.length).toBe(whole)
    expect(read(disk.files.get(path)!.bytes).status).toMatchObject({ state: 'end', closed: false })
    // Retries while the disk is full create nothing that stays and are not counted again.
    await until(
      () => lines.some((l) => l.msg === 'recording is still failing for this room'),
      'a retry fails',
    )
    expect((await failures.get()).values[0].value).toBe(1)
    disk.space = 1 << 20
    await until(() => lines.some((l) => l.msg === 'recording resumed in a new log'), 'recording resumed')
    const logs = [...disk.files.entries()].filter(([, f]) => f.bytes.length > 0)
    expect(logs).toHaveLength(2)
    const { records } = read(logs[1][1].bytes)
    expect(records[0]).toMatchObject({ type: 'header', scene: 'pyramid' })
    expect(records[0].tick).toBe(sim.tick)
    await recorder.close('test over')
    expect(read(logs[1][1].bytes).status.closed).toBe(true)
  })

  it('notices a log deleted under it and starts a new one with a header at once, counting the failure', async () => {
    const { disk, openLog } = smallDisk(1 << 20)
    const { sim, recorder, failures } = recorderOn(openLog, 60_000)
    recorder.start(0)
    for (let i = 0; i < 30; i++) sim.runTick()
    await recorder.flush()
    const [path] = disk.files.keys()
    disk.files.get(path)!.linked = false
    // The check runs with the once-a-second flush.
    await until(() => disk.files.size === 2, 'a new log', 5000)
    expect((await failures.get()).values[0].value).toBe(1)
    for (let i = 0; i < 30; i++) sim.runTick()
    await recorder.flush()
    const next = [...disk.files.values()][1]
    expect(read(next.bytes).records[0]).toMatchObject({ type: 'header' })
    await recorder.close('test over')
  })

  it("a failed write at a rotation gives the old log up: its close says 'recording failed', never 'rotated' after half a record", async () => {
    const files = new Map<string, { bytes: Buffer; breakNext: boolean }>()
    const openLog = async (path: string): Promise<LogFile> => {
      const file = { bytes: Buffer.alloc(0), breakNext: false }
      files.set(path, file)
      return {
        write: async (b) => {
          if (file.breakNext) {
            // Part of the write lands, then the disk fails.
            file.breakNext = false
            file.bytes = Buffer.concat([file.bytes, b.subarray(0, 5)])
            throw Object.assign(new Error('EIO: i/o error, write'), { code: 'EIO' })
          }
          file.bytes = Buffer.concat([file.bytes, b])
          return { bytesWritten: b.length }
        },
        sync: async () => {},
        close: async () => {},
        truncate: async (size) => {
          file.bytes = file.bytes.subarray(0, size)
        },
        remove: async () => {
          files.delete(path)
        },
      }
    }
    const sim = new RoomSimulation({
      game: sandbox,
      name: 'rot',
      scene: 'tower',
      maxBodies: 5000,
      controls: true,
    })
    const { logger, lines } = capturingLogger('info')
    const recorder = new RoomRecorder('rot', sim, {
      dir: '/nonexistent',
      fsync: 'none',
      keyframeTicks: 600,
      maxBytes: 4096,
      retryMs: 50,
      compress: true,
      log: logger,
      failures: new Counter({ name: 'test_rotation_fail', help: 'test', registers: [] }),
      openNames: new Set(),
      openLog,
    })
    recorder.start(0)
    sim.join(1, 'p', '#ffffff')
    await recorder.flush()
    const [oldPath] = files.keys()
    const first = recorder.name
    files.get(oldPath)!.breakNext = true
    // Commands until the log rotates (no await: the first write after the header is the rotation's).
    for (let i = 0; recorder.name === first; i++) {
      sim.apply(1, { k: 'spawn', shape: { type: 'circle', radius: 0.2 }, x: (i % 40) - 20, y: 30 + (i % 7) })
      sim.runTick()
      if (i > 5000) throw new Error('no rotation')
    }
    await until(() => lines.some((l) => l.msg === 'recording resumed in a new log'), 'recording resumed')
    const old = read(files.get(oldPath)!.bytes)
    expect(old.status).toMatchObject({ state: 'end', closed: true })
    expect(old.records.at(-1)).toMatchObject({ type: 'close', reason: 'recording failed' })
    // The log the rotation began (nothing whole in it) is gone; the retry's log starts with a header.
    const rest = [...files.entries()].filter(([path]) => path !== oldPath)
    expect(rest).toHaveLength(1)
    expect(read(rest[0][1].bytes).records[0]).toMatchObject({ type: 'header' })
    await recorder.close('test over')
  })
})
