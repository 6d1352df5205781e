/*
 * The room directory shared by every server of a deployment, in Redis (--redis URL). A room name
 * maps to the one server that holds it; a server that is asked for a room held by another sends
 * the client there (the `moved` message, shared/protocol/PROTOCOL.md).
 *
 * Keys (all with a time to live, refreshed by a heartbeat every ttl/3):
 *   concord:room:NAME   -> server id     claimed atomically (a Lua script: take it if free,
 *                                         refresh it if ours, else report the holder), so a room
 *                                         name is never open on two servers at once
 *   concord:server:ID   -> public URL    where clients reach that server
 * A server that dies stops refreshing: its rooms and its address expire after the ttl and the next
 * join anywhere claims the room afresh. A server that finds one of its rooms taken by another (it
 * lost Redis for longer than the ttl) is told through onLost and closes that room. Releasing a
 * room (disposal, shutdown) deletes the key only if this server still holds it.
 */
import { randomUUID } from 'node:crypto'
import { Redis } from 'ioredis'
import type { Logger } from 'pino'

/** Where a room lives. */
export type RoomLocation = { holder: 'self' } | { holder: 'other'; url: string; server: string }

/** Claim or refresh KEYS[1] for ARGV[1] with ttl ARGV[2] ms; returns the holder's id. */
const CLAIM = `
local owner = redis.call('GET', KEYS[1])
if not owner then
  redis.call('SET', KEYS[1], ARGV[1], 'PX', ARGV[2])
  return ARGV[1]
end
if owner == ARGV[1] then redis.call('PEXPIRE', KEYS[1], ARGV[2]) end
return owner`

/**
 * Refresh every KEYS[i] held by ARGV[1], take back keys that vanished (Redis restarted without
 * its data), and return 1 per key kept, 0 per key another server holds now.
 */
const REFRESH = `
local kept = {}
for i, key in ipairs(KEYS) do
  local owner = redis.call('GET', key)
  if owner == ARGV[1] then
    redis.call('PEXPIRE', key, ARGV[2])
    kept[i] = 1
  elseif not owner then
    redis.call('SET', key, ARGV[1], 'PX', ARGV[2])
    kept[i] = 1
  else
    kept[i] = 0
  end
end
return kept`

/** Delete KEYS[i] that ARGV[1] still holds. */
const RELEASE = `
local n = 0
for _, key in ipairs(KEYS) do
  if redis.call('GET', key) == ARGV[1] then n = n + redis.call('DEL', key) end
end
return n`

/** Prefix of every key the directory writes. */
export const KEY_PREFIX = 'concord:'

/** The shared room directory of one server. */
export class RoomDirectory {
  /** This server's id in the directory. */
  readonly serverId = randomUUID()
  /** Called when a room this server held was claimed by another (lost Redis for too long). */
  onLost: ((room: string) => void) | null = null
  private readonly held = new Set<string>()
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

  /** Claim a room for this server, or find out who holds it. Throws when Redis cannot answer. */
  async claim(room: string): Promise<RoomLocation> {
    const holder = String(await this.redis.eval(CLAIM, 1, roomKey(room), this.serverId, this.ttlMs))
    if (holder === this.serverId) {
      this.held.add(room)
      return { holder: 'self' }
    }
    const url = await this.redis.get(serverKey(holder))
    if (url === null) throw new Error(`room ${room} is held by server ${holder}, whose address has expired`)
    return { holder: 'other', url, server: holder }
  }

  /** Give up a room (disposed); a no-op if another server holds it by now. */
  async release(room: string): Promise<void> {
    this.held.delete(room)
    await this.redis.eval(RELEASE, 1, roomKey(room), this.serverId)
  }

  /** Rooms this server holds. */
  rooms(): string[] {
    return [...this.held]
  }

  /** Release every room and the address, stop the heartbeat, disconnect. */
  async close(): Promise<void> {
    if (this.timer) clearInterval(this.timer)
    this.timer = null
    const keys = [...this.held].map(roomKey)
    this.held.clear()
    try {
      if (keys.length > 0) await this.redis.eval(RELEASE, keys.length, ...keys, this.serverId)
      await this.redis.eval(RELEASE, 1, serverKey(this.serverId), this.publicUrl)
    } catch (error) {
      this.logError('could not release rooms at shutdown', error as Error)
    }
    this.redis.disconnect()
  }

  /** Refresh this server's address and every held room; report rooms taken by another server. */
  private async heartbeat(): Promise<void> {
    const names = [...this.held]
    try {
      await this.redis.set(serverKey(this.serverId), this.publicUrl, 'PX', this.ttlMs)
      if (names.length === 0) return
      const kept = (await this.redis.eval(
        REFRESH,
        names.length,
        ...names.map(roomKey),
        this.serverId,
        this.ttlMs,
      )) as number[]
      names.forEach((name, i) => {
        if (kept[i] === 1 || !this.held.has(name)) return
        this.held.delete(name)
        this.log.error({ room: name }, 'room directory: another server holds this room now; closing it here')
        this.onLost?.(name)
      })
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

function serverKey(id: string): string {
  return `${KEY_PREFIX}server:${id}`
}
