/*
 * The room directory shared by every server of a deployment, in Redis (--redis URL). A room name
 * maps to the one server that holds it; a server that is asked for a room held by another sends
 * the client there (the `moved` message, shared/protocol/PROTOCOL.md).
 *
 * Keys (all with a time to live, refreshed by a heartbeat every ttl/3):
 *   concord:room:NAME   -> server id     claimed atomically (a Lua script: take it if free,
 *                                         refresh it if ours, else report the holder), so a room
 *                                         name is never open on two servers at once
 *   concord:age:NAME    -> ms            when the holder's copy of the room opened (its clock)
 *   concord:server:ID   -> public URL    where clients reach that server
 * A server that dies stops refreshing: its rooms and its address expire after the ttl and the next
 * join anywhere claims the room afresh. Releasing a room (disposal, shutdown) deletes its keys
 * only if this server still holds it.
 *
 * Redis restarted without its data (issue 30, point 9): every claim is gone at once. Each server
 * re-claims its rooms at its next heartbeat, and at once when its connection comes back ('ready').
 * A join that reached another server in between may have opened a second copy there; the copies
 * meet at a heartbeat, and the older room keeps the name (opened earlier; the server id breaks a
 * tie): its server takes the key back, and the other server hands its copy over, sending its
 * players `moved` with the keeper's URL before the 4006 close (onLost). A live room is never
 * closed without `moved`: while the keeper's address is unknown the copy stays open. The same
 * rule settles a server that lost Redis for longer than the ttl.
 *
 * A server restarted within a claim's lifetime gets a new id, while its old claims and address
 * (the same URL) live on: a join for such a room would send the client `moved` to this very
 * server, again and again. A claim held by an id whose address is this server's URL is taken
 * over instead (TAKEOVER), atomically, only if that id still holds it.
 */
import { randomUUID } from 'node:crypto'
import { Redis } from 'ioredis'
import type { Logger } from 'pino'

/** Where a room lives. */
export type RoomLocation = { holder: 'self' } | { holder: 'other'; url: string; server: string }

/**
 * Claim or refresh room KEYS[1] (age key KEYS[2]) for ARGV[1] with ttl ARGV[2] ms, a free one as
 * opened at ARGV[3] ms; returns the holder's id and its room's age.
 */
const CLAIM = `
local owner = redis.call('GET', KEYS[1])
if not owner then
  redis.call('SET', KEYS[1], ARGV[1], 'PX', ARGV[2])
  redis.call('SET', KEYS[2], ARGV[3], 'PX', ARGV[2])
  return {ARGV[1], ARGV[3]}
end
if owner == ARGV[1] then
  redis.call('PEXPIRE', KEYS[1], ARGV[2])
  redis.call('PEXPIRE', KEYS[2], ARGV[2])
end
return {owner, redis.call('GET', KEYS[2]) or '0'}`

/**
 * Refresh every room (KEYS[2i-1], its age KEYS[2i]) held by ARGV[1]; take back the rooms whose
 * keys vanished (Redis restarted without its data) and those another server claimed with a
 * younger copy (its age after ours, ARGV[2+i], or the same age and a greater id). Returns 1 per
 * room kept, 0 per room another server keeps.
 */
const REFRESH = `
local kept = {}
for i = 1, #KEYS / 2 do
  local key, age, ours = KEYS[2 * i - 1], KEYS[2 * i], tonumber(ARGV[2 + i])
  local owner = redis.call('GET', key)
  local theirs = tonumber(redis.call('GET', age) or '')
  if owner == ARGV[1] then
    redis.call('PEXPIRE', key, ARGV[2])
    redis.call('SET', age, ARGV[2 + i], 'PX', ARGV[2])
    kept[i] = 1
  elseif not owner or theirs == nil or theirs > ours or (theirs == ours and owner > ARGV[1]) then
    redis.call('SET', key, ARGV[1], 'PX', ARGV[2])
    redis.call('SET', age, ARGV[2 + i], 'PX', ARGV[2])
    kept[i] = 1
  else
    kept[i] = 0
  end
end
return kept`

