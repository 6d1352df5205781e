import pino from 'pino'
import { describe, expect, it } from 'vitest'
import { loadConfig, type ServerConfig } from '../../../server/config/config.ts'
import { createMetrics } from '../../../server/hosting/metrics.ts'
import { DROP_CONNECTION, type PlayerConnection } from '../../../server/rooms/player-connection.ts'
import { Room } from '../../../server/rooms/room.ts'
import { RoomManager } from '../../../server/rooms/room-manager.ts'
import type { RoomPlayer } from '../../../server/rooms/room-player.ts'
import {
  ClientMirror,
  decodeServerMessage,
  encodeMessage,
  type JoinMode,
  MAX_POSITION_ERROR,
  type ServerMessage,
} from '../../../shared/index.ts'

/** A connection without a socket: decodes what it is sent into a mirror, as a client would. */
class FakeConnection implements PlayerConnection {
  readonly received: ServerMessage[] = []
  readonly mirror = new ClientMirror()
  bufferedBytes = 0
  closed: { code: number; reason: string } | null = null
  player: RoomPlayer | null = null
  onClose: (() => void) | null = null

  send(message: ServerMessage): void {
    this.sendBytes(encodeMessage(message))
  }
  sendBytes(bytes: Uint8Array): void {
    if (this.closed) return
    const decoded = decodeServerMessage(bytes)
    if (!decoded.ok) throw new Error(`the room sent undecodable bytes: ${decoded.reason}`)
    this.received.push(decoded.value)
    const ack = this.mirror.handle(decoded.value)
    if (ack && this.player) this.player.encoder.ack(ack.tick)
  }
  sendError(code: string, reason: string, seq?: number): void {
    this.send(seq === undefined ? { t: 'error', code, reason } : { t: 'error', code, reason, seq })
  }
  buffered(): number {
    return this.bufferedBytes
  }
  close(code: number, reason: string): void {
    if (this.closed) return
    this.closed = { code, reason }
    this.onClose?.()
  }
  count(t: ServerMessage['t']): number {
    return this.received.filter((m) => m.t === t).length
  }
}

function makeRoom(overrides: Partial<ServerConfig> = {}): Room {
  const config = loadConfig([], {}, { defaultScene: 'empty', logLevel: 'silent', ...overrides })
  return new Room('unit', config, createMetrics(false), pino({ level: 'silent' }))
}

function join(room: Room, name: string, mode: JoinMode = 'snapshot'): FakeConnection {
  const conn = new FakeConnection()
  const player = room.join(conn, name, undefined, mode)
  if (typeof player === 'string') throw new Error(player)
  conn.player = player
  // What the transport does when a socket closes.
  conn.onClose = () => room.leave(player)
  return conn
}

