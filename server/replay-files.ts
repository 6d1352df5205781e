/*
 * The replay directory: log file names (room, UTC start time, a counter on collision), the one
 * pattern a name must match to be served or read (so `..`, absolute paths, slashes and NUL can
 * never name a file), summaries for GET /replays (read by streaming each file through the log
 * reader, cached by size and mtime), and pruning to --replay-keep files.
 */
import { createReadStream } from 'node:fs'
import { readdir, readFile, stat, unlink } from 'node:fs/promises'
import { join } from 'node:path'
import { PREAMBLE_BYTES, type Preamble, REPLAY_MAGIC, type ReplayRecord } from '../shared/replay-log.ts'
import { type ReadStatus, ReplayLogReader } from '../shared/replay-log-reader.ts'

/** Extension of replay logs. */
export const LOG_EXTENSION = '.cclog'
/** A valid log name: room, start time (UTC, ms), optional counter, extension; nothing else. */
export const LOG_NAME_PATTERN = /^[A-Za-z0-9_-]{1,32}-\d{8}T\d{9}Z(?:-\d{1,4})?\.cclog$/

/**
 * A log name's room and start stamp (with its counter), read from the fixed-format end of the name:
 * a room name may itself contain what looks like a stamp (`lobby-99999999T` is a valid room name).
 */
const LOG_NAME_PARTS = /^(.+)-(\d{8}T\d{9}Z(?:-\d{1,4})?)\.cclog$/

/** The room a log belongs to (its name before the start stamp), or '' for a name that is not a log's. */
export function roomOfLog(name: string): string {
  return LOG_NAME_PARTS.exec(name)?.[1] ?? ''
}

/** A log's start stamp and counter as they appear at the end of its name, or ''. */
function stampOfLog(name: string): string {
  return LOG_NAME_PARTS.exec(name)?.[2] ?? ''
}

/** The file name for a room log started at `startMs` (counter > 0 on a name collision). */
export function logFileName(room: string, startMs: number, counter = 0): string {
  const stamp = new Date(startMs).toISOString().replace(/[-:.]/g, '')
  return `${room}-${stamp}${counter > 0 ? `-${counter}` : ''}${LOG_EXTENSION}`
}

/** Whether a requested name is a log name (and so names a file directly inside the directory). */
export function isLogName(name: string): boolean {
  return LOG_NAME_PATTERN.test(name)
}

/** A log as GET /replays lists it. */
export interface LogSummary {
  name: string
  room: string
  /** Start, UTC ISO 8601. */
  start: string
  /** Recorded time (ticks / tick rate), seconds. */
  duration: number
  ticks: number
  size: number
  /**
   * clean: ends with a close record; recording: still being written; torn/corrupt: cut short;
   * empty: its writer stopped before the header was whole (nothing to play); invalid: not a log.
   */
  status: 'clean' | 'recording' | 'torn' | 'corrupt' | 'empty' | 'invalid'
  /** Why it is torn, corrupt or invalid. */
  problem?: string
  /** The process that wrote it. */
  writer?: { host: string; pid: number }
}

/** Everything learned from reading a log through once, without loading any world. */
export interface LogScan {
  preamble: Preamble | null
  header: Extract<ReplayRecord, { type: 'header' }> | null
  status: ReadStatus
  /** Byte offset just past the last hash or keyframe record (0 when none). */
  checkpointBytes: number
  checkpointTick: number
}

/** Stream a log through the reader; `onRecord` sees every accepted record in order. */
export async function scanLog(path: string, onRecord?: (r: ReplayRecord) => void): Promise<LogScan> {
  const reader = new ReplayLogReader()
  const scan: LogScan = {
    preamble: null,
    header: null,
    status: reader.current,
    checkpointBytes: 0,
    checkpointTick: -1,
  }
  for await (const chunk of createReadStream(path, { highWaterMark: 1 << 20 })) {
    reader.push(chunk as Buffer, (r, end) => {
      if (r.type === 'header') scan.header = r
      onRecord?.(r)
      if (r.type === 'hash' || r.type === 'keyframe' || r.type === 'header') {
        scan.checkpointBytes = end
        scan.checkpointTick = r.tick
      }
    })
    if (reader.current.state !== 'reading') break
  }
  scan.preamble = reader.preamble
  scan.status = reader.finish()
  return scan
}