/** Take room KEYS[1] (age KEYS[2]) from ARGV[1] for ARGV[2], opened at ARGV[4], ttl ARGV[3]; 1 when taken. */
const TAKEOVER = `
if redis.call('GET', KEYS[1]) ~= ARGV[1] then return 0 end
redis.call('SET', KEYS[1], ARGV[2], 'PX', ARGV[3])
redis.call('SET', KEYS[2], ARGV[4], 'PX', ARGV[3])
return 1`

/** Delete KEYS[i] that ARGV[1] still holds (a room's age key goes with it: KEYS[i + 1] when ARGV[2] is 'room'). */
const RELEASE = `
local n = 0
local step = ARGV[2] == 'room' and 2 or 1
for i = 1, #KEYS, step do
  if redis.call('GET', KEYS[i]) == ARGV[1] then
    n = n + redis.call('DEL', KEYS[i])
    if step == 2 then redis.call('DEL', KEYS[i + 1]) end
  end
end
return n`

/** Prefix of every key the directory writes. */
export const KEY_PREFIX = 'concord:'

/** The shared room directory of one server. */
export class RoomDirectory {
  /** This server's id in the directory. */
  readonly serverId = randomUUID()
  /**
   * Called when another server keeps a room this server held (an older copy of it, after Redis
   * lost its data or this server lost Redis for too long), with that server's URL: hand the room
   * over (`moved`, then close 4006).
   */
  onLost: ((room: string, url: string) => void) | null = null
  /** The rooms this server holds, each with when its copy opened (ms, this server's clock). */
  private readonly held = new Map<string, number>()
  private readonly redis: Redis
  private timer: NodeJS.Timeout | null = null
  private lastErrorLog = Number.NEGATIVE_INFINITY
  private lastError: Error | null = null

  /** Where clients reach this server (a ws:// or wss:// base URL), set by register(). */
  publicUrl = ''

  constructor(
    private readonly url: string,
    /** Time to live of every key (ms); a dead server's rooms are free after this. */
    readonly ttlMs: number,
    private readonly log: Logger,
  ) {
    this.redis = new Redis(url, { lazyConnect: true, maxRetriesPerRequest: 1, enableOfflineQueue: false })
    this.redis.on('error', (error: Error) => {
      this.lastError = error
      this.logError('redis error', error)
    })
    // Back after a disconnect (Redis restarted, maybe without its data): re-claim every room now
    // rather than at the next heartbeat, so a join elsewhere rarely finds one free.
    this.redis.on('ready', () => {
      if (this.timer) void this.heartbeat()
    })
  }

  /** Connect to Redis; throws naming the URL when it cannot be reached. */
  async connect(): Promise<void> {
    try {
      await this.redis.connect()
      await this.redis.ping()
    } catch (error) {
      this.redis.disconnect()
      const cause = this.lastError?.message ?? (error as Error).message
      throw new Error(`cannot reach the room directory at ${this.url}: ${cause}`)
    }
  }

  /** Register this server's public URL and start the heartbeat. */
  async register(publicUrl: string): Promise<void> {
    this.publicUrl = publicUrl
    await this.heartbeat()
    this.timer = setInterval(() => void this.heartbeat(), Math.max(50, Math.floor(this.ttlMs / 3)))
    this.timer.unref()
    this.log.info({ server: this.serverId, url: this.publicUrl, ttlMs: this.ttlMs }, 'room directory joined')
  }

