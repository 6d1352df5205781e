/*
 * A seeded stream of random and malformed client messages against a real server process (issue
 * 11: nothing a client sends may reach an uncaught throw; every number that leaves the server is
 * finite). fast-check builds every kind of client message with fields drawn from hostile values
 * (NaN, infinities, -0, 1e308, 2^53, wrong types, unknown keys, bad shapes, bodies and joints
 * that do not exist), and eight clients in snapshot, lockstep and predict mode send them to rooms
 * on two worker threads with the rate limits raised, so the messages reach validation and the
 * rooms instead of being cut by the budget; one frame in 20 is random bytes. A client the server drops reconnects and joins again.
 * Every frame the server sends is decoded and walked for non-finite numbers; at the end the
 * process is alive, /healthz answers 200, a new client joins, and no error-level line was logged.
 */
import { encode } from '@msgpack/msgpack'
import fc from 'fast-check'
import { Unpackr } from 'msgpackr'
import { afterAll, beforeAll, expect, it } from 'vitest'
import WebSocket from 'ws'
import { PROTOCOL_VERSION } from '../../../shared/index.ts'
import { type ServerProcess, startServerProcess } from '../../support/server-process.ts'
import { until } from '../../support/wait.ts'

const MESSAGES = 30_000
const SEED = 11
/** Ping ids of the round trips, above the ids the stream's own pings use (fc.nat()). */
const PING_BASE = 2 ** 40
const ROOMS = ['lobby', 'fuzz-a', 'fuzz-b', 'fuzz-c']
const MODES = ['snapshot', 'lockstep', 'predict'] as const

const unpackr = new Unpackr({ useRecords: false, mapsAsObjects: true, int64AsType: 'number' })

const hostile = fc.oneof(
  fc.constantFrom(0, -0, 1, -1, 0.5, 1e308, -1e308, 5e-324, 2 ** 31, -(2 ** 31), 2 ** 32, 2 ** 53, 1e9),
  fc.constantFrom(Number.NaN, Number.POSITIVE_INFINITY, Number.NEGATIVE_INFINITY),
  fc.double(),
  fc.integer(),
  fc.string({ maxLength: 40 }),
  fc.boolean(),
  fc.constant(null),
  fc.array(fc.integer(), { maxLength: 5 }),
  fc.dictionary(fc.string({ maxLength: 5 }), fc.integer(), { maxKeys: 3 }),
  fc.constantFrom('pyramid', 'lobby', 'empty', '__proto__', 'constructor', ''),
)
/** Mostly plausible values, so that most commands get past the schema to the rooms. */
const mostly = <T>(plausible: fc.Arbitrary<T>) =>
  fc.oneof({ weight: 4, arbitrary: plausible }, { weight: 1, arbitrary: hostile })
const coordinate = mostly(fc.double({ min: -600, max: 600, noNaN: true }))
const id = mostly(fc.integer({ min: -2, max: 300 }))
const extent = mostly(fc.double({ min: 0, max: 5, noNaN: true }))
/** Points on a circle in angle order (convex, though possibly degenerate), as the flat list `v`. */
const convexRing = fc
  .tuple(
    fc.integer({ min: 3, max: 8 }),
    fc.double({ min: 0, max: 4, noNaN: true }),
    fc.array(fc.double({ min: 0, max: 2 * Math.PI, noNaN: true }), { minLength: 8, maxLength: 8 }),
  )
  .map(([n, r, angles]) =>
    angles
      .slice(0, n)
      .sort((a, b) => a - b)
      .flatMap((a) => [r * Math.cos(a), r * Math.sin(a)]),
  )