describe('a room driven tick by tick with fake connections', () => {
  it('welcomes players, applies their commands, and snapshots reproduce the world', () => {
    const room = makeRoom({ snapshotRate: 30 })
    const a = join(room, 'ada')
    const b = join(room, 'bob')
    expect(a.mirror.clientId).toBe(1)
    expect(b.mirror.clientId).toBe(2)
    expect([...a.mirror.players.values()].map((p) => p.name)).toEqual(['ada', 'bob'])
    const before = room.world.bodyCount
    const spawn = { k: 'spawn', shape: { type: 'circle', radius: 0.5 }, x: 1, y: 6 } as const
    expect(room.queueInput(a.player!, 1, spawn)).toBeNull()
    expect(room.queueInput(b.player!, 1, { k: 'delete', body: 9999 })).toBeNull()
    room.runTick()
    expect(room.tick).toBe(1)
    expect(room.world.bodyCount).toBe(before + 1)
    // Both saw the creation event; only b got a refusal, naming its input's sequence number.
    expect(b.mirror.bodies.size).toBe(before + 1)
    expect(b.received.find((m) => m.t === 'error')).toEqual({
      t: 'error',
      code: 'refused',
      reason: 'body 9999 does not exist or is static',
      seq: 1,
    })
    expect(a.count('error')).toBe(0)
    const body = room.world.bodyIds().at(-1)!
    room.queueInput(b.player!, 2, { k: 'grab', body, lx: 0, ly: 0 })
    for (let t = 0; t < 39; t++) {
      room.queueInput(b.player!, 3 + t, { k: 'move', x: 3, y: 5 + t / 10 })
      room.runTick()
    }
    expect(room.grabCounts.get(body)).toBe(1)
    // Snapshots every 2 ticks reached both; the mirrors hold the server's poses within quantization.
    expect(a.count('snap')).toBe(20)
    for (const c of [a, b]) {
      expect(c.mirror.tick).toBe(room.tick)
      const p = room.world.getPosition(body)
      const m = c.mirror.bodies.get(body)!
      expect(Math.abs(m.x - p.x)).toBeLessThanOrEqual(MAX_POSITION_ERROR)
      expect(Math.abs(m.y - p.y)).toBeLessThanOrEqual(MAX_POSITION_ERROR)
      expect(c.mirror.cursors.get(2)?.body).toBe(body)
    }
    // A hash checkpoint every second: run to it and compare with the room's state hash (the world's,
    // continued over the colours of the bodies players spawned: PROTOCOL.md, Lockstep and predict).
    while (room.tick < 60) room.runTick()
    expect(room.sim.bodyColors.size).toBeGreaterThan(0)
    expect(a.mirror.lastHash).toEqual({ tick: 60, step: room.world.tick, hash: room.sim.hash() })
    // Leaving releases the grab.
    b.close(1000, 'bye')
    expect(room.grabCounts.size).toBe(0)
    expect(room.players.size).toBe(1)
    expect(a.received.at(-1)).toEqual({ t: 'players', players: [{ id: 1, name: 'ada', color: '#e6194b' }] })
  })

  it("inputs over a tick's budget wait for the next ticks in order; only beyond 4 ticks' worth are refused", () => {
    const room = makeRoom({ inputsPerTick: 8, maxBodies: 500 })
    const a = join(room, 'ada')
    const before = room.world.bodyCount
    // 60 spawns in one tick, each at its own x so the order of creation can be read back.
    const refused: number[] = []
    for (let i = 0; i < 60; i++) {
      const spawn = { k: 'spawn', shape: { type: 'circle', radius: 0.2 }, x: -20 + i * 0.5, y: 5 } as const
      if (room.queueInput(a.player!, i + 1, spawn) !== null) refused.push(i + 1)
      // A move in the middle of the burst waits in its place; a second move right after it
      // replaces it there (only the latest cursor position matters).
      if (i === 20) {
        expect(room.queueInput(a.player!, 1000, { k: 'move', x: 1, y: 1 })).toBeNull()
        expect(room.queueInput(a.player!, 1001, { k: 'move', x: 2, y: 2 })).toBeNull()
      }
    }
    // 8 this tick, then 32 waiting: spawns 9-21, the move, spawns 22-39; spawns 40-60 refused.
    expect(refused).toEqual(Array.from({ length: 21 }, (_, i) => 40 + i))
    expect(room.queueInput(a.player!, 1002, { k: 'move', x: 3, y: 3 })).toMatch(/budget exceeded/)
    const created: number[] = []
    for (let t = 1; t <= 6; t++) {
      room.runTick()
      created.push(room.world.bodyCount - before)
    }
    // Hand count: 8 inputs per tick, the move taking one of the third tick's 8.
    expect(created).toEqual([8, 16, 23, 31, 39, 39])
    const xs = room.world
      .bodyIds()
      .filter((id) => room.world.getBodyType(id) === 'dynamic')
      .map((id) => room.world.getPosition(id).x)
    expect(xs).toEqual(Array.from({ length: 39 }, (_, i) => -20 + i * 0.5))
    expect(room.sim.saveState().players).toEqual([{ id: a.player!.id, grab: null, cursorX: 2, cursorY: 2 }])
  })

  it('skips snapshots to a connection with too much buffered, then closes it if it stays behind', () => {
    const room = makeRoom({ snapshotRate: 60, sendBufferBytes: 10_000, slowClientSeconds: 1 })
    const fast = join(room, 'fast')
    const slow = join(room, 'slow')
    room.runTick()
    expect(slow.count('snap')).toBe(1)
    slow.bufferedBytes = 10_001
    for (let t = 0; t < 60; t++) room.runTick()
    // Skipped for a whole second (not more than slowClientSeconds), still in the room.
    expect(slow.count('snap')).toBe(1)
    expect(slow.closed).toBeNull()
    expect(fast.count('snap')).toBe(61)
    room.runTick()
    room.runTick()
    expect(slow.closed?.code).toBe(DROP_CONNECTION)
    expect(room.players.has(slow.player!.id)).toBe(false)
    expect(fast.count('snap')).toBe(63)
  })

  it('a connection that catches up in time is not closed; one past the hard limit is closed at once', () => {
    const room = makeRoom({ snapshotRate: 60, sendBufferBytes: 10_000, slowClientSeconds: 1 })
    const wobbly = join(room, 'wobbly')
    const flooded = join(room, 'flooded')
    wobbly.bufferedBytes = 20_000
    for (let t = 0; t < 50; t++) room.runTick()
    wobbly.bufferedBytes = 0
    for (let t = 0; t < 50; t++) room.runTick()
    expect(wobbly.closed).toBeNull()
    expect(wobbly.count('snap')).toBe(50)
    flooded.bufferedBytes = (1 << 20) + 1
    room.runTick()
    expect(flooded.closed?.code).toBe(DROP_CONNECTION)
    expect(wobbly.closed).toBeNull()
  })
})

