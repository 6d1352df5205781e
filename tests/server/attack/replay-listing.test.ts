/*
 * GET /replays, which anyone may request, against the logs being recorded. Listing a log reads it
 * through to summarize it, and a log being recorded changes every second, so every listing once
 * read every open log again from its first byte: a cost that grows with the logs (up to
 * --replay-max-bytes, 256 MiB, each) paid on the main thread, which holds every socket, for each
 * request. Now a log that has only grown is read on from where the last listing stopped. Against
 * a real recording server: the second listing reads only what was appended since the first.
 */
import { mkdtemp, stat } from 'node:fs/promises'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { afterAll, beforeAll, describe, expect, it } from 'vitest'
import { logBytesRead } from '../../../server/replay/replay-files.ts'
import type { RunningServer } from '../../../server/server.ts'
import { startTestServer } from '../../support/test-server.ts'
import { until } from '../../support/wait.ts'

let server: RunningServer
let dir: string

beforeAll(async () => {
  dir = await mkdtemp(join(tmpdir(), 'concord-listing-'))
  // A pyramid: the log's header holds a saved world of 211 bodies; what follows each second is small.
  server = await startTestServer({ workers: 1, record: true, replayDir: dir, defaultScene: 'pyramid' })
})
afterAll(async () => {
  await server.close()
})

/** GET /replays: name and size of each log. */
async function listing(): Promise<Array<{ name: string; size: number; status: string }>> {
  return (await (await fetch(`${server.url}/replays`)).json()) as Array<{
    name: string
    size: number
    status: string
  }>
}

describe('GET /replays while a room records', { timeout: 20_000 }, () => {
  it('reads only the bytes appended to a log since the last listing, not the whole log again', async () => {
    await until(
      async () => (await listing()).some((l) => l.status === 'recording' && l.size > 0),
      'a log being recorded, its header written',
    )
    const before = logBytesRead.total
    const [first] = await listing()
    const firstRead = logBytesRead.total - before
    // The recorder appends at least once a second.
    await until(async () => (await stat(join(dir, first.name))).size > first.size, 'the log to grow')
    const again = logBytesRead.total
    const [second] = await listing()
    const secondRead = logBytesRead.total - again
    expect(second.name).toBe(first.name)
    expect(second.size).toBeGreaterThan(first.size)
    expect(firstRead).toBeLessThanOrEqual(first.size + 4096)
    // Not the header and the first listing's bytes again: only what was appended after them.
    expect(secondRead).toBeLessThan(first.size)
    expect(secondRead).toBeGreaterThan(0)
  })
})