  /**
   * Claim a room for this server, or find out who holds it. A claim of a previous run of this
   * server (its address is this server's URL) is taken over. Throws when Redis cannot answer.
   */
  async claim(room: string): Promise<RoomLocation> {
    const now = Date.now()
    const keys = [roomKey(room), ageKey(room)]
    const [holder, age] = (await this.redis.eval(CLAIM, 2, ...keys, this.serverId, this.ttlMs, now)) as [
      string,
      string,
    ]
    if (holder === this.serverId) {
      this.held.set(room, this.held.get(room) ?? Number(age))
      return { holder: 'self' }
    }
    const url = await this.redis.get(serverKey(holder))
    if (url === null) throw new Error(`room ${room} is held by server ${holder}, whose address has expired`)
    if (url === this.publicUrl) {
      const taken = await this.redis.eval(TAKEOVER, 2, ...keys, holder, this.serverId, this.ttlMs, now)
      if (taken === 1) {
        this.log.info(
          { room, previous: holder },
          'room directory: took over a claim of a previous run of this server',
        )
        this.held.set(room, now)
        return { holder: 'self' }
      }
      return this.claim(room)
    }
    return { holder: 'other', url, server: holder }
  }

  /** Give up a room (disposed); a no-op if another server holds it by now. */
  async release(room: string): Promise<void> {
    this.held.delete(room)
    await this.redis.eval(RELEASE, 2, roomKey(room), ageKey(room), this.serverId, 'room')
  }

  /** Rooms this server holds. */
  rooms(): string[] {
    return [...this.held.keys()]
  }

  /** Release every room and the address, stop the heartbeat, disconnect. */
  async close(): Promise<void> {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    const keys = [...this.held.keys()].flatMap((room) => [roomKey(room), ageKey(room)])
    this.held.clear()
    try {
      if (keys.length > 0) await this.redis.eval(RELEASE, keys.length, ...keys, this.serverId, 'room')
      await this.redis.eval(RELEASE, 1, serverKey(this.serverId), this.publicUrl, 'key')
    } catch (error) {
      this.logError('could not release rooms at shutdown', error as Error)
    }
    this.redis.disconnect()
  }

  /**
   * Refresh this server's address and every held room (taking back vanished and younger claims);
   * hand over the rooms another server keeps, once its address is known.
   */
  private async heartbeat(): Promise<void> {
    const names = [...this.held.keys()]
    try {
      await this.redis.set(serverKey(this.serverId), this.publicUrl, 'PX', this.ttlMs)
      if (names.length === 0) return
      const kept = (await this.redis.eval(
        REFRESH,
        2 * names.length,
        ...names.flatMap((name) => [roomKey(name), ageKey(name)]),
        this.serverId,
        this.ttlMs,
        ...names.map((name) => this.held.get(name) ?? 0),
      )) as number[]
      for (const [i, name] of names.entries()) {
        if (kept[i] === 1 || !this.held.has(name)) continue
        const holder = await this.redis.get(roomKey(name))
        const url = holder === null ? null : await this.redis.get(serverKey(holder))
        if (url === null || !this.held.has(name)) {
          // Keep the room open: the next heartbeat looks again (or takes the key back).
          this.logError(
            `room ${name} is claimed by server ${holder}, whose address is unknown`,
            new Error('no address'),
          )
          continue
        }
        this.held.delete(name)
        this.log.error(
          { room: name, server: holder, url },
          'room directory: another server keeps an older copy of this room; handing it over (moved)',
        )
        this.onLost?.(name, url)
      }
    } catch (error) {
      this.logError('heartbeat failed', error as Error)
    }
  }

  private logError(what: string, error: Error): void {
    const now = Date.now()
    if (now - this.lastErrorLog < 10_000) return
    this.lastErrorLog = now
    this.log.warn({ err: error.message }, `room directory: ${what}`)
  }
}

function roomKey(room: string): string {
  return `${KEY_PREFIX}room:${room}`
}

function ageKey(room: string): string {
  return `${KEY_PREFIX}age:${room}`
}

function serverKey(id: string): string {
  return `${KEY_PREFIX}server:${id}`
}