describe('the slow-reader rule for lockstep players (their tick stream is never skipped)', () => {
  it('closes one over the send-buffer budget for --slow-client-seconds or over the hard limit, not one that catches up', () => {
    const room = makeRoom({ snapshotRate: 60, sendBufferBytes: 10_000, slowClientSeconds: 1 })
    const behind = join(room, 'behind', 'lockstep')
    const wobbly = join(room, 'wobbly', 'lockstep')
    const flooded = join(room, 'flooded', 'lockstep')
    room.runTick()
    behind.bufferedBytes = 10_001
    wobbly.bufferedBytes = 20_000
    for (let t = 0; t < 50; t++) room.runTick()
    wobbly.bufferedBytes = 0
    for (let t = 0; t < 10; t++) room.runTick()
    // Behind for a whole second (not more than slowClientSeconds): still in the room.
    expect(behind.closed).toBeNull()
    room.runTick()
    room.runTick()
    expect(behind.closed?.code).toBe(DROP_CONNECTION)
    expect(room.players.has(behind.player!.id)).toBe(false)
    for (let t = 0; t < 60; t++) room.runTick()
    expect(wobbly.closed).toBeNull()
    flooded.bufferedBytes = (1 << 20) + 1
    room.runTick()
    expect(flooded.closed?.code).toBe(DROP_CONNECTION)
    expect(wobbly.closed).toBeNull()
    // Its tick stream was sent all along: lockstep players get no snapshots to skip.
    expect(wobbly.count('ticks')).toBeGreaterThan(0)
    expect(wobbly.count('snap')).toBe(0)
  })
})

describe('per-room tick budget', () => {
  /** A manager whose room ticks are timed by a hand-set clock: `slow` rooms take 60 ms per tick. */
  function budgetedManager(slow: Set<string>) {
    const config = loadConfig(
      [],
      {},
      { defaultScene: 'empty', logLevel: 'silent', roomTickBudgetMs: 50, roomOverrunTicks: 30 },
    )
    let now = 0
    const metrics = createMetrics(false)
    const rooms = new RoomManager(config, metrics, pino({ level: 'silent' }), () => now)
    const open = (name: string): Room => {
      const room = rooms.getOrCreate(name)!
      const runTick = room.runTick.bind(room)
      room.runTick = () => {
        runTick()
        now += slow.has(name) ? 60 : 1
      }
      return room
    }
    return { rooms, open, metrics }
  }

  it('a room over budget in 30 ticks of a second is closed with a notice; its neighbour is untouched', async () => {
    const { rooms, open, metrics } = budgetedManager(new Set(['hog']))
    const hog = open('hog')
    open('calm')
    const player = join(hog, 'victim')
    const neighbour = join(rooms.get('calm')!, 'neighbour')
    for (let i = 0; i < 29; i++) rooms.tickAll()
    expect(rooms.get('hog')).toBe(hog)
    expect(player.closed).toBeNull()
    rooms.tickAll()
    expect(rooms.get('hog')).toBeUndefined()
    expect(player.closed?.code).toBe(4007)
    expect(player.received.some((m) => m.t === 'error' && m.code === 'overloaded')).toBe(true)
    expect(rooms.get('calm')).toBeDefined()
    expect(neighbour.closed).toBeNull()
    expect((await metrics.roomsClosedOverBudget.get()).values[0].value).toBe(1)
  })

  it('the count restarts every second: 29 slow ticks per second forever never close the room', () => {
    const slow = new Set(['bursty'])
    const { rooms, open } = budgetedManager(slow)
    open('bursty')
    for (let second = 0; second < 5; second++) {
      for (let t = 0; t < 60; t++) {
        if (t < 29) slow.add('bursty')
        else slow.delete('bursty')
        rooms.tickAll()
      }
    }
    expect(rooms.get('bursty')).toBeDefined()
  })
})