/**
 * Whether a log the reader calls invalid is only a start cut short: no byte contradicts a log (the
 * bytes are a prefix of the magic, or a good preamble followed by an incomplete header).
 */
function cutBeforeHeader(scan: LogScan, size: number, head: Uint8Array): boolean {
  if (scan.status.state !== 'invalid') return false
  if (scan.preamble) return scan.status.records === 0 && scan.status.reason === 'the log has no header record'
  return size < PREAMBLE_BYTES && head.every((b, i) => i >= REPLAY_MAGIC.length || b === REPLAY_MAGIC[i])
}

function statusOf(s: ReadStatus): LogSummary['status'] {
  if (s.closed) return 'clean'
  if (s.state === 'corrupt' || s.state === 'invalid') return s.state
  return 'torn'
}

const cache = new Map<string, { size: number; mtime: number; summary: LogSummary }>()

/** Summarize one log (cached while its size and mtime stay the same). */
export async function summarize(dir: string, name: string, open: ReadonlySet<string>): Promise<LogSummary> {
  const path = join(dir, name)
  const info = await stat(path)
  const hit = cache.get(path)
  let summary: LogSummary
  if (hit && hit.size === info.size && hit.mtime === info.mtimeMs) summary = hit.summary
  else {
    const scan = await scanLog(path)
    const head = info.size < PREAMBLE_BYTES ? new Uint8Array(await readFile(path)) : new Uint8Array(0)
    const empty = cutBeforeHeader(scan, info.size, head)
    const rate = scan.preamble?.tickRate || 60
    const ticks = scan.header ? scan.status.lastTick - scan.status.firstTick : 0
    summary = {
      name,
      room: scan.header?.room ?? roomOfLog(name),
      start: new Date(scan.header?.start ?? info.mtimeMs).toISOString(),
      duration: ticks / rate,
      ticks,
      size: info.size,
      status: empty ? 'empty' : statusOf(scan.status),
    }
    if (scan.header) summary.writer = { host: scan.header.host, pid: scan.header.pid }
    if (empty)
      summary.problem = `nothing recorded: the writer stopped before the header was whole (${info.size} bytes)`
    else if (scan.status.reason) summary.problem = scan.status.reason
    else if (!scan.status.closed) summary.problem = 'no clean-close record'
    cache.set(path, { size: info.size, mtime: info.mtimeMs, summary })
  }
  return open.has(name) ? { ...summary, status: 'recording', problem: undefined } : summary
}

/** Log names in the directory, oldest first (an absent directory has none). */
export async function listLogNames(dir: string): Promise<string[]> {
  let names: string[]
  try {
    names = await readdir(dir)
  } catch {
    return []
  }
  const logs = names.filter(isLogName)
  const stamp = stampOfLog
  return logs.sort((a, b) => (stamp(a) < stamp(b) ? -1 : stamp(a) > stamp(b) ? 1 : a < b ? -1 : 1))
}

/** Summaries of every log, newest first. */
export async function listLogs(dir: string, open: ReadonlySet<string>): Promise<LogSummary[]> {
  const out: LogSummary[] = []
  for (const name of (await listLogNames(dir)).reverse()) {
    try {
      out.push(await summarize(dir, name, open))
    } catch {
      // Deleted between readdir and stat (pruning): not listed.
    }
  }
  return out
}

/** Delete the oldest logs beyond `keep`, never one that is open. Returns the names deleted. */
export async function pruneLogs(dir: string, keep: number, open: ReadonlySet<string>): Promise<string[]> {
  const names = await listLogNames(dir)
  const deleted: string[] = []
  let excess = names.length - keep
  for (const name of names) {
    if (excess <= 0) break
    if (open.has(name)) continue
    await unlink(join(dir, name)).catch(() => {})
    deleted.push(name)
    excess--
  }
  return deleted
}
