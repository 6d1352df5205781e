/*
 * Seeded random request targets against a real server on 127.0.0.1 (issue 11: any request target
 * gets an answer, never a crash; files come only from the static directory and the replay
 * directory). fast-check builds targets from the pieces path tricks are made of (dot segments
 * plain and percent-encoded, encoded slashes and backslashes, NUL, overlong UTF-8, bad escapes,
 * the server's own routes and file names, long segments, queries), and a few raw strings; each is
 * written byte for byte on its own connection with a random method, with and without upgrade
 * headers. A canary file sits beside the static and replay directories. Every answer must be a
 * complete HTTP response below 500 that holds neither the canary nor package.json nor
 * /etc/passwd; afterwards the server is healthy, a player can join, and nothing was logged at
 * error level.
 */
import { randomBytes } from 'node:crypto'
import { mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import fc from 'fast-check'
import { afterAll, beforeAll, expect, it } from 'vitest'
import { BotClient } from '../../../bots/bot-client.ts'
import type { RunningServer } from '../../../server/server.ts'
import { capturingLogger, healthy, rawConnect, upgradeRequest } from '../../support/raw-client.ts'
import { startTestServer } from '../../support/test-server.ts'

const REQUESTS = 1500
const SEED = 23

/** Dot segments, plain and encoded (with encoded slashes and backslashes, which URL parsing keeps). */
const climb = fc.constantFrom(
  '..',
  '%2e%2e',
  '%2E%2E',
  '.%2e',
  '..%2f',
  '..%5c',
  '%2e%2e%2f',
  '..%2f..',
  '..\\',
  '.',
)
/** Names of things worth reaching: the canary, files, the server's routes. */
const name = fc.constantFrom(
  'secret.txt',
  'static',
  'index.html',
  'replays',
  'healthz',
  'readyz',
  'metrics',
  'rooms',
  'ws',
  'lobby.clog',
  'package.json',
)
/** Bytes that break decoders and parsers. */
const junk = fc.constantFrom(
  '%2f',
  '%5c',
  '\\',
  '%00',
  '%',
  '%zz',
  '%c0%ae%c0%ae',
  '%ff',
  'é',
  '~',
  '',
  'x'.repeat(300),
)
const piece = fc.oneof(
  { weight: 5, arbitrary: climb },
  { weight: 3, arbitrary: name },
  { weight: 2, arbitrary: junk },
)
const path = fc
  .tuple(
    fc.oneof(
      { weight: 6, arbitrary: fc.constantFrom('/', '/replays/', '/static/') },
      { weight: 1, arbitrary: fc.constantFrom('//', '', '*', 'http://127.0.0.1/', '/ws/') },
    ),
    fc.array(piece, { minLength: 0, maxLength: 8 }),
    fc.constantFrom('', '?room=lobby', '?room=../x', '?%', '#frag', '?a=%zz&b'),
  )
  .map(([start, pieces, query]) => `${start}${pieces.join('/')}${query}`)
/** A climb out of the served directory toward a named file. */
const breakout = fc
  .tuple(
    fc.constantFrom('/', '/replays/', '/static/'),
    fc.array(climb, { minLength: 1, maxLength: 4 }),
    fc.constantFrom('/', ''),
    name,
  )
  .map(([start, climbs, join, file]) => `${start}${climbs.join(join)}${join}${file}`)
const target = fc.oneof(
  { weight: 5, arbitrary: path },
  { weight: 4, arbitrary: breakout },
  {
    weight: 1,
    arbitrary: fc.string({ maxLength: 60, unit: 'binary' }).map((s) => s.replace(/[\r\n ]/g, '')),
  },
)
const request = fc.record({
  method: fc.constantFrom('GET', 'GET', 'GET', 'HEAD', 'POST', 'OPTIONS', 'BREW'),
  target,
  upgrade: fc.boolean(),
})

/**
 * Everything the server answers to `text` on a fresh connection, as latin1: it closes after one
 * answer, except after a 101 (an accepted upgrade), where the head is all there is to read.
 */
async function exchange(port: number, text: string): Promise<string> {
  const socket = await rawConnect(port)
  let received = ''
  socket.on('data', (chunk: Buffer) => {
    received += chunk.toString('latin1')
    if (received.startsWith('HTTP/1.1 101') && received.includes('\r\n\r\n')) socket.destroy()
  })
  const closed = new Promise<void>((resolve) => {
    socket.on('error', () => {})
    socket.once('close', () => resolve())
  })
  socket.write(Buffer.from(text, 'utf8'))
  await closed
  return received
}

const capture = capturingLogger('warn')
const dir = mkdtempSync(join(tmpdir(), 'concord-http-fuzz-'))
const canary = `canary-${randomBytes(16).toString('hex')}`
let server: RunningServer

beforeAll(async () => {
  mkdirSync(join(dir, 'static'))
  mkdirSync(join(dir, 'replays'))
  writeFileSync(join(dir, 'static', 'index.html'), '<!doctype html><title>fuzz</title>\n')
  writeFileSync(join(dir, 'secret.txt'), `${canary}\n`)
  server = await startTestServer(
    { staticDir: join(dir, 'static'), replayDir: join(dir, 'replays'), record: true },
    capture.logger,
  )
})
afterAll(async () => {
  await server.close()
  rmSync(dir, { recursive: true, force: true })
})

it(`${REQUESTS} seeded hostile request targets: answers below 500, no file from outside, the server carries on`, async () => {
  // A room with a recording, so /replays/ has a real log to find.
  const player = await BotClient.connect({ url: server.url, room: 'lobby', name: 'fuzz' })
  await player.close()

  const forbidden = [canary, readFileSync('package.json', 'utf8').slice(0, 40), 'root:x:0:0']
  const problems: string[] = []
  const statuses = new Map<number, number>()
  for (const r of fc.sample(request, { numRuns: REQUESTS, seed: SEED })) {
    const line = `${r.method} ${r.target} HTTP/1.1`
    const text = r.upgrade
      ? upgradeRequest(r.target).replace(/^GET /, `${r.method} `)
      : `${line}\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n`
    const answer = await exchange(server.port, text)
    const status = Number(/^HTTP\/1\.1 (\d{3})/.exec(answer)?.[1] ?? 0)
    statuses.set(status, (statuses.get(status) ?? 0) + 1)
    if (status === 0 || status >= 500) problems.push(`${JSON.stringify(line)}: ${answer.slice(0, 60)}`)
    for (const text of forbidden)
      if (answer.includes(text)) problems.push(`${JSON.stringify(line)} leaked ${text}`)
  }

  expect(problems).toEqual([])
  expect(await healthy(server.url)).toBe(true)
  const after = await BotClient.connect({ url: server.url, room: 'lobby', name: 'after' })
  await after.close()
  expect(capture.lines.filter((l) => Number(l.level) >= 50)).toEqual([])
  // The stream reached the routes: files and probes answered, bad targets were refused.
  expect(statuses.get(200) ?? 0).toBeGreaterThan(0)
  expect(statuses.get(400) ?? 0).toBeGreaterThan(0)
  expect(statuses.get(404) ?? 0).toBeGreaterThan(0)
}, 120_000)