const shape = fc.oneof(
  fc.record({ type: fc.constant('circle'), radius: extent }),
  fc.record({ type: fc.constant('box'), hw: extent, hh: extent }),
  fc.record({ type: fc.constant('polygon'), v: convexRing }),
  fc.record({
    type: fc.constant('polygon'),
    v: fc.array(mostly(fc.double({ min: -10, max: 10, noNaN: true })), { minLength: 5, maxLength: 17 }),
  }),
  fc.record({ type: fc.constantFrom('circle', 'box', 'polygon'), radius: hostile, hw: hostile, v: hostile }),
  hostile,
)
const anything = fc.dictionary(fc.string({ maxLength: 6 }), hostile, { maxKeys: 6 })
const command = fc.oneof(
  fc.record(
    {
      k: fc.constant('spawn'),
      shape,
      x: coordinate,
      y: coordinate,
      angle: coordinate,
      vx: coordinate,
      vy: coordinate,
      w: coordinate,
      density: mostly(fc.double({ min: 0, max: 20, noNaN: true })),
      friction: mostly(fc.double({ min: 0, max: 2, noNaN: true })),
      restitution: mostly(fc.double({ min: 0, max: 1, noNaN: true })),
    },
    { requiredKeys: ['k', 'shape', 'x', 'y'] },
  ),
  fc.record({ k: fc.constant('grab'), body: id, lx: coordinate, ly: coordinate }),
  fc.record({ k: fc.constant('move'), x: coordinate, y: coordinate }),
  fc.record({ k: fc.constant('release') }),
  fc.record({ k: fc.constant('delete'), body: id }),
  fc.record({ k: fc.constant('pin'), a: id, b: id, x: coordinate, y: coordinate }),
  fc.record({
    k: fc.constant('rope'),
    a: id,
    b: id,
    ax: coordinate,
    ay: coordinate,
    bx: coordinate,
    by: coordinate,
  }),
  fc.record({ k: fc.constant('unjoint'), joint: id }),
  fc.record({ k: fc.constant('scene'), name: hostile }),
  fc.record({ k: fc.constant('pause'), paused: hostile }),
  fc.record({ k: fc.constant('step') }),
  fc.record({ k: fc.constant('reset') }),
  fc.record({ k: fc.constant('gravity'), x: coordinate, y: coordinate }),
  fc.record({ k: fc.constant('inspect'), body: id }),
  anything,
)
const message = fc.oneof(
  {
    weight: 12,
    arbitrary: fc.record({ t: fc.constant('input'), seq: mostly(fc.nat()), cmd: command }),
  },
  {
    weight: 1,
    arbitrary: fc.record({ t: fc.constant('ack'), tick: fc.oneof(fc.nat({ max: 100_000 }), hostile) }),
  },
  { weight: 1, arbitrary: fc.record({ t: fc.constant('ping'), id: hostile, time: hostile }) },
  {
    weight: 1,
    arbitrary: fc.record({ t: fc.constant('desync'), tick: hostile, hash: hostile, server: hostile }),
  },
  { weight: 1, arbitrary: fc.record({ t: fc.constant('resync') }) },
  {
    weight: 1,
    arbitrary: fc.record({
      t: fc.constant('join'),
      v: fc.oneof({ weight: 9, arbitrary: fc.constant(PROTOCOL_VERSION) }, { weight: 1, arbitrary: hostile }),
      room: hostile,
      name: hostile,
      mode: fc.oneof(fc.constantFrom(...MODES), hostile),
      token: hostile,
      hold: hostile,
    }),
  },
  { weight: 1, arbitrary: anything },
)

/** Binary frames: mostly encoded messages, some random bytes (rarely MessagePack at all). */
const frame = fc.oneof(
  { weight: 19, arbitrary: message.map((m) => encode(m, { ignoreUndefined: true })) },
  { weight: 1, arbitrary: fc.uint8Array({ minLength: 1, maxLength: 64 }) },
)

/** The path and value of the first non-finite number in a decoded message, or null. */
function firstNonFinite(value: unknown, path: string): string | null {
  if (typeof value === 'number') return Number.isFinite(value) ? null : `${path} = ${value}`
  if (value instanceof Float32Array || value instanceof Float64Array) {
    const i = value.findIndex((x) => !Number.isFinite(x))
    return i < 0 ? null : `${path}[${i}] = ${value[i]}`
  }
  if (ArrayBuffer.isView(value)) return null
  if (Array.isArray(value)) {
    for (let i = 0; i < value.length; i++) {
      const found = firstNonFinite(value[i], `${path}[${i}]`)
      if (found) return found
    }
    return null
  }
  if (value !== null && typeof value === 'object') {
    for (const [key, item] of Object.entries(value)) {
      const found = firstNonFinite(item, `${path}.${key}`)
      if (found) return found
    }
  }
  return null
}

/** What every fuzzing client saw from the server. */
const seen = { byType: new Map<string, number>(), problems: [] as string[], reconnects: 0 }

/** One fuzzing client: connects, joins its room in its mode, and checks every frame it receives. */
class FuzzClient {
  socket: WebSocket | null = null
  private pong = -1

  constructor(
    private readonly port: number,
    private readonly room: string,
    private readonly mode: (typeof MODES)[number],
  ) {}