describe('the tick loop on a machine that keeps falling behind', () => {
  it('logs at most 3 overrun warnings per 10 s, however many ticks it drops (one line per event, not per tick)', () => {
    const lines: Array<{ msg: string; dropped?: number }> = []
    const log = pino({ level: 'warn' }, { write: (line: string) => lines.push(JSON.parse(line)) })
    const config = loadConfig([], {}, { defaultScene: 'empty', logLevel: 'silent' })
    const metrics = createMetrics(false)
    const rooms = new RoomManager(config, metrics, log)
    rooms.getOrCreate('late')
    // 200 wake-ups, each 10 ticks late: 4 run, 6 dropped every time.
    rooms.clock.reset(0)
    for (let i = 1; i <= 200; i++) rooms.clock.pump((i * 10 * 1000) / 60)
    expect(rooms.clock.overruns).toBe(200 * 6)
    const overruns = lines.filter((l) => l.msg === 'tick loop fell behind; dropped ticks')
    expect(overruns.length).toBe(3)
    expect(overruns.map((l) => l.dropped)).toEqual([6, 6, 6])
  })
})

describe('rooms opened together spread their periodic work over the clock', () => {
  /** Runs n clock ticks; per connection, the clock ticks (1, 2, ...) at which it got each message type. */
  function run(rooms: RoomManager, conns: FakeConnection[], n: number, from = 0) {
    const at = conns.map(() => ({ snap: [] as number[], hash: [] as Array<{ clock: number; tick: number }> }))
    for (let clock = from + 1; clock <= from + n; clock++) {
      const seen = conns.map((c) => c.received.length)
      rooms.tickAll()
      conns.forEach((c, k) => {
        for (const m of c.received.slice(seen[k])) {
          if (m.t === 'snap') at[k].snap.push(clock)
          if (m.t === 'hash') at[k].hash.push({ clock, tick: m.tick })
        }
      })
    }
    return at
  }

  it('snapshots take turns: at 30 per second, rooms 1 and 3 send on one clock tick, 2 and 4 on the next, each every other tick', () => {
    const config = loadConfig([], {}, { defaultScene: 'pyramid', logLevel: 'silent', snapshotRate: 30 })
    const rooms = new RoomManager(config, createMetrics(false), pino({ level: 'silent' }))
    const conns: FakeConnection[] = []
    for (let k = 1; k <= 4; k++) conns.push(join(rooms.getOrCreate(`turns-${k}`)!, `p${k}`))
    const at = run(rooms, conns, 12)
    const parity = at[0].snap[0] % 2
    expect(at[0].snap).toEqual([1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12].filter((c) => c % 2 === parity))
    expect(at[1].snap).toEqual([1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12].filter((c) => c % 2 !== parity))
    expect(at[2].snap).toEqual(at[0].snap)
    expect(at[3].snap).toEqual(at[1].snap)
    // Every snapshot still decodes into the room's state (the mirror acked each one).
    for (const c of conns) expect(c.count('error')).toBe(0)
  })

  it('checkpoints: 20 rooms opened in one tick hash on 20 different clock ticks, at room ticks that are multiples of 60; a room opened later takes a free clock tick', () => {
    const config = loadConfig([], {}, { defaultScene: 'empty', logLevel: 'silent', snapshotRate: 20 })
    const rooms = new RoomManager(config, createMetrics(false), pino({ level: 'silent' }))
    const conns: FakeConnection[] = []
    for (let k = 0; k < 20; k++) conns.push(join(rooms.getOrCreate(`burst-${k}`)!, `p${k}`))
    for (const room of rooms.list()) expect(room.tick).toBeLessThan(60)
    const at = run(rooms, conns, 120)
    for (const a of at) {
      // Once a second, on a room tick that is a multiple of 60 (the protocol's checkpoint ticks).
      expect(a.hash.length).toBe(2)
      expect(a.hash[0].tick % 60).toBe(0)
      expect(a.hash[1].clock - a.hash[0].clock).toBe(60)
    }
    const clocks = at.map((a) => a.hash[0].clock % 60)
    expect(new Set(clocks).size).toBe(20)
    // Snapshots (every 3rd tick): the 20 rooms take the 3 slots 7, 7 and 6 at a time.
    const perClock = new Map<number, number>()
    for (const a of at) for (const c of a.snap) perClock.set(c, (perClock.get(c) ?? 0) + 1)
    expect(Math.max(...perClock.values())).toBe(7)
    expect(Math.min(...perClock.values())).toBe(6)
    // A 21st room, opened 35 ticks later, avoids the 20 clock ticks already taken.
    for (let i = 0; i < 35; i++) rooms.tickAll()
    const late = join(rooms.getOrCreate('late')!, 'late')
    const lateAt = run(rooms, [late], 60, 155)
    expect(lateAt[0].hash).toHaveLength(1)
    expect(lateAt[0].hash[0].tick % 60).toBe(0)
    expect(clocks).not.toContain(lateAt[0].hash[0].clock % 60)
  })
})