  /** Whether the socket is open (a dropped client reconnects on its next message). */
  get open(): boolean {
    return this.socket?.readyState === WebSocket.OPEN
  }

  /** Opens a socket and joins; resolves once it is open or has failed. */
  async connect(): Promise<void> {
    const socket = new WebSocket(`ws://127.0.0.1:${this.port}/ws?room=${this.room}`)
    this.socket = socket
    socket.on('error', () => {})
    socket.on('message', (data: Buffer, isBinary: boolean) => this.receive(data, isBinary))
    await new Promise((resolve) => {
      socket.once('open', resolve)
      socket.once('close', resolve)
    })
    if (this.open)
      socket.send(encode({ t: 'join', v: PROTOCOL_VERSION, room: this.room, name: 'fuzz', mode: this.mode }))
  }

  /** Sends a ping and resolves once its pong is back: the server has handled everything before it. */
  async roundTrip(id: number): Promise<void> {
    if (!this.open) return
    this.socket?.send(encode({ t: 'ping', id, time: 0 }))
    await until(() => this.pong === id || !this.open, `pong ${id} from room ${this.room}`, 60_000)
  }

  private receive(data: Buffer, isBinary: boolean): void {
    if (!isBinary) {
      seen.problems.push('a text frame')
      return
    }
    let decoded: unknown
    try {
      decoded = unpackr.unpack(data)
    } catch (error) {
      seen.problems.push(`an undecodable frame: ${error}`)
      return
    }
    const t = String((decoded as { t?: unknown }).t)
    seen.byType.set(t, (seen.byType.get(t) ?? 0) + 1)
    if (t === 'pong') this.pong = Number((decoded as { id?: unknown }).id)
    const bad = firstNonFinite(decoded, t)
    if (bad) seen.problems.push(bad)
  }
}

let server: ServerProcess

beforeAll(async () => {
  server = await startServerProcess([
    '--workers',
    '2',
    '--max-rejects',
    '100000',
    '--max-messages-per-second',
    '100000',
    '--inputs-per-tick',
    '1000',
    '--max-bodies',
    '400',
  ])
})
afterAll(async () => {
  if (server.process.exitCode === null) {
    server.process.kill('SIGTERM')
    await server.exited
  }
})

it(`${MESSAGES} seeded hostile messages from 8 clients: the server lives, serves, and sends only finite numbers`, async () => {
  const clients = Array.from(
    { length: 8 },
    (_, i) => new FuzzClient(server.port, ROOMS[i % ROOMS.length], MODES[i % MODES.length]),
  )
  for (const client of clients) await client.connect()
  const messages = fc.sample(frame, { numRuns: MESSAGES, seed: SEED })
  for (let i = 0; i < messages.length; i++) {
    const client = clients[i % clients.length]
    if (!client.open) {
      seen.reconnects++
      await client.connect()
      continue
    }
    client.socket?.send(messages[i])
    // Every 25 messages per client, a round trip: the server has handled what came before, and a
    // client it dropped (a join with a wrong version closes the socket) reconnects before it sends more.
    if (i % 200 === 199) await Promise.all(clients.map((c, k) => c.roundTrip(PING_BASE + i + k)))
  }
  await Promise.all(clients.map((c, k) => c.roundTrip(PING_BASE + messages.length + k)))

  expect(server.process.exitCode).toBe(null)
  expect((await fetch(`${server.url}/healthz`)).status).toBe(200)
  const fresh = new FuzzClient(server.port, 'lobby', 'snapshot')
  const welcomes = seen.byType.get('welcome') ?? 0
  await fresh.connect()
  await until(() => (seen.byType.get('welcome') ?? 0) > welcomes, 'a welcome for a new client')
  fresh.socket?.close()
  for (const client of clients) client.socket?.close()

  expect(seen.problems).toEqual([])
  const errors = server.lines.filter((line) => Number((line as { level?: unknown }).level) >= 50)
  expect(errors).toEqual([])
  // The stream reached the rooms in every mode: snapshots, lockstep ticks and refusals came back.
  expect(seen.byType.get('snap') ?? 0).toBeGreaterThan(0)
  expect(seen.byType.get('ticks') ?? 0).toBeGreaterThan(0)
  expect(seen.byType.get('error') ?? 0).toBeGreaterThan(0)
  // Joins with a wrong version dropped clients, and the dropped clients came back.
  expect(seen.reconnects).toBeGreaterThan(0)
}, 240_000)
